#!/usr/bin/env python3
"""Figures, mesh renders and an HTML report from an arcs results directory.

Driven by `arcs plot`, `arcs render` and `arcs report` (app/cmd_plot.cpp), or
run directly:

  arcs_plot.py plot RESULTS_DIR [--figure NAME]... [--out DIR] [--formats png,pdf]
                    [--reference-runtime CSV] [--reference-shapes CSV] [--reference-voxel CSV]
  arcs_plot.py render MESH... --out IMAGE [--labels A,B,...] [--size PX]
  arcs_plot.py report RESULTS_DIR [--out FILE.html] [--max-renders N] (+ the plot options)

Figures (each skipped, with the reason printed, when the results lack what it needs):
  runtime   the paper's Fig. 14: method wall time (and Chamfer) against the number of
            SDF samples, log-log, one line per method; the paper's curves beside when
            the runtime CSV is there (../shared/reference/rfta_paper_runtime.csv).
  scatter   the paper's Fig. 19: per shape and resolution, one method's metric against
            another's (every pair, y = x drawn), and ours against the paper's per-shape
            values (../shared/reference/rfta_paper_results.csv) where shapes match.
  ablation  every swept parameter x every metric: mean over items, one line per method.
  voxel     the voxelization tables (Luo et al.): doph_chamfer / doph_hausdorff against
            the resolution per method, the paper's methods beside (doph_paper_tables.csv).
Renders: saved meshes (reference | method | method ...) side by side, Lambert-shaded,
orthographic, all panels in the reference's frame and scale (matplotlib, Agg, headless).

Only Debian's python3-matplotlib and python3-numpy are needed.
"""
import argparse
import base64
import csv
import html
import io
import math
import os
import re
import struct
import sys
from collections import OrderedDict, defaultdict

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

# Results columns that are not parameters or metrics.
META = {"case_id", "status", "error", "dataset", "item", "input", "method", "seed", "wall_s", "peak_rss_mb",
        "method_wall_s", "method_peak_rss_mb", "method_extra_rss_mb", "input_wall_s", "input_samples",
        "output_file", "output_points_file", "reference_file", "ref_faces", "ref_genus", "ref_closed"}
# Metrics shown first (the paper's), then any other numeric column.
PREFERRED = ["chamfer", "hausdorff", "e_sdf", "chamfer_p2s", "hausdorff_sampled", "doph_chamfer",
             "doph_hausdorff", "chamfer_2d", "hausdorff_2d", "method_wall_s"]


def fail(msg):
    print("arcs plot: error: " + msg, file=sys.stderr)
    sys.exit(1)


def shared_dir():
    if os.environ.get("ARCS_SHARED_DIR"):
        return os.environ["ARCS_SHARED_DIR"]
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared")


def default_ref(name):
    p = os.path.join(shared_dir(), "reference", name)
    return p if os.path.exists(p) else None


