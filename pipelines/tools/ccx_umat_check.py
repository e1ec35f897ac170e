#!/usr/bin/python3
"""The cell's law in CalculiX, for real: ccx built with dualcell's umat
(tools/build_ccx_umat.sh) and the card of `dualcell-export --format umat`, the cone-wise law
(layout 1) or the exact law (layout 2, its cell file beside the card).

usage:
  ccx_umat_check.py element CCX CARD.inp OUT.md [--law LAW.h5 --bin BIN_DIR]
      One plane-strain element (two CPE3 on the unit square, every node displaced by u = ε·x,
      a uniform strain) per strain state: tension and compression along x and y, pure shear
      of both signs, and random states; the stresses ccx prints against the law: the cone-wise
      law of the card's constants (σ = C_c ε + Σ β_k ⟨q_k·ε⟩₊ q_k, bonded: the strains stay
      below the onset), or for the exact law what `BIN_DIR/dualcell-law --law LAW.h5` gives.
  ccx_umat_check.py cube CCX CARD.inp OUT.md --law LAW.h5 --bin BIN_DIR [--form cell|small]
      The whole ply's exact law (layout 3): one C3D8 brick, the unit cube, every node displaced
      by u = ε·x (a uniform 3D strain, material axes x, y in the plane of the cells, z along the
      fibres) per state: the six unit load cases (each strain component alone, both signs),
      random states, and states past the bonds' strength (the shear along the fibres and the
      transverse tension that break them); ccx's six stresses against `dualcell-law --full`.
  ccx_umat_check.py beam CCX CARD.inp STRUCTURE.h5 SCENE.toml OUT.md
      The structure of STRUCTURE.h5 (dualcell-structure's mesh, p2 → CPE6, same node order) with
      the edges of SCENE.toml — a roller left edge, one point held in y, a traction linear
      along the right edge (consistent nodal forces) — solved by ccx, against dualcell-structure's
      displacements of the same nodes: the end rotation and the largest nodal difference.

ccx runs in a temporary folder beside OUT.md with one thread (DUALCELL_CELL_DIR: the card's
folder). Writes OUT.md (a table) and fails (exit 1) when a check misses its bound: 1e-6 relative
for the element and the cube (ccx prints 7 significant digits), 1e-5 for the beam's end rotation.
"""
import csv
import math
import os
import random
import re
import shutil
import sys
import tempfile
import tomllib

import numpy as np

import common


def card_constants(card):
    """The *USER MATERIAL constants and the material name of the card."""
    text = open(card).read()
    name = re.search(r"\*MATERIAL,\s*NAME=(\S+)", text).group(1)
    block = text.split("*USER MATERIAL", 1)[1].split("\n", 1)[1].split("*", 1)[0]
    values = [float(v) for v in block.replace("\n", ",").split(",") if v.strip()]
    return name, values, text


def bonded_law(k):
    """C_c, planes c (rows) and β of the bonded law in the constants (src/umat/dualcell_umat.c)."""
    Kb = int(k[1])
    C = np.array(k[7:16]).reshape(3, 3)
    planes = np.array(k[16:16 + 4 * Kb]).reshape(Kb, 4)
    return C, planes[:, :3], planes[:, 3]


def law_stress(law, e):
    C, c, beta = law
    return C @ e + c.T @ (beta * np.maximum(c @ e, 0.0))


def run_ccx(ccx, work, deck, card):
    """Runs ccx on the deck (numbers in it at most 20 characters: ccx reads fields of 20);
    returns the text of its .dat file and ccx's wall seconds."""
    with open(os.path.join(work, "job.inp"), "w") as f:
        f.write(deck)
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1", CCX_NPROC_RESULTS="1",
               CCX_NPROC_STIFFNESS="1", DUALCELL_CELL_DIR=os.path.dirname(os.path.abspath(card)))
    run = common.run([os.path.abspath(ccx), "job"], env, check=False, cwd=work)
    if run.returncode != 0 or "ERROR" in run.stdout:
        sys.exit(f"ccx_umat_check.py: ccx failed in {work}:\n{run.stdout[-2000:]}{run.stderr[-1000:]}")
    return open(os.path.join(work, "job.dat")).read(), run.seconds


