#!/usr/bin/python3
"""Error of E_tension and E_compression against run time, for the convergence study.

usage: convergence_table.py CONV_DIR OUT.csv CASE...

Each CASE (k<degree>_t<tolerance>) holds law.h5, mesh.h5 and `seconds` (wall time of mesh +
sweep). The reference is a Richardson extrapolation over the three finest degrees at the
tightest tolerance: E(h) = E* + C h^p with h = 1/degree; p from
(E1 − E2)/(E2 − E3) = (h1^p − h2^p)/(h2^p − h3^p) by bisection, then E* from the finest two.
Writes OUT.csv (comment lines with the reference and p, then one row per case).
"""
import os
import sys

import h5py

import common


def richardson(points):
    """points: [(h, E)] for the three finest meshes, h decreasing. Returns (E*, p)."""
    (h1, e1), (h2, e2), (h3, e3) = points
    target = (e1 - e2) / (e2 - e3)

    def ratio(p):
        return (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p)

    lo, hi = 0.05, 8.0
    if not (min(ratio(lo), ratio(hi)) <= target <= max(ratio(lo), ratio(hi))):
        return e3, float("nan")  # not in the asymptotic range: the finest value is the reference
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (ratio(mid) - target) * (ratio(lo) - target) > 0:
            lo = mid
        else:
            hi = mid
    p = 0.5 * (lo + hi)
    return e3 - (e2 - e3) * h3 ** p / (h2 ** p - h3 ** p), p


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("conv_dir", metavar="CONV_DIR")
    parser.add_argument("out", metavar="OUT.csv")
    parser.add_argument("cases", metavar="CASE", nargs="+")
    args = parser.parse_args(argv[1:])
    conv_dir, out = args.conv_dir, args.out
    rows = []
    for case in args.cases:
        degree = int(case[1:case.index("_t")])
        tolerance = float(case[case.index("_t") + 2:])
        d = os.path.join(conv_dir, case)
        with h5py.File(os.path.join(d, "law.h5"), "r") as f:
            e_t, e_c = float(f["/law/E_tension"][0]), float(f["/law/E_compression"][0])
        with h5py.File(os.path.join(d, "mesh.h5"), "r") as f:
            dofs = 2 * f["/mesh/nodes"].shape[0]
        seconds = float(open(os.path.join(d, "seconds")).read())
        rows.append(dict(case=case, degree=degree, tolerance=tolerance, dofs=dofs, seconds=seconds, E_tension=e_t,
                         E_compression=e_c))
    tightest = min(r["tolerance"] for r in rows)
    finest = sorted((r for r in rows if r["tolerance"] == tightest), key=lambda r: r["degree"])[-3:]
    refs = {}
    for which in ("tension", "compression"):
        refs[which] = richardson([(1.0 / r["degree"], r["E_" + which]) for r in finest])
    lines = [f"# reference (Richardson over degrees {[r['degree'] for r in finest]} at tolerance {tightest:g}):",
             f"# E_tension* = {refs['tension'][0]:.10g} (order p = {refs['tension'][1]:.3f}), "
             f"E_compression* = {refs['compression'][0]:.10g} (p = {refs['compression'][1]:.3f})",
             "case,degree,tolerance,dofs,seconds,E_tension,E_compression,error_tension,error_compression"]
    for r in sorted(rows, key=lambda r: (r["degree"], -r["tolerance"])):
        err = {w: abs(r["E_" + w] - refs[w][0]) / abs(refs[w][0]) for w in ("tension", "compression")}
        lines.append(f"{r['case']},{r['degree']},{r['tolerance']:g},{r['dofs']},{r['seconds']:.4f},"
                     f"{r['E_tension']:.10g},{r['E_compression']:.10g},{err['tension']:.3e},{err['compression']:.3e}")
    text = "\n".join(lines) + "\n"
    common.write_atomic(out, text)
    sys.stdout.write(text)


if __name__ == "__main__":
    common.main_guard(main)
