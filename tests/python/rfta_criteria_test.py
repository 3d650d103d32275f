"""scripts/rfta_criteria.py: RFTA's Table 2 rows against the paper's, per grid."""
import importlib.util
import io
import os
import tempfile
import unittest
from contextlib import redirect_stdout

_HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("rfta_criteria", os.path.join(_HERE, "..", "..", "scripts", "rfta_criteria.py"))
rc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rc)

HEADER = ("case_id,status,item,method,sdf_grid.n,chamfer,e_sdf,hausdorff,components_match,genus_matches,"
          "final_infeasible,method_wall_s\n")
PAPER = ("# the paper's Table 2\n"
         "group,grid,chamfer_mc,chamfer_rfta,esdf_rfta\n"
         "all,10,0.17,0.05,0.03\n"
         "genus0,10,0.15,0.01,0.01\n"
         "all,20,0.07,0.03,0.0125\n")


class RftaCriteriaTest(unittest.TestCase):
    def write(self, d, name, text):
        path = os.path.join(d, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_means_verdicts_and_rates_per_grid(self):
        with tempfile.TemporaryDirectory() as d:
            results = self.write(d, "r.csv", HEADER +
                                 "a1,ok,a,RFTA,10,0.04,0.02,0.10,true,true,0,2\n"
                                 "b1,ok,b,RFTA,10,0.07,0.05,0.20,false,true,3,4\n"
                                 "c1,failed,c,RFTA,10,,,,,,,\n"
                                 "a2,ok,a,MC,10,0.2,30,0.30,true,false,,0\n"
                                 "b2,ok,b,MC,10,0.1,20,0.10,true,false,,0\n"
                                 "c2,ok,c,MC,10,0.3,40,0.50,false,false,,0\n"
                                 "a3,ok,a,RFTA,20,0.02,0.01,0.05,true,true,0,10\n")
            paper = rc.read_paper(self.write(d, "p.csv", PAPER))
            self.assertEqual(paper[10], {"chamfer": 0.05, "e_sdf": 0.03})  # group `all`, not genus0
            s10, s20 = rc.summarize(rc.read_rows([results]), paper, "RFTA", "MC")
            self.assertEqual((s10["n"], s10["shapes"]), (10, 2))  # c failed
            self.assertAlmostEqual(s10["chamfer"], 0.055)
            self.assertFalse(s10["chamfer_ok"])  # 0.055 > 0.05
            self.assertAlmostEqual(s10["e_sdf"], 0.035)
            self.assertFalse(s10["e_sdf_ok"])
            # Hausdorff over the shapes where both succeeded (a, b): 0.15 against MC's 0.20.
            self.assertEqual(s10["both"], 2)
            self.assertAlmostEqual(s10["hausdorff"], 0.15)
            self.assertAlmostEqual(s10["mc_hausdorff"], 0.20)
            self.assertTrue(s10["hausdorff_ok"])
            self.assertEqual(s10["components"], (1, 2))
            self.assertEqual(s10["genus"], (2, 2))
            self.assertEqual(s10["mc_components"], (2, 3))
            self.assertEqual(s10["mc_genus"], (0, 3))
            self.assertEqual(s10["final_infeasible"], 3)
            self.assertEqual((s10["time_median"], s10["time_max"]), (3.0, 4.0))
            # n = 20: at or below the paper; no MC rows there, so no Hausdorff verdict.
            self.assertTrue(s20["chamfer_ok"] and s20["e_sdf_ok"])
            self.assertIsNone(s20["hausdorff_ok"])
            out = io.StringIO()
            with redirect_stdout(out):
                rc.print_table([s10, s20], "RFTA", "MC")
            lines = out.getvalue().splitlines()
            self.assertTrue(lines[2].startswith("| 10 | 2 | 0.0550 | 0.0500 | no |"), lines[2])
            self.assertIn("| 1 / 2 (50 %) | 2 / 3 (67 %) |", lines[2])
            self.assertIn("| 0.1500 | 0.2000 | yes |", lines[2])
            self.assertIn("| — | — | — |", lines[3])  # n = 20 without MC

    def test_mc_rows_from_other_files(self):
        with tempfile.TemporaryDirectory() as d:
            ours = self.write(d, "r.csv", HEADER + "a1,ok,a,RFTA,10,0.04,0.02,0.10,true,true,0,2\n")
            # An older run with its own RFTA rows: only its MC rows are read.
            other = self.write(d, "o.csv", HEADER + "x1,ok,a,RFTA,10,0.09,0.09,0.90,false,false,0,2\n"
                                                    "x2,ok,a,MC,10,0.2,30,0.05,true,false,,0\n")
            paper = rc.read_paper(self.write(d, "p.csv", PAPER))
            (s,) = rc.summarize(rc.read_rows([ours]), paper, "RFTA", "MC", rc.read_rows([other]))
            self.assertAlmostEqual(s["chamfer"], 0.04)
            self.assertAlmostEqual(s["mc_hausdorff"], 0.05)
            self.assertFalse(s["hausdorff_ok"])  # 0.10 is not below 0.05

    def test_two_cases_of_a_method_on_one_shape_are_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            first = self.write(d, "1.csv", HEADER + "a1,ok,a,RFTA,10,0.04,0.02,0.10,true,true,0,2\n")
            second = self.write(d, "2.csv", HEADER + "z9,ok,a,RFTA,10,0.05,0.02,0.10,true,true,0,2\n")
            paper = rc.read_paper(self.write(d, "p.csv", PAPER))
            with self.assertRaises(SystemExit) as e:
                rc.summarize(rc.read_rows([first, second]), paper, "RFTA", "MC")
            self.assertIn("a1", str(e.exception))
            self.assertIn("z9", str(e.exception))
            self.assertIn("2.csv", str(e.exception))

    def test_parts_merge_by_case_id(self):
        # A later part's ok row replaces a failed one of the same case; a failure never replaces an ok row.
        with tempfile.TemporaryDirectory() as d:
            p1 = self.write(d, "1.csv", HEADER + "a1,failed,a,RFTA,10,,,,,,,\nb1,ok,b,RFTA,10,0.06,0.02,0.1,true,true,0,2\n")
            p2 = self.write(d, "2.csv", HEADER + "a1,ok,a,RFTA,10,0.02,0.02,0.1,true,true,0,2\nb1,failed,b,RFTA,10,,,,,,,\n")
            paper = rc.read_paper(self.write(d, "p.csv", PAPER))
            (s,) = rc.summarize(rc.read_rows([p1, p2]), paper, "RFTA", "MC")
            self.assertEqual(s["shapes"], 2)
            self.assertAlmostEqual(s["chamfer"], 0.04)

    def test_bad_files_name_what_and_where(self):
        with tempfile.TemporaryDirectory() as d:
            bad = self.write(d, "bad.csv", "case_id,status,item\n1,ok,a\n")
            with self.assertRaises(SystemExit) as e:
                rc.read_rows([bad])
            self.assertIn("bad.csv", str(e.exception))
            self.assertIn("method", str(e.exception))
            paper = self.write(d, "p.csv", "group,grid,chamfer_rfta,esdf_rfta\nall,ten,0.1,0.1\n")
            with self.assertRaises(SystemExit) as e:
                rc.read_paper(paper)
            self.assertIn("p.csv:2", str(e.exception))


if __name__ == "__main__":
    unittest.main()
