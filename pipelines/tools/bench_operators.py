#!/usr/bin/python3
"""A sweep at the cost of its QPs: whole commands, per [solver] dual_operator.

usage: bench_operators.py BIN_DIR SCENE.toml REPEAT OUT_DIR

Meshes SCENE once, then times (best of REPEAT, the machine is shared) one `dualcell-solve` of
its first stress (σ̄ = 0.02 along x) and the whole `dualcell-sweep` of the scene (a fresh output
each time, nothing resumed), for dual_operator = "implicit", "auto" and "explicit". The sweep's
target is ≤ 20 × one solve, both whole commands of the same operator choice ("auto"). Writes
OUT_DIR/sweep_operators.md and .csv atomically (one row per operator: solve_seconds,
sweep_seconds, paths, ratio). Errors: one line on stderr, exit 1.
"""
import os
import re

import h5py

import common

OPERATORS = ("implicit", "auto", "explicit")


def scene_with(scene, operator, out):
    """SCENE with [solver] dual_operator set (a table of its own: the scene has no [solver])."""
    with open(scene) as f:
        text = f.read()
    if re.search(r"^\[solver\]", text, re.M):
        raise ValueError(f"{scene}: has a [solver] table; the bench sets dual_operator itself")
    base = os.path.dirname(os.path.abspath(scene))
    # The material path is relative to the scene's folder: make it absolute for the copy.
    text = re.sub(r'^material = "([^"]+)"', lambda m: f'material = "{os.path.join(base, m.group(1))}"', text,
                  flags=re.M)
    common.write_atomic(out, text + f'\n[solver]\ndual_operator = "{operator}"\n')


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("bin_dir", metavar="BIN_DIR")
    parser.add_argument("scene", metavar="SCENE.toml")
    parser.add_argument("repeat", metavar="REPEAT", type=int)
    parser.add_argument("out_dir", metavar="OUT_DIR")
    args = parser.parse_args(argv[1:])
    if args.repeat < 1:
        raise ValueError(f"REPEAT {args.repeat} must be >= 1")
    work = os.path.join(args.out_dir, "operators")
    os.makedirs(work, exist_ok=True)
    binary = lambda stage: os.path.join(args.bin_dir, stage)
    mesh = os.path.join(work, "mesh.h5")
    common.run([binary("dualcell-mesh"), "--quiet", "--config", args.scene, "--out", mesh])
    rows = []
    for operator in OPERATORS:
        scene = os.path.join(work, f"{operator}.toml")
        scene_with(args.scene, operator, scene)
        solution = os.path.join(work, f"solve-{operator}.h5")
        solve = [binary("dualcell-solve"), "--quiet", "--config", scene, "--mesh", mesh, "--stress", "0.02,0,0",
                 "--out", solution]
        solve_seconds = min(common.run(solve).seconds for _ in range(args.repeat))
        with h5py.File(solution, "r") as f:
            explicit = int(f["/solver"].attrs["explicit_subdomains"])
            subdomains = int(f["/solver"].attrs["subdomains"])
        sweep_out = os.path.join(work, f"sweep-{operator}.h5")
        sweep_seconds = []
        for _ in range(args.repeat):
            if os.path.exists(sweep_out):
                os.remove(sweep_out)
            sweep_seconds.append(common.run([binary("dualcell-sweep"), "--quiet", "--config", scene, "--mesh", mesh,
                                             "--out", sweep_out]).seconds)
        with h5py.File(sweep_out, "r") as f:
            paths = int(f.attrs["n_paths"])
        rows.append((operator, f"{explicit} of {subdomains}", solve_seconds, min(sweep_seconds), paths))
    header = "dual_operator,explicit_subdomains_in_solve,solve_seconds,sweep_seconds,paths,ratio"
    csv = [header] + [f"{o},{e},{s:.4f},{w:.3f},{p},{w / s:.2f}" for o, e, s, w, p in rows]
    common.write_atomic(os.path.join(args.out_dir, "sweep_operators.csv"), "\n".join(csv) + "\n")
    md = ["# A sweep at the cost of its QPs", "",
          f"`{os.path.basename(args.scene)}`: one `dualcell-solve` (σ̄ = 0.02 along x) and the whole "
          f"`dualcell-sweep`, whole commands, best of {args.repeat}, per `[solver] dual_operator`. Target: the "
          "sweep ≤ 20 × one solve (auto).", "",
          "| dual_operator | explicit subdomains (solve) | solve s | sweep s | paths | sweep / solve |",
          "|---|---|---|---|---|---|"]
    md += [f"| {o} | {e} | {s:.3f} | {w:.2f} | {p} | **{w / s:.1f}×** |" for o, e, s, w, p in rows]
    common.write_atomic(os.path.join(args.out_dir, "sweep_operators.md"), "\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    common.main_guard(main)
