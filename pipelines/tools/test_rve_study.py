#!/usr/bin/python3
"""Tests of rve_study.py (run by ctest): the scene it writes is an RVE scene with the study's
numbers, and its judgement of representativeness is the smallest N from which mean and scatter
stay within the tolerance.
"""
import math
import tomllib
import unittest

import rve_study


class Study(unittest.TestCase):
    def test_scenes(self):
        bonded = tomllib.loads(rve_study.scene_text("/m.toml", 9, 3, 0.5, 2, True))
        side = math.sqrt(9 * math.pi / 0.5)
        self.assertEqual(bonded["geometry"]["size"], [side, side])
        self.assertEqual(bonded["geometry"]["kind"], "random")
        self.assertEqual(bonded["geometry"]["seed"], 3)
        self.assertEqual(bonded["load"]["boundary"], "periodic")
        self.assertGreater(bonded["interface"]["normal_strength"], 0)
        contact = tomllib.loads(rve_study.scene_text("/m.toml", 9, 3, 0.5, 2, False))
        self.assertNotIn("interface", contact)
        self.assertEqual(contact["sweep"]["magnitudes"], [-1e-2, 1e-2])

    def test_exact_law_lines(self):
        kept = {"rows": 100, "note": "", "against": "the exact law", "max_error": 0.1}
        none = {"rows": None, "note": "more than 3000 rows", "against": "held-out sweep directions",
                "max_error": 0.3}
        lines = rve_study.exact_law_lines({(0.5, 4): [kept, kept], (0.5, 64): [none, kept]})
        self.assertEqual(lines[2], "| 0.5 | 4 | 2 of 2 | 100 |  | the exact law: 10.0 % |")
        self.assertEqual(lines[3], "| 0.5 | 64 | 1 of 2 | 100 | more than 3000 rows | "
                                   "held-out sweep directions, the exact law: 20.0 % |")
        unbounded = dict(none, max_error=math.inf)
        lines = rve_study.exact_law_lines({(0.5, 64): [unbounded]})
        self.assertTrue(lines[2].endswith("| held-out sweep directions: unbounded (no law fits the other directions "
                                          "alone) |"), lines[2])

    def test_representative(self):
        def samples(means, sds):
            return {n: {"E_mean": m, "E_sd": s} for n, m, s in zip((1, 4, 16, 36), means, sds)}
        # Mean within 1 % from N = 16, scatter below 1 % from 16: 16.
        self.assertEqual(rve_study.representative(samples([9.0, 9.8, 10.05, 10.0], [0.0, 0.2, 0.05, 0.05]), "E", 0.01), 16)
        # A later N leaving the band moves the answer past it.
        self.assertEqual(rve_study.representative(samples([10.0, 10.0, 9.5, 10.0], [0.0, 0.0, 0.0, 0.0]), "E", 0.01), 36)
        # Scatter above the tolerance at the largest N: none.
        self.assertIsNone(rve_study.representative(samples([10.0, 10.0, 10.0, 10.0], [0.5, 0.5, 0.5, 0.5]), "E", 0.01))
        # One realisation (sd NaN) judges the mean alone.
        self.assertEqual(rve_study.representative(samples([12.0, 10.0, 10.0, 10.0], [math.nan] * 4), "E", 0.05), 4)


if __name__ == "__main__":
    unittest.main()
