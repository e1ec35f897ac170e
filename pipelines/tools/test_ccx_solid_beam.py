#!/usr/bin/python3
"""Tests of ccx_solid_beam.py without CalculiX: the consistent nodal forces of a traction linear
along the right edge on the extruded faces carry the traction's resultant and moment exactly
(3 × 3 Gauss points integrate the quadratic face's shape functions times a linear traction), on
an uneven edge, and the bottom and top layers carry equal shares, as the plane strain needs.

usage: test_ccx_solid_beam.py (or python3 -m unittest test_ccx_solid_beam)
"""
import unittest

import numpy as np

import ccx_solid_beam


class FaceForces(unittest.TestCase):
    def test_resultant_and_moment_of_a_linear_traction(self):
        # A right edge x = 2 of three p2 segments, uneven, from y = 0 to y = 1.5.
        ys = [0.0, 0.2, 0.4, 0.7, 1.0, 1.25, 1.5]
        nodes = np.array([[2.0, y] for y in ys])
        edge = list(range(len(ys)))
        N = len(ys)

        def layer(i, level):
            return i + 1 + level * N

        t0, t1 = [0.01, 0.002], [-0.01, 0.004]
        f = ccx_solid_beam.face_forces(nodes, edge, layer, t0, t1)
        total = sum(f.values())
        # Resultant of t(y) = t0 + (t1 − t0) y/H over the height H, unit thickness: (t0 + t1) H/2.
        H = ys[-1]
        np.testing.assert_allclose(total, (np.array(t0) + t1) * H / 2, rtol=1e-13, atol=1e-16)
        # Moment about y = 0 of the x component: ∫ t_x(y) y dy = t0 H²/2 + (t1 − t0) H²/3.
        moment = sum(v[0] * nodes[(n - 1) % N, 1] for n, v in f.items())
        self.assertAlmostEqual(moment, t0[0] * H ** 2 / 2 + (t1[0] - t0[0]) * H ** 2 / 3, places=14)
        # The bottom layer (level 0) and the top (level 2) carry the same; so the field is even in z.
        for i in edge:
            if layer(i, 0) in f:
                np.testing.assert_allclose(f[layer(i, 0)], f[layer(i, 2)], rtol=1e-13, atol=1e-18)


if __name__ == "__main__":
    unittest.main()
