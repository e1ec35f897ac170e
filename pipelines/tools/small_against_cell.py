#!/usr/bin/env python3
"""The small cell a law.h5 keeps (/law/small) against its exact law (/law/cell) at N random unit
stress directions (seeded; unit in (sxx, syy, sqrt2 sxy), load s), none of them the fit's:
dualcell-law --form cell at the stresses gives the exact strains, dualcell-law --form small at
those strains the small cell's stresses; the relative stress error per direction, its max and
rms. For a cell whose exact law is too large for the fit's dense check (above 1 000 rows) but
still formed, as the 36-fibre RVE's: only the kept cell is measured, not the ladder (that is
dualcell-bench --small-cell). Writes OUT (markdown). Without adhesion only (the law is
homogeneous: s does not matter).

    small_against_cell.py BIN LAW OUT [--directions 1000] [--seed 36] [--load 0.01]
"""
import os
import subprocess
import tempfile
import time

import numpy as np

import common


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin")
    parser.add_argument("law")
    parser.add_argument("out")
    parser.add_argument("--directions", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=36)
    parser.add_argument("--load", type=float, default=0.01)
    args = parser.parse_args(argv[1:])
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    rng = np.random.default_rng(args.seed)
    N = rng.normal(size=(args.directions, 3))
    N /= np.linalg.norm(N, axis=1)[:, None]
    N[:, 2] /= np.sqrt(2)
    sigma = args.load * N
    law = os.path.join(args.bin, "dualcell-law")
    with tempfile.TemporaryDirectory(dir=os.path.dirname(os.path.abspath(args.out))) as work:
        stress_csv, cell_csv = os.path.join(work, "stress.csv"), os.path.join(work, "cell.csv")
        strain_csv, small_csv = os.path.join(work, "strain.csv"), os.path.join(work, "small.csv")
        with open(stress_csv, "w") as f:
            f.write("path,sxx,syy,sxy\n" + "".join(f"{i},{s[0]!r},{s[1]!r},{s[2]!r}\n" for i, s in enumerate(sigma)))
        seconds = {}
        for form, inp, out, kind in (("cell", stress_csv, cell_csv, "--stress"), ("small", strain_csv, small_csv,
                                                                                  "--strain")):
            if form == "small":
                strains = np.loadtxt(cell_csv, delimiter=",", skiprows=1, usecols=(1, 2, 3))
                with open(strain_csv, "w") as f:
                    f.write("path,exx,eyy,gxy\n" + "".join(f"{i},{e[0]!r},{e[1]!r},{e[2]!r}\n"
                                                            for i, e in enumerate(strains)))
            start = time.monotonic()
            subprocess.run([law, "--quiet", "--law", args.law, kind, inp, "--out", out, "--form", form], check=True)
            seconds[form] = time.monotonic() - start
        got = np.loadtxt(small_csv, delimiter=",", skiprows=1, usecols=(1, 2, 3))
    error = np.linalg.norm(got - sigma, axis=1) / np.linalg.norm(sigma, axis=1)
    worst = int(np.argmax(error))
    text = ("# The kept small cell against the exact law\n\n"
            f"Law: {args.law}. {args.directions} random unit stress directions (seed {args.seed}), load {args.load}: "
            "the exact law's strain there (dualcell-law --form cell), the small cell's stress at it (--form small).\n\n"
            f"Stress error: max {100 * error.max():.2f} % (at sxx,syy,sxy = {N[worst, 0]:.3f},{N[worst, 1]:.3f},"
            f"{N[worst, 2]:.3f}), rms {100 * np.sqrt(np.mean(error ** 2)):.2f} %. "
            f"Seconds: exact law {seconds['cell']:.1f}, small cell {seconds['small']:.2f}.\n")
    common.write_atomic(args.out, text)
    print(text, end="")


if __name__ == "__main__":
    common.main_guard(main)