def dat_blocks(dat, what):
    """Rows of the .dat blocks whose header mentions `what`, as lists of numbers."""
    rows, inside = [], False
    for line in dat.splitlines():
        if line.strip().startswith(what):
            inside = True
            continue
        if inside:
            parts = line.split()
            if not parts:
                continue
            try:
                rows.append([float(p) for p in parts])
            except ValueError:
                inside = False
    return rows


def material_cards(card_text):
    """The card's *MATERIAL ... up to its end (without comment lines)."""
    lines = [l for l in card_text.splitlines() if not l.startswith("**")]
    return "\n".join(lines) + "\n"


def exact_law_stresses(law_h5, bin_dir, strains, work):
    """σ of the exact law at each strain (each from the unloaded cell), by dualcell-law."""
    points, values = os.path.join(work, "points.csv"), os.path.join(work, "values.csv")
    with open(points, "w") as f:
        f.write("exx,eyy,gxy\n" + "".join(f"{e[0]:.17g},{e[1]:.17g},{e[2]:.17g}\n" for e in strains))
    common.run([os.path.join(bin_dir, "dualcell-law"), "--quiet", "--law", law_h5, "--strain", points, "--out", values,
                "--form", "cell"])
    with open(values) as f:
        return [np.array([float(r["sxx"]), float(r["syy"]), float(r["sxy"])]) for r in csv.DictReader(f)]


def element(ccx, card, out, law=None, bin=None):
    name, k, text = card_constants(card)
    exact = k[0] == 2
    if exact and not (law and bin):
        sys.exit("ccx_umat_check.py: element: the card has the exact law: give --law LAW.h5 and --bin BIN_DIR")
    cone = None if exact else bonded_law(k)
    rng = random.Random(11)
    scale = 1e-4  # small enough to stay inside the onset surface of a bonded law
    states = {"tension x": (1, 0, 0), "compression x": (-1, 0, 0), "tension y": (0, 1, 0),
              "compression y": (0, -1, 0), "shear +": (0, 0, 1), "shear -": (0, 0, -1)}
    for i in range(6):
        states[f"random {i + 1}"] = tuple(rng.uniform(-1, 1) for _ in range(3))
    work = tempfile.mkdtemp(prefix="ccx-umat-", dir=os.path.dirname(os.path.abspath(out)))
    rows, worst = [], 0.0
    try:
        strains = [scale * np.array(d) for d in states.values()]
        wanted = exact_law_stresses(law, bin, strains, work) if exact else [law_stress(cone, e) for e in strains]
        for (label, direction), want in zip(states.items(), wanted):
            e = scale * np.array(direction)  # (εxx, εyy, γxy)
            H = np.array([[e[0], e[2] / 2], [e[2] / 2, e[1]]])
            nodes = {1: (0, 0), 2: (1, 0), 3: (1, 1), 4: (0, 1)}
            deck = "*NODE\n" + "".join(f"{n}, {x}, {y}, 0\n" for n, (x, y) in nodes.items())
            deck += "*ELEMENT, TYPE=CPE3, ELSET=E\n1, 1, 2, 3\n2, 1, 3, 4\n"
            deck += material_cards(text[text.index("*MATERIAL"):])
            deck += f"*SOLID SECTION, ELSET=E, MATERIAL={name}\n1.\n*BOUNDARY\n"
            for n, x in nodes.items():
                u = H @ np.array(x, dtype=float)
                deck += f"{n}, 1, 1, {u[0]:.13e}\n{n}, 2, 2, {u[1]:.13e}\n"
            deck += "*STEP\n*STATIC\n1., 1.\n*EL PRINT, ELSET=E\nS\n*END STEP\n"
            stresses = dat_blocks(run_ccx(ccx, work, deck, card)[0], "stresses")
            # Rows: element, integration point, sxx, syy, szz, sxy, sxz, syz.
            got = np.array([[r[2], r[3], r[5]] for r in stresses]).mean(axis=0)
            error = np.linalg.norm(got - want) / np.linalg.norm(want)
            worst = max(worst, error)
            rows.append(f"| {label} | {e[0]:.3e}, {e[1]:.3e}, {e[2]:.3e} | {got[0]:.6e}, {got[1]:.6e}, {got[2]:.6e} | "
                        f"{want[0]:.6e}, {want[1]:.6e}, {want[2]:.6e} | {error:.1e} |")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    md = ["# One element in CalculiX with dualcell's umat", "",
          f"Material {name} from {os.path.basename(card)}; two CPE3 on the unit square under the uniform",
          "strain ε (engineering shear); ccx's stresses (7 significant digits) against " +
          ("the exact law by dualcell-law." if exact else "the law of the card."), "",
          "| state | ε (xx, yy, γxy) | ccx σ (xx, yy, xy) | law σ | relative difference |", "|---|---|---|---|---|"]
    md += rows + ["", f"Largest relative difference: {worst:.1e} (bound 1e-6: the printed digits)."]
    common.write_atomic(out, "\n".join(md) + "\n")
    print("\n".join(md))
    if worst > 1e-6:
        sys.exit(f"ccx_umat_check.py: element: largest difference {worst:.1e} > 1e-6")


