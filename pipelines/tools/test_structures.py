#!/usr/bin/python3
"""Tests of structures.py's scene writer (run by ctest): the resolved and the homogenised beam of
one case are the same beam (cells, edges, load) and valid scenes for their stages.

The resolved scene is checked by dualcell-mesh itself (the stages' folder is the argument), the
structure scene against the keys dualcell-structure reads.
"""
import os
import subprocess
import sys
import tempfile
import tomllib
import unittest

import structures

BIN = None
HERE = os.path.dirname(os.path.abspath(__file__))
CELL = os.path.join(HERE, "..", "scenes", "structure-cell-contact.toml")


class Scenes(unittest.TestCase):
    def test_every_kind_gives_the_same_beam_twice(self):
        for kind in ("bending", "cantilever", "threepoint"):
            with self.subTest(kind=kind), tempfile.TemporaryDirectory() as out:
                structures.scenes(CELL, "contact", kind, 2, out)
                with open(os.path.join(out, "resolved.toml"), "rb") as f:
                    resolved = tomllib.load(f)
                with open(os.path.join(out, "structure.toml"), "rb") as f:
                    homogenised = tomllib.load(f)
                # Length 8H, depth H, in cells, both ways.
                self.assertEqual(resolved["geometry"]["cells"], [16, 2])
                self.assertEqual(homogenised["structure"]["cells"], [16, 2])
                self.assertEqual(resolved["load"]["boundary"], "edges")
                for key in ("edges", "support", "point_load"):
                    self.assertEqual(resolved.get(key), homogenised.get(key), key)
                # Contact only: the cell's adhesion is dropped.
                self.assertEqual(resolved.get("interface", {}).get("normal_strength", 0), 0)
                # The resolved scene is one dualcell-mesh takes.
                done = subprocess.run([os.path.join(BIN, "dualcell-mesh"), "--quiet", "--config",
                                       os.path.join(out, "resolved.toml"), "--out", os.path.join(out, "mesh.h5")],
                                      capture_output=True, text=True)
                self.assertEqual(done.returncode, 0, done.stderr)

    def test_the_fuse_case_steps_both_beams_past_the_break_with_adhesion(self):
        cell = os.path.join(HERE, "..", "scenes", "structure-cell-adhesion.toml")
        with tempfile.TemporaryDirectory() as out:
            structures.scenes(cell, "adhesion", "fuse", 2, out)
            scenes = {}
            for name in ("resolved", "structure"):
                with open(os.path.join(out, f"{name}.toml"), "rb") as f:
                    scenes[name] = tomllib.load(f)
            for scene in scenes.values():
                self.assertEqual(scene["steps"]["factors"], structures.FUSE_STEPS)
                self.assertEqual(scene["edges"]["left"]["type"], "fixed")  # the cantilever
            self.assertGreater(scenes["resolved"]["interface"]["normal_strength"], 0)
            # Without adhesion there is nothing to break: refused.
            with self.assertRaises(SystemExit):
                structures.scenes(CELL, "contact", "fuse", 2, out)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: test_structures.py BIN_DIR")
    BIN = sys.argv.pop(1)
    unittest.main()
