#!/usr/bin/python3
"""What the cure does to the debond onset (docs/theory/model.md §1a): a scene with [load] delta_T
is meshed once and swept twice, as written and with delta_T = 0; per path the onset s* (the first
bond at its strength, from the cool-down where there is one), its change, and the bonds the
cool-down broke by itself; and the onset surfaces side by side (plot.py cure).

usage: cure_onset.py BIN_DIR SCENE OUT_DIR

Writes OUT_DIR/table.md (and table.csv), onset.png, onset.svg; the sweeps and the scene without the
temperature change (scene-warm.toml) stay in OUT_DIR.
"""
import math
import os
import re
import sys

import h5py

import common


def paths_of(sweep):
    """Per path: its label (θ and sign, or the stress tensor), the onset s* and the bonds broken at
    its first step (the cool-down's, load 0, where the file has delta_T)."""
    rows = []
    with h5py.File(sweep, "r") as f:
        delta_T = float(f.attrs["delta_T"]) if "delta_T" in f.attrs else 0.0
        for name in sorted(f["paths"]):
            g = f["paths"][name]
            theta, sign = float(g.attrs["direction_deg"]), int(g.attrs["sign"])
            N = [float(v) for v in g.attrs["unit_stress"]]
            label = (f"uniaxial θ = {theta:g}°" if not math.isnan(theta)
                     else "σ̄ ∝ ({:g}, {:g}, {:g})".format(*N)) + (", tension" if sign > 0 else ", compression")
            onset = float(g["fuse/onset_load"][0]) if "fuse" in g else float("nan")
            cooled = int(g["broken_bonds"][0]) if delta_T != 0 and float(g["load"][0]) == 0 else 0
            rows.append({"path": name, "label": label, "onset": onset, "cool_down_broken": cooled})
    return delta_T, rows


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("bin_dir")
    parser.add_argument("scene")
    parser.add_argument("out_dir")
    args = parser.parse_args(argv[1:])
    os.makedirs(args.out_dir, exist_ok=True)
    with open(args.scene) as f:
        text = f.read()
    if not re.search(r"^delta_T\s*=", text, re.M):
        sys.exit(f"cure_onset.py: {args.scene}: no [load] delta_T to compare against")
    # The same scene without the temperature change, in OUT_DIR: a material file named relative to
    # the scene is named by its absolute path there.
    warm_scene = os.path.join(args.out_dir, "scene-warm.toml")
    scene_dir = os.path.dirname(os.path.abspath(args.scene))
    text_warm = re.sub(r'^(material\s*=\s*)"([^"]*)"',
                       lambda m: m.group(1) + '"' + os.path.join(scene_dir, m.group(2)) + '"', text, flags=re.M)
    stage = lambda name: os.path.join(args.bin_dir, f"dualcell-{name}")  # noqa: E731
    mesh = os.path.join(args.out_dir, "mesh.h5")
    sweeps = {k: os.path.join(args.out_dir, f"sweep-{k}.h5") for k in ("cooled", "warm")}
    common.write_atomic(warm_scene, re.sub(r"^delta_T\s*=.*$", "delta_T = 0", text_warm, flags=re.M))
    common.run_stage([stage("mesh"), "--quiet", "--config", args.scene, "--out", mesh], mesh)
    for kind, scene in (("cooled", args.scene), ("warm", warm_scene)):
        common.run_stage([stage("sweep"), "--quiet", "--config", scene, "--mesh", mesh, "--out", sweeps[kind]],
                         sweeps[kind])
    delta_T, cooled = paths_of(sweeps["cooled"])
    _, warm = paths_of(sweeps["warm"])
    rows = []
    for c, w in zip(cooled, warm):
        change = 100 * (abs(c["onset"]) / abs(w["onset"]) - 1) if w["onset"] else float("nan")
        rows.append({"path": c["path"], "load": c["label"], "onset_warm": f"{w['onset']:.4g}",
                     "onset_cured": f"{c['onset']:.4g}", "change_percent": f"{change:+.1f}",
                     "cool_down_broken": c["cool_down_broken"]})
    broken = max((r["cool_down_broken"] for r in rows), default=0)
    md = [f"# What the cure does to the debond onset ({os.path.basename(args.scene)}, delta_T = {delta_T:g} K)\n\n",
          "Made by `make -C pipelines cure` (pipelines/tools/cure_onset.py): the scene swept as written and with\n",
          "delta_T = 0 on one mesh; s* the load factor of the path's unit stress at which the first bond reaches its\n",
          f"strength, from the cool-down where there is one. The cool-down alone broke {broken} bonds.\n\n",
          "| path | load | s* without ΔT | s* cured | change | broken by the cool-down |\n",
          "|---|---|---:|---:|---:|---:|\n"]
    for r in rows:
        md.append(f"| {r['path']} | {r['load']} | {r['onset_warm']} | {r['onset_cured']} | {r['change_percent']} % "
                  f"| {r['cool_down_broken']} |\n")
    common.write_table(os.path.join(args.out_dir, "table.md"), "".join(md),
                       ["path", "load", "onset_warm", "onset_cured", "change_percent", "cool_down_broken"], rows)
    here = os.path.dirname(os.path.abspath(__file__))
    common.run([sys.executable, os.path.join(here, "plot.py"), "cure", sweeps["cooled"],
                os.path.join(args.out_dir, "onset"), "--warm", sweeps["warm"]])
    print("".join(md), end="")


if __name__ == "__main__":
    common.main_guard(main)
