#!/usr/bin/env python3
"""The small cell in a structure: beams in pure bending (a linear end traction, the other end a
roller) of homogeneous cells following one law.h5, with its small cell, its cone-wise law and,
on the small beam only, its exact law (docs/method.md §16c). Per beam and form: the end
displacement (ux, uy) at the neutral line's end, its error against the exact law (small beam),
and the seconds of dualcell-structure. Writes OUT_DIR/structure.md.

With --fuse SCENE, a structure scene loaded past the fuse (a law with adhesion: its small cell
carries the fuse, docs/method.md §16d) instead: per load step the watched displacement of the
small cell, the cone-wise law and the exact law, the errors of the first two against the third,
and the cells broken (fused) at the end; and the cost of one evaluation of the small cell and of
the exact law (dualcell-law, stress-driven with history along each triangle's stresses of the
exact law's run, step by step). Writes OUT_DIR/fuse.md.

    small_cell_structure.py BIN LAW OUT_DIR [--beams 8x2 128x16] [--fuse SCENE]
"""
import os
import re

import h5py
import numpy as np

import common

SCENE = """[structure]
cells = [{nx}, {ny}]
elements_per_cell = 2
element = "p2"
[edges.left]
type = "roller"
[edges.right]
type = "traction"
traction = [0.01, 0]
traction_end = [-0.01, 0]
[[support]]
at = [0, 0]
fix = "y"
[output]
watch = [{nx}.0, 0]
[steps]
factors = [1]
"""


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin")
    parser.add_argument("law")
    parser.add_argument("out_dir")
    parser.add_argument("--beams", nargs="+", default=["8x2", "128x16"])
    parser.add_argument("--fuse", help="a structure scene loaded past the fuse")
    args = parser.parse_args(argv[1:])
    os.makedirs(args.out_dir, exist_ok=True)
    if args.fuse:
        fuse(args)
        return
    rows = []
    for beam in args.beams:
        nx, ny = (int(v) for v in beam.split("x"))
        scene = os.path.join(args.out_dir, f"beam-{beam}.toml")
        with open(scene, "w") as f:
            f.write(SCENE.format(nx=nx, ny=ny))
        forms = ["small", "cone"] + (["cell"] if nx * ny <= 16 else [])
        result = {}
        for form in forms:
            out = os.path.join(args.out_dir, f"beam-{beam}-{form}.h5")
            done = common.run_stage([os.path.join(args.bin, "dualcell-structure"), "--quiet", "--config", scene,
                                     "--law", args.law, "--out", out, "--form", form], out)
            with h5py.File(out, "r") as h:
                u = h["/steps/watch_displacement"][-1]
            result[form] = (u, done.seconds)
        for form in forms:
            u, seconds = result[form]
            error = ("%+.2f %% / %+.2f %%" % tuple(100 * (u[k] / result["cell"][0][k] - 1) for k in range(2))
                     if "cell" in result else "–")
            ratio = seconds / result["cone"][1]
            rows.append(f"| {nx} × {ny} | {form} | {u[0]:.6e} | {u[1]:.6e} | {error} | {seconds:.2f} | {ratio:.2f} |")
    table = ("# The small cell in a structure\n\n" + f"Law: {args.law}. Bending, right end traction ±0.01 "
             "(linear over the depth), left end a roller; end displacement at the neutral line's end.\n\n"
             "| cells | form | ux | uy | error against the exact law (ux / uy) | seconds | / cone-wise |\n"
             "|---|---|---|---|---|---|---|\n" + "\n".join(rows) + "\n")
    exact = [beam for beam in args.beams if os.path.exists(os.path.join(args.out_dir, f"beam-{beam}-cell.h5"))]
    if exact:
        table += (f"\nOne evaluation, {exact[0]} beam: " +
                  evaluation_cost(args, os.path.join(args.out_dir, f"beam-{exact[0]}-cell.h5"), f"beam-{exact[0]}") + "\n")
    common.write_atomic(os.path.join(args.out_dir, "structure.md"), table)
    print(table, end="")


