"""scripts/paired_ratios.py: per-shape ratios, ours (arcs results files) beside the paper's long file."""
import importlib.util
import io
import math
import os
import tempfile
import unittest
from contextlib import redirect_stdout

_HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("paired_ratios", os.path.join(_HERE, "..", "..", "scripts", "paired_ratios.py"))
pr = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(pr)

HEADER = "case_id,status,item,method,sdf_grid.n,ref_genus,chamfer\n"


class PairedRatiosTest(unittest.TestCase):
    def write(self, d, name, text):
        path = os.path.join(d, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def printed(self, args, n):
        """What main(args) prints, and its line for grid n, all shapes."""
        out = io.StringIO()
        with redirect_stdout(out):
            pr.main(args)
        text = out.getvalue()
        return text, [l for l in text.splitlines() if l.startswith("| %d | all" % n)][0]

    def test_ratios_over_shapes_where_both_methods_succeeded(self):
        with tempfile.TemporaryDirectory() as d:
            ours = self.write(d, "r.csv", HEADER +
                              "a1,ok,a,MC,10,0,0.2\na2,ok,a,RFTA,10,0,0.05\n"
                              "b1,ok,b,MC,10,1,0.1\nb2,ok,b,RFTA,10,1,0.1\n"
                              "c1,ok,c,MC,10,0,0.3\nc2,failed,c,RFTA,10,0,\n")
            shapes = pr.read_ours([ours], "chamfer")
            n, med, gm = pr.ratio_stats(shapes, 10, "RFTA", "MC", lambda g: True)
            self.assertEqual(n, 2)  # c: RFTA failed
            self.assertAlmostEqual(gm, math.sqrt(0.25 * 1.0))
            self.assertAlmostEqual(med, 0.625)
            n0, _, gm0 = pr.ratio_stats(shapes, 10, "RFTA", "MC", lambda g: g == 0)
            self.assertEqual((n0, round(gm0, 12)), (1, 0.25))

    def test_a_later_ok_row_replaces_a_failed_one(self):
        with tempfile.TemporaryDirectory() as d:
            first = self.write(d, "1.csv", HEADER + "a1,ok,a,MC,10,0,0.2\na2,failed,a,RFTA,10,0,\n")
            second = self.write(d, "2.csv", HEADER + "a2,ok,a,RFTA,10,0,0.1\n")
            shapes = pr.read_ours([first, second], "chamfer")
            self.assertEqual(pr.ratio_stats(shapes, 10, "RFTA", "MC", lambda g: True)[0], 1)

    def test_a_later_ok_row_replaces_an_earlier_ok_one_and_a_failure_does_not(self):
        # As `arcs table` merges parts: a method re-run in a later part replaces its rows.
        with tempfile.TemporaryDirectory() as d:
            first = self.write(d, "1.csv", HEADER + "a1,ok,a,MC,10,0,0.2\na2,ok,a,RFTA,10,0,0.1\n")
            second = self.write(d, "2.csv", HEADER + "a2,ok,a,RFTA,10,0,0.05\n")
            third = self.write(d, "3.csv", HEADER + "a2,failed,a,RFTA,10,0,\n")
            shapes = pr.read_ours([first, second, third], "chamfer")
            n, med, _ = pr.ratio_stats(shapes, 10, "RFTA", "MC", lambda g: True)
            self.assertEqual((n, round(med, 12)), (1, 0.25))

    def test_paper_file_and_printed_table(self):
        with tempfile.TemporaryDirectory() as d:
            ours = self.write(d, "r.csv", HEADER + "a1,ok,a,MC,10,0,0.2\na2,ok,a,RFTA,10,0,0.1\n")
            paper = self.write(d, "p.csv", "# comment\nmesh,genus,resolution,method,metric,error\n"
                               "x,0.0,10,mc,chf,0.4\nx,0.0,10,rfta,chf,0.1\nx,0.0,10,rfta,hd,9\n")
            _, line = self.printed([ours, "--paper", paper, "--pairs", "RFTA/MC"], 10)
            self.assertIn("0.500 (0.500) [1]", line)  # ours
            self.assertIn("0.250 (0.250) [1]", line)  # paper

    def test_ours_and_the_papers_methods_named_apart(self):
        with tempfile.TemporaryDirectory() as d:
            ours = self.write(d, "r.csv", HEADER + "a1,ok,a,MC,50,0,0.2\na2,ok,a,DCSDD,50,0,0.1\n")
            paper = self.write(d, "p.csv", "mesh,genus,resolution,method,metric,error\n"
                               "x,0.0,50,mc,chf,0.4\nx,0.0,50,ndc,chf,0.3\n")
            text, line = self.printed([ours, "--paper", paper, "--pairs", "DCSDD/MC=NDC/MC"], 50)
            self.assertIn("DCSDD/MC ours | NDC/MC paper", text)
            self.assertIn("0.500 (0.500) [1]", line)  # ours: DCSDD / MC
            self.assertIn("0.750 (0.750) [1]", line)  # paper: NDC / MC
            with self.assertRaises(SystemExit) as e:
                pr.main([ours, "--pairs", "DCSDD/MC=NDC"])
            self.assertIn("is not METHOD/METHOD or METHOD/METHOD=METHOD/METHOD", str(e.exception))

    def test_bad_input_names_file_line_and_column(self):
        with tempfile.TemporaryDirectory() as d:
            bad = self.write(d, "bad.csv", "case_id,status,item\nx,ok,a\n")
            with self.assertRaises(SystemExit) as e:
                pr.read_ours([bad], "chamfer")
            self.assertIn("bad.csv:2: no column 'method'", str(e.exception))
            with self.assertRaises(SystemExit) as e:
                pr.main([bad, "--pairs", "RFTA"])
            self.assertIn("--pairs: 'RFTA' is not METHOD/METHOD", str(e.exception))


if __name__ == "__main__":
    unittest.main()
