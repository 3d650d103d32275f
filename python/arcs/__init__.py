"""arcs: surfaces from signed distances and point clouds, and how well it went.

numpy in, numpy out. Every function that runs a stage takes that stage's
parameters as keyword arguments, with the schema's defaults (the papers'),
ranges and one-line docs (``help(arcs.reach_for_the_arcs)``,
``arcs.describe("rfta")``). Bad input (shapes, values, parameters, files)
raises ValueError with the message the ``arcs`` program prints.

    import numpy as np, arcs
    x = np.linspace(-1, 1, 21)
    U = np.stack(np.meshgrid(x, x, x, indexing="ij"), -1).reshape(-1, 3)
    S = np.linalg.norm(U, axis=1) - 0.5
    V, F = arcs.reach_for_the_arcs(U, S)

Long calls release the GIL; ``arcs.set_threads(n)`` bounds their threads
(0 = all cores). Arrays returned are not copies: they own the C++ result.
``arcs.keep_freed_memory()`` makes glibc's malloc keep freed memory for reuse,
as the ``arcs`` program does (RFTA about 15 % faster; process-wide, so opt-in).
"""
import csv as _csv
import inspect as _inspect
import os as _os
import sys as _sys

try:
    import numpy as np
except ImportError:  # e.g. a pyenv python3 first on PATH, Debian's numpy beside /usr/bin/python3
    from . import _build_info
    _ver = "%d.%d" % _sys.version_info[:2]
    if _build_info.numpy_site and _build_info.python_version.startswith(_ver + ".") \
            and _os.path.isdir(_build_info.numpy_site):
        _sys.path.append(_build_info.numpy_site)
        import numpy as np
    else:
        raise ImportError("arcs needs numpy: this python3 (%s, %s) has none, and arcs was built for %s (%s); "
                          "install python3-numpy or run it with %s"
                          % (_sys.executable, _ver, _build_info.python, _build_info.python_version,
                             _build_info.python)) from None

from . import _arcs

__all__ = ["reach_for_the_arcs", "marching_cubes", "signed_distance", "sdf_grid", "winding_number", "voxelize",
           "reconstruct", "metrics", "run", "stages", "describe", "set_threads", "read_mesh", "write_mesh",
           "read_points", "read_sdf", "shape", "normalize_transform", "version", "keep_freed_memory"]

set_threads = _arcs.set_threads
keep_freed_memory = _arcs.keep_freed_memory
read_mesh = _arcs.read_mesh
write_mesh = _arcs.write_mesh
read_points = _arcs.read_points
shape = _arcs.shape
version = _arcs.version

_SCHEMAS = {s["name"]: s for s in _arcs.stages()}
# Reconstructors that need oriented points; normals are estimated for them
# when none are given (estimate_normals=None).
_NEEDS_NORMALS = {"screened_poisson", "ball_pivoting", "screened_poisson_2d"}


def stages(role=None):
    """Names of the registered stages (of one role, e.g. "reconstructor", when given)."""
    if role is not None and role not in {s["role"] for s in _SCHEMAS.values()}:
        raise ValueError("unknown role '%s' (roles: %s)" % (role, ", ".join(sorted({s["role"] for s in _SCHEMAS.values()}))))
    return [n for n, s in _SCHEMAS.items() if role is None or s["role"] == role]


def describe(name):
    """A stage's schema: {name, role, doc, origin, params: [{name, type, default, allowed, doc}], outputs}."""
    if name not in _SCHEMAS:
        _arcs.run_pipeline([(name, {})], {})  # raises the registry's "unknown stage ... (did you mean ...)"
    return _SCHEMAS[name]


def _params_doc(stage):
    s = _SCHEMAS[stage]
    lines = ["Parameters of stage '%s' (%s): %s" % (stage, s["role"], s["doc"])]
    for p in s["params"]:
        lines.append("    %s : %s = %r  %s  -- %s" % (p["name"], p["type"], p["default"], p["allowed"], p["doc"]))
    return "\n".join(lines)


