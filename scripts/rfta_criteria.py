#!/usr/bin/env python3
"""RFTA's Table 2 rows against the paper's, per grid: the checks a reproduction is held to.

From arcs results files of an `sdf_grid` experiment (`sdf_methods_table.yaml`, `rfta_table1.yaml`
or any part of them) this prints, for each grid n:

- RFTA's mean Chamfer and E_SDF over the shapes where it succeeded, beside the paper's RFTA column
  (`rfta_paper_table2.csv`, group `all`), and whether ours is at or below it;
- RFTA's mean Hausdorff beside our marching cubes' over the shapes where both succeeded, and
  whether ours is below;
- how often the output has the reference's component count and genus, RFTA and MC side by side;
- the final points left inside a sphere by more than tol (`final_infeasible`, summed), and RFTA's
  median and largest method time.

    python3 scripts/rfta_criteria.py docs/runs/rfta_gauss_seidel/s38_n50.csv ... \
        [--mc-results docs/runs/sdf_methods_table/s19_n30_all_methods.csv ...] \
        [--paper ${ARCS_SHARED_DIR}/reference/rfta_paper_table2.csv] [--method RFTA] [--mc MC]

Our method's rows come from the results files, MC's from the same files or, with --mc-results,
from other runs (marching cubes on the same grid does not change between runs). Rows are merged
by case id as `arcs table` merges parts (the last `ok` row of a case wins), so a run split into
parts reads as one; two different cases of one method on one shape and grid are an error, not
averaged (pick the run with --method or fewer files). A column a file lacks (an older file, a run
without MC) is printed as "—", never guessed. The paper's shapes are not ours: the means compare trends, and
scripts/paired_ratios.py gives the per-shape view.
"""
import argparse
import csv
import os
import statistics
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paired_ratios import merged_rows  # noqa: E402  (the project's one merge rule for results files)

NEEDED = ("case_id", "status", "item", "method", "sdf_grid.n")


def read_rows(paths):
    """The ok rows of arcs results files, merged by case id as `arcs table` merges them
    (paired_ratios.merged_rows), each with its file under "_file"."""
    return [r for r in merged_rows(paths, NEEDED).values() if r["status"] == "ok"]


def read_paper(path):
    """{n: {"chamfer": .., "e_sdf": ..}} from the paper's Table 2 file, group `all`."""
    out = {}
    with open(path, newline="") as f:
        for line_no, row in enumerate(csv.DictReader(line for line in f if not line.startswith("#")), start=2):
            try:
                if row["group"] != "all":
                    continue
                out[int(row["grid"])] = {"chamfer": float(row["chamfer_rfta"]), "e_sdf": float(row["esdf_rfta"])}
            except (KeyError, ValueError) as e:
                raise SystemExit("%s:%d: %s (the paper's Table 2 file: group, grid, chamfer_rfta, esdf_rfta)"
                                 % (path, line_no, e))
    return out


def number(row, col):
    v = row.get(col, "")
    if v in ("", "nan", None):
        return None
    return float(v)


def flag(row, col):
    v = row.get(col, "")
    if v in ("", None):
        return None
    return v.strip().lower() in ("1", "true", "yes")


def present(values):
    """The values that are there (a column a row lacks reads None)."""
    return [v for v in values if v is not None]


def mean(values):
    values = present(values)
    return sum(values) / len(values) if values else None


def rate(rows, col):
    """(matching, counted) over the rows that have the column."""
    flags = present(flag(r, col) for r in rows)
    return (sum(flags), len(flags)) if flags else None


def fmt(v, spec="%.4f"):
    return "—" if v is None else spec % v


def verdict(ok):
    return "—" if ok is None else ("yes" if ok else "no")


def by_grid(rows, method):
    """{n: {item: row}} for one method; two different cases of it on one shape and grid are an error."""
    out = defaultdict(dict)
    for r in rows:
        if r["method"] != method:
            continue
        n = int(float(r["sdf_grid.n"]))
        old = out[n].get(r["item"])
        if old is not None:
            raise SystemExit("two cases of %s on %s at n = %d: %s (%s) and %s (%s); pass one run's rows"
                             % (method, r["item"], n, old["case_id"], old["_file"], r["case_id"], r["_file"]))
        out[n][r["item"]] = r
    return out


