#!/usr/bin/python3
"""The ply's nine engineering constants per bond state, in tension and in compression
(docs/method.md §3c): what a 3D model of a ply with contact and debonding needs beside the bonded
constants of tools/ply_constants.py.

usage:
  ply_states.py BIN OUT.md SCENE_MESH... [--fuse SXX,SYY,SXY] [--law CELL=LAW.h5]... [--ccx PATH]
                                       SCENE_MESH: scene.toml:mesh.h5 (a periodic cell)

The fibres run along z, the ply's axis 1; x and y are its axes 2 and 3. The states of a cell:
  bonded       every bond intact (a cell with adhesion);
  after fuse   the bonds the fuse load (--fuse, default σxx = 0.04: four times the pipelines'
               interface strengths) left, its cascade run to the end by dualcell-solve;
  contact      a cell without adhesion (frictionless contact from the start).
Per state and sign, with the state held (loads of 1e-8: no bond breaks, and a contact cell is
positively homogeneous of degree one, so the size of the load does not matter, only its sign),
each constant is a secant from one uniaxial load:
  axis 1   σ̄ = 0, ε33 = ±1e-8: E1 = σ33/ε33, ν12 = −εxx/ε33, ν13 = −εyy/ε33;
  axis 2   σxx = ±1e-8, σ33 = 0: E2 = σxx/εxx, ν23 = −εyy/εxx;
  axis 3   σyy = ±1e-8, σ33 = 0: E3 = σyy/εyy;
  shear    σxy = ±1e-8, σ33 = 0: G23 = σxy/γxy;
and G12, G13 are the longitudinal shear moduli of the state (no sign: frictionless contact carries
no longitudinal shear, open or closed). σ33 = 0 is met by secant steps on ε33 (σ33 is monotone and
piecewise linear in ε33 at a fixed σ̄), to 1e-7 of the load: column `σ33 left` gives the largest
left. A solve that breaks a bond or changes the state is refused.

Checks:
  bonded       the same constants from superposition (ply_constants.constants: seven linear
               solves, another route); column `check` is their largest relative difference;
  every bond broken (or contact): shortened along the fibres, the rims open whole and the phases
               work apart, so ν12 in compression is the matrix's ν exactly (docs/method.md §3a);
               `check` is |ν12/ν_m − 1|.
With --ccx PATH the cards of the states other than bonded (whose card is ply_constants.py's
<cell>.inp) go to the OUT folder (<cell>_<state>_<sign>.inp: *ELASTIC, TYPE=ENGINEERING
CONSTANTS, the fibres along axis 1) are checked by CalculiX on a cube (ply_constants.ccx_check):
column `ccx`. A bimodular ply has one card per sign: a 3D model whose ply is loaded both ways takes
the law itself (the umat), the cards hold where the sign is known. A set of secants from loads
that close different contacts need not be one elastic material: a state whose compliance (the
orthotropic 6 × 6 of its constants, symmetric by construction) is not positive definite gets no
card, and the table says so.

With --law CELL=LAW.h5 (a law fitted from the same cell with [load] macro = "full", whose fit
tabulates the ply's constants from the exact law, /law/ply, docs/method.md §3c) the cell's fuse
load is the law's (σxx = /law/ply/fuse_stress, four times its onset along x) and column `law`
gives the largest relative difference of the law's nine constants from these solves' at the
same state and sign (and says so where the law's state broke other pairs): the exact law's
constants measured against the cell.

Writes OUT.md (one row per cell, state and sign) and OUT.csv beside it, atomically, and the
picture OUT.png/.svg: the moduli of each row as bars, on a log scale (E1 is ten times the others).
"""
import contextlib
import os
import tomllib

import h5py
import numpy

import common
import plot
import ply_constants

COLUMNS = ["cell", "state", "sign", "broken", "E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23",
           "sigma33_left", "check", "law", "ccx"]
CONSTANTS = COLUMNS[4:13]
LOAD = 1e-8
SIGMA33_TOLERANCE = 1e-7  # of the load; the solves' own relative error is about 1e-9 (ply_constants)


