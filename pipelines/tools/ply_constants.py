#!/usr/bin/python3
"""The nine engineering constants of a bonded ply from its cell (docs/method.md §3a, §3b).

usage:
  ply_constants.py BIN OUT.md SCENE_MESH...     SCENE_MESH: scene.toml:mesh.h5 (a periodic cell
                                                 with adhesion, whose bonds hold at the loads used)

The fibres run along z, the ply's axis 1; x and y are its axes 2 and 3 (the export's solid
cards, law/solid.hpp, put the fibres on their axis 3 instead). Per cell, with the bonds intact
(loads of 1e-8: linear, nothing breaks), dualcell-solve gives seven solves: the unit in-plane
stresses at ε33 = 0 (with the longitudinal shear moduli G of ⟨τxz, τyz⟩ = G (γxz, γyz)), ε33
alone, and both together (σzz is written only with ε33): the in-plane response
ε = S_ps σ̄ + a ε33 and σ33 = b·σ̄ + c ε33 make the compliance in (σxx, σyy, σxy, σ33),

    S = [ S_ps − a bᵀ/c   a/c ]
        [ −bᵀ/c           1/c ],

which reciprocity makes symmetric (a = −b: its asymmetry is printed as a check), and

    E1 = 1/S33, ν12 = −S03/S33, ν13 = −S13/S33, E2 = 1/S00, E3 = 1/S11, ν23 = −S10/S00,
    G23 = 1/S22, G12 = 1/(G⁻¹)00, G13 = 1/(G⁻¹)11 (compliances, as the others).

An orthotropic ply has no coupling of shear to the normal components nor of the two longitudinal
shears; a cell without its symmetries has some, and column `coupling` gives the largest of
|S_i2|/√(S_ii S22) (i = 0, 1, 3) and |G01|/√(G00 G11): the constants leave it out.

Writes OUT.md (one row per cell) and OUT.csv beside it, atomically.
"""
import csv
import io
import math
import os

import h5py

import common

COLUMNS = ["cell", "E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23", "reciprocity", "coupling"]


def solve(bin_dir, scene, mesh, out, stress, eps33=None, shear=False):
    command = [os.path.join(bin_dir, "dualcell-solve"), "--quiet", "--config", scene, "--mesh", mesh,
               "--stress", ",".join(f"{v:.17g}" for v in stress), "--out", out]
    if eps33 is not None:
        command += ["--eps33", f"{eps33:.17g}"]
    if shear:
        command.append("--longitudinal-shear")
    common.run_stage(command, out)
    with h5py.File(out, "r") as f:
        strain = f["/macro/strain"][:]
        bonded = f["/interface/bonded"][:]
        if len(bonded) == 0 or bonded.max() == 0:
            raise ValueError(f"{scene}: no adhesion: the bonded constants need bonds (a contact cell's differ "
                             "in tension and compression)")
        if bonded.min() == 0:
            raise ValueError(f"{scene}: a bond broke at the load {stress} (the constants are the bonded cell's)")
        zz = float(f["/macro/average_stress_zz"][0]) if "/macro/average_stress_zz" in f else None
        G = f["/macro/longitudinal_shear_moduli"][:] if shear else None
    # engineering shear γxy = 2 εxy
    return [strain[0], strain[1], 2 * strain[2]], zz, G


def constants(bin_dir, scene, mesh, folder):
    s = e = 1e-8  # loads far below any interface strength of the pipelines' scenes (1e-2): bonded, linear
    columns, b = [], []
    for k in range(3):
        unit = [0.0, 0.0, 0.0]
        unit[k] = s
        strain, _, G = solve(bin_dir, scene, mesh, os.path.join(folder, f"unit-{k}.h5"), unit, shear=(k == 0))
        if k == 0:
            G_long = G
        columns.append([v / s for v in strain])
    strain, zz, _ = solve(bin_dir, scene, mesh, os.path.join(folder, "eps33.h5"), [0.0, 0.0, 0.0], eps33=e)
    a = [v / e for v in strain]
    c = zz / e
    # b from the solves at ε33 = e with σ̄ = unit: σ33 = b·σ̄ + c ε33.
    for k in range(3):
        unit = [0.0, 0.0, 0.0]
        unit[k] = s
        _, zz_k, _ = solve(bin_dir, scene, mesh, os.path.join(folder, f"mixed-{k}.h5"), unit, eps33=e)
        b.append((zz_k - c * e) / s)
    S = [[columns[j][i] - a[i] * b[j] / c for j in range(3)] + [a[i] / c] for i in range(3)]
    S.append([-b[j] / c for j in range(3)] + [1 / c])
    reciprocity = max(abs(S[i][3] - S[3][i]) for i in range(3)) / max(abs(S[3][3]), 1e-300)
    det = G_long[0][0] * G_long[1][1] - G_long[0][1] * G_long[1][0]
    coupling = max([abs(S[i][2]) / math.sqrt(S[i][i] * S[2][2]) for i in (0, 1, 3)] +
                   [abs(G_long[0][1]) / math.sqrt(G_long[0][0] * G_long[1][1])])
    return {"E1": 1 / S[3][3], "E2": 1 / S[0][0], "E3": 1 / S[1][1], "nu12": -S[0][3] / S[3][3],
            "nu13": -S[1][3] / S[3][3], "nu23": -S[1][0] / S[0][0], "G12": det / G_long[1][1],
            "G13": det / G_long[0][0], "G23": 1 / S[2][2], "reciprocity": reciprocity, "coupling": coupling}


def markdown(rows):
    lines = ["| cell | E1 | E2 | E3 | ν12 | ν13 | ν23 | G12 | G13 | G23 | reciprocity | coupling |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['cell']} | " + " | ".join(f"{r[k]:.5g}" for k in COLUMNS[1:-2]) +
                     f" | {r['reciprocity']:.1e} | {r['coupling']:.1e} |")
    return "\n".join(lines) + "\n"


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin")
    parser.add_argument("out")
    parser.add_argument("cells", nargs="+", help="scene.toml:mesh.h5")
    args = parser.parse_args(argv[1:])
    rows = []
    for cell in args.cells:
        scene, mesh = cell.split(":", 1)
        folder = os.path.join(os.path.dirname(os.path.abspath(args.out)), "solves",
                              os.path.basename(os.path.dirname(os.path.abspath(mesh))))
        os.makedirs(folder, exist_ok=True)
        r = constants(args.bin, scene, mesh, folder)
        r["cell"] = os.path.basename(os.path.dirname(os.path.abspath(mesh)))
        rows.append(r)
    common.write_atomic(args.out, markdown(rows))
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    common.write_atomic(os.path.splitext(args.out)[0] + ".csv", text.getvalue())
    print(markdown(rows), end="")


if __name__ == "__main__":
    common.main_guard(main)
