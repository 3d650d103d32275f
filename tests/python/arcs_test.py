"""The Python module `arcs` (python/): numpy in and out, schema keywords, ValueError.

Run from ctest (python_arcs_suite) with PYTHONPATH=build/python; ARCS_EXE names the
`arcs` program for the tests that compare messages with the CLI's.
"""
import inspect
import os
import subprocess
import tempfile
import threading
import time
import unittest

import numpy as np

import arcs


def sphere_grid(n=21, r=0.5):
    x = np.linspace(-1, 1, n)
    U = np.stack(np.meshgrid(x, x, x, indexing="ij"), -1).reshape(-1, 3)
    return U, np.linalg.norm(U, axis=1) - r


def sphere_points(count=3000, r=0.5, seed=1):
    rng = np.random.default_rng(seed)
    N = rng.normal(size=(count, 3))
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    return r * N, N


class ReachForTheArcs(unittest.TestCase):
    def test_sphere_21_grid_mean_radius_within_1_percent(self):
        U, S = sphere_grid(21, 0.5)
        V, F = arcs.reach_for_the_arcs(U, S)
        self.assertEqual(V.shape[1], 3)
        self.assertEqual(F.shape[1], 3)
        self.assertGreater(F.shape[0], 100)
        radius = np.linalg.norm(V, axis=1).mean()
        self.assertLess(abs(radius - 0.5) / 0.5, 0.01, "mean radius %.5f" % radius)

    def test_keep_freed_memory_then_the_same_surface(self):
        # glibc (Debian) accepts the thresholds; the setting changes no result.
        U, S = sphere_grid(11)
        V0, F0 = arcs.reach_for_the_arcs(U, S, iterations=2, seed=3)
        self.assertTrue(arcs.keep_freed_memory())
        V1, F1 = arcs.reach_for_the_arcs(U, S, iterations=2, seed=3)
        np.testing.assert_array_equal(V0, V1)
        np.testing.assert_array_equal(F0, F1)

    def test_mismatched_arrays_raise_value_error(self):
        U, S = sphere_grid(11)
        with self.assertRaisesRegex(ValueError, "U has 1331 points but S has 1330 values"):
            arcs.reach_for_the_arcs(U, S[:-1])
        with self.assertRaisesRegex(ValueError, r"U: expected shape \(N, 2 or 3\)"):
            arcs.reach_for_the_arcs(U[:, :1], S)
        with self.assertRaisesRegex(ValueError, "not finite"):
            arcs.reach_for_the_arcs(U, np.where(S > 0.8, np.nan, S))

    def test_parameters_come_from_the_schema(self):
        sig = inspect.signature(arcs.reach_for_the_arcs)
        self.assertEqual(sig.parameters["iterations"].default, 10)  # the paper's k_max
        self.assertEqual(sig.parameters["max_points_per_sphere"].default, 3)
        self.assertIn("k_max", arcs.reach_for_the_arcs.__doc__)
        U, S = sphere_grid(11)
        with self.assertRaisesRegex(ValueError, "stage 'rfta' has no parameter 'iteration' \\(valid: "):
            arcs.reach_for_the_arcs(U, S, iteration=3)
        with self.assertRaisesRegex(ValueError, "rfta.iterations"):
            arcs.reach_for_the_arcs(U, S, iterations=-1)
        with self.assertRaisesRegex(ValueError, "must be an integer"):
            arcs.reach_for_the_arcs(U, S, iterations=2.5)

    def test_same_message_as_the_cli(self):
        exe = os.environ.get("ARCS_EXE")
        if not exe:
            self.skipTest("ARCS_EXE not set (run from ctest)")
        U, S = sphere_grid(11)
        with tempfile.TemporaryDirectory() as d:
            np.save(os.path.join(d, "s.npy"), np.column_stack([U, S]))
            cli = subprocess.run([exe, "reconstruct", os.path.join(d, "s.npy"), os.path.join(d, "o.ply"),
                                  "--param", "iteration=3"], capture_output=True, text=True)
        self.assertNotEqual(cli.returncode, 0)
        with self.assertRaises(ValueError) as e:
            arcs.reach_for_the_arcs(U, S, iteration=3)
        self.assertIn(str(e.exception), cli.stderr)

    def test_gil_released_during_the_call(self):
        U, S = sphere_grid(21)
        ticks = [0]
        t = threading.Thread(target=lambda: arcs.reach_for_the_arcs(U, S))
        start = time.perf_counter()
        t.start()
        while t.is_alive():
            ticks[0] += 1
            time.sleep(0.001)
        elapsed = time.perf_counter() - start
        # With the GIL held, this loop could not run until the call returned.
        self.assertGreater(ticks[0], min(10, elapsed * 100), "elapsed %.2f s, ticks %d" % (elapsed, ticks[0]))

    def test_outputs_are_not_copies(self):
        U, S = sphere_grid(11)
        V, F = arcs.marching_cubes(S.reshape(11, 11, 11))
        self.assertFalse(V.flags.owndata)  # a view of the C++ result, owned by a capsule
        self.assertIsNotNone(V.base)
        self.assertEqual(F.dtype, np.int32)