def ply_law_stresses(law_h5, bin_dir, strains, work, form="cell"):
    """The six stresses (σ11, σ22, σ33, σ12, σ13, σ23) of the whole ply's law (the exact law, or
    with form "small" its small cell) at each 3D strain (ε11, ε22, ε33, γ12, γ13, γ23), each from
    the unloaded cell, by dualcell-law --full (whose order is xx, yy, xy, zz, xz, yz), and the
    broken pairs."""
    points, values = os.path.join(work, "points.csv"), os.path.join(work, "values.csv")
    order = [0, 1, 3, 2, 4, 5]  # the law's component of each of Abaqus's
    with open(points, "w") as f:
        f.write("exx,eyy,gxy,e33,gxz,gyz\n")
        for e in strains:
            f.write(",".join(f"{e[order.index(k)]:.17g}" for k in range(6)) + "\n")
    common.run([os.path.join(bin_dir, "dualcell-law"), "--quiet", "--law", law_h5, "--strain", points, "--out", values,
                "--form", form, "--full"])
    with open(values) as f:
        rows = list(csv.DictReader(f))
    names = ["sxx", "syy", "szz", "sxy", "sxz", "syz"]
    return [np.array([float(r[n]) for n in names]) for r in rows], [int(r["broken_pairs"]) for r in rows]


