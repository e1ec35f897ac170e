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

With --ccx PATH each cell's constants are also written as a CalculiX card (OUT folder,
<cell>.inp: *ELASTIC, TYPE=ENGINEERING CONSTANTS, the fibres along the material's axis 1) and
checked by CalculiX itself: one C3D8 cube under uniaxial stress along each axis in turn (uniform
stress, so the element is exact) gives back E1, E2, E3 and the ν's; column `ccx` is their largest
relative difference (the .dat file's 7 digits limit it to about 1e-7). And the cell itself goes to
CalculiX as an independent code (tools/ccx_ply.py: the mesh extruded to a periodic 3D slab of
C3D15 wedges, the stiffness from the strain energies of 21 unit strain cases): column `ccx 3D`
is the largest relative difference of its nine constants from these.

Writes OUT.md (one row per cell) and OUT.csv beside it, atomically.
"""
import math
import os

import h5py

import ccx_ply
import common

COLUMNS = ["cell", "E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23", "reciprocity", "coupling", "ccx", "ccx_3d"]


def solve(bin_dir, scene, mesh, out, stress, eps33=None, shear=False, bonds=None):
    """One dualcell-solve of the cell at the macro stress `stress` (tensor shear), with a
    longitudinal strain `eps33`, the longitudinal shear moduli with `shear`, from the bond state of
    the solution file `bonds` (default intact). Returns the macro strain (engineering shear), the
    average σzz (None at ε33 = 0: not written), the 2 × 2 longitudinal shear moduli (None without
    `shear`) and the bond state per pair after the load."""
    command = [os.path.join(bin_dir, "dualcell-solve"), "--quiet", "--config", scene, "--mesh", mesh,
               "--stress", ",".join(f"{v:.17g}" for v in stress), "--out", out]
    if eps33 is not None:
        command += ["--eps33", f"{eps33:.17g}"]
    if shear:
        command.append("--longitudinal-shear")
    if bonds is not None:
        command += ["--bonds", bonds]
    common.run_stage(command, out)
    with h5py.File(out, "r") as f:
        strain = f["/macro/strain"][:]
        bonded = f["/interface/bonded"][:]
        zz = float(f["/macro/average_stress_zz"][0]) if "/macro/average_stress_zz" in f else None
        G = f["/macro/longitudinal_shear_moduli"][:] if shear else None
    # engineering shear γxy = 2 εxy
    return [strain[0], strain[1], 2 * strain[2]], zz, G, bonded


def bonded_solve(bin_dir, scene, mesh, out, stress, eps33=None, shear=False):
    """solve() of the intact cell, refused when it has no bonds or one broke."""
    strain, zz, G, bonded = solve(bin_dir, scene, mesh, out, stress, eps33, shear)
    if len(bonded) == 0 or bonded.max() == 0:
        raise ValueError(f"{scene}: no adhesion: the bonded constants need bonds (a contact cell's differ "
                         "in tension and compression: tools/ply_states.py)")
    if bonded.min() == 0:
        raise ValueError(f"{scene}: a bond broke at the load {stress} (the constants are the bonded cell's)")
    return strain, zz, G


def constants(bin_dir, scene, mesh, folder):
    s = e = 1e-8  # loads far below any interface strength of the pipelines' scenes (1e-2): bonded, linear
    columns, b = [], []
    for k in range(3):
        unit = [0.0, 0.0, 0.0]
        unit[k] = s
        strain, _, G = bonded_solve(bin_dir, scene, mesh, os.path.join(folder, f"unit-{k}.h5"), unit, shear=(k == 0))
        if k == 0:
            G_long = G
        columns.append([v / s for v in strain])
    strain, zz, _ = bonded_solve(bin_dir, scene, mesh, os.path.join(folder, "eps33.h5"), [0.0, 0.0, 0.0], eps33=e)
    a = [v / e for v in strain]
    c = zz / e
    # b from the solves at ε33 = e with σ̄ = unit: σ33 = b·σ̄ + c ε33.
    for k in range(3):
        unit = [0.0, 0.0, 0.0]
        unit[k] = s
        _, zz_k, _ = bonded_solve(bin_dir, scene, mesh, os.path.join(folder, f"mixed-{k}.h5"), unit, eps33=e)
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


def card(name, c):
    """The CalculiX material of the constants `c`, fibres along axis 1 (shear moduli G12, G13, G23)."""
    return (f"*MATERIAL, NAME={name}\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n"
            + ", ".join(f"{c[k]:.12g}" for k in ("E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13")) +
            f"\n{c['G23']:.12g}, 0.\n")


def ccx_check(ccx, folder, name, c):
    """The largest relative difference between the constants and what CalculiX gives back from the
    card: a unit C3D8 cube, symmetric supports on the faces x = 0, y = 0, z = 0, a unit force on the
    opposite face along each axis in turn (three steps), strains from the far corner's
    displacement."""
    nodes = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    order = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    number = {p: nodes.index(p) + 1 for p in nodes}
    deck = ["*NODE"] + [f"{number[p]}, {p[0]}, {p[1]}, {p[2]}" for p in nodes]
    deck += ["*ELEMENT, TYPE=C3D8, ELSET=CUBE", "1, " + ", ".join(str(number[p]) for p in order)]
    deck += [card(name, c).rstrip("\n"), f"*SOLID SECTION, ELSET=CUBE, MATERIAL={name}"]
    deck += ["*BOUNDARY"] + [f"{number[p]}, {axis + 1}, {axis + 1}" for p in nodes for axis in range(3)
                             if p[axis] == 0]
    for axis in range(3):
        deck += ["*STEP", "*STATIC", "*CLOAD, OP=NEW"]  # each step its own load, not added to the last
        deck += [f"{number[p]}, {axis + 1}, 0.25" for p in nodes if p[axis] == 1]
        deck += ["*NODE PRINT, NSET=NALL", "U", "*END STEP"]
    deck.insert(deck.index("*ELEMENT, TYPE=C3D8, ELSET=CUBE"), "*NSET, NSET=NALL, GENERATE\n1, 8, 1")
    job = os.path.join(folder, "cube")
    with open(job + ".inp", "w") as f:
        f.write("\n".join(deck) + "\n")
    common.run_ccx(ccx, folder, "cube")
    # The far corner (1, 1, 1) of each step: its displacement is the strain (unit lengths).
    corner, strains, reading = str(number[(1, 1, 1)]), [], False
    with open(job + ".dat") as f:
        for line in f:
            if line.strip().startswith("displacements"):
                reading = True
                continue
            words = line.split()
            if reading and words and words[0] == corner:
                strains.append([float(v) for v in words[1:4]])
                reading = False
    if len(strains) != 3:
        raise RuntimeError(f"ccx printed {len(strains)} displacements of the corner, not 3")
    got = {"E1": 1 / strains[0][0], "E2": 1 / strains[1][1], "E3": 1 / strains[2][2],
           "nu12": -strains[0][1] / strains[0][0], "nu13": -strains[0][2] / strains[0][0],
           "nu23": -strains[1][2] / strains[1][1]}
    return max(abs(got[k] / c[k] - 1) for k in got)


def markdown(rows):
    ccx = all("ccx" in r for r in rows)
    lines = ["| cell | E1 | E2 | E3 | ν12 | ν13 | ν23 | G12 | G13 | G23 | reciprocity | coupling |" +
             (" CalculiX from the card | CalculiX's 3D cell |" if ccx else ""),
             "|---|---|---|---|---|---|---|---|---|---|---|---|" + ("---|---|" if ccx else "")]
    for r in rows:
        lines.append(f"| {r['cell']} | " + " | ".join(f"{r[k]:.5g}" for k in COLUMNS[1:-4]) +
                     f" | {r['reciprocity']:.1e} | {r['coupling']:.1e} |" +
                     (f" {r['ccx']:.1e} | {r['ccx_3d']:.1e} |" if ccx else ""))
    return "\n".join(lines) + "\n"


def scene_meshes(cells):
    """The command line's cells, scene.toml:mesh.h5 each, as (scene, mesh) pairs."""
    for cell in cells:
        if ":" not in cell:
            raise ValueError(f"{cell}: expected scene.toml:mesh.h5 (the cell's scene and its mesh, a colon between)")
        yield tuple(cell.split(":", 1))


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin")
    parser.add_argument("out")
    parser.add_argument("cells", nargs="+", help="scene.toml:mesh.h5")
    parser.add_argument("--ccx", help="CalculiX: write each cell's card and check it on a cube")
    args = parser.parse_args(argv[1:])
    rows = []
    for scene, mesh in scene_meshes(args.cells):
        folder = os.path.join(os.path.dirname(os.path.abspath(args.out)), "solves",
                              os.path.basename(os.path.dirname(os.path.abspath(mesh))))
        os.makedirs(folder, exist_ok=True)
        r = constants(args.bin, scene, mesh, folder)
        r["cell"] = os.path.basename(os.path.dirname(os.path.abspath(mesh)))
        if args.ccx:
            name = r["cell"].upper().replace("-", "_")
            common.write_atomic(os.path.join(os.path.dirname(os.path.abspath(args.out)), r["cell"] + ".inp"),
                                card(name, r))
            r["ccx"] = ccx_check(args.ccx, folder, name, r)
            independent = ccx_ply.constants(mesh, args.ccx)
            r["ccx_3d"] = max(abs(independent[k] / r[k] - 1) for k in COLUMNS[1:10])
        rows.append(r)
    common.write_table(args.out, markdown(rows), COLUMNS, rows)
    print(markdown(rows), end="")


if __name__ == "__main__":
    common.main_guard(main)