class Primitives(unittest.TestCase):
    def test_marching_cubes_sphere(self):
        U, S = sphere_grid(31, 0.6)
        V, F = arcs.marching_cubes(S.reshape(31, 31, 31), bounds=((-1, -1, -1), (1, 1, 1)))
        self.assertLess(abs(np.linalg.norm(V, axis=1).mean() - 0.6), 0.01)
        # Bounds are honoured: the same grid over [0, 2]^3 moves the mesh by +1.
        V2, _ = arcs.marching_cubes(S.reshape(31, 31, 31), bounds=((0, 0, 0), (2, 2, 2)))
        np.testing.assert_allclose(V2, V + 1, atol=1e-12)
        with self.assertRaisesRegex(ValueError, "grid must have shape"):
            arcs.marching_cubes(S)

    def test_sdf_grid_signed_distance_winding_number(self):
        V, F = arcs.shape("sphere")
        r = np.linalg.norm(V, axis=1).mean()
        U, S = arcs.sdf_grid(V, F, n=10)
        self.assertEqual(U.shape, (11 ** 3, 3))
        np.testing.assert_allclose(S, np.linalg.norm(U, axis=1) - r, atol=0.02 * r)
        # the grid is in meshgrid("ij") order: S.reshape works with marching_cubes
        Vm, _ = arcs.marching_cubes(S.reshape(11, 11, 11))
        self.assertLess(abs(np.linalg.norm(Vm, axis=1).mean() - r), 0.03 * r)
        Q = np.array([[0, 0, 0], [2 * r, 0, 0]], dtype=float)
        sd = arcs.signed_distance(Q, V, F)
        self.assertLess(sd[0], 0)
        self.assertAlmostEqual(sd[1], r, delta=0.02 * r)
        w = arcs.winding_number(V, F, Q)
        np.testing.assert_allclose(w, [1, 0], atol=1e-2)  # hierarchical: far-field error (0.004 at 2r)
        np.testing.assert_allclose(arcs.winding_number(V, F, Q, exact=True), [1, 0], atol=1e-9)
        with self.assertRaisesRegex(ValueError, "face 0 has vertex index"):
            arcs.winding_number(V, F + len(V), Q)

    def test_voxelize_sphere_volume(self):
        V, F = arcs.shape("sphere")
        r = np.linalg.norm(V, axis=1).mean()
        occ = arcs.voxelize(V, F, 40)
        self.assertEqual(occ.shape, (40, 40, 40))
        frac = occ.mean()  # nodes of linspace(-1, 1, 40)^3 inside the sphere
        self.assertAlmostEqual(frac, 4 / 3 * np.pi * r ** 3 / 8, delta=0.1 * frac)


class Reconstruct(unittest.TestCase):
    def test_every_reconstructor_on_sphere_points_in_the_input_frame(self):
        P, N = sphere_points(2000)
        P = 3.0 * P + np.array([10.0, -2.0, 5.0])  # not the unit frame: the output must come back here
        for method in arcs.stages("reconstructor"):
            if method.endswith("_2d"):
                continue
            with self.subTest(method=method):
                V, F = arcs.reconstruct(P, N, method=method)
                self.assertGreater(len(F), 20)  # graph_voronoi keeps only its sites: coarse
                d = np.linalg.norm(V - np.array([10.0, -2.0, 5.0]), axis=1)
                self.assertLess(abs(np.median(d) - 1.5), 0.1 * 1.5, method)

    def test_normals_estimated_on_demand(self):
        P, _ = sphere_points(2000)
        V, F = arcs.reconstruct(P, method="screened_poisson")  # no N: estimate_normals runs first
        self.assertLess(abs(np.linalg.norm(V, axis=1).mean() - 0.5), 0.03)

    def test_sdf_to_mesh_methods(self):
        U, S = sphere_grid(21)
        V, F = arcs.reconstruct(None, S=S.reshape(21, 21, 21), method="marching_cubes")
        self.assertLess(abs(np.linalg.norm(V, axis=1).mean() - 0.5), 0.01)
        V, F = arcs.reconstruct(U, S=S, method="rfta", iterations=2)
        self.assertLess(abs(np.linalg.norm(V, axis=1).mean() - 0.5), 0.02)
        with self.assertRaisesRegex(ValueError, "is a evaluator stage|is an? evaluator stage"):
            arcs.reconstruct(U, method="chamfer")
        with self.assertRaisesRegex(ValueError, "unknown stage 'screened_poison'.*screened_poisson"):
            arcs.reconstruct(U, method="screened_poison")


