#!/usr/bin/python3
"""The shear along the fibres through its debond cascade: the exact law of a full periodic cell
(`dualcell-law --full`) against the one-body antiplane solves the sweep recorded (/shear_check,
docs/method.md §16a), with a picture.

usage:
  ply_shear.py BIN LAW.h5 SWEEP.h5 OUT.md

For each of the sweep's four Γ paths (0°, 45°, 90°, 135° in the (γxz, γyz) plane) the law is
evaluated twice: at the checks' own Γ in their order, from the intact cell (table: the largest
relative difference of ⟨τ⟩ from the one-body solve's and whether the broken pairs agree), and
along a fine ramp of Γ to the path's largest and back to 0 (the picture: τ along the path's
direction against |Γ|, the checks as points; the unloading shows the pairs that broke stay
broken). Writes OUT.md and OUT.png/.svg beside it, atomically; fails (exit 1) when a check differs
by more than 1e-9 or breaks other pairs.
"""
import csv
import math
import os
import sys
import tempfile

import h5py
import numpy

import common
import plot

RAMP = 60  # steps up, and as many down


def law_rows(bin_dir, law, points, work):
    """dualcell-law --full at rows (path, Γ) from the intact cell along each path: ⟨τ⟩, broken."""
    source, values = os.path.join(work, "points.csv"), os.path.join(work, "values.csv")
    with open(source, "w") as f:
        f.write("path,exx,eyy,gxy,e33,gxz,gyz\n")
        for path, g in points:
            f.write(f"{path},0,0,0,0,{g[0]:.17g},{g[1]:.17g}\n")
    common.run([os.path.join(bin_dir, "dualcell-law"), "--quiet", "--law", law, "--strain", source, "--out", values,
                "--full"])
    with open(values) as f:
        return [(numpy.array([float(r["sxz"]), float(r["syz"])]), int(r["broken_pairs"])) for r in csv.DictReader(f)]


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin")
    parser.add_argument("law")
    parser.add_argument("sweep")
    parser.add_argument("out")
    args = parser.parse_args(argv[1:])
    with h5py.File(args.sweep, "r") as f:
        if "/shear_check" not in f:
            sys.exit(f"ply_shear.py: {args.sweep}: no /shear_check (a scene with [load] macro = \"full\", periodic)")
        g = f["/shear_check"]
        paths, gammas, taus, broken = g["path"][:], g["gamma"][:], g["tau"][:], g["broken"][:]
    rows, data, worst, mismatches = [], {}, 0.0, 0
    with tempfile.TemporaryDirectory() as work:
        checked = law_rows(args.bin, args.law, [(int(p), gm) for p, gm in zip(paths, gammas)], work)
        ramps = []
        for p in sorted(set(int(p) for p in paths)):
            mine = [i for i in range(len(paths)) if paths[i] == p]
            top = max(numpy.linalg.norm(gammas[i]) for i in mine)
            unit = gammas[mine[0]] / numpy.linalg.norm(gammas[mine[0]])
            steps = [top * k / RAMP for k in range(1, RAMP + 1)] + [top * k / RAMP for k in range(RAMP - 1, -1, -1)]
            ramps += [(p, s * unit) for s in steps]
            errors = [numpy.linalg.norm(checked[i][0] - taus[i]) / numpy.linalg.norm(taus[i]) for i in mine]
            differ = sum(checked[i][1] != broken[i] for i in mine)
            worst, mismatches = max(worst, max(errors)), mismatches + differ
            angle = math.degrees(math.atan2(unit[1], unit[0]))
            rows.append(f"| {angle:.0f}° | {len(mine)} | " + ", ".join(f"{numpy.linalg.norm(gammas[i]):.4g}" for i in mine)
                        + " | " + ", ".join(str(int(broken[i])) for i in mine) + f" | {max(errors):.1e} | "
                        + ("the same" if differ == 0 else f"{differ} differ") + " |")
            data[f"checks{p}.dat"] = "".join(f"{numpy.linalg.norm(gammas[i]):.9g} {taus[i] @ unit:.9g}\n" for i in mine)
        curve = law_rows(args.bin, args.law, ramps, work)
    for p in sorted(set(int(p) for p in paths)):
        data[f"law{p}.dat"] = "".join(f"{numpy.linalg.norm(g):.9g} {tau @ (g / max(numpy.linalg.norm(g), 1e-300)):.9g}\n"
                                      for (q, g), (tau, _) in zip(ramps, curve) if q == p and numpy.linalg.norm(g) > 0)
    labels = {0: "0°", 1: "45°", 2: "90°", 3: "135°"}
    plots = []
    for k, p in enumerate(sorted(set(int(p) for p in paths))):
        plots.append(f"'law{p}.dat' using 1:2 with lines lw 2 lc {k + 1} title 'exact law, Γ along {labels.get(p, p)}'")
        plots.append(f"'checks{p}.dat' using 1:2 with points pt 7 ps 1.5 lc {k + 1} title 'one-body solves'")
    script = ("set xlabel '|Γ| (shear along the fibres)'\nset ylabel 'τ along Γ'\nset grid\nset key right bottom\n"
              "set title 'The shear along the fibres through its debond cascade, loaded and unloaded'\n"
              "plot " + ", ".join(plots) + "\n")
    outbase = os.path.splitext(args.out)[0]
    plot.gnuplot(script, outbase, data)
    md = ["# The shear along the fibres through its debond cascade", "",
          f"Law {os.path.basename(os.path.dirname(os.path.abspath(args.law)))}/{os.path.basename(args.law)} "
          "(dualcell-law --full) against the "
          "one-body antiplane solves of its sweep (/shear_check), each path from the intact cell.", "",
          "| Γ along | checks | \\|Γ\\| | broken (one-body) | largest difference of ⟨τ⟩ | broken pairs |",
          "|---|---|---|---|---|---|"] + rows + [
          "", f"Largest relative difference {worst:.1e} (bound 1e-9); broken pairs differ at {mismatches} checks.",
          f"Picture: {os.path.basename(outbase)}.png (τ along Γ against |Γ|, loaded to the path's largest and unloaded)."]
    common.write_atomic(args.out, "\n".join(md) + "\n")
    print("\n".join(md))
    if worst > 1e-9 or mismatches:
        sys.exit(f"ply_shear.py: the law misses the one-body solves by {worst:.1e} or breaks other pairs ({mismatches})")


if __name__ == "__main__":
    common.main_guard(main)