def fuse(args):
    forms = ["cell", "small", "cone"]
    result = {}
    for form in forms:
        out = os.path.join(args.out_dir, f"fuse-{form}.h5")
        done = common.run_stage([os.path.join(args.bin, "dualcell-structure"), "--quiet", "--config", args.fuse,
                                 "--law", args.law, "--out", out, "--form", form], out)
        with h5py.File(out, "r") as h:
            u = h["/steps/watch_displacement"][:]
            last = sorted(k for k in h["/steps"].keys() if k.isdigit())[-1]
            fused = h[f"/steps/{last}/fused"][:]
        result[form] = (u, done.seconds, f"{int((fused != 0).sum())} of {len(fused)}")
    exact = result["cell"][0]
    rows = []
    for i in range(len(exact)):
        cells = [f"{exact[i][1]:.6e}"]
        for form in ("small", "cone"):
            u = result[form][0][i]
            cells.append(f"{u[1]:.6e} ({100 * (u[1] / exact[i][1] - 1):+.2f} %)")
        rows.append(f"| {i} | " + " | ".join(cells) + " |")
    summary = " · ".join(f"{form}: {result[form][1]:.2f} s, {result[form][2]} triangles fused at the end"
                         for form in forms)
    summary += "\n\nOne evaluation, " + evaluation_cost(args, os.path.join(args.out_dir, "fuse-cell.h5"), "fuse")
    table = ("# The small cell with a fuse in a structure\n\n"
             f"Law: {args.law}. Scene: {args.fuse}; the watched point's uy per load step.\n\n"
             "| step | exact law | small cell (error) | cone-wise law (error) |\n|---|---|---|---|\n" + "\n".join(rows) +
             f"\n\n{summary}\n")
    common.write_atomic(os.path.join(args.out_dir, "fuse.md"), table)
    print(table, end="")


def evaluation_cost(args, structure, prefix):
    """dualcell-law's milliseconds per row, small cell and exact law, over the paths of every
    triangle's stress in `structure` (a dualcell-structure output) through its load steps; its
    files are OUT_DIR/`prefix`-points*.csv."""
    with h5py.File(structure, "r") as h:
        steps = sorted(k for k in h["/steps"].keys() if k.isdigit())
        stress = [h[f"/steps/{k}/stress"][:] for k in steps]
    points = os.path.join(args.out_dir, f"{prefix}-points.csv")
    common.write_atomic(points, "path,sxx,syy,sxy\n" + "".join(
        f"{t},{s[t][0]:.17g},{s[t][1]:.17g},{s[t][2]:.17g}\n" for t in range(len(stress[0])) for s in stress))
    cost, values = {}, {}
    # The exact law twice: its QP bordering the kept factorisation (the default) and factorising
    # every new free set (--factorise-each, the reference): the same values to round-off, and
    # what the bordering saves.
    for name, form, extra in (("small", "small", []), ("cell", "cell", []),
                              ("factorised", "cell", ["--factorise-each"])):
        out = os.path.join(args.out_dir, f"{prefix}-points-{name}.csv")
        done = common.run([os.path.join(args.bin, "dualcell-law"), "--law", args.law, "--stress", points, "--out",
                           out, "--form", form] + extra)
        per_row = re.search(r"([0-9.e+-]+) ms per row", done.stderr + done.stdout)
        if not per_row:
            raise ValueError(f"dualcell-law printed no 'ms per row': {(done.stderr + done.stdout).strip()}")
        cost[name] = 1e3 * float(per_row.group(1))
        values[name] = np.genfromtxt(out, delimiter=",", skip_header=1)[:, 1:]
    a, b = values["cell"], values["factorised"]
    difference = np.max(np.abs(a - b), axis=0) / np.maximum(np.max(np.abs(b), axis=0), np.finfo(float).tiny)
    return (f"stress-driven along the {len(stress[0])} triangles' stress paths of the exact law's run "
            f"({len(stress)} steps each, dualcell-law): small cell {cost['small']:.1f} µs, exact law "
            f"{cost['cell']:.1f} µs per point ({cost['factorised']:.1f} µs with every new free set of its QP "
            f"factorised, --factorise-each; the two differ by {difference.max():.1e} of each column's largest "
            f"value).")


if __name__ == "__main__":
    common.main_guard(main)
