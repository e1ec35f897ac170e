#!/usr/bin/python3
"""The bonded ply from published constituents against the lamina a laboratory measured
(docs/results/lamina.md).

usage: lamina_table.py BIN_DIR DATA.csv MATERIALS_DIR OUT_DIR [--size S] [--seed N] [--degree D]

DATA.csv has one row per material system (data/lamina-wwfe-1998.csv): `system`, `material` (a
file in MATERIALS_DIR: the fibre and matrix with their expansion), `v_f` (the measured lamina's
fibre volume fraction) and the measured E1, E2, G12, nu12, nu23, alpha1, alpha2 (GPa, 1/K; axis
1 the fibres; an empty cell: not measured).

Per system a random RVE of fibres of one radius at that v_f (side S fibre radii, seed N),
periodic, bonded (strengths nothing reaches), with the whole ply's strain (`macro = "full"`),
goes mesh -> sweep -> fit (the user's chain, OUT_DIR/<system>/; no small cell: the constants
come from the exact law). The fit's law.h5 gives the nine
constants from the exact law (/law/ply, bonded) and the sweep's expansion (/law/expansion). A
random RVE is transversely isotropic only on average: E2 is the mean of its E2 and E3, G12 of
G12 and G13, nu12 of nu12 and nu13, alpha2 of alpha2 and alpha3; column `spread` is the largest
relative difference within those pairs, what this one sample leaves of the anisotropy. The rule
of mixtures E1 = v_f E_L + (1 - v_f) E_m is printed beside E1 (Hill's E1 lies a little above it).

A system whose law.h5 is newer than an unchanged scene is not run again (an interrupted run
resumes). Writes OUT_DIR/table.md and table.csv (one row per system and constant), and the
picture OUT_DIR/lamina.png and .svg (plot.py lamina: this RVE against the laboratory, per constant).
alpha1, near zero for a carbon ply, is compared in 1/K, not relatively, and is not in the picture.
"""
import csv
import math
import os
import sys
import tomllib

import h5py

import common

# The constants compared, in the table's order: (column of DATA.csv, how the RVE gives it).
# ply: /law/ply/constants' columns E1 E2 E3 nu12 nu13 nu23 G12 G13 G23 (axis 1 the fibres).
CONSTANTS = [("E1", ("ply", 0, 0)), ("E2", ("ply", 1, 2)), ("G12", ("ply", 6, 7)), ("nu12", ("ply", 3, 4)),
             ("nu23", ("ply", 5, 5)), ("alpha1", ("alpha", "alpha1", "alpha1")),
             ("alpha2", ("alpha", "alpha2", "alpha3"))]
COLUMNS = ["system", "v_f", "constant", "measured", "rve", "difference_percent", "difference", "spread_percent",
           "compared"]
# A constant near zero (a carbon ply's alpha1: about -1e-6 against alpha2's 3e-5) has no useful
# relative difference: the table gives it in its own units, and the picture leaves it out.
ABSOLUTE = {"alpha1"}

SCENE = """# {system} at v_f {v_f}: a random RVE of the constituents of {material}, bonded, the whole ply
# (written by pipelines/tools/lamina_table.py).
material = "{material_path}"

[geometry]
size = [{size}, {size}]
kind = "random"
volume_fraction = {v_f}
radius = [1.0, 0.0]
seed = {seed}
degree = {degree}

[interface]
normal_strength = 1e6
tangential_strength = 1e6

[load]
boundary = "periodic"
macro = "full"

[sweep]
directions_deg = [0]
magnitudes = [0.01]
"""


def slug(system):
    return "".join(c if c.isalnum() or c in "-_" else "-" for c in system.lower())


def predicted(law):
    """The RVE's constants by name: (value, spread) from law.h5 (bonded state, first row); exits
    naming the file where the fit wrote no constants or no expansion (ok 0: its note says why)."""
    with h5py.File(law, "r") as f:
        if "law/ply/constants" not in f or "law/expansion" not in f:
            sys.exit(f"lamina_table.py: {law}: no /law/ply or /law/expansion (a fit without the exact law's ply "
                     "constants, or phases without alpha)")
        expansion = f["law/expansion"].attrs
        if int(expansion.get("ok", 0)) != 1:
            sys.exit(f"lamina_table.py: {law}: the bonded expansion failed: {common.text(expansion.get('note', ''))}")
        ply = f["law/ply/constants"][0]
        if int(f["law/ply/broken"][0]) != 0:
            sys.exit(f"lamina_table.py: {law}: the first row of /law/ply is not the bonded state")
        alpha = {k: float(v) for k, v in expansion.items() if k.startswith("alpha")}
    out = {}
    for name, (source, a, b) in CONSTANTS:
        x, y = (float(ply[a]), float(ply[b])) if source == "ply" else (alpha[a], alpha[b])
        mean = 0.5 * (x + y)
        out[name] = (mean, abs(x - y) / abs(mean) if mean else 0.0)
    return out