def positive_definite(c):
    """Whether the orthotropic compliance of the constants `c` is positive definite (a stiffness
    CalculiX can take: it does not check)."""
    E = [c["E1"], c["E2"], c["E3"]]
    nu = {(0, 1): c["nu12"], (0, 2): c["nu13"], (1, 2): c["nu23"]}
    S = numpy.zeros((6, 6))
    for i in range(3):
        S[i, i] = 1 / E[i]
    for (i, j), v in nu.items():
        S[i, j] = S[j, i] = -v / E[i]
    for i, k in enumerate(("G12", "G13", "G23")):
        S[3 + i, 3 + i] = 1 / c[k]
    return numpy.linalg.eigvalsh(S).min() > 0


def matrix_nu(mesh):
    """The matrix's Poisson ratio: the material the mesh was made with (its scene's file or the
    scene's own [matrix] table)."""
    with h5py.File(mesh, "r") as f:
        for name in ("material", "scene"):
            if name in f.attrs:
                table = tomllib.loads(common.text(f.attrs[name]))
                if "matrix" in table:
                    return float(table["matrix"]["nu"])
    raise ValueError(f"{mesh}: no [matrix] material among its attributes")


class State:
    """Solves of one cell in one bond state: `bonds` a solution file holding it (None: intact)."""

    def __init__(self, bin_dir, scene, mesh, folder, bonds, held=None):
        """`held`: the bond state per pair the solves must keep (None: the first solve's)."""
        self.bin_dir, self.scene, self.mesh, self.folder, self.bonds = bin_dir, scene, mesh, folder, bonds
        self.held = None if held is None else list(held)
        self.count = 0

    def solve(self, stress, eps33=None, shear=False):
        self.count += 1
        out = os.path.join(self.folder, f"solve-{self.count}.h5")
        strain, zz, G, bonded = ply_constants.solve(self.bin_dir, self.scene, self.mesh, out, stress, eps33, shear,
                                                    self.bonds)
        bonded = list(bonded)
        if self.held is None:
            self.held = bonded
        elif bonded != self.held:
            raise RuntimeError(f"{self.scene}: the load {stress}, ε33 {eps33} changed the bond state "
                               f"({sum(self.held)} bonded pairs, then {sum(bonded)})")
        return strain, zz, G

    def uniaxial_33(self, sign):
        """σ̄ = 0, ε33 = sign·LOAD: E1, ν12, ν13 and the longitudinal shear moduli."""
        strain, zz, G = self.solve([0.0, 0.0, 0.0], eps33=sign * LOAD, shear=True)
        e = sign * LOAD
        return {"E1": zz / e, "nu12": -strain[0] / e, "nu13": -strain[1] / e}, G

    def plane_stress(self, k, sign, E1, nu12):
        """The macro strain under σ̄ = sign·LOAD·e_k (tensor shear) with σ33 = 0, and |σ33|/LOAD
        left: secant steps on ε33 from the linear guess ε33 = −ν12 σ_k / E1."""
        stress = [0.0, 0.0, 0.0]
        stress[k] = sign * LOAD
        guess = -nu12 * stress[k] / E1 if k < 2 else LOAD / E1 * 1e-3  # nonzero: σzz is written only then
        points = []
        e = guess
        for _ in range(12):
            if e == 0:  # σzz is written only with ε33 ≠ 0; a step that lands on 0 moves off it
                e = 1e-12 * LOAD
            strain, zz, _ = self.solve(stress, eps33=e)
            points.append((e, zz))
            if abs(zz) <= SIGMA33_TOLERANCE * LOAD:
                return strain, abs(zz) / LOAD
            if len(points) == 1:
                slope = E1  # ∂σ33/∂ε33 at a fixed σ̄ is the local E1
            else:
                (e0, z0), (e1, z1) = points[-2], points[-1]
                slope = (z1 - z0) / (e1 - e0)
            e = e - zz / slope
        raise RuntimeError(f"{self.scene}: σ33 = 0 not reached under σ̄ = {stress} in 12 steps (left {zz:.3g})")

    def constants(self, sign):
        """The nine secant constants of the state under loads of `sign`, and σ33's residual."""
        c, G = self.uniaxial_33(sign)
        det = G[0][0] * G[1][1] - G[0][1] * G[1][0]
        c["G12"], c["G13"] = det / G[1][1], det / G[0][0]
        left = 0.0
        for k in range(3):
            strain, r = self.plane_stress(k, sign, c["E1"], c["nu12"])
            left = max(left, r)
            if k == 0:
                c["E2"], c["nu23"] = sign * LOAD / strain[0], -strain[1] / strain[0]
            elif k == 1:
                c["E3"] = sign * LOAD / strain[1]
            else:
                c["G23"] = sign * LOAD / strain[2]
        c["sigma33_left"] = left
        return c


