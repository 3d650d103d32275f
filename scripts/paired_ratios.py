#!/usr/bin/env python3
"""Per-shape ratios between methods, ours beside the paper's: a comparison the shape set cancels out of.

Table 2's means depend on the shapes: the paper's are 99 rotated Thingi10K meshes, ours the 27
bench meshes. A method's error divided by another method's error *on the same shape* mostly
does not, so the paired ratios (RFTA / MC, RFTS / MC, RFTA / RFTS ...) say whether our method
stands to the others as the paper's did, which the means cannot.

    python3 scripts/paired_ratios.py docs/runs/sdf_methods_table/*.csv \
        [--paper ${ARCS_SHARED_DIR}/reference/rfta_paper_results.csv] \
        [--metric chamfer] [--pairs RFTA/MC,RFTS/MC,RFTA/RFTS,DCSDD/MC=NDC/MC]

A pair OURS=PAPER sets our methods and the paper's apart: DCSDD/MC=NDC/MC prints our DCSDD / MC
beside the paper's NDC / MC (a method the paper did not run against one it did).

Ours: arcs results files (`arcs run` results.csv; rows merged by case id as `arcs table` merges
them, the last `ok` row winning; `ok` rows only), method
column `method`, grid column `sdf_grid.n`, genus `ref_genus`. Paper: the long per-shape file
(mesh, genus, resolution, method, metric, error). A shape counts for a pair at a grid where both
methods have a value. Printed per grid and genus group: shapes, median and geometric mean of
the ratio (below 1: the first method is better on that shape).
"""
import argparse
import csv
import math
import os
import statistics
import sys
from collections import defaultdict

# Our metric column -> the paper file's metric name; our method names -> the paper's.
PAPER_METRIC = {"chamfer": "chf", "hausdorff": "hd", "e_sdf": "sdf"}
GROUPS = [("all", lambda g: True), ("genus 0", lambda g: g == 0), ("genus > 0", lambda g: g > 0)]


def merged_rows(paths, columns):
    """{case_id: row} from arcs results files merged as `arcs table` merges them: the last ok row of
    a case wins (a later part re-running a method replaces the earlier rows), a failure never
    replaces an ok row. Each row keeps its file under "_file"; a row without one of `columns` is
    an error naming the file and line."""
    by_case = {}
    for path in paths:
        with open(path, newline="") as f:
            for line_no, row in enumerate(csv.DictReader(f), start=2):
                for col in columns:
                    if col not in row:
                        raise SystemExit("%s:%d: no column '%s' (an arcs results file of an sdf_grid experiment?)"
                                         % (path, line_no, col))
                row["_file"] = path
                old = by_case.get(row["case_id"])
                if old is None or row["status"] == "ok" or old["status"] != "ok":
                    by_case[row["case_id"]] = row
    return by_case


def read_ours(paths, metric):
    """{(item, n): {"genus": g, METHOD: value}} from arcs results files (ok rows, merged by case id)."""
    by_case = merged_rows(paths, ("case_id", "status", "item", "method", "sdf_grid.n", "ref_genus", metric))
    shapes = defaultdict(dict)
    for row in by_case.values():
        if row["status"] != "ok" or row[metric] in ("", "nan"):
            continue
        key = (row["item"], int(float(row["sdf_grid.n"])))
        shapes[key]["genus"] = int(float(row["ref_genus"]))
        shapes[key][row["method"].upper()] = float(row[metric])
    return shapes


def read_paper(path, metric):
    """{(mesh, n): {"genus": g, METHOD: value}} from the paper's long per-shape file."""
    want = PAPER_METRIC[metric]
    shapes = defaultdict(dict)
    with open(path, newline="") as f:
        rows = csv.reader(line for line in f if not line.startswith("#"))
        header = next(rows)
        if header[:6] != ["mesh", "genus", "resolution", "method", "metric", "error"]:
            raise SystemExit("%s: expected the columns mesh,genus,resolution,method,metric,error, got %s"
                             % (path, ",".join(header)))
        for r in rows:
            if r[4] != want:
                continue
            key = (r[0], int(float(r[2])))
            shapes[key]["genus"] = int(float(r[1]))
            shapes[key][r[3].upper()] = float(r[5])
    return shapes


def ratio_stats(shapes, n, a, b, keep):
    """(count, median, geometric mean) of a / b over the shapes at grid n with both values."""
    ratios = [v[a] / v[b] for (item, grid), v in shapes.items()
              if grid == n and keep(v["genus"]) and a in v and b in v and v[b] > 0 and v[a] > 0]
    if not ratios:
        return 0, float("nan"), float("nan")
    gmean = math.exp(sum(math.log(x) for x in ratios) / len(ratios))
    return len(ratios), statistics.median(ratios), gmean


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+", help="arcs results files (results.csv)")
    shared = os.environ.get("ARCS_SHARED_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "shared"))
    ap.add_argument("--paper", default=os.path.join(shared, "reference", "rfta_paper_results.csv"))
    ap.add_argument("--metric", default="chamfer", choices=sorted(PAPER_METRIC))
    ap.add_argument("--pairs", default="RFTA/MC,RFTS/MC,RFTA/RFTS")
    args = ap.parse_args(argv)
    pairs = []  # ((ours a, ours b), (paper a, paper b))
    for p in args.pairs.split(","):
        sides = p.split("=")
        if len(sides) > 2 or any(side.count("/") != 1 for side in sides):
            raise SystemExit("--pairs: '%s' is not METHOD/METHOD or METHOD/METHOD=METHOD/METHOD" % p)
        parsed = [tuple(x.strip().upper() for x in side.split("/")) for side in sides]
        pairs.append((parsed[0], parsed[-1]))
    ours = read_ours(args.results, args.metric)
    paper = read_paper(args.paper, args.metric) if os.path.exists(args.paper) else {}
    if not paper:
        print("(no paper file at %s: ours only)" % args.paper, file=sys.stderr)
    grids = sorted({n for _, n in ours})
    head = "| n | group | " + " | ".join("%s ours | %s paper" % ("/".join(o), "/".join(q)) for o, q in pairs) + " |"
    print("Paired %s ratios per shape: geometric mean (median) [shapes]\n" % args.metric)
    print(head)
    print("|---|---|" + "---:|" * (2 * len(pairs)))
    for n in grids:
        for name, keep in GROUPS:
            cells = []
            for o, q in pairs:
                for src, (a, b) in ((ours, o), (paper, q)):
                    c, med, gm = ratio_stats(src, n, a, b, keep)
                    cells.append("%.3f (%.3f) [%d]" % (gm, med, c) if c else "–")
            print("| %d | %s | %s |" % (n, name, " | ".join(cells)))


if __name__ == "__main__":
    main(sys.argv[1:])
