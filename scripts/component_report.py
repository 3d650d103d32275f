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
samples' frame. Reads, distances and winding numbers through the `arcs`
Python module (build/python; README, "Python"); a diagnostic, not a metric.
"""
import json
import sys

import arcs
import numpy as np


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


def distance(points, verts, faces):
    """Unsigned distance of `points` to the mesh (verts, faces)."""
    return np.abs(arcs.signed_distance(points, verts, faces))


def main(argv):
    if len(argv) not in (3, 4):
        sys.exit(__doc__)
    verts, faces = arcs.read_mesh(argv[1])
    ref_v, ref_f = arcs.read_mesh(argv[2])
    lab = components(len(verts), faces)
    face_lab = lab[faces[:, 0]]
    ids, counts = np.unique(face_lab, return_counts=True)
    order = np.argsort(-counts)
    main_f = faces[face_lab == ids[order[0]]]
    print(f"{argv[1]}: {len(verts)} vertices, {len(faces)} faces, {len(ids)} components")
    print("  faces     extent   to-ref mean   to-ref max   gap to largest")
    for j in order:
        p = verts[np.unique(faces[face_lab == ids[j]])]
        d = distance(p, ref_v, ref_f)
        gap = 0.0 if j == order[0] else distance(p, verts, main_f).min()
        print(f"  {counts[j]:8d}  {np.ptp(p, axis=0).max():8.4f}  {d.mean():11.4f}  {d.max():11.4f}  {gap:14.4f}")
    if len(argv) < 4:
        return
    frame = json.load(open(argv[1] + ".transform.json"))
    sframe = json.load(open(argv[3] + ".transform.json"))
    nodes, grid = arcs.read_sdf(argv[3])  # a grid's S.ravel() matches U
    if grid.ndim != 3:
        sys.exit(f"{argv[3]}: grid samples expected (arcs sdf MESH OUT.npz --n N)")
    vals = grid.ravel()
    ijk = np.stack(np.unravel_index(np.arange(vals.size), grid.shape), axis=1)
    h = (nodes.max(0) - nodes.min(0)) / (np.asarray(grid.shape) - 1)
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
        hit = np.abs(arcs.winding_number(verts, faces[face_lab == ids[j]], c_in, exact=True)) > 0.5
        owner[hit & (owner < 0)] = rank
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
