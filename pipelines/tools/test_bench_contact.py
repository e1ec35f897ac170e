#!/usr/bin/python3
"""Tests of bench_contact.py (run by ctest with the stages' folder): a one-rung ladder (the RVE of
4 fibres, one realisation, no beams) on the real stages writes one row per mode whose counts are
the solution files' own, the ratio is the contact (break) count over the bonded one, a finished
case is read again instead of re-run, and the beam scenes keep the cell's geometry with the
strengths raised (bonded) or as in the cell (break).
"""
import csv
import os
import sys
import tempfile
import tomllib
import unittest

import h5py

import bench_contact

HERE = os.path.dirname(os.path.abspath(__file__))
MATERIAL = os.path.join(HERE, "..", "..", "materials", "glass-epoxy.toml")
CELL = os.path.join(HERE, "..", "scenes", "structure-cell-adhesion.toml")
BIN = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "build", "bin")


class Ladder(unittest.TestCase):
    def test_one_rung(self):
        with tempfile.TemporaryDirectory() as out:
            argv = ["bench_contact.py", BIN, MATERIAL, CELL, out, "--fibres", "4", "--seeds", "1", "--depths",
                    "--cut-fibres", "0", "--adhesion-depths"]
            bench_contact.main(argv)
            with open(os.path.join(out, "contact.csv")) as f:
                rows = {r["mode"]: r for r in csv.DictReader(f)}
            self.assertEqual(sorted(rows), ["bonded", "break", "contact"])
            for mode, row in rows.items():
                with h5py.File(os.path.join(out, "contact", "rve-N4-s1", mode, "solution.h5"), "r") as f:
                    self.assertEqual(int(row["operator_applications"]), int(f["solver"].attrs["operator_applications"]))
                    self.assertEqual(int(row["debond_rounds"]), int(f["solver"].attrs["debond_rounds"]))
            bonded = int(rows["bonded"]["operator_applications"])
            for mode in ("contact", "break"):
                self.assertAlmostEqual(float(rows[mode]["ratio"]),
                                       int(rows[mode]["operator_applications"]) / bonded, places=12)
            # Past the first break the cascade runs more than one round; bonded and contact do not.
            self.assertGreater(int(rows["break"]["debond_rounds"]), 1)
            self.assertEqual(int(rows["contact"]["debond_rounds"]), 1)
            for ext in ("md", "png", "svg"):
                self.assertTrue(os.path.getsize(os.path.join(out, f"contact.{ext}")) > 0)
            # Resumed: a finished case is read, not solved again.
            solution = os.path.join(out, "contact", "rve-N4-s1", "contact", "solution.h5")
            before = os.stat(solution).st_mtime_ns
            bench_contact.main(argv)
            self.assertEqual(os.stat(solution).st_mtime_ns, before)

    def test_beam_scenes(self):
        with tempfile.TemporaryDirectory() as out:
            with open(CELL, "rb") as f:
                cell = tomllib.load(f)
            bonded = tomllib.loads(bench_contact.beam_text(CELL, "adhesion", "bending", 4, out,
                                                           bench_contact.BEAM_BONDED_STRENGTH))
            self.assertEqual(bonded["geometry"]["cells"], [32, 4])
            self.assertEqual(bonded["geometry"]["fibre_radius"], cell["geometry"]["fibre_radius"])
            self.assertEqual(bonded["interface"]["normal_strength"], bench_contact.BEAM_BONDED_STRENGTH)
            self.assertEqual(bonded["interface"]["tangential_strength"], bench_contact.BEAM_BONDED_STRENGTH)
            fuse = tomllib.loads(bench_contact.beam_text(CELL, "adhesion", "fuse", 4, out))
            self.assertEqual(fuse["interface"]["normal_strength"], cell["interface"]["normal_strength"])
            contact = tomllib.loads(bench_contact.beam_text(CELL, "contact", "bending", 4, out))
            self.assertNotIn("interface", contact)


if __name__ == "__main__":
    unittest.main()