def rule_of_mixtures(material, v_f):
    with open(material, "rb") as f:
        m = tomllib.load(f)
    E_L = m["fibre"].get("E_L", m["fibre"]["E"])
    return v_f * E_L + (1 - v_f) * m["matrix"]["E"]


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("bin_dir")
    parser.add_argument("data")
    parser.add_argument("materials")
    parser.add_argument("out_dir")
    parser.add_argument("--size", type=float, default=8.0, help="the RVE's side in fibre radii (default 8)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--degree", type=int, default=2, choices=[1, 2])
    args = parser.parse_args(argv[1:])
    with open(args.data, newline="") as f:
        systems = list(csv.DictReader(f))
    os.makedirs(args.out_dir, exist_ok=True)
    rows, md = [], []
    for n, s in enumerate(systems, 1):
        folder = os.path.join(args.out_dir, slug(s["system"]))
        os.makedirs(folder, exist_ok=True)
        material = os.path.abspath(os.path.join(args.materials, s["material"]))
        scene_file, law = os.path.join(folder, "scene.toml"), os.path.join(folder, "law.h5")
        scene = SCENE.format(system=s["system"], v_f=s["v_f"], material=s["material"], material_path=material,
                             size=f"{args.size:g}", seed=args.seed, degree=args.degree)
        done = (os.path.exists(law) and os.path.exists(scene_file) and open(scene_file).read() == scene
                and os.path.getmtime(law) >= os.path.getmtime(scene_file))
        print(f"lamina_table.py: [{n}/{len(systems)}] {s['system']}: "
              + ("law.h5 kept" if done else "mesh, sweep, fit"), file=sys.stderr)
        if not done:
            common.write_atomic(scene_file, scene)
            common.law_chain(args.bin_dir, scene_file, folder, ["--no-small-cell"])
        rve = predicted(law)
        v_f = float(s["v_f"])
        for name, _ in CONSTANTS:
            value, spread = rve[name]
            measured = float(s[name]) if s.get(name, "").strip() else math.nan
            # nu23 is the same 0.4 for every system of the source: an estimate, not a measurement.
            compared = name != "nu23" and not math.isnan(measured)
            diff = 100 * (value / measured - 1) if not math.isnan(measured) else math.nan
            rows.append({"system": s["system"], "v_f": v_f, "constant": name, "measured": f"{measured:.4g}",
                         "rve": f"{value:.5g}", "difference_percent": f"{diff:+.1f}",
                         "difference": f"{value - measured:+.3g}", "spread_percent": f"{100 * spread:.1f}",
                         "compared": "yes" if compared else "no"})
        rows[-len(CONSTANTS)]["rule_of_mixtures"] = f"{rule_of_mixtures(material, v_f):.5g}"
    unit = {"E1": "GPa", "E2": "GPa", "G12": "GPa", "nu12": "", "nu23": "", "alpha1": "1/K", "alpha2": "1/K"}
    md = ["# The bonded RVE from published constituents against the measured lamina\n\n",
          "Made by `make -C pipelines lamina` (pipelines/tools/lamina_table.py, "
          f"{os.path.basename(args.data)}): per system a random RVE (side {args.size:g} fibre radii, seed "
          f"{args.seed}, degree {args.degree}) at the lamina's v_f, bonded, mesh -> sweep -> fit; the constants "
          "from law.h5. `spread`: the RVE's own anisotropy (E2 against E3, ...). ν23 is not compared (the "
          "source gives 0.4 for every system); α1, near zero for carbon, differs in 1/K.\n\n",
          "| system | v_f | constant | measured | this RVE | difference | spread | rule of mixtures |\n",
          "|---|---:|---|---:|---:|---:|---:|---:|\n"]
    for r in rows:
        name = r["constant"] + (f" ({unit[r['constant']]})" if unit[r["constant"]] else "")
        diff = r["difference"] + " /K" if r["constant"] in ABSOLUTE else f"{r['difference_percent']} %"
        diff = diff if r["compared"] == "yes" else f"({diff})"
        md.append(f"| {r['system']} | {r['v_f']:.2f} | {name} | {r['measured']} | {r['rve']} | {diff} "
                  f"| {r['spread_percent']} % | {r.get('rule_of_mixtures', '')} |\n")
    by_constant = {}
    for r in rows:
        if r["compared"] == "yes":
            key = "difference" if r["constant"] in ABSOLUTE else "difference_percent"
            by_constant.setdefault(r["constant"], []).append(abs(float(r[key])))
    md.append("\nLargest |difference| per constant: "
              + ", ".join(f"{k} {max(v):.3g} /K" if k in ABSOLUTE else f"{k} {max(v):.1f} %"
                          for k, v in by_constant.items()) + ".\n")
    table = os.path.join(args.out_dir, "table.md")
    common.write_table(table, "".join(md), COLUMNS + ["rule_of_mixtures"], rows)
    here = os.path.dirname(os.path.abspath(__file__))
    common.run([sys.executable, os.path.join(here, "plot.py"), "lamina", os.path.join(args.out_dir, "table.csv"),
                os.path.join(args.out_dir, "lamina")])
    print("".join(md), end="")


if __name__ == "__main__":
    common.main_guard(main)