def summarize(rows, paper, method, mc, mc_rows=None):
    """One dict per grid n with the figures the table prints. mc_rows: MC's rows, when not in rows."""
    ours_by_n = by_grid(rows, method)
    mc_by_n = by_grid(rows if mc_rows is None else mc_rows, mc)
    out = []
    for n in sorted(ours_by_n):
        ours = ours_by_n[n]
        mcs = mc_by_n.get(n, {})
        both = sorted(set(ours) & set(mcs))
        s = {"n": n, "shapes": len(ours)}
        s["chamfer"] = mean(number(r, "chamfer") for r in ours.values())
        s["e_sdf"] = mean(number(r, "e_sdf") for r in ours.values())
        s["paper_chamfer"] = paper.get(n, {}).get("chamfer")
        s["paper_e_sdf"] = paper.get(n, {}).get("e_sdf")
        s["hausdorff"] = mean(number(ours[i], "hausdorff") for i in both) if both else None
        s["mc_hausdorff"] = mean(number(mcs[i], "hausdorff") for i in both) if both else None
        s["both"] = len(both)
        s["components"] = rate(ours.values(), "components_match")
        s["genus"] = rate(ours.values(), "genus_matches")
        s["mc_components"] = rate(mcs.values(), "components_match") if mcs else None
        s["mc_genus"] = rate(mcs.values(), "genus_matches") if mcs else None
        left = present(number(r, "final_infeasible") for r in ours.values())
        s["final_infeasible"] = int(sum(left)) if left else None
        times = present(number(r, "method_wall_s") for r in ours.values())
        s["time_median"] = statistics.median(times) if times else None
        s["time_max"] = max(times) if times else None

        def at_or_below(a, b):
            return None if a is None or b is None else a <= b

        s["chamfer_ok"] = at_or_below(s["chamfer"], s["paper_chamfer"])
        s["e_sdf_ok"] = at_or_below(s["e_sdf"], s["paper_e_sdf"])
        s["hausdorff_ok"] = (None if s["hausdorff"] is None or s["mc_hausdorff"] is None
                             else s["hausdorff"] < s["mc_hausdorff"])
        out.append(s)
    return out


def fmt_rate(r):
    return "—" if r is None else "%d / %d (%d %%)" % (r[0], r[1], round(100.0 * r[0] / r[1]) if r[1] else 0)


def print_table(summary, method, mc):
    print("| n | shapes | Chamfer %s | paper | <= | E_SDF %s | paper | <= | Hausdorff %s | %s (same shapes) | < "
          "| components right %s | %s | genus right %s | %s | final_infeasible | time median / max s |"
          % (method, method, method, mc, method, mc, method, mc))
    print("|---:|---:|---:|---:|---|---:|---:|---|---:|---:|---|---|---|---|---|---:|---|")
    for s in summary:
        print("| %d | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s / %s |" % (
            s["n"], s["shapes"], fmt(s["chamfer"]), fmt(s["paper_chamfer"]), verdict(s["chamfer_ok"]),
            fmt(s["e_sdf"]), fmt(s["paper_e_sdf"]), verdict(s["e_sdf_ok"]),
            fmt(s["hausdorff"]), fmt(s["mc_hausdorff"]), verdict(s["hausdorff_ok"]),
            fmt_rate(s["components"]), fmt_rate(s["mc_components"]),
            fmt_rate(s["genus"]), fmt_rate(s["mc_genus"]),
            "—" if s["final_infeasible"] is None else str(s["final_infeasible"]),
            fmt(s["time_median"], "%.1f"), fmt(s["time_max"], "%.1f")))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+", help="arcs results files (results.csv of sdf_grid experiments)")
    shared = os.environ.get("ARCS_SHARED_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared"))
    ap.add_argument("--paper", default=os.path.join(shared, "reference", "rfta_paper_table2.csv"),
                    help="the paper's Table 2 (group, grid, chamfer_rfta, esdf_rfta)")
    ap.add_argument("--method", default="RFTA", help="our method's name in the results (default RFTA)")
    ap.add_argument("--mc", default="MC", help="the marching-cubes method's name (default MC)")
    ap.add_argument("--mc-results", nargs="+", default=None,
                    help="take MC's rows from these files instead of the results files")
    args = ap.parse_args(argv)
    if not os.path.exists(args.paper):
        raise SystemExit("%s: not found (set ARCS_SHARED_DIR or pass --paper)" % args.paper)
    mc_rows = read_rows(args.mc_results) if args.mc_results else None
    summary = summarize(read_rows(args.results), read_paper(args.paper), args.method, args.mc, mc_rows)
    if not summary:
        raise SystemExit("no ok rows of method '%s' in %s" % (args.method, ", ".join(args.results)))
    print_table(summary, args.method, args.mc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
