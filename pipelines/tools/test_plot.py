#!/usr/bin/python3
"""Tests of plot.py (run by ctest with the stages' folder as argument): every picture of the
default chain drawn from real stage outputs of a small cell, as PNG and SVG files that open.

The outputs come from the stages themselves (mesh, sweep, fit, solve), so a change of a file
layout that plot.py reads fails here, not in a pipeline run hours later.
"""
import csv
import os
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ElementTree

import h5py

import plot

BIN = None  # the stages' folder, the first argument

SCENE = """[geometry]
cells = [1, 1]
fibre_radius = 0.3
degree = 2
[fibre]
E = 10.0
nu = 0.2
[matrix]
E = 1.0
nu = 0.3
[interface]
normal_strength = 0.05
[load]
boundary = "periodic"
[sweep]
directions_deg = [0, 30, 45, 60, 90]
magnitudes = [-0.1, -0.02, 0.02, 0.1]
"""


def stage(name, *args):
    subprocess.run([os.path.join(BIN, name), "--quiet", *args], check=True)


class Pictures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        cls.files = {k: os.path.join(d, k) for k in ("scene.toml", "mesh.h5", "sweep.h5", "law.h5", "solution.h5")}
        with open(cls.files["scene.toml"], "w") as f:
            f.write(SCENE)
        stage("dualcell-mesh", "--config", cls.files["scene.toml"], "--out", cls.files["mesh.h5"])
        stage("dualcell-sweep", "--config", cls.files["scene.toml"], "--mesh", cls.files["mesh.h5"],
              "--out", cls.files["sweep.h5"])
        stage("dualcell-fit", "--sweep", cls.files["sweep.h5"], "--out", cls.files["law.h5"])
        stage("dualcell-solve", "--config", cls.files["scene.toml"], "--mesh", cls.files["mesh.h5"],
              "--stress", "0.01,0,0", "--out", cls.files["solution.h5"])

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def assert_picture(self, outbase):
        with open(outbase + ".png", "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", outbase + ".png is not a PNG")
        self.assertGreater(os.path.getsize(outbase + ".png"), 1000)
        root = ElementTree.parse(outbase + ".svg").getroot()
        self.assertTrue(root.tag.endswith("svg"), outbase + ".svg is not an SVG")
        leftovers = [n for n in os.listdir(os.path.dirname(outbase)) if ".tmp" in n]
        self.assertEqual(leftovers, [], "temporaries left")

    def test_stress_strain(self):
        out = os.path.join(self.tmp.name, "stress_strain")
        plot.stress_strain(self.files["sweep.h5"], out)
        self.assert_picture(out)

    def test_polar_draws_the_law_from_its_file(self):
        out = os.path.join(self.tmp.name, "polar")
        plot.polar(self.files["law.h5"], out)
        self.assert_picture(out)
        # The fitted law's curve is drawn from /law/cone/polar_* as dualcell-fit wrote them.
        svg = open(out + ".svg").read()
        self.assertIn("cone-wise law, tension", svg)

    def test_deformed(self):
        out = os.path.join(self.tmp.name, "deformed")
        plot.deformed(self.files["solution.h5"], out)
        self.assert_picture(out)

    def test_deformed_marks_broken_rims_and_open_gaps_only_past_the_onset(self):
        # Below the onset (0.01): bonded, closed, no mark. Past it (0.2): the rim breaks and opens.
        bonded = os.path.join(self.tmp.name, "deformed_bonded")
        plot.deformed(self.files["solution.h5"], bonded, self.files["mesh.h5"])
        self.assert_picture(bonded)
        svg = open(bonded + ".svg").read()
        self.assertNotIn("broken bond", svg)
        self.assertNotIn("open gap", svg)
        past = os.path.join(self.tmp.name, "past.h5")
        stage("dualcell-solve", "--config", self.files["scene.toml"], "--mesh", self.files["mesh.h5"],
              "--stress", "0.2,0,0", "--out", past)
        debonded = os.path.join(self.tmp.name, "deformed_debonded")
        plot.deformed(past, debonded, self.files["mesh.h5"])
        self.assert_picture(debonded)
        svg = open(debonded + ".svg").read()
        self.assertIn("broken bond", svg)
        self.assertIn("open gap", svg)

    def test_cure_tool_compares_the_onsets_of_its_two_sweeps(self):
        # cure_onset.py on a cell with adhesion and a cool-down: its table's onsets are the two
        # sweeps' own (fuse/onset_load), the cool-down's sweep records delta_T, and the picture opens.
        d = os.path.join(self.tmp.name, "cure")
        os.makedirs(d)
        scene = os.path.join(d, "cure.toml")
        with open(scene, "w") as f:
            f.write(SCENE.replace("nu = 0.2\n", "nu = 0.2\nalpha = 5e-6\n", 1)
                    .replace("nu = 0.3\n", "nu = 0.3\nalpha = 6e-5\n", 1)
                    .replace("[interface]\nnormal_strength = 0.05\n",
                             "[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n")
                    .replace('boundary = "periodic"\n', 'boundary = "periodic"\ndelta_T = -50\n'))
        here = os.path.dirname(os.path.abspath(__file__))
        subprocess.run([sys.executable, os.path.join(here, "cure_onset.py"), BIN, scene, d], check=True,
                       stdout=subprocess.DEVNULL)
        self.assert_picture(os.path.join(d, "onset"))
        with open(os.path.join(d, "table.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 10)
        with h5py.File(os.path.join(d, "sweep-cooled.h5"), "r") as cooled, \
                h5py.File(os.path.join(d, "sweep-warm.h5"), "r") as warm:
            self.assertEqual(float(cooled.attrs["delta_T"]), -50)
            self.assertNotIn("delta_T", warm.attrs)
            for r in rows:
                for kind, f in (("onset_cured", cooled), ("onset_warm", warm)):
                    solved = float(f["paths"][r["path"]]["fuse/onset_load"][0])
                    self.assertAlmostEqual(float(r[kind]) / solved, 1, delta=5e-4)  # printed to 4 digits
            # The cure moves the onset: the uniaxial tension along x differs by more than 1 %.
            self.assertGreater(abs(float(rows[0]["change_percent"])), 1)

    def test_lamina_tool_reads_the_fits_constants_and_resumes(self):
        # lamina_table.py on a system whose law.h5 is already there (the resume path: the stages'
        # folder given is empty, so a chain run would fail): the RVE's E2 is the mean of its E2 and
        # E3, its spread their difference, the difference from the measured lamina in per cent, the
        # rule of mixtures from the material file, and nu23 is shown but not compared.
        import lamina_table
        d = os.path.join(self.tmp.name, "lamina")
        os.makedirs(os.path.join(d, "out", "x-y"))
        with open(os.path.join(d, "m.toml"), "w") as f:
            f.write("[fibre]\nE = 10.0\nnu = 0.2\nE_L = 200.0\nnu_LT = 0.2\nG_LT = 20.0\nalpha = 1e-5\n"
                    "[matrix]\nE = 4.0\nnu = 0.35\nalpha = 5e-5\n")
        data = os.path.join(d, "data.csv")
        with open(data, "w") as f:
            f.write("system,material,v_f,E1,E2,G12,nu12,nu23,alpha1,alpha2\nX/Y,m.toml,0.5,100,8,4,0.25,0.4,1e-6,3e-5\n")
        folder = os.path.join(d, "out", "x-y")
        with open(os.path.join(folder, "scene.toml"), "w") as f:
            f.write(lamina_table.SCENE.format(system="X/Y", v_f="0.5", material="m.toml",
                                              material_path=os.path.join(d, "m.toml"), size="8", seed=1, degree=2))
        with h5py.File(os.path.join(folder, "law.h5"), "w") as f:
            f["law/ply/constants"] = [[102.0, 9.0, 7.0, 0.26, 0.24, 0.3, 4.2, 3.8, 3.0]]
            f["law/ply/broken"] = [0]
            expansion = f.create_group("law/expansion")
            for k, v in (("alpha1", 2e-6), ("alpha2", 3.3e-5), ("alpha3", 2.7e-5), ("alpha23", 1e-7), ("ok", 1)):
                expansion.attrs[k] = v
        run = lambda *extra: subprocess.run(  # noqa: E731
            [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "lamina_table.py"),
             os.path.join(d, "no-stages"), data, d, os.path.join(d, "out"), *extra],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        done = run()
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("law.h5 kept", done.stderr)
        self.assert_picture(os.path.join(d, "out", "lamina"))
        with open(os.path.join(d, "out", "table.csv")) as f:
            rows = {r["constant"]: r for r in csv.DictReader(f)}
        self.assertEqual(float(rows["E1"]["rve"]), 102)
        self.assertEqual(rows["E1"]["difference_percent"], "+2.0")
        self.assertAlmostEqual(float(rows["E1"]["rule_of_mixtures"]), 0.5 * 200 + 0.5 * 4)
        self.assertEqual(float(rows["E2"]["rve"]), 8)  # (9 + 7) / 2
        self.assertEqual(rows["E2"]["spread_percent"], "25.0")  # |9 - 7| / 8
        self.assertEqual(float(rows["G12"]["rve"]), 4)
        self.assertEqual(float(rows["nu12"]["rve"]), 0.25)
        self.assertEqual(float(rows["alpha2"]["rve"]), 3e-5)
        self.assertEqual(rows["alpha2"]["spread_percent"], "20.0")
        self.assertEqual(rows["nu23"]["compared"], "no")
        self.assertEqual(rows["E2"]["compared"], "yes")
        # Another seed is another RVE: the tool runs the chain (and fails here, without stages).
        self.assertNotEqual(run("--seed", "2").returncode, 0)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: test_plot.py BIN_DIR")
    BIN = sys.argv.pop(1)
    unittest.main()
