#!/usr/bin/python3
"""Tests of ccx_cell.py without CalculiX: the boundary-strain formula, the penalty ladder, the
command line and the readers of ccx's .dat and .sta files.

usage: test_ccx_cell.py (or python3 -m unittest test_ccx_cell)
"""
import math
import os
import tempfile
import types
import unittest

import numpy as np

import ccx_cell


def square(quadratic, ys=(0.0, 0.3, 1.0)):
    """A strip [0, 1] × [0, 1] of triangles between the left and right edges, the edge nodes at
    heights ys (uneven on purpose); 6-node triangles get their mid-side nodes at the midpoints."""
    nodes = [(x, y) for y in ys for x in (0.0, 1.0)]
    triangles = []
    for j in range(len(ys) - 1):
        a, b, c, d = 2 * j, 2 * j + 1, 2 * j + 3, 2 * j + 2  # counter-clockwise quad
        triangles += [[a, b, c], [a, c, d]]
    if quadratic:
        index = {}

        def mid(p, q):
            key = (min(p, q), max(p, q))
            if key not in index:
                index[key] = len(nodes)
                nodes.append(tuple((np.array(nodes[p]) + np.array(nodes[q])) / 2))
            return index[key]
        triangles = [t + [mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0])] for t in triangles]
    return types.SimpleNamespace(nodes=np.array(nodes), triangles=np.array(triangles), quadratic=quadratic)


def strain_xx(mesh, ux):
    right = ccx_cell.boundary_faces(mesh, 0, 1.0, 1e-12)
    left = ccx_cell.boundary_faces(mesh, 0, 0.0, 1e-12)
    return ccx_cell.edge_integral(right, mesh.nodes, ux) - ccx_cell.edge_integral(left, mesh.nodes, ux)


class BoundaryStrain(unittest.TestCase):
    def test_homogeneous_field_gives_its_strain(self):
        # u_x = ε x + c: ε̄xx = ε on the unit square, whatever the rigid shift c, for both orders.
        for quadratic in (False, True):
            mesh = square(quadratic)
            ux = 0.0123 * mesh.nodes[:, 0] - 0.7
            self.assertAlmostEqual(strain_xx(mesh, ux), 0.0123, delta=1e-15)

    def test_edge_rules_are_exact_for_their_order(self):
        # ∫_0^1 u dy on x = 1: trapezoid exact for linear u, the 1/6, 4/6, 1/6 rule for quadratic u
        # (on uneven edges); left edge u = 0.
        mesh = square(True)
        y, x = mesh.nodes[:, 1], mesh.nodes[:, 0]
        ux = np.where(x > 0.5, 2.0 - 3.0 * y + 5.0 * y ** 2, 0.0)
        self.assertAlmostEqual(strain_xx(mesh, ux), 2.0 - 1.5 + 5.0 / 3.0, delta=1e-14)
        mesh = square(False)
        y, x = mesh.nodes[:, 1], mesh.nodes[:, 0]
        ux = np.where(x > 0.5, 2.0 - 3.0 * y, 0.0)
        self.assertAlmostEqual(strain_xx(mesh, ux), 0.5, delta=1e-15)

    def test_faces_carry_calculix_face_numbers(self):
        # Face k (1, 2, 3) of a triangle is its edge from corner k to corner k+1 (cyclic), and
        # both corners of every face found lie on the line.
        mesh = square(False)
        for e, face, (a, b, _) in ccx_cell.boundary_faces(mesh, 0, 1.0, 1e-12):
            tri = mesh.triangles[e - 1]
            self.assertEqual((tri[face - 1], tri[face % 3]), (a, b))
            self.assertEqual((mesh.nodes[a, 0], mesh.nodes[b, 0]), (1.0, 1.0))


class Deck(unittest.TestCase):
    def test_penalty_ladder(self):
        self.assertEqual(ccx_cell.penalty_ladder(1e5), [1e3, 1e4, 1e5])
        ladder = ccx_cell.penalty_ladder(1e5, math.sqrt(10))
        self.assertEqual(len(ladder), 5)
        self.assertEqual(ladder[-1], 1e5)
        self.assertEqual(ccx_cell.penalty_ladder(50.0), [50.0])

    def test_reals_fit_calculix_fields(self):
        for x in (1.0, -0.01, 0.7942355841209018, -1.2345678901234567e-300, 1e-8, 6.4e7):
            text = ccx_cell.real(x)
            self.assertIn(".", text)
            self.assertLessEqual(len(text), 20)
            self.assertAlmostEqual(float(text), x, delta=abs(x) * 1e-12)

    def test_negative_load_is_positional(self):
        args = ccx_cell.parse_args(["mesh.h5", "-1e-2", "out.csv", "--penalty", "1e4"])
        self.assertEqual((args.mesh, args.load, args.out, args.penalty), ("mesh.h5", -0.01, "out.csv", 1e4))
        with self.assertRaises(ValueError):
            ccx_cell.parse_args(["mesh.h5", "0.01", "out.csv", "--nonsense"])
        with self.assertRaises(ValueError):
            ccx_cell.parse_args(["mesh.h5", "0.01"])


class Readers(unittest.TestCase):
    def test_last_displacement_block_and_status(self):
        dat = ("\n displacements (vx,vy,vz) for set NPRINT and time  0.1000000E+01\n\n"
               "         1  1.000000E+00  2.000000E+00  0.000000E+00\n\n"
               " displacements (vx,vy,vz) for set NPRINT and time  0.2000000E+01\n\n"
               "         1  3.000000E+00 -4.000000E+00  0.000000E+00\n"
               "         7  5.000000E-01  0.000000E+00  0.000000E+00\n")
        sta = ("SUMMARY OF JOB INFORMATION\n  STEP      INC     ATT  ITRS     TOT TIME     STEP TIME      INC TIME\n"
               "     1          1     1U  200  0.000000E+00  0.000000E+00  0.100000E+01\n"
               "     1          1     2    13  0.100000E+01  0.100000E+01  0.100000E+01\n"
               "     2          1     1     4  0.200000E+01  0.100000E+01  0.100000E+01\n")
        with tempfile.TemporaryDirectory() as d:
            for name, text in (("a.dat", dat), ("a.sta", sta)):
                with open(os.path.join(d, name), "w") as f:
                    f.write(text)
            self.assertEqual(ccx_cell.read_displacements(os.path.join(d, "a.dat")), {1: (3.0, -4.0), 7: (0.5, 0.0)})
            self.assertEqual(ccx_cell.read_status(os.path.join(d, "a.sta")), (217, 1))


if __name__ == "__main__":
    unittest.main()
