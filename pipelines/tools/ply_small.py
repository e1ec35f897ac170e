#!/usr/bin/python3
"""The small cell of the whole ply (docs/method.md §16e) per scene, from its law.h5.

usage:
  ply_small.py OUT.md LAW.h5...     one row per law (the scene is the law's folder name)

Per law: the small cell's rows (with adhesion: its facet rows in the plane and along z, and the
rows past the fuse), its fit along the fibres (/law/small_ply_check: training points, largest and
rms error of the six stresses) and its check along the six-component strain paths of other
directions (directions, points, largest and rms error, and below the onset). A law whose small
cell does not carry the whole ply is refused. Writes OUT.md atomically.
"""
import os
import sys

import h5py

import common


def row(path):
    scene = os.path.basename(os.path.dirname(os.path.abspath(path)))
    with h5py.File(path, "r") as f:
        g = f["law"]
        if "small_ply_check" not in g:
            sys.exit(f"ply_small.py: {path}: no small cell of the whole ply ("
                     f"{common.text(g.attrs.get('small_note', 'the scene is not macro = full, periodic'))})")
        k = {name: g["small_ply_check"][name][0] for name in g["small_ply_check"] if name != "worst"}
        s = g["small"]
        rows, shear_rows = len(s["pair"]), int(s["shear_rows"][0]) if "shear_rows" in s else 0
        m = int(g["small_fit/rows"][0])
        cells = f"{rows - m} + {shear_rows} facet rows, {m} past the fuse" if rows > m else f"{m} rows"
        return (f"| {scene} | {cells} | {int(k['training_points'])}: {100 * k['training_max_error']:.1f} %, "
                f"{100 * k['training_rms_error']:.1f} % | {int(k['directions'])} ({int(k['points'])} points): "
                f"{100 * k['max_error']:.1f} %, {100 * k['rms_error']:.1f} % | {k['bonded_max_error']:.1e} |")


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("out")
    parser.add_argument("laws", nargs="+")
    args = parser.parse_args(argv[1:])
    lines = ["# The small cell of the whole ply against its exact law", "",
             "Each cell's small cell in six components (docs/method.md §16e): ε33 fitted along the fibres "
             "(y33), the shear along them the open cell's, with adhesion the bonded ply and its onset exactly; "
             "measured along the exact law's six-component strain paths of other directions (to twice the "
             "onset with adhesion). Errors: ‖σ − σ_exact‖/‖σ_exact‖ of the six stresses.", "",
             "| scene | small cell | fit along the fibres: points, max, rms | check: directions, max, rms | "
             "below the onset |", "|---|---|---|---|---|"]
    lines += [row(p) for p in args.laws]
    common.write_atomic(args.out, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    common.main_guard(main)
