#!/usr/bin/python3
"""Tests of accuracy_table.py (run by ctest): reference, errors and the time to 1e-4.

Synthetic ladders with a known limit and order stand for dualcell's p2 rungs; the table must
recover the limit, give every row its relative error against it, and pick per code the fastest
row at or below 1e-4 (or the most accurate one when none gets there).
"""
import csv
import os
import tempfile
import unittest

import accuracy_table

HEADER = "code,element,degree,nodes,dofs,load,E,seconds"


def write_rows(folder, name, rows):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(HEADER + "\n" + "\n".join(",".join(str(v) for v in r) for r in rows) + "\n")
    return path


class AccuracyTable(unittest.TestCase):
    def test_reference_errors_and_time_to_target(self):
        limit = {0.01: 0.5, -0.01: 1.4}
        with tempfile.TemporaryDirectory() as tmp:
            ours = []
            for k, seconds in ((2, 0.01), (4, 0.02), (8, 0.05), (16, 0.3)):
                for load in (0.01, -0.01):
                    # E = E* + 0.2 h^3 exactly: the Richardson limit over 4, 8, 16 is E*.
                    ours.append(("dualcell", "p2", k, 0, 2 * k * k, load, limit[load] + 0.2 / k ** 3, seconds))
            # CalculiX: 1e-3 at 1 s, 5e-5 at 30 s and at 50 s: the fastest row below 1e-4 is 30 s.
            theirs = [("ccx", "CPE6", k, 0, 10 * k, load, limit[load] * (1 + err), s)
                      for load in (0.01, -0.01) for k, err, s in ((4, 1e-3, 1.0), (8, 5e-5, 30.0), (16, -5e-5, 50.0))]
            paths = [write_rows(tmp, "ours.csv", ours), write_rows(tmp, "theirs.csv", theirs)]
            accuracy_table.main(["accuracy_table.py", tmp] + paths)
            with open(os.path.join(tmp, "table.csv")) as f:
                rows = list(csv.DictReader(f))
            for r in rows:
                E, load = float(r["E"]), float(r["load"])
                self.assertAlmostEqual(float(r["relative_error"]), abs(E - limit[load]) / limit[load],
                                       delta=1e-3 * abs(E - limit[load]) / limit[load] + 1e-12)
            md = open(os.path.join(tmp, "table.md")).read()
            # p2: error 0.2/8³/E* = 7.8e-4 (tension) at k = 8, 0.2/16³/0.5 = 9.8e-5 at k = 16 (0.3 s).
            self.assertIn("| dualcell | p2 | tension | yes | 9.77e-05 | 512 | 0.300 |", md)
            self.assertIn("| ccx | CPE6 | tension | yes | 5.00e-05 | 80 | 30.000 |", md)
            self.assertIn("tension: dualcell p2 reaches 0.0001 in 0.300 s; the best CalculiX row reaches it in "
                          "30.000 s: ratio 100", md)

    def test_too_few_reference_rungs_is_an_error(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = write_rows(tmp, "ours.csv", [("dualcell", "p2", 2, 0, 8, 0.01, 0.6, 0.1),
                                                ("dualcell", "p2", 4, 0, 32, 0.01, 0.55, 0.2)])
            with self.assertRaisesRegex(ValueError, "need three dualcell p2 rungs"):
                accuracy_table.main(["accuracy_table.py", tmp, path])


if __name__ == "__main__":
    unittest.main()