def cube(ccx, card, out, law=None, bin=None, form="cell"):
    name, k, text = card_constants(card)
    if k[0] != 3 or not (law and bin):
        sys.exit("ccx_umat_check.py: cube: the card must be the whole ply's law (layout 3), with --law and --bin")
    labels = ["ε11", "ε22", "ε33", "γ12", "γ13", "γ23"]
    scale = 1e-4  # far below the bonds' strength: the unit load cases see the bonded cell
    states = {}
    for i, label in enumerate(labels):
        for sign in (1, -1):
            states[f"{label} {'+' if sign > 0 else '−'}"] = scale * sign * np.eye(6)[i]
    rng = random.Random(13)
    for i in range(4):
        states[f"random {i + 1}"] = scale * np.array([rng.uniform(-1, 1) for _ in range(6)])
    # Past the strength: sheared along the fibres (bonds break along z) and stretched across them.
    states["γ13 past the bonds"] = np.array([0, 0, 0, 0, 2e-2, 0])
    states["ε11 past the bonds"] = np.array([2e-2, 0, 0, 0, 0, 0])
    work = tempfile.mkdtemp(prefix="ccx-cube-", dir=os.path.dirname(os.path.abspath(out)))
    rows, worst = [], 0.0
    try:
        wanted, broken = ply_law_stresses(law, bin, list(states.values()), work, form)
        nodes = {1: (0, 0, 0), 2: (1, 0, 0), 3: (1, 1, 0), 4: (0, 1, 0),
                 5: (0, 0, 1), 6: (1, 0, 1), 7: (1, 1, 1), 8: (0, 1, 1)}
        for (label, e), want, b in zip(states.items(), wanted, broken):
            H = np.array([[e[0], e[3] / 2, e[4] / 2], [e[3] / 2, e[1], e[5] / 2], [e[4] / 2, e[5] / 2, e[2]]])
            deck = "*NODE\n" + "".join(f"{n}, {x}, {y}, {z}\n" for n, (x, y, z) in nodes.items())
            deck += "*ELEMENT, TYPE=C3D8, ELSET=E\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
            deck += material_cards(text[text.index("*MATERIAL"):])
            deck += f"*SOLID SECTION, ELSET=E, MATERIAL={name}\n*BOUNDARY\n"
            for n, x in nodes.items():
                u = H @ np.array(x, dtype=float)
                deck += "".join(f"{n}, {d + 1}, {d + 1}, {u[d]:.13e}\n" for d in range(3))
            deck += "*STEP\n*STATIC\n1., 1.\n*EL PRINT, ELSET=E\nS\n*END STEP\n"
            stresses = dat_blocks(run_ccx(ccx, work, deck, card)[0], "stresses")
            # Rows: element, integration point, sxx, syy, szz, sxy, sxz, syz (the same at each point).
            got = np.array([r[2:8] for r in stresses]).mean(axis=0)
            error = np.linalg.norm(got - want) / np.linalg.norm(want)
            worst = max(worst, error)
            rows.append(f"| {label} | {b} | " + ", ".join(f"{v:.4e}" for v in got) + " | " +
                        ", ".join(f"{v:.4e}" for v in want) + f" | {error:.1e} |")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    what = "exact law" if form == "cell" else "small cell"
    md = [f"# One 3D element in CalculiX with the whole ply's {what}", "",
          f"Material {name} from {os.path.basename(card)} (layout 3: all six components from the cell); one C3D8,",
          "the unit cube, under the uniform strain ε (engineering shears; x, y the plane of the cells, z the fibres),",
          f"each state from the unloaded cell; ccx's stresses (7 significant digits) against dualcell-law --full --form {form}.",
          "",
          "| state | broken pairs | ccx σ (11, 22, 33, 12, 13, 23) | law σ | relative difference |",
          "|---|---|---|---|---|"]
    md += rows + ["", f"Largest relative difference: {worst:.1e} (bound 1e-6: the printed digits)."]
    common.write_atomic(out, "\n".join(md) + "\n")
    print("\n".join(md))
    if worst > 1e-6:
        sys.exit(f"ccx_umat_check.py: cube: largest difference {worst:.1e} > 1e-6")


def edge_forces(nodes, edge_nodes, t_start, t_end):
    """Consistent nodal forces of a traction linear from t_start to t_end along a straight p2
    edge list (corner, mid, corner, mid, ..., corner, ordered along the edge)."""
    f = {}
    first, last = nodes[edge_nodes[0]], nodes[edge_nodes[-1]]
    length = np.linalg.norm(last - first)
    gauss = [(0.5 - math.sqrt(15) / 10, 5 / 18), (0.5, 8 / 18), (0.5 + math.sqrt(15) / 10, 5 / 18)]
    for k in range(0, len(edge_nodes) - 2, 2):
        a, m, b = edge_nodes[k], edge_nodes[k + 1], edge_nodes[k + 2]
        xa, xb = nodes[a], nodes[b]
        h = np.linalg.norm(xb - xa)
        for s, w in gauss:
            phi = {a: (1 - s) * (1 - 2 * s), b: s * (2 * s - 1), m: 4 * s * (1 - s)}
            position = np.linalg.norm(xa + s * (xb - xa) - first) / length
            t = np.array(t_start) + position * (np.array(t_end) - np.array(t_start))
            for n, p in phi.items():
                f[n] = f.get(n, np.zeros(2)) + w * h * p * t
    return f