def _with_schema(stage, fixed_doc):
    """Gives a function the stage's keyword parameters in its signature and docstring."""
    def wrap(fn):
        sig = _inspect.signature(fn)
        params = [p for p in sig.parameters.values() if p.kind != p.VAR_KEYWORD]
        var_kw = [p for p in sig.parameters.values() if p.kind == p.VAR_KEYWORD]
        taken = {p.name for p in params}
        for p in _SCHEMAS[stage]["params"]:
            if p["name"] not in taken:
                params.append(_inspect.Parameter(p["name"], _inspect.Parameter.KEYWORD_ONLY, default=p["default"]))
        # reconstruct takes any method's parameters: its **params stays visible.
        keep_var_kw = var_kw and fn.__name__ == "reconstruct"
        fn.__signature__ = sig.replace(parameters=params + (var_kw if keep_var_kw else []))
        fn.__doc__ = fixed_doc.strip("\n") + "\n\n" + _params_doc(stage)
        return fn
    return wrap


def _mesh_out(out, what):
    if "V" in out:
        return out["V"], out["F"]
    if "curve_V" in out:
        return out["curve_V"], out["curve_E"]
    raise ValueError("%s produced no mesh" % what)


@_with_schema("rfta", """
reach_for_the_arcs(U, S, *, seed=1, return_points=False, **params) -> (V, F)

Reach for the Arcs (Sellan et al. 2024): a mesh from SDF samples. U: (N, 3)
sample points (or (N, 2): a 2D curve comes back as (V, E)), S: (N,) signed
distances, negative inside. With return_points, also the oriented tangency
points: (V, F, P, N).
""")
def reach_for_the_arcs(U, S, *, seed=1, return_points=False, **params):
    out = _arcs.run_pipeline([("rfta", params)], {"U": U, "S": S}, seed)
    V, F = _mesh_out(out, "rfta")
    if return_points:
        return V, F, out.get("P"), out.get("N")
    return V, F


@_with_schema("marching_cubes", """
marching_cubes(S, bounds=None, *, level=0.0) -> (V, F)

Marching cubes of a grid S of shape (nx, ny, nz), S[i, j, k] at
(x_i, y_j, z_k), x = numpy.linspace(bounds[0][0], bounds[1][0], nx) (the
meshgrid(..., indexing="ij") layout); bounds = ((xmin, ymin, zmin), (xmax,
ymax, zmax)), default [-1, 1]^3.
""")
def marching_cubes(S, bounds=None, **params):
    out = _arcs.run_pipeline([("marching_cubes", params)], {"grid": S, "bounds": bounds})
    return _mesh_out(out, "marching_cubes")


def signed_distance(Q, V, F, exact=False):
    """Signed distances (N,) of points Q (N, 3) to the mesh (V, F): exact distance to the
    triangles, negative where the winding number exceeds 1/2 (fast hierarchical winding
    number; exact=True: the O(#F) sum)."""
    return _arcs.signed_distance(Q, V, F, exact)


def winding_number(V, F, Q, exact=False):
    """Generalized winding numbers (N,) of the mesh (V, F) at points Q (N, 3): 1 inside a
    closed outward mesh, 0 outside (hierarchical; exact=True: the O(#F) sum)."""
    return _arcs.winding_number(V, F, Q, exact)


def _grid_points(bounds, shape):
    axes = [np.linspace(bounds[0][a], bounds[1][a], shape[a]) for a in range(len(shape))]
    return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(shape))


@_with_schema("sdf_grid", """
sdf_grid(V, F, n=20, **params) -> (U, S)

The RFTA paper's SDF protocol on the mesh (V, F) as given (normalise it first
for the paper's frame, see normalize_transform): the (n+1)^3 nodes U of
linspace(lo, hi, n+1)^3 in meshgrid(indexing="ij") order and their signed
distances S, so S.reshape((n+1,)*3) is the grid marching_cubes takes.
""")
def sdf_grid(V, F, n=20, **params):
    params["n"] = n
    out = _arcs.run_pipeline([("sdf_grid", params)], {"reference": (V, F)})
    grid = out["grid"]
    return _grid_points(out["bounds"], grid.shape), grid.reshape(-1)