def to_float(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def read_csv_commented(path):
    """A CSV whose leading lines may be '#' comments (the reference CSVs)."""
    with open(path, newline="") as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    return list(csv.DictReader(lines))


class Results:
    def __init__(self, d):
        self.dir = d
        path = os.path.join(d, "results.csv")
        if not os.path.exists(path):
            fail(path + ": no results file (is " + d + " a results directory? run `arcs run` first)")
        with open(path, newline="") as f:
            self.all = list(csv.DictReader(f))
        if not self.all:
            fail(path + ": no rows")
        self.columns = list(self.all[0].keys())
        self.rows = [r for r in self.all if r.get("status") == "ok"]
        self.failed = len(self.all) - len(self.rows)
        self.methods = list(OrderedDict.fromkeys(r["method"] for r in self.rows))
        self.params = [c for c in self.columns if "." in c and c not in META]
        num = [c for c in self.columns if c not in META and "." not in c and
               any(to_float(r.get(c)) is not None for r in self.rows)]
        self.metrics = [m for m in PREFERRED if m in num or m == "method_wall_s" and m in self.columns]
        self.metrics += [m for m in num if m not in self.metrics]
        # Input parameters: set for every case (a method's own are empty for other methods).
        self.input_params = [c for c in self.params if all(r.get(c, "") != "" for r in self.rows)]
        self.swept = [c for c in self.params if len({r.get(c, "") for r in self.rows if r.get(c, "") != ""}) > 1]

    def value(self, r, c):
        return to_float(r.get(c))


def grid_n(r):
    for c in ("sdf_grid.n", "sdf_grid_2d.n"):
        v = to_float(r.get(c))
        if v is not None:
            return int(v)
    return None


def save(fig, out_dir, name, formats):
    os.makedirs(out_dir, exist_ok=True)
    paths = []
    for fmt in formats:
        p = os.path.join(out_dir, name + "." + fmt)
        fig.savefig(p, dpi=110, bbox_inches="tight")
        paths.append(p)
    plt.close(fig)
    print("wrote " + ", ".join(paths))
    return paths


def mean(xs):
    xs = [x for x in xs if x is not None]
    return sum(xs) / len(xs) if xs else None


# ---------------------------------------------------------------- figures

def fig_runtime(res, out, formats, ref_csv):
    """Fig. 14: time (and Chamfer) against the number of samples."""
    pts = defaultdict(lambda: defaultdict(list))  # method -> samples -> [seconds]
    chf = defaultdict(lambda: defaultdict(list))
    for r in res.rows:
        s, t = res.value(r, "input_samples"), res.value(r, "method_wall_s")
        if s is None or t is None:
            continue
        pts[r["method"]][s].append(t)
        c = res.value(r, "chamfer")
        if c is not None:
            chf[r["method"]][s].append(c)
    if not any(len(v) > 1 for v in pts.values()):
        return None, "needs input_samples and method_wall_s at two or more sample counts"
    ref = defaultdict(list)
    if ref_csv and os.path.exists(ref_csv):
        for row in read_csv_commented(ref_csv):
            ref[row["method"]].append((float(row["n_cubed"]), float(row["seconds"]), to_float(row.get("chamfer"))))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    colors = {}
    for i, m in enumerate(list(pts) + [k for k in ref if k not in pts]):
        colors[m] = "C%d" % (i % 10)
    for m, d in pts.items():
        xs = sorted(d)
        axes[0].plot(xs, [np.median(d[x]) for x in xs], "o-", color=colors[m], label=m + " (ours)")
        if chf[m]:
            xc = sorted(chf[m])
            axes[1].plot(xc, [np.mean(chf[m][x]) for x in xc], "o-", color=colors[m], label=m + " (ours)")
    for m, rows in ref.items():
        rows.sort()
        axes[0].plot([a for a, _, _ in rows], [b for _, b, _ in rows], "s--", color=colors[m], alpha=0.6,
                     mfc="none", label=m + " (paper)")
        if any(c is not None for _, _, c in rows):
            axes[1].plot([a for a, _, c in rows if c is not None], [c for _, _, c in rows if c is not None], "s--",
                         color=colors[m], alpha=0.6, mfc="none", label=m + " (paper, bunny)")
    axes[0].set(xscale="log", yscale="log", xlabel="SDF samples (n³ on a grid)", ylabel="method wall time (s)",
                title="runtime (paper Fig. 14)")
    axes[1].set(xscale="log", yscale="log", xlabel="SDF samples", ylabel="Chamfer (mean over items)",
                title="error")
    for a in axes:
        a.grid(True, which="both", alpha=0.25)
        a.legend(fontsize=7)
    return save(fig, out, "runtime", formats), None


PAPER_METRIC = {"chamfer": "chf", "hausdorff": "hd", "e_sdf": "sdf"}


def fig_scatter(res, out, formats, ref_csv):
    """Fig. 19: per case, method against method, and ours against the paper's per-shape values."""
    metrics = [m for m in ("chamfer", "hausdorff", "e_sdf") if m in res.metrics] or res.metrics[:1]
    if not metrics:
        return None, "no metric columns"
    key_cols = ["dataset", "item", "input"] + res.input_params
    by_case = defaultdict(dict)  # case key -> method -> row
    for r in res.rows:
        by_case[tuple(r.get(c, "") for c in key_cols)][r["method"]] = r
    pairs = [(a, b) for i, a in enumerate(res.methods) for b in res.methods[i + 1:]]
    paper = {}
    if ref_csv and os.path.exists(ref_csv):
        for row in read_csv_commented(ref_csv):
            paper[(row["mesh"], int(float(row["resolution"])), row["method"], row["metric"])] = float(row["error"])
    ours_vs_paper = defaultdict(list)  # (method, metric) -> [(paper, ours)]
    for r in res.rows:
        n = grid_n(r)
        for m in metrics:
            v = res.value(r, m)
            p = paper.get((r["item"], n, r["method"].lower(), PAPER_METRIC.get(m, m))) if n else None
            if v is not None and p is not None:
                ours_vs_paper[(r["method"], m)].append((p, v))
    pair_pts = {}
    for (a, b) in pairs:
        for m in metrics:
            pts = []
            for case, d in by_case.items():
                if a in d and b in d:
                    x, y = res.value(d[a], m), res.value(d[b], m)
                    if x is not None and y is not None and x > 0 and y > 0:
                        pts.append((x, y, grid_n(d[a]) or 0))
            if pts:
                pair_pts[(a, b, m)] = pts
    panels = [("pair", a, b, m) for (a, b, m) in pair_pts]
    panels += [("paper", meth, None, m) for (meth, m) in ours_vs_paper]
    if not panels:
        return None, "needs two methods on the same cases, or shapes in the paper's per-shape CSV"
    cols = min(3, len(panels))
    rows_n = (len(panels) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(4.2 * cols, 3.9 * rows_n), squeeze=False)
    for ax, (kind, a, b, m) in zip(axes.flat, panels):
        if kind == "pair":
            xs, ys, cs = (list(t) for t in zip(*pair_pts[(a, b, m)]))
            sc = ax.scatter(xs, ys, c=cs, cmap="viridis", s=18)
            if any(cs):
                fig.colorbar(sc, ax=ax, label="grid n")
            better = sum(1 for x, y in zip(xs, ys) if y < x)
            ax.set(xlabel="%s %s" % (a, m), ylabel="%s %s" % (b, m),
                   title="%s vs %s: %s lower on %d of %d" % (b, a, b, better, len(xs)))
        else:
            d = ours_vs_paper[(a, m)]
            xs, ys = [p for p, _ in d], [v for _, v in d]
            ax.scatter(xs, ys, s=14, color="C1")
            ax.set(xlabel="paper %s %s" % (a, m), ylabel="ours %s %s" % (a, m),
                   title="%s: ours vs paper per shape (%d)" % (a, len(xs)))
        if xs:
            lo, hi = min(xs + ys), max(xs + ys)
            ax.plot([lo, hi], [lo, hi], "k--", lw=0.8)
            if lo > 0:
                ax.set(xscale="log", yscale="log")
        ax.grid(True, alpha=0.25)
        ax.title.set_fontsize(8)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    fig.suptitle("per-shape comparison (paper Fig. 19)")
    fig.tight_layout()
    return save(fig, out, "scatter", formats), None


def sort_key(v):
    f = to_float(v)
    return (0, f, "") if f is not None else (1, 0, v)


def fig_ablation(res, out, formats):
    """Every swept parameter x metric, mean over items, one line per method."""
    metrics = [m for m in res.metrics if m in PREFERRED] or res.metrics[:4]
    sweeps = [c for c in res.swept]
    if not sweeps or not metrics:
        return None, "no swept parameter"
    fig, axes = plt.subplots(len(sweeps), len(metrics), figsize=(3.6 * len(metrics), 3.2 * len(sweeps)),
                             squeeze=False)
    for i, p in enumerate(sweeps):
        vals = sorted({r[p] for r in res.rows if r.get(p, "") != ""}, key=sort_key)
        numeric = all(to_float(v) is not None for v in vals)
        for j, m in enumerate(metrics):
            ax = axes[i][j]
            for meth in res.methods:
                xs, ys = [], []
                for k, v in enumerate(vals):
                    y = mean([res.value(r, m) for r in res.rows if r["method"] == meth and r.get(p) == v])
                    if y is not None:
                        xs.append(to_float(v) if numeric else k)
                        ys.append(y)
                if xs:
                    ax.plot(xs, ys, "o-", label=meth, ms=4)
            if numeric:
                fv = [to_float(v) for v in vals]
                if min(fv) > 0 and max(fv) / min(fv) > 20:
                    ax.set_xscale("log")
            else:
                ax.set_xticks(range(len(vals)))
                ax.set_xticklabels([textwrap_short(v) for v in vals], rotation=30, ha="right", fontsize=6)
            ys_all = [l.get_ydata() for l in ax.get_lines()]
            if ys_all and min(min(y) for y in ys_all) > 0 and max(max(y) for y in ys_all) / min(min(y) for y in ys_all) > 20:
                ax.set_yscale("log")
            ax.set(xlabel=p, ylabel=m)
            ax.grid(True, alpha=0.25)
            if i == 0 and j == 0 and ax.get_lines():
                ax.legend(fontsize=7)
    fig.suptitle("ablation: metric against every swept parameter (mean over items)")
    fig.tight_layout()
    return save(fig, out, "ablation", formats), None


def textwrap_short(v, n=24):
    return v if len(v) <= n else v[:n - 1] + "…"


def fig_voxel(res, out, formats, ref_csv):
    """The voxelization tables as curves: doph metrics against resolution, paper beside."""
    rc = next((c for c in res.params if c.endswith(".resolution")), None)
    ms = [m for m in ("doph_chamfer", "doph_hausdorff") if m in res.metrics]
    if not rc or not ms:
        return None, "needs a voxelizer resolution column and doph_metrics"
    faces = {r.get("ref_faces") for r in res.rows}
    paper = defaultdict(lambda: defaultdict(list))  # (metric, method) -> res -> [values]
    if ref_csv and os.path.exists(ref_csv):
        for row in read_csv_commented(ref_csv):
            if row.get("faces") in faces:
                paper[(row["metric"], row["method"])][float(row["resolution"])].append(float(row["value"]))
    fig, axes = plt.subplots(1, len(ms), figsize=(5.5 * len(ms), 4.2), squeeze=False)
    for ax, m in zip(axes[0], ms):
        for meth in res.methods:
            d = defaultdict(list)
            for r in res.rows:
                if r["method"] == meth and to_float(r.get(rc)) is not None:
                    d[to_float(r[rc])].append(res.value(r, m))
            xs = [x for x in sorted(d) if mean(d[x]) is not None]
            if xs:
                ax.plot(xs, [mean(d[x]) for x in xs], "o-", label=meth + " (ours)")
        pm = m.replace("doph_", "")
        for (metric, meth), d in paper.items():
            if metric == pm:
                xs = sorted(d)
                ax.plot(xs, [mean(d[x]) for x in xs], "s--", mfc="none", alpha=0.7, label=meth + " (paper)")
        ax.set(xscale="log", xlabel="voxel resolution", ylabel=m + " (mean over meshes)",
               title="voxelization (Luo et al. tables): " + m)
        ticks = {to_float(r[rc]) for r in res.rows if to_float(r.get(rc))}
        for (metric, _), d in paper.items():
            ticks |= set(d) if metric == pm else set()
        ax.set_xticks(sorted(ticks))
        ax.get_xaxis().set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.get_xaxis().set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.grid(True, alpha=0.25)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return save(fig, out, "voxel", formats), None


FIGURES = ["runtime", "scatter", "ablation", "voxel"]


def make_figures(res, args):
    out = args.out or os.path.join(res.dir, "figures")
    formats = [f for f in args.formats.split(",") if f]
    for f in formats:
        if f not in ("png", "pdf", "svg"):
            fail("--formats: unknown format '%s' (png, pdf, svg)" % f)
    wanted = args.figure or FIGURES
    for f in wanted:
        if f not in FIGURES:
            fail("--figure: unknown figure '%s' (one of: %s)" % (f, ", ".join(FIGURES)))
    made, skipped = OrderedDict(), OrderedDict()
    for f in wanted:
        if f == "runtime":
            p, why = fig_runtime(res, out, formats, args.reference_runtime)
        elif f == "scatter":
            p, why = fig_scatter(res, out, formats, args.reference_shapes)
        elif f == "ablation":
            p, why = fig_ablation(res, out, formats)
        else:
            p, why = fig_voxel(res, out, formats, args.reference_voxel)
        if p:
            made[f] = p
        else:
            skipped[f] = why
            print("skipped figure %s: %s" % (f, why))
    return made, skipped


# ---------------------------------------------------------------- meshes and renders

PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
             "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError(path + ": not a PLY file")
    nl = data.index(b"\n", end)
    header = data[:nl].decode("ascii", "replace").splitlines()
    body = data[nl + 1:]
    fmt, elements = "ascii", []
    for ln in header:
        t = ln.split()
        if not t:
            continue
        if t[0] == "format":
            fmt = t[1]
        elif t[0] == "element":
            elements.append((t[1], int(t[2]), []))
        elif t[0] == "property":
            elements[-1][2].append(tuple(t[1:]))
    V, F = None, None
    if fmt == "ascii":
        toks = body.split()
        pos = 0
        for name, count, props in elements:
            if name == "vertex":
                k = len(props)
                arr = np.array(toks[pos:pos + k * count], dtype=float).reshape(count, k)
                names = [p[-1] for p in props]
                V = arr[:, [names.index("x"), names.index("y"), names.index("z")]]
                pos += k * count
            elif name == "face":
                faces = []
                for _ in range(count):
                    c = int(toks[pos])
                    idx = [int(x) for x in toks[pos + 1:pos + 1 + c]]
                    pos += 1 + c + (len(props) - 1)  # other face properties: one token each
                    faces += [[idx[0], idx[i], idx[i + 1]] for i in range(1, c - 1)]
                F = np.array(faces, dtype=np.int64).reshape(-1, 3)
            else:
                pos += count * len(props)
    else:
        bo = "<" if fmt == "binary_little_endian" else ">"
        pos = 0
        for name, count, props in elements:
            if all(p[0] != "list" for p in props):
                dt = np.dtype([(p[1], bo + PLY_TYPES[p[0]]) for p in props])
                arr = np.frombuffer(body, dtype=dt, count=count, offset=pos)
                pos += dt.itemsize * count
                if name == "vertex":
                    V = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(float)
            elif name == "face" and len(props) == 1:
                ct, it = PLY_TYPES[props[0][1]], PLY_TYPES[props[0][2]]
                dt = np.dtype([("c", bo + ct), ("i", bo + it, (3,))])
                arr = np.frombuffer(body, dtype=dt, count=count, offset=pos) if count else None
                if count and np.all(arr["c"] == 3):
                    F = arr["i"].astype(np.int64)
                    pos += dt.itemsize * count
                else:  # polygons: walk
                    faces = []
                    cs, isz = np.dtype(bo + ct), np.dtype(bo + it)
                    for _ in range(count):
                        c = int(np.frombuffer(body, cs, 1, pos)[0])
                        idx = np.frombuffer(body, isz, c, pos + cs.itemsize)
                        pos += cs.itemsize + c * isz.itemsize
                        faces += [[idx[0], idx[i], idx[i + 1]] for i in range(1, c - 1)]
                    F = np.array(faces, dtype=np.int64).reshape(-1, 3)
            else:
                raise ValueError(path + ": unsupported PLY element '%s' layout for rendering" % name)
    if V is None:
        raise ValueError(path + ": no vertex element")
    return V, (F if F is not None else np.zeros((0, 3), np.int64))


def read_mesh(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ply":
        return read_ply(path)
    V, F = [], []
    with open(path, errors="replace") as f:
        if ext == ".off":
            toks = f.read().split()
            if toks[0] != "OFF":
                raise ValueError(path + ": not an OFF file")
            nv, nf = int(toks[1]), int(toks[2])
            V = np.array(toks[4:4 + 3 * nv], float).reshape(nv, 3)
            pos = 4 + 3 * nv
            for _ in range(nf):
                c = int(toks[pos])
                idx = [int(x) for x in toks[pos + 1:pos + 1 + c]]
                pos += 1 + c
                F += [[idx[0], idx[i], idx[i + 1]] for i in range(1, c - 1)]
            return V, np.array(F, np.int64).reshape(-1, 3)
        if ext != ".obj":
            raise ValueError(path + ": cannot render '%s' files (PLY, OBJ, OFF)" % ext)
        for ln in f:
            t = ln.split()
            if not t:
                continue
            if t[0] == "v":
                V.append([float(eval_frac(x)) for x in t[1:4]])
            elif t[0] == "f":
                idx = [int(x.split("/")[0]) for x in t[1:]]
                idx = [i - 1 if i > 0 else len(V) + i for i in idx]
                F += [[idx[0], idx[i], idx[i + 1]] for i in range(1, len(idx) - 1)]
    return np.array(V, float).reshape(-1, 3), np.array(F, np.int64).reshape(-1, 3)


def eval_frac(x):
    if "/" in x:
        p, q = x.split("/")
        return float(p) / float(q)
    return float(x)


def view_matrix(elev=20.0, azim=-30.0):
    """Turn by azim about +y (up), then tilt by elev about x; the viewer looks along -z."""
    a, e = math.radians(azim), math.radians(elev)
    ry = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
    rx = np.array([[1, 0, 0], [0, math.cos(e), -math.sin(e)], [0, math.sin(e), math.cos(e)]])
    return rx @ ry


def draw_mesh(ax, V, F, frame, color=(0.62, 0.72, 0.86), max_faces=60000):
    """Orthographic, painter's algorithm, two-sided Lambert shading."""
    center, scale, R = frame
    ax.set_aspect("equal")
    ax.set_xlim(-0.55, 0.55)
    ax.set_ylim(-0.55, 0.55)
    ax.axis("off")
    if len(F) == 0:
        ax.text(0, 0, "empty", ha="center")
        return
    if len(F) > max_faces:  # a uniform subset keeps the picture and bounds the time
        F = F[np.linspace(0, len(F) - 1, max_faces).astype(np.int64)]
    X = (V - center) @ R.T / scale
    T = X[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    ln = np.linalg.norm(n, axis=1)
    ok = ln > 0
    T, n = T[ok], n[ok] / ln[ok, None]
    light = np.array([0.35, 0.45, 0.82])
    light /= np.linalg.norm(light)
    front = n[:, 2] >= 0
    lam = np.abs(n @ light)
    shade = 0.22 + 0.78 * lam
    base = np.array(color)
    back = np.array([0.85, 0.55, 0.45])  # back faces (inside visible: holes, flipped faces) reddish
    cols = np.where(front[:, None], base[None, :], back[None, :]) * shade[:, None]
    order = np.argsort(T[:, :, 2].mean(axis=1))  # far first
    pc = PolyCollection(T[order][:, :, :2], facecolors=np.clip(cols[order], 0, 1), edgecolors="none",
                        antialiased=False)
    ax.add_collection(pc)


def render_panels(paths, labels, out, size=300, elev=20.0, azim=-30.0, own_frame=False):
    meshes = []
    for p in paths:
        try:
            meshes.append(read_mesh(p))
        except (OSError, ValueError) as e:
            fail(str(e))
    R = view_matrix(elev, azim)

    def frame_of(V):
        lo, hi = V.min(axis=0), V.max(axis=0)
        X = (V - (lo + hi) / 2) @ R.T
        return (lo + hi) / 2, max(np.ptp(X[:, 0]), np.ptp(X[:, 1]), 1e-12), R

    for p, (V, _) in zip(paths, meshes):
        if len(V) == 0 and (own_frame or p == paths[0]):
            fail(p + ": no vertices")
    frame = frame_of(meshes[0][0])  # every panel in the first mesh's frame and scale
    k = len(meshes)
    fig, axes = plt.subplots(1, k, figsize=(size / 100 * k, size / 100 + 0.35), squeeze=False)
    for ax, (V, F), lab in zip(axes[0], meshes, labels):
        draw_mesh(ax, V, F, frame_of(V) if own_frame else frame)
        ax.set_title(lab, fontsize=8)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.9, wspace=0.02)
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def case_groups(res):
    """Cases sharing item, input and input parameters: reference | each method."""
    key_cols = ["dataset", "item", "input"] + [c for c in res.input_params if c in res.swept]
    groups = OrderedDict()
    for r in res.rows:
        if not r.get("output_file"):
            continue
        k = tuple(r.get(c, "") for c in key_cols)
        groups.setdefault(k, []).append(r)
    out = []
    for k, rows in groups.items():
        label = " ".join([k[1]] + ["%s=%s" % (c.split(".")[-1], v) for c, v in zip(key_cols[3:], k[3:])])
        out.append((label, rows))
    return out


def render_results(res, out_dir, max_renders):
    groups = case_groups(res)
    if not groups:
        return [], "no saved outputs (run with --save-outputs)"
    made = []
    odir = os.path.join(res.dir, "outputs")
    for label, rows in groups[:max_renders]:
        paths, labels = [], []
        ref = rows[0].get("reference_file")
        if ref and os.path.exists(os.path.join(odir, ref)):
            paths.append(os.path.join(odir, ref))
            labels.append("reference")
        for r in rows:
            p = os.path.join(odir, r["output_file"])
            if os.path.exists(p) and p.endswith((".ply", ".obj", ".off")):
                paths.append(p)
                extra = ""
                if to_float(r.get("chamfer")) is not None:
                    extra = "\nChamfer %.4f" % float(r["chamfer"])
                labels.append(r["method"] + extra)
        if len(paths) < 1 or (len(paths) == 1 and labels[0] == "reference"):
            continue
        name = re.sub(r"[^A-Za-z0-9_.-]+", "_", label)
        png = os.path.join(out_dir, "render_" + name + ".png")
        render_panels(paths, labels, png)
        made.append((label, png))
    print("wrote %d render(s) to %s" % (len(made), out_dir))
    return made, None


# ---------------------------------------------------------------- report

def data_uri(path):
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode("ascii")


def csv_to_html(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return ""
    h = ["<table><thead><tr>" + "".join("<th>%s</th>" % html.escape(c) for c in rows[0]) + "</tr></thead><tbody>"]
    for r in rows[1:]:
        h.append("<tr>" + "".join("<td>%s</td>" % html.escape(c) for c in r) + "</tr>")
    h.append("</tbody></table>")
    return "\n".join(h)


def summary_table(res):
    ms = [m for m in res.metrics if m in PREFERRED][:6]
    h = ["<table><thead><tr><th>method</th><th>cases ok</th>" +
         "".join("<th>mean %s</th>" % html.escape(m) for m in ms) + "</tr></thead><tbody>"]
    for meth in res.methods:
        rows = [r for r in res.rows if r["method"] == meth]
        cells = []
        for m in ms:
            v = mean([res.value(r, m) for r in rows])
            cells.append("<td>%s</td>" % ("%.4g" % v if v is not None else ""))
        h.append("<tr><td>%s</td><td>%d</td>%s</tr>" % (html.escape(meth), len(rows), "".join(cells)))
    h.append("</tbody></table>")
    return "\n".join(h)


CSS = """body{font-family:sans-serif;margin:2em;max-width:1300px;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1.5em;font-size:12px}
td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}th{background:#eee}
td:first-child,th:first-child{text-align:left}img{max-width:100%;border:1px solid #ddd}
h2{border-bottom:1px solid #ccc;margin-top:2em}.note{color:#777;font-size:12px}
figure{margin:0 0 1.5em}figcaption{font-size:13px;color:#444}"""

# Marks the page after load: each <img> gets data-loaded="1"/"0" (naturalWidth > 0) and
# #image-check says how many loaded (what the headless-browser test reads).
CHECK_JS = """window.addEventListener('load', function () {
  var imgs = document.images, ok = 0, bad = [];
  for (var i = 0; i < imgs.length; i++) {
    var good = imgs[i].complete && imgs[i].naturalWidth > 0;
    imgs[i].setAttribute('data-loaded', good ? '1' : '0');
    if (good) ok++; else bad.push(imgs[i].alt);
  }
  var el = document.getElementById('image-check');
  el.textContent = 'images loaded: ' + ok + ' of ' + imgs.length + (bad.length ? ' (failed: ' + bad.join(', ') + ')' : '');
  el.setAttribute('data-ok', ok); el.setAttribute('data-total', imgs.length);
});"""


def report(args):
    res = Results(args.results_dir)
    fig_dir = os.path.join(res.dir, "figures")
    args.out_figures = fig_dir
    if args.out is None:
        args.out = os.path.join(res.dir, "report.html")
    pargs = argparse.Namespace(out=fig_dir, formats="png,pdf", figure=None,
                               reference_runtime=args.reference_runtime, reference_shapes=args.reference_shapes,
                               reference_voxel=args.reference_voxel)
    figs, skipped = make_figures(res, pargs)
    renders, why_none = render_results(res, os.path.join(res.dir, "renders"), args.max_renders)
    name = os.path.basename(os.path.normpath(res.dir))
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>arcs report: %s</title>" % html.escape(name),
             "<style>%s</style></head><body>" % CSS,
             "<h1>arcs report: %s</h1>" % html.escape(name),
             "<p>%d cases, %d ok, %d failed; methods: %s. Self-contained page (images embedded); "
             "PDF figures in <code>figures/</code>.</p>" % (len(res.all), len(res.rows), res.failed,
                                                           html.escape(", ".join(res.methods)))]
    parts.append("<h2>Summary</h2>" + summary_table(res))
    tdir = os.path.join(res.dir, "tables")
    if os.path.isdir(tdir):
        tables = sorted(f for f in os.listdir(tdir) if f.endswith(".csv"))
        if tables:
            parts.append("<h2>Tables</h2>")
            for t in tables:
                parts.append("<h3>%s</h3>" % html.escape(t[:-4]) + csv_to_html(os.path.join(tdir, t)))
    parts.append("<h2>Figures</h2>")
    for f, paths in figs.items():
        png = next(p for p in paths if p.endswith(".png"))
        parts.append("<figure><img alt='figure %s' src='%s'><figcaption>%s</figcaption></figure>" %
                     (f, data_uri(png), html.escape(FIGURE_CAPTIONS[f])))
    for f, why in skipped.items():
        parts.append("<p class='note'>figure %s not drawn: %s</p>" % (html.escape(f), html.escape(why)))
    parts.append("<h2>Renders</h2>")
    if renders:
        parts.append("<p class='note'>Each row: the reference (normalised frame) and every method's saved "
                     "mesh, same view and scale; back faces reddish.</p>")
        for label, png in renders:
            parts.append("<figure><img alt='render %s' src='%s'><figcaption>%s</figcaption></figure>" %
                         (html.escape(label, quote=True), data_uri(png), html.escape(label)))
    else:
        parts.append("<p class='note'>no renders: %s</p>" % html.escape(why_none or ""))
    prov = os.path.join(res.dir, "provenance.yaml")
    if os.path.exists(prov):
        with open(prov, errors="replace") as f:
            parts.append("<h2>Provenance</h2><pre>%s</pre>" % html.escape(f.read()))
    parts.append("<p id='image-check' class='note'>images: not checked (scripts off)</p>")
    parts.append("<script>%s</script></body></html>" % CHECK_JS)
    with open(args.out, "w") as f:
        f.write("\n".join(parts))
    print("wrote %s (%d figures, %d renders)" % (args.out, len(figs), len(renders)))


FIGURE_CAPTIONS = {
    "runtime": "Method wall time and Chamfer against the number of SDF samples (paper Fig. 14); dashed: "
               "the paper's curves (bunny, authors' machine) where the runtime CSV is present.",
    "scatter": "Per case, one method's metric against another's (paper Fig. 19); y = x dashed. Ours against "
               "the paper's per-shape values where the shapes match.",
    "ablation": "Every swept parameter against each metric, mean over items, one line per method.",
    "voxel": "Voxelization tables (Luo et al.) as curves: metric against resolution; dashed: the paper's.",
}


def main(argv):
    ap = argparse.ArgumentParser(prog="arcs", description="figures, renders and reports of arcs results")
    sub = ap.add_subparsers(dest="cmd", required=True)

    def refs(p):
        p.add_argument("--reference-runtime", default=default_ref("rfta_paper_runtime.csv"),
                       help="the paper's runtime CSV (default: ../shared/reference/rfta_paper_runtime.csv if present)")
        p.add_argument("--reference-shapes", default=default_ref("rfta_paper_results.csv"),
                       help="the paper's per-shape CSV (default: ../shared/reference/rfta_paper_results.csv)")
        p.add_argument("--reference-voxel", default=default_ref("doph_paper_tables.csv"),
                       help="the voxelization paper's tables (default: ../shared/reference/doph_paper_tables.csv)")

    p = sub.add_parser("plot", help="figures of a results directory (PNG and PDF)")
    p.add_argument("results_dir")
    p.add_argument("--figure", action="append", help="one of %s (repeatable; default all)" % ", ".join(FIGURES))
    p.add_argument("--out", help="output directory (default RESULTS_DIR/figures)")
    p.add_argument("--formats", default="png,pdf", help="comma-separated: png, pdf, svg (default png,pdf)")
    refs(p)
    r = sub.add_parser("render", help="render meshes side by side into one image")
    r.add_argument("meshes", nargs="+")
    r.add_argument("--out", required=True, help="image file (.png, .pdf)")
    r.add_argument("--labels", help="comma-separated panel titles (default: file names)")
    r.add_argument("--size", type=int, default=300, help="panel size in pixels (default 300)")
    r.add_argument("--elev", type=float, default=20.0, help="view elevation in degrees (default 20)")
    r.add_argument("--azim", type=float, default=-30.0, help="view azimuth about +y in degrees (default -30)")
    r.add_argument("--own-frame", action="store_true",
                   help="frame each panel to its own mesh (default: all in the first mesh's frame and scale)")
    q = sub.add_parser("report", help="one self-contained HTML page: tables, figures, renders")
    q.add_argument("results_dir")
    q.add_argument("--out", help="HTML file (default RESULTS_DIR/report.html)")
    q.add_argument("--max-renders", type=int, default=40, help="at most this many render rows (default 40)")
    refs(q)
    a = ap.parse_args(argv)
    if a.cmd == "plot":
        res = Results(a.results_dir)
        made, _ = make_figures(res, a)
        if not made:
            fail("no figure could be drawn from " + a.results_dir)
    elif a.cmd == "render":
        labels = a.labels.split(",") if a.labels else [os.path.basename(m) for m in a.meshes]
        if len(labels) != len(a.meshes):
            fail("--labels: %d labels for %d meshes" % (len(labels), len(a.meshes)))
        if a.size < 50 or a.size > 4000:
            fail("--size must be in [50, 4000], got %d" % a.size)
        render_panels(a.meshes, labels, a.out, a.size, a.elev, a.azim, a.own_frame)
        print("wrote " + a.out)
    else:
        if a.max_renders < 0:
            fail("--max-renders must be >= 0")
        report(a)


if __name__ == "__main__":
    main(sys.argv[1:])