def end_rotation(nodes, right, disp, H):
    """The end section's rotation and neutral axis y_n/H: the line u_x = −θ y + b fitted through
    the right edge's nodes `right` (least squares), θ and −b/θ/H."""
    y = nodes[right, 1]
    A = np.column_stack([y, np.ones_like(y)])
    (s, b), *_ = np.linalg.lstsq(A, disp[right, 0], rcond=None)
    return -s, -b / s / H


def beam(ccx, card, structure_h5, scene_file, out):
    import h5py
    name, _, text = card_constants(card)
    with open(scene_file, "rb") as f:
        scene = tomllib.load(f)
    edges = scene.get("edges", {})
    if edges.get("left", {}).get("type") != "roller" or edges.get("right", {}).get("type") != "traction":
        sys.exit("ccx_umat_check.py: beam: the scene must have a roller left edge and a traction right edge")
    supports = scene.get("support", [])
    factor = scene.get("steps", {}).get("factors", [1.0])[-1]
    with h5py.File(structure_h5, "r") as f:
        nodes, tri = f["/mesh/nodes"][:], f["/mesh/triangles"][:]
        last = sorted(k for k in f["/steps"].keys() if k.isdigit())[-1]
        u_ref = f[f"/steps/{last}/displacement"][:]
    if tri.shape[1] != 6:
        sys.exit("ccx_umat_check.py: beam: the structure must be meshed with p2 triangles (CPE6)")
    L, H = nodes[:, 0].max(), nodes[:, 1].max()
    tol = 1e-9 * max(L, H)
    left = [i for i in range(len(nodes)) if abs(nodes[i, 0]) < tol]
    right = sorted((i for i in range(len(nodes)) if abs(nodes[i, 0] - L) < tol), key=lambda i: nodes[i, 1])
    right_edge = edges["right"]
    t0 = [factor * v for v in right_edge["traction"]]
    t1 = [factor * v for v in right_edge.get("traction_end", right_edge["traction"])]
    forces = edge_forces(nodes, right, t0, t1)
    deck = "*NODE\n" + "".join(f"{i + 1}, {x:.13e}, {y:.13e}, 0\n" for i, (x, y) in enumerate(nodes))
    deck += "*ELEMENT, TYPE=CPE6, ELSET=E\n" + "".join(
        f"{t + 1}, " + ", ".join(str(n + 1) for n in row) + "\n" for t, row in enumerate(tri))
    deck += material_cards(text[text.index("*MATERIAL"):])
    deck += f"*SOLID SECTION, ELSET=E, MATERIAL={name}\n1.\n*BOUNDARY\n"
    deck += "".join(f"{i + 1}, 1, 1, 0.\n" for i in left)
    for s in supports:
        at = np.array(s["at"], dtype=float)
        i = int(np.argmin(np.linalg.norm(nodes - at, axis=1)))
        for c, axis in (("x", 1), ("y", 2)):
            if c in s.get("fix", "xy"):
                deck += f"{i + 1}, {axis}, {axis}, 0.\n"
    # Newton with the umat's exact tangent; tight residual control so that ccx's answer is
    # converged well below the 0.5 % bound (ccx's default is 0.5 % of the average force).
    deck += "*STEP, INC=1000\n*STATIC\n0.1, 1., 1e-6, 0.1\n*CONTROLS, PARAMETERS=FIELD\n1e-10, 1e-10\n*CLOAD\n"
    for i, fv in sorted(forces.items()):
        deck += f"{i + 1}, 1, {fv[0]:.13e}\n{i + 1}, 2, {fv[1]:.13e}\n"
    deck += "*NODE PRINT, NSET=NALL\nU\n*END STEP\n"
    deck = deck.replace("*BOUNDARY\n", "*NSET, NSET=NALL, GENERATE\n1, " + str(len(nodes)) + ", 1\n*BOUNDARY\n", 1)
    work = tempfile.mkdtemp(prefix="ccx-beam-", dir=os.path.dirname(os.path.abspath(out)))
    try:
        dat, seconds = run_ccx(ccx, work, deck, card)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    rows = dat_blocks(dat, "displacements")
    # The last block printed is the end of the step: keep the last row per node.
    u = np.zeros((len(nodes), 2))
    for r in rows:
        u[int(r[0]) - 1] = r[1:3]

    rot_ccx, axis_ccx = end_rotation(nodes, right, u, H)
    rot_ref, axis_ref = end_rotation(nodes, right, u_ref, H)
    error = (rot_ccx - rot_ref) / rot_ref
    nodal = np.abs(u - u_ref).max() / np.abs(u_ref).max()
    md = ["# The bimodular beam in CalculiX with dualcell's umat", "",
          f"{os.path.basename(structure_h5)}'s mesh ({len(tri)} CPE6, {len(nodes)} nodes) and edges from "
          f"{os.path.basename(scene_file)}, material {name}.", "",
          "| | end rotation | neutral axis y_n/H |", "|---|---|---|",
          f"| dualcell-structure | {rot_ref:.7e} | {axis_ref:.5f} |",
          f"| CalculiX with the umat ({seconds:.2f} s) | {rot_ccx:.7e} | {axis_ccx:.5f} |", "",
          f"End rotation: relative difference {error:.2e} (bound 1e-5); largest nodal displacement difference "
          f"{nodal:.2e} of the largest displacement."]
    common.write_atomic(out, "\n".join(md) + "\n")
    print("\n".join(md))
    if abs(error) > 1e-5:
        sys.exit(f"ccx_umat_check.py: beam: end rotation differs by {error:.2e} > 1e-5")