@_with_schema("voxelize", """
voxelize(V, F, res=128, **params) -> occupancy (res, res, res)

Winding-number occupancy (Luo et al.) of the mesh (V, F) at the nodes of
linspace(lo, hi, res)^3, in meshgrid(indexing="ij") order.
""")
def voxelize(V, F, res=128, **params):
    params["resolution"] = res
    out = _arcs.run_pipeline([("voxelize", params)], {"reference": (V, F)})
    return out["volume"]


def normalize_transform(P, longest_side=1.0):
    """(scale, translation) of the framework's normalisation: x' = scale * (x + translation)
    centres the bounding box of P at the origin with its longest side `longest_side`."""
    P = np.asarray(P, dtype=float)
    if P.ndim != 2 or P.shape[0] == 0:
        raise ValueError("normalize_transform: expected a non-empty (N, d) array")
    lo, hi = P.min(axis=0), P.max(axis=0)
    side = float((hi - lo).max())
    if not side > 0:
        raise ValueError("normalize_transform: the points' bounding box is a single point")
    return longest_side / side, -(lo + hi) / 2


@_with_schema("screened_poisson", """
reconstruct(P, N=None, method="screened_poisson", *, S=None, bounds=None,
            estimate_normals=None, normals={}, normalize=True, seed=1, **params) -> (V, F)

A mesh from a point cloud with any reconstructor stage (stages("reconstructor"):
screened_poisson, graph_voronoi, ball_pivoting, alpha_shape, advancing_front,
...), or from SDF samples with any sdf_to_mesh stage (stages("sdf_to_mesh"):
rfta, marching_cubes, ...): then P is U (N, 3) and S the values, or S a grid
(nx, ny, nz) with `bounds` and P None.

Point clouds: N (N, 3) normals or None. estimate_normals: None = estimate them
when the method needs oriented points and N is None; True = always (the
estimate_normals stage, with parameters `normals`); False = never. normalize:
the points are moved into the unit frame (bounding box centred, longest side 1)
for the method and the mesh is mapped back into P's frame.
The parameters below are screened_poisson's; describe(method) lists another's.
""")
def reconstruct(P, N=None, method="screened_poisson", *, S=None, bounds=None, estimate_normals=None, normals=None,
                normalize=True, seed=1, **params):
    info = describe(method)
    if info["role"] == "sdf_to_mesh":
        if S is None:
            raise ValueError("reconstruct: method '%s' is an sdf_to_mesh stage: give S (values, or a grid)" % method)
        S_arr = np.asarray(S)
        inputs = {"grid": S_arr, "bounds": bounds} if S_arr.ndim >= 2 and P is None else {"U": P, "S": S}
        return _mesh_out(_arcs.run_pipeline([(method, params)], inputs, seed), method)
    if info["role"] != "reconstructor":
        raise ValueError("reconstruct: '%s' is a %s stage; a reconstructor or sdf_to_mesh stage is needed "
                         "(reconstructors: %s)" % (method, info["role"], ", ".join(stages("reconstructor"))))
    if P is None:
        raise ValueError("reconstruct: P (points) is required for the reconstructor '%s'" % method)
    P = np.asarray(P, dtype=float)
    scale, shift = 1.0, None
    if normalize and P.ndim == 2 and P.shape[0] > 0 and P.shape[1] == 3:
        scale, shift = normalize_transform(P)
        P = scale * (P + shift)
    pipeline = []
    if estimate_normals or (estimate_normals is None and N is None and method in _NEEDS_NORMALS):
        pipeline.append(("estimate_normals", dict(normals or {}, when="always" if estimate_normals else "missing")))
    pipeline.append((method, params))
    out = _arcs.run_pipeline(pipeline, {"P": P, "N": N}, seed)
    V, F = _mesh_out(out, method)
    if shift is not None:
        V /= scale
        V -= shift
    return V, F


