#!/usr/bin/python3
"""How a 3D model uses the ply's constants: a [0/90]s laminated beam of C3D20R bricks in
CalculiX, the plies' material the cell's bonded card (tools/ply_constants.py), against classical
laminate theory (docs/results/ply.md).

usage:
  ccx_laminate.py CONSTANTS.csv CELL OUT_FOLDER [--ccx PATH]

The beam: length L = 20, width b = 2, four plies of t = 0.25 (h = 1), stacked 0/90/90/0 from the
bottom; 0° puts the fibres (the card's axis 1) along the beam's x, 90° along its y (*ORIENTATION).
Two steps:
  tension   x = 0 held along x (and against rigid motion), x = L moved by δ: the axial modulus
            E_x = F L / (δ b h) against the laminate's, 1/(h a11) with a = A⁻¹ (N_y = 0: a free
            width) and A11/h (ε_y = 0: a wide plate), which bracket a narrow beam;
  bending   x = 0 clamped, a tip load P along −z on the end face (the serendipity face's consistent
            nodal loads: corners −1/12, midsides 1/3 of each face's share): the tip deflection
            against Euler–Bernoulli with the laminate's bending stiffness b/d11 (d = D⁻¹, free
            width) and with Timoshenko's shear term (shear correction 5/6, the plies' transverse
            shear moduli in series: G13 at 0°, G23 at 90°), and σxx through the thickness at mid-span (elements' means of
            their 2 × 2 × 2 points, at their centroids, the four around x = L/2, y = b/2) against
            the laminate's ply stresses Q̄(z) z κ, κ = d M.
Writes OUT_FOLDER/laminate.md, laminate.csv (the through-thickness stresses) and laminate.png/.svg
(σxx against z: CalculiX's points, the laminate theory's lines).
"""
import csv
import os

import numpy as np

import common
from ccx_cell import real
import plot
import ply_constants

L, B, T, PLIES = 20.0, 2.0, 0.25, (0, 90, 90, 0)
NX, NY, NZ_PER_PLY = 40, 4, 4
H = T * len(PLIES)
DELTA, P = 0.01, 1e-3


def read_constants(path, cell):
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["cell"] == cell:
                return {k: float(row[k]) for k in ("E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23")}
    raise ValueError(f"{path}: no row of cell {cell}")