def main(argv):
    parser = common.Parser(__doc__)
    checks = parser.add_subparsers(dest="check", metavar="CHECK", required=True)
    p = checks.add_parser("element")
    p.add_argument("ccx", metavar="CCX")
    p.add_argument("card", metavar="CARD.inp")
    p.add_argument("out", metavar="OUT.md")
    p.add_argument("--law", metavar="LAW.h5", help="the law.h5 of an exact-law card")
    p.add_argument("--bin", metavar="BIN_DIR", help="the folder of dualcell-law")
    p = checks.add_parser("cube")
    p.add_argument("ccx", metavar="CCX")
    p.add_argument("card", metavar="CARD.inp")
    p.add_argument("out", metavar="OUT.md")
    p.add_argument("--law", metavar="LAW.h5", help="the law.h5 of the card", required=True)
    p.add_argument("--bin", metavar="BIN_DIR", help="the folder of dualcell-law", required=True)
    p.add_argument("--form", choices=["cell", "small"], default="cell",
                   help="the card's form: the exact law (default) or its small cell (dualcell-export --form)")
    p = checks.add_parser("beam")
    p.add_argument("ccx", metavar="CCX")
    p.add_argument("card", metavar="CARD.inp")
    p.add_argument("structure_h5", metavar="STRUCTURE.h5")
    p.add_argument("scene_file", metavar="SCENE.toml")
    p.add_argument("out", metavar="OUT.md")
    args = vars(parser.parse_args(argv[1:]))
    {"element": element, "cube": cube, "beam": beam}[args.pop("check")](**args)


if __name__ == "__main__":
    common.main_guard(main)