def metrics(V, F, Vref, Fref, names=("chamfer", "hausdorff", "chamfer_p2s"), *, U=None, S=None, frame="reference",
            seed=1, params=None, **common):
    """The evaluator stages `names` (stages("evaluator")) of the mesh (V, F) against the
    reference (Vref, Fref) -> {metric: value}. U, S: the SDF samples (for e_sdf).
    frame: "reference" (default) = both meshes (and U, S) in the reference's normalised
    frame (bounding box centred, longest side 1), as `arcs eval` and the paper; "each" =
    each mesh normalised by its own box; "none" = as given. params: {stage: {param: value}};
    other keywords (e.g. samples=100000) go to every named stage that has that parameter."""
    if isinstance(names, str):
        names = [names]
    for n in names:
        if describe(n)["role"] != "evaluator":
            raise ValueError("metrics: '%s' is a %s stage, not an evaluator (evaluators: %s)"
                             % (n, describe(n)["role"], ", ".join(stages("evaluator"))))
    for k in common:
        if not any(k in {p["name"] for p in describe(n)["params"]} for n in names):
            raise ValueError("metrics: no stage of %s has a parameter '%s'" % (list(names), k))
    V, Vref = np.asarray(V, dtype=float), np.asarray(Vref, dtype=float)
    if frame not in ("reference", "each", "none"):
        raise ValueError("metrics: frame must be 'reference', 'each' or 'none', got %r" % (frame,))
    if frame != "none":
        sr, tr = normalize_transform(Vref)
        sm, tm = (sr, tr) if frame == "reference" else normalize_transform(V)
        V, Vref = sm * (V + tm), sr * (Vref + tr)
        if U is not None:
            U = sr * (np.asarray(U, dtype=float) + tr)
            S = sr * np.asarray(S, dtype=float)
    inputs = {"reference": (Vref, Fref), "mesh": (V, F)}
    if U is not None or S is not None:
        inputs.update(U=U, S=S)
    pipeline = []
    for n in names:
        own = {p["name"] for p in describe(n)["params"]}
        pp = {k: v for k, v in common.items() if k in own}
        pp.update((params or {}).get(n, {}))
        pipeline.append((n, pp))
    return dict(_arcs.run_pipeline(pipeline, inputs, seed)["metrics"])


def read_sdf(path):
    """SDF samples of a file (.npy grid / (N, d+1), .npz, text) -> (U, S); a grid's S is
    (nx, ny, nz) with U its nodes in meshgrid("ij") order (S.ravel() matches U)."""
    out = _arcs.read_sdf(path)
    if "grid" in out:
        return _grid_points(out["bounds"], out["grid"].shape), out["grid"]
    return out["U"], out["S"]


def _yaml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_yaml_value(x) for x in v) + "]"
    return str(v)


def _number(cell):
    try:
        return float(cell) if any(c in cell for c in ".eEn") else int(cell)
    except ValueError:
        return cell


def run(yaml_path, out=None, *, jobs=1, threads=0, isolate=True, save_outputs=False, progress=False, set=None,
        **overrides):
    """Runs an experiment file, as `arcs run` -> {"out_dir", "total", "ok", "failed", "skipped",
    "interrupted", "rows"} (rows: results.csv as dicts, numbers converted). Overrides are
    `--set` paths: set={"inputs.grid.sdf_grid.n": [20, 40]}, or keywords with "__" for
    ".": seed=3, methods__MC__marching_cubes__level=0.01."""
    sets = ["%s=%s" % (k, _yaml_value(v)) for k, v in (set or {}).items()]
    sets += ["%s=%s" % (k.replace("__", "."), _yaml_value(v)) for k, v in overrides.items()]
    res = dict(_arcs.run_experiment(_os.fspath(yaml_path), sets, "" if out is None else _os.fspath(out), jobs,
                                    threads, isolate, save_outputs, progress))
    rows = []
    path = _os.path.join(res["out_dir"], "results.csv")
    if _os.path.exists(path):
        with open(path, newline="") as f:
            rows = [{k: _number(v) for k, v in r.items()} for r in _csv.DictReader(l for l in f if not l.startswith("#"))]
    res["rows"] = rows
    return res