class Grid:
    """The serendipity brick grid: points (i, j, k) on half steps with at most one odd index."""

    def __init__(self):
        self.nz = NZ_PER_PLY * len(PLIES)
        self.number = {}
        for k in range(2 * self.nz + 1):
            for j in range(2 * NY + 1):
                for i in range(2 * NX + 1):
                    if (i % 2) + (j % 2) + (k % 2) <= 1:
                        self.number[(i, j, k)] = len(self.number) + 1

    def x(self, p):
        i, j, k = p
        return (L * i / (2 * NX), B * j / (2 * NY), H * k / (2 * self.nz))

    def element(self, e, f, g):
        """The 20 nodes of brick (e, f, g) in CalculiX's order."""
        i, j, k = 2 * e, 2 * f, 2 * g
        c = [(i, j, k), (i + 2, j, k), (i + 2, j + 2, k), (i, j + 2, k)]
        c += [(a, b_, k + 2) for a, b_, _ in c]
        mid = lambda p, q: tuple((u + v) // 2 for u, v in zip(p, q))  # noqa: E731
        edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
        return [self.number[p] for p in c] + [self.number[mid(c[a], c[b_])] for a, b_ in edges]


def deck(c, grid):
    lines = ["*NODE"] + [f"{n}, {real(x)}, {real(y)}, {real(z)}" for p, n in grid.number.items()
                         for x, y, z in [grid.x(p)]]
    elements, mid = {0: [], 90: []}, []
    for g in range(grid.nz):
        angle = PLIES[g // NZ_PER_PLY]
        for f in range(NY):
            for e in range(NX):
                number = 1 + e + NX * (f + NY * g)
                nodes = [str(n) for n in grid.element(e, f, g)]  # a card line holds 16 entries
                elements[angle].append(f"{number}, " + ", ".join(nodes[:15]) + ",\n" + ", ".join(nodes[15:]))
                if e in (NX // 2 - 1, NX // 2) and f in (NY // 2 - 1, NY // 2):
                    mid.append(number)
    for angle, rows in elements.items():
        lines += [f"*ELEMENT, TYPE=C3D20R, ELSET=PLY{angle}"] + rows
    lines += ["*ELSET, ELSET=MID"] + [str(n) for n in mid]
    at = lambda axis, value: [n for p, n in grid.number.items() if p[axis] == value]  # noqa: E731
    lines += ["*NSET, NSET=FIX"] + [str(n) for n in at(0, 0)]
    lines += ["*NSET, NSET=END"] + [str(n) for n in at(0, 2 * NX)]
    lines += [ply_constants.card("PLY", c).rstrip("\n")]
    lines += ["*ORIENTATION, NAME=OR0, SYSTEM=RECTANGULAR", "1., 0., 0., 0., 1., 0.",
              "*ORIENTATION, NAME=OR90, SYSTEM=RECTANGULAR", "0., 1., 0., -1., 0., 0."]
    for angle in (0, 90):
        lines.append(f"*SOLID SECTION, ELSET=PLY{angle}, MATERIAL=PLY, ORIENTATION=OR{angle}")
    tip = grid.number[(2 * NX, NY, grid.nz)]
    lines.insert(lines.index("*NSET, NSET=FIX"), f"*NSET, NSET=TIP\n{tip}")
    corner, side = grid.number[(0, 0, 0)], grid.number[(0, 2 * NY, 0)]
    # One job per case: a step's *BOUNDARY, OP=NEW does not simply drop the last step's.
    tension = lines + ["*STEP", "*STATIC", "*BOUNDARY", "FIX, 1, 1", f"{corner}, 2, 3", f"{side}, 3, 3",
                       f"END, 1, 1, {DELTA}", "*NODE PRINT, NSET=END, TOTALS=ONLY", "RF", "*END STEP"]
    bending = lines + ["*STEP", "*STATIC", "*BOUNDARY", "FIX, 1, 3", "*CLOAD"]
    bending += [f"{n}, 3, {real(-v)}" for n, v in tip_loads(grid).items()]
    bending += ["*NODE PRINT, NSET=TIP", "U", "*EL PRINT, ELSET=MID", "S", "*END STEP"]
    return {"tension": "\n".join(tension) + "\n", "bending": "\n".join(bending) + "\n"}, mid


def tip_loads(grid):
    """Consistent nodal loads of a uniform shear traction of total P on the end face."""
    loads = {}
    share = P / (NY * grid.nz)
    for f in range(NY):
        for g in range(grid.nz):
            j, k = 2 * f, 2 * g
            corners = [(j, k), (j + 2, k), (j + 2, k + 2), (j, k + 2)]
            mids = [(j + 1, k), (j + 2, k + 1), (j + 1, k + 2), (j, k + 1)]
            for (a, b_), w in [(p, -1 / 12) for p in corners] + [(p, 1 / 3) for p in mids]:
                n = grid.number[(2 * NX, a, b_)]
                loads[n] = loads.get(n, 0.0) + w * share
    return loads


def laminate(c):
    """Classical laminate theory of the stack: A, D and each ply's Q̄ with its z range."""
    nu21 = c["nu12"] * c["E2"] / c["E1"]
    den = 1 - c["nu12"] * nu21
    Q = np.array([[c["E1"] / den, c["nu12"] * c["E2"] / den, 0], [c["nu12"] * c["E2"] / den, c["E2"] / den, 0],
                  [0, 0, c["G12"]]])
    Q90 = Q[[1, 0, 2]][:, [1, 0, 2]]
    A, D, plies = np.zeros((3, 3)), np.zeros((3, 3)), []
    for n, angle in enumerate(PLIES):
        z0, z1 = -H / 2 + n * T, -H / 2 + (n + 1) * T
        Qb = Q if angle == 0 else Q90
        A += Qb * (z1 - z0)
        D += Qb * (z1 ** 3 - z0 ** 3) / 3
        plies.append((z0, z1, Qb))
    return A, D, plies


def read_dat(paths, mid):
    """The tension job's total reaction along x, the bending job's tip deflection and the mean
    stresses of the mid-span elements, from their .dat files."""
    force, tip, stress = None, None, {}
    for path in paths:
        section = None
        with open(path) as f:
            for line in f:
                words = line.split()
                if words and words[0] in ("total", "displacements", "stresses"):
                    section = words[0]
                    continue
                values = []
                for w in words:  # a stress line ends with its orientation's name
                    try:
                        values.append(float(w))
                    except ValueError:
                        break
                if not values:
                    continue
                if section == "total" and force is None:
                    force = values[0]
                elif section == "displacements":
                    tip = values[3]
                elif section == "stresses" and int(values[0]) in mid:
                    # CalculiX prints an element's stresses in its orientation's axes (the name
                    # ends the line): OR90's local y is −x, so σxx is its σ22 there.
                    sxx = values[3] if words[-1] == "OR90" else values[2]
                    stress.setdefault(int(values[0]), []).append(sxx)
    if force is None or tip is None or len(stress) != len(mid):
        raise RuntimeError(f"{paths}: the reaction, the tip deflection or the mid-span stresses are missing")
    return force, tip, {e: sum(v) / len(v) for e, v in stress.items()}


def study(c, folder, ccx="ccx"):
    """The two jobs in `folder` with the ply constants `c`: the figures of laminate.md by name, the
    through-thickness rows, the laminate theory's σxx(z) and the seconds of CalculiX."""
    os.makedirs(folder, exist_ok=True)
    grid = Grid()
    jobs, mid = deck(c, grid)
    seconds = 0.0
    for job, text in jobs.items():
        with open(os.path.join(folder, job + ".inp"), "w") as f:
            f.write(text)
        seconds += common.run_ccx(ccx, folder, job).seconds
    force, tip, stress = read_dat([os.path.join(folder, job + ".dat") for job in jobs], mid)

    A, D, plies = laminate(c)
    a, d = np.linalg.inv(A), np.linalg.inv(D)
    # the beam's x–z plane: the ply's 1–3 plane at 0° (fibres along x), its 2–3 plane at 90°
    G_xz = H / sum(T / (c["G13"] if angle == 0 else c["G23"]) for angle in PLIES)
    w_eb = P * L ** 3 / (3 * B / d[0, 0])
    kappa = d @ np.array([P * (L / 2) / B, 0, 0])  # M_x per unit width at mid-span

    def theory(z, Qb=None):
        """σxx of the laminate theory at z, in the ply holding z or of stiffness Qb."""
        if Qb is None:
            Qb = next(q for z0, z1, q in plies if z0 <= z <= z1)
        return (Qb @ (z * kappa))[0]

    layers = {}
    for e, s in stress.items():
        layers.setdefault((e - 1) // (NX * NY), []).append(s)
    rows = []
    for g in sorted(layers):
        z = -H / 2 + (g + 0.5) * H / grid.nz
        rows.append({"z": z, "sxx_ccx": sum(layers[g]) / len(layers[g]), "sxx_laminate": theory(z)})
    peak = max(abs(r["sxx_laminate"]) for r in rows)
    figures = {"Ex": force * L / (DELTA * B * H), "Ex_free": 1 / (H * a[0, 0]), "Ex_wide": A[0, 0] / H,
               "w": -tip, "w_eb": w_eb, "w_timoshenko": w_eb + P * L / (5 / 6 * G_xz * B * H), "peak": peak,
               "sigma_error": max(abs(r["sxx_ccx"] - r["sxx_laminate"]) for r in rows) / peak}
    return figures, rows, plies, theory, seconds


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("constants")
    parser.add_argument("cell")
    parser.add_argument("out")
    parser.add_argument("--ccx", default="ccx")
    args = parser.parse_args(argv[1:])
    c = read_constants(args.constants, args.cell)
    f, rows, plies, theory, seconds = study(c, args.out, args.ccx)
    md = [f"[0/90]s beam of the `{args.cell}` cell's bonded ply in CalculiX: {NX} × {NY} × "
          f"{NZ_PER_PLY * len(PLIES)} C3D20R (L = {L:g}, b = {B:g}, h = {H:g}), {seconds:.2f} s.", "",
          "| quantity | CalculiX | laminate theory | difference |", "|---|---|---|---|",
          f"| E_x, free width (N_y = 0) | {f['Ex']:.5g} | {f['Ex_free']:.5g} | {f['Ex'] / f['Ex_free'] - 1:+.2%} |",
          f"| E_x, wide plate (ε_y = 0) | {f['Ex']:.5g} | {f['Ex_wide']:.5g} | {f['Ex'] / f['Ex_wide'] - 1:+.2%} |",
          f"| tip deflection, Euler–Bernoulli | {f['w']:.5g} | {f['w_eb']:.5g} | {f['w'] / f['w_eb'] - 1:+.2%} |",
          f"| tip deflection, with shear (Timoshenko) | {f['w']:.5g} | {f['w_timoshenko']:.5g} | "
          f"{f['w'] / f['w_timoshenko'] - 1:+.2%} |",
          f"| σxx through the thickness at mid-span, largest difference over the peak | | {f['peak']:.4g} (peak) | "
          f"{f['sigma_error']:.2%} |", ""]
    common.write_atomic(os.path.join(args.out, "laminate.md"), "\n".join(md))
    common.write_csv(os.path.join(args.out, "laminate.csv"), ["z", "sxx_ccx", "sxx_laminate"], rows)
    # one line per ply (a blank line breaks gnuplot's line at the ply's faces)
    line = "\n\n".join("\n".join(f"{z:.9g} {theory(z, Qb):.9g}" for z in np.linspace(z0, z1, 11))
                        for z0, z1, Qb in plies) + "\n"
    points = "\n".join(f"{r['z']:.9g} {r['sxx_ccx']:.9g}" for r in rows) + "\n"
    script = ("set xlabel 'σxx at mid-span (GPa; tip load 1e-3 on a beam of length 20, width 2, height 1)'\n"
              "set ylabel 'z'\nset grid\nset key left top\n"
              "set title '[0/90]s beam, plies from the cell: CalculiX C3D20R against laminate theory'\n"
              "plot 'theory.dat' using 2:1 with lines lw 2 title 'laminate theory', "
              "'ccx.dat' using 2:1 with points pt 7 ps 1.5 title 'CalculiX, element means'\n")
    plot.gnuplot(script, os.path.join(args.out, "laminate"), {"theory.dat": line, "ccx.dat": points})
    print("\n".join(md))


if __name__ == "__main__":
    common.main_guard(main)
