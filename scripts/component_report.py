#!/usr/bin/env python3
"""Per-component report of a reconstructed mesh (issue 10, criterion 3).

For each connected component of MESH: faces, extent, distance of its vertices
to REFERENCE (mean, max; vertex to vertex, a subsample), and the gap to the
largest component. With the case's SDF samples (`arcs sdf MESH OUT.npz --n N`,
the same n as the run), also what the samples alone say: inside samples whose
balls overlap are connected through the shape's interior (every inside ball
lies inside the shape), so the report prints the clusters of overlapping
inside balls, which output component holds each inside sample (winding
number > 1/2), clusters split across components, and components that hold no
inside sample (the samples neither require nor forbid them).

  scripts/component_report.py MESH.ply REFERENCE.ply [SAMPLES.npz]

MESH and REFERENCE are `arcs run --save-outputs` files (the case's frame,
described by MESH.ply.transform.json); SAMPLES.npz.transform.json maps the
samples' frame. Brute force in numpy (a few seconds per 100k faces): a
diagnostic, not a metric.
"""
import json
import sys

import numpy as np


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    if "binary_little_endian" not in header:
        sys.exit(f"{path}: only binary little-endian PLY is read here")
    nv = int(header.split("element vertex ")[1].split()[0])
    nf = int(header.split("element face ")[1].split()[0]) if "element face " in header else 0
    props = [l.split()[-1] for l in header.split("element vertex")[1].split("element")[0].splitlines()
             if l.startswith("property")]
    dt = "<f8" if "property double x" in header else "<f4"
    verts = np.frombuffer(data, dtype=dt, count=nv * len(props), offset=end).reshape(nv, len(props))[:, :3]
    off = end + nv * len(props) * np.dtype(dt).itemsize
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=nf, offset=off)["i"]
    return verts.astype(float), faces.copy()


def components(nv, faces):
    """Vertex labels (the smallest vertex index of the component)."""
    lab = np.arange(nv)
    while True:
        m = lab[faces].min(axis=1)
        old = lab.copy()
        for k in range(3):
            np.minimum.at(lab, faces[:, k], m)
        lab = lab[lab]
        if np.array_equal(old, lab):
            return lab


def min_dist(a, b, chunk=4000):
    out = np.full(len(a), np.inf)
    for i in range(0, len(b), chunk):
        out = np.minimum(out, ((a[:, None, :] - b[None, i:i + chunk, :]) ** 2).sum(-1).min(1))
    return np.sqrt(out)


def winding(points, tris, chunk=20000):
    """Generalised winding number of `points` with respect to triangles (atan2 solid angles)."""
    w = np.zeros(len(points))
    for i in range(0, len(tris), chunk):
        a, b, c = (tris[i:i + chunk, k][None] - points[:, None] for k in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
        dot = lambda x, y: np.einsum("pfi,pfi->pf", x, y)
        den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb
        w += 2 * np.arctan2(det, den).sum(1)
    return w / (4 * np.pi)


def main(argv):
    if len(argv) not in (3, 4):
        sys.exit(__doc__)
    verts, faces = read_ply(argv[1])
    ref, _ = read_ply(argv[2])
    lab = components(len(verts), faces)
    face_lab = lab[faces[:, 0]]
    ids, counts = np.unique(face_lab, return_counts=True)
    order = np.argsort(-counts)
    rng = np.random.default_rng(0)
    ref_s = ref[rng.choice(len(ref), min(len(ref), 40000), replace=False)]
    main_v = verts[np.unique(faces[face_lab == ids[order[0]]])]
    main_s = main_v[::max(1, len(main_v) // 30000)]
    print(f"{argv[1]}: {len(verts)} vertices, {len(faces)} faces, {len(ids)} components")
    print("  faces     extent   to-ref mean   to-ref max   gap to largest")
    for j in order:
        p = verts[np.unique(faces[face_lab == ids[j]])]
        ps = p[::max(1, len(p) // 500)]
        d = min_dist(ps, ref_s)
        gap = 0.0 if j == order[0] else min_dist(ps, main_s).min()
        print(f"  {counts[j]:8d}  {np.ptp(p, axis=0).max():8.4f}  {d.mean():11.4f}  {d.max():11.4f}  {gap:14.4f}")
    if len(argv) < 4:
        return
    frame = json.load(open(argv[1] + ".transform.json"))
    sframe = json.load(open(argv[3] + ".transform.json"))
    z = np.load(argv[3])
    grid, nodes = z["S"], z["U"]
    n = grid.shape[0]
    lo = nodes.min(0)
    h = (nodes.max(0) - lo) / (n - 1)
    ijk = np.rint((nodes - lo) / h).astype(int)
    vals = grid[ijk[:, 0], ijk[:, 1], ijk[:, 2]]
    # samples' frame -> input frame -> the mesh's frame (both maps y = s R (x + t)).
    x = (np.asarray(sframe["rotation"]).T @ (nodes / sframe["scale"]).T).T - np.asarray(sframe["translation"])
    centres = frame["scale"] * (np.asarray(frame["rotation"]) @ (x + np.asarray(frame["translation"])).T).T
    radii = np.abs(vals) / sframe["scale"] * frame["scale"]
    inside = np.where(vals < 0)[0]
    c_in, r_in = centres[inside], radii[inside]
    parent = np.arange(len(inside))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    dist = np.linalg.norm(c_in[:, None] - c_in[None], axis=-1)
    for a, b in zip(*np.where(np.triu(dist < r_in[:, None] + r_in[None], 1))):
        fa, fb = find(a), find(b)
        if fa != fb:
            parent[fa] = fb
    cluster = np.array([find(a) for a in range(len(inside))])
    owner = np.full(len(inside), -1)
    for rank, j in enumerate(order):
        tris = verts[faces[face_lab == ids[j]]]
        for s in range(0, len(c_in), 50):
            hit = np.abs(winding(c_in[s:s + 50], tris)) > 0.5
            owner[s:s + 50][hit & (owner[s:s + 50] < 0)] = rank
    print(f"samples: {len(vals)}, {len(inside)} inside, grid spacing {h[0] / sframe['scale'] * frame['scale']:.4f} "
          f"(mesh frame); {len(np.unique(cluster))} clusters of overlapping inside balls; "
          f"{(owner < 0).sum()} inside samples in no component")
    for rank in range(len(order)):
        held = np.unique(cluster[owner == rank])
        print(f"  component {rank} ({counts[order[rank]]} faces): {(owner == rank).sum()} inside samples, "
              f"{len(held)} clusters")
    # Grid-adjacent inside nodes (6-neighbours): marching cubes' prior joins
    # them (no sign change on the edge), the balls prove it only when they
    # overlap.
    node_rank = {tuple(ijk[i]): (owner[k], k) for k, i in enumerate(inside)}
    split = 0
    for (a, b, c), (oa, ka) in node_rank.items():
        for d in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
            q = node_rank.get((a + d[0], b + d[1], c + d[2]))
            if q is not None and q[0] != oa and min(q[0], oa) >= 0:
                split += 1
    print(f"  grid-adjacent inside node pairs in different components: {split}")
    for k in np.unique(cluster):
        o = sorted(set(owner[cluster == k]) - {-1})
        if len(o) > 1:
            print(f"  a cluster of {(cluster == k).sum()} overlapping inside balls is split across components {o}")


if __name__ == "__main__":
    main(sys.argv)