def fuse_bonds(bin_dir, scene, mesh, folder, fuse):
    """The solution file of the fuse load (its bond state), the pairs it broke and the state."""
    out = os.path.join(folder, "fuse.h5")
    _, _, _, bonded = ply_constants.solve(bin_dir, scene, mesh, out, fuse)
    return out, len(bonded) - int(sum(bonded)), len(bonded), bonded


def cell_rows(bin_dir, scene, mesh, folder, fuse):
    """The rows of one cell: its states, each in tension and compression."""
    cell = os.path.basename(os.path.dirname(os.path.abspath(mesh)))
    intact = os.path.join(folder, "intact")
    os.makedirs(intact, exist_ok=True)
    _, _, _, bonded = ply_constants.solve(bin_dir, scene, mesh, os.path.join(intact, "probe.h5"), [0.0, 0.0, 0.0])
    states = []
    if len(bonded) and max(bonded) == 1:
        states.append(("bonded", None, f"0/{len(bonded)}", bonded))
        bonds, broken, pairs, after = fuse_bonds(bin_dir, scene, mesh, folder, fuse)
        states.append(("after fuse", bonds, f"{broken}/{pairs}", after))
    else:
        states.append(("contact", None, "no bonds", bonded))
    nu_m = matrix_nu(mesh)
    rows = []
    for state, bonds, broken, held in states:
        sub = os.path.join(folder, state.replace(" ", "-"))
        os.makedirs(sub, exist_ok=True)
        solves = State(bin_dir, scene, mesh, sub, bonds, held)
        reference = ply_constants.constants(bin_dir, scene, mesh, sub) if state == "bonded" else None
        all_broken = state == "contact" or broken.split("/")[0] == broken.split("/")[1]
        for sign, name in ((1, "tension"), (-1, "compression")):
            c = solves.constants(sign)
            c.update(cell=cell, state=state, sign=name, broken=broken)
            if reference is not None:
                c["check"] = max(abs(c[k] / reference[k] - 1) for k in CONSTANTS)
            elif all_broken and sign < 0:
                c["check"] = abs(c["nu12"] / nu_m - 1)
            rows.append(c)
    return rows


def law_table(law_h5):
    """The exact law's ply constants (/law/ply): {(state, sign): (constants, broken)} and its fuse
    stress."""
    states = {0: "bonded", 1: "after fuse", 2: "contact"}
    with h5py.File(law_h5, "r") as f:
        if "/law/ply" not in f:
            raise ValueError(f"{law_h5}: no /law/ply (fit a scene with [load] macro = \"full\" and a periodic boundary)")
        g = f["/law/ply"]
        table = {}
        for i, state in enumerate(g["state"][:]):
            sign = "tension" if g["sign"][i] > 0 else "compression"
            table[(states[int(state)], sign)] = (dict(zip(CONSTANTS, g["constants"][i])), int(g["broken"][i]))
        return table, float(g["fuse_stress"][0])


def compare_with_law(rows, table):
    """Column `law`: the law's largest relative difference from the solves, per row."""
    for r in rows:
        entry = table.get((r["state"], r["sign"]))
        if entry is None:
            r["law"] = "no such state in the law"
            continue
        constants, broken = entry
        solved_broken = 0 if r["broken"] in ("no bonds",) else int(r["broken"].split("/")[0])
        difference = max(abs(constants[k] / r[k] - 1) for k in CONSTANTS)
        r["law"] = difference if broken == solved_broken else f"{difference:.1e} ({broken} broken in the law)"


