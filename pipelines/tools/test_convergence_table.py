#!/usr/bin/python3
"""Tests of the Richardson extrapolation in convergence_table.py (run by ctest).

Sequences with a known limit and order: the extrapolation must recover both.
"""
import math
import unittest

from convergence_table import richardson


def sequence(limit, c, p, degrees, d=0.0, q=0.0):
    """[(h, E)] with E(h) = limit + c h^p + d h^q, h = 1/degree."""
    return [(1.0 / k, limit + c * (1.0 / k) ** p + d * (1.0 / k) ** q) for k in degrees]


class Richardson(unittest.TestCase):
    def test_exact_power_law_gives_limit_and_order(self):
        # E = E* + C h^p exactly: the order comes from a bisection run to machine precision and
        # the limit from a closed formula, so both are exact up to rounding of the inputs
        # (relative 1e-16, amplified by 1/(h2^p - h3^p) ~ 10): 1e-12 leaves a wide margin and
        # still fails for any wrong formula.
        for limit, c, p, degrees in [(1.7, 0.9, 2.0, (4, 8, 16)), (5.35, -3.0, 2.0, (8, 12, 16)),
                                     (1.0, 0.2, 1.0, (2, 3, 4)), (-2.0, 5.0, 3.5, (6, 9, 12))]:
            with self.subTest(limit=limit, p=p, degrees=degrees):
                estimate, order = richardson(sequence(limit, c, p, degrees))
                self.assertAlmostEqual(order, p, delta=1e-9)
                self.assertLess(abs(estimate - limit) / abs(limit), 1e-12)

    def test_higher_order_term_is_mostly_removed(self):
        # E = E* + C h^2 + D h^3: the three-point extrapolation fits an effective order near 2
        # and leaves an error of order h^3 of the finest mesh, well below the finest value's own
        # error C h^2 (here h = 1/16: h^3/h^2 = 1/16, so at least 5 times smaller).
        points = sequence(1.0, 0.5, 2.0, (4, 8, 16), d=0.3, q=3.0)
        estimate, order = richardson(points)
        self.assertLess(abs(order - 2.0), 0.3)
        self.assertLess(abs(estimate - 1.0), abs(points[-1][1] - 1.0) / 5)

    def test_outside_the_asymptotic_range_falls_back_to_the_finest(self):
        # Differences that grow as h shrinks fit no order in (0.05, 8): the finest value is
        # returned and the order is NaN, as the table then says.
        points = [(0.25, 1.0), (0.125, 1.01), (0.0625, 1.5)]
        estimate, order = richardson(points)
        self.assertEqual(estimate, 1.5)
        self.assertTrue(math.isnan(order))


if __name__ == "__main__":
    unittest.main()