class MetricsAndRun(unittest.TestCase):
    def test_metrics_one_frame(self):
        V, F = arcs.shape("knot")
        m = arcs.metrics(V * 5 + 3, F, V * 5 + 3, F, samples=100000)
        self.assertLess(m["chamfer"], 0.01)
        self.assertLess(m["chamfer_p2s"], 1e-6)
        self.assertLess(m["hausdorff"], 1e-9)
        # "each" ignores placement and scale; "reference" does not
        moved = arcs.metrics(V * 2, F, V, F, samples=20000)
        each = arcs.metrics(V * 2, F, V, F, samples=20000, frame="each")
        self.assertGreater(moved["chamfer"], 0.1)
        self.assertLess(each["chamfer"], 0.02)
        with self.assertRaisesRegex(ValueError, "no stage of"):
            arcs.metrics(V, F, V, F, names=["hausdorff"], samples=10)

    def test_run_experiment_file(self):
        with tempfile.TemporaryDirectory() as d:
            exp = os.path.join(d, "tiny.yaml")
            with open(exp, "w") as f:
                f.write("name: tiny\nseed: 1\ndatasets:\n  - name: s\n    shapes: [sphere]\n"
                        "inputs:\n  - name: grid\n    pipeline:\n      - stage: sdf_grid\n        params: {n: 10}\n"
                        "methods:\n  - name: MC\n    pipeline: [marching_cubes]\n"
                        "metrics:\n  - stage: chamfer\n    params: {samples: 20000}\n")
            res = arcs.run(exp, os.path.join(d, "out"), inputs__grid__sdf_grid__n=[8, 12])
            self.assertEqual(res["total"], 2)
            self.assertEqual(res["ok"], 2)
            self.assertEqual(sorted(r["sdf_grid.n"] for r in res["rows"]), [8, 12])
            by_n = {r["sdf_grid.n"]: r["chamfer"] for r in res["rows"]}
            self.assertLess(by_n[12], by_n[8])  # a finer grid, a closer MC surface
            self.assertLess(by_n[12], 0.1)
            with self.assertRaisesRegex(ValueError, "tiny.yaml"):
                arcs.run(exp, os.path.join(d, "out2"), set={"methods.MC.marching_cubes.lvel": 0.1})

    def test_stages_and_describe(self):
        self.assertIn("rfta", arcs.stages("sdf_to_mesh"))
        self.assertIn("graph_voronoi", arcs.stages("reconstructor"))
        d = arcs.describe("sdf_grid")
        self.assertEqual([p["name"] for p in d["params"]][:1], ["n"])
        self.assertEqual(d["params"][0]["default"], 20)
        with self.assertRaisesRegex(ValueError, "did you mean 'rfta'"):
            arcs.describe("rftaa")


class Files(unittest.TestCase):
    def test_npz_from_numpy_savez_and_compressed(self):
        U, S = sphere_grid(9)
        with tempfile.TemporaryDirectory() as d:
            for save in (np.savez, np.savez_compressed):
                p = os.path.join(d, save.__name__ + ".npz")
                save(p, U=U, S=S)
                U2, S2 = arcs.read_sdf(p)
                np.testing.assert_array_equal(U2, U)
                np.testing.assert_array_equal(S2, S)
                g = os.path.join(d, save.__name__ + "_grid.npz")
                save(g, S=S.reshape(9, 9, 9), bounds=np.array([[0, 0, 0], [2, 2, 2.0]]))
                Ug, Sg = arcs.read_sdf(g)
                np.testing.assert_array_equal(Sg, S.reshape(9, 9, 9))
                np.testing.assert_allclose(Ug, U + 1, atol=1e-15)
            np.savez(os.path.join(d, "bad.npz"), U=U, S=S[:-1])
            with self.assertRaisesRegex(ValueError, "'U' has 729 points but 'S' has 728 values"):
                arcs.read_sdf(os.path.join(d, "bad.npz"))

    def test_mesh_round_trip(self):
        V, F = arcs.shape("torus")
        with tempfile.TemporaryDirectory() as d:
            arcs.write_mesh(os.path.join(d, "t.ply"), V, F)
            V2, F2 = arcs.read_mesh(os.path.join(d, "t.ply"))
        np.testing.assert_array_equal(V, V2)
        np.testing.assert_array_equal(F, F2)
        with self.assertRaisesRegex(ValueError, "cannot open"):
            arcs.read_mesh("/nonexistent/x.obj")


if __name__ == "__main__":
    unittest.main()