def markdown(rows):
    ccx = any("ccx" in r for r in rows)
    law = any("law" in r for r in rows)
    head = ["cell", "state", "load", "broken", "E1", "E2", "E3", "ν12", "ν13", "ν23", "G12", "G13", "G23",
            "σ33 left", "check"] + (["exact law"] if law else []) + (["CalculiX from the card"] if ccx else [])
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [r["cell"], r["state"], r["sign"], r["broken"]] + [f"{r[k]:.5g}" for k in CONSTANTS]
        cells += [f"{r['sigma33_left']:.1e}", f"{r['check']:.1e}" if "check" in r else ""]
        if law:
            cells.append(r["law"] if isinstance(r.get("law"), str) else f"{r['law']:.1e}" if "law" in r else "")
        if ccx:
            cells.append(r["ccx"] if isinstance(r.get("ccx"), str) else f"{r['ccx']:.1e}" if "ccx" in r else "")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def picture(rows, outbase):
    """The six moduli of every row (cell, state, load) as clustered bars, log scale."""
    moduli = ["E1", "E2", "E3", "G12", "G13", "G23"]
    data = "row " + " ".join(moduli) + "\n" + "".join(
        f"\"{r['cell']} {r['state']} {r['sign']}\" " + " ".join(f"{r[k]:.6g}" for k in moduli) + "\n" for r in rows)
    script = ("set style data histogram\nset style histogram cluster gap 1\nset style fill solid 0.8 border -1\n"
              "set logscale y\nset ylabel 'modulus, in the scene units'\nset xtics rotate by -30\n"
              "set key outside right top\nset grid ytics\nset bmargin 9\n"
              "set title 'The ply per bond state: secant moduli in tension and compression (fibres along 1)'\n"
              "plot for [k=2:7] 'moduli.dat' using k:xtic(1) title columnheader(k)\n")
    plot.gnuplot(script, outbase, {"moduli.dat": data})


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin")
    parser.add_argument("out")
    parser.add_argument("cells", nargs="+", help="scene.toml:mesh.h5")
    parser.add_argument("--fuse", default="0.04,0,0", help="the fuse load sxx,syy,sxy (tensor shear)")
    parser.add_argument("--ccx", help="CalculiX: write each state's cards and check them on a cube")
    parser.add_argument("--law", action="append", default=[], metavar="CELL=LAW.h5",
                        help="the cell's full law: its fuse load, and its constants against these solves")
    args = parser.parse_args(argv[1:])
    laws = {}
    for item in args.law:
        cell, _, law_h5 = item.partition("=")
        if not law_h5:
            raise ValueError(f"--law {item}: expected CELL=LAW.h5")
        laws[cell] = law_table(law_h5)
    fuse = [float(v) for v in args.fuse.split(",")]
    if len(fuse) != 3:
        raise ValueError(f"--fuse {args.fuse}: expected three stresses sxx,syy,sxy")
    rows = []
    out_folder = os.path.dirname(os.path.abspath(args.out))
    for scene, mesh in ply_constants.scene_meshes(args.cells):
        folder = os.path.join(out_folder, "states", os.path.basename(os.path.dirname(os.path.abspath(mesh))))
        os.makedirs(folder, exist_ok=True)
        cell = os.path.basename(os.path.dirname(os.path.abspath(mesh)))
        cell_fuse = [laws[cell][1], 0.0, 0.0] if cell in laws else fuse
        cell_results = cell_rows(args.bin, scene, mesh, folder, cell_fuse)
        if cell in laws:
            compare_with_law(cell_results, laws[cell][0])
        for r in cell_results:
            name = f"{r['cell']}-{r['state']}-{r['sign']}".upper().replace("-", "_").replace(" ", "_")
            path = os.path.join(out_folder, name.lower() + ".inp")
            if not args.ccx:
                pass
            elif r["state"] == "bonded":
                r["ccx"] = f"card {r['cell']}.inp (constants.md)"
            elif not positive_definite(r):
                r["ccx"] = "no card: not positive definite"
                with contextlib.suppress(FileNotFoundError):
                    os.remove(path)  # a card of an earlier run
            else:
                common.write_atomic(path, ply_constants.card(name, r))
                r["ccx"] = ply_constants.ccx_check(args.ccx, folder, name, r)
            rows.append(r)
    common.write_table(args.out, markdown(rows), COLUMNS, rows)
    picture(rows, os.path.splitext(args.out)[0])
    print(markdown(rows), end="")


if __name__ == "__main__":
    common.main_guard(main)
