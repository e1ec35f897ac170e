#!/usr/bin/python3
"""The nine constants of a bonded cell from an independent code: the cell in CalculiX as a 3D
periodic slab (docs/method.md §3a, §3b).

usage: ccx_ply.py MESH.h5 [--ccx PATH] [--work DIR]     prints the constants as JSON

The p2 mesh of dualcell-mesh is extruded one layer along z (the fibres) into 15-node wedges
(C3D15), every interface pair and glue pair merged (bonded). Periodicity in x, y and z ties every
node to the first node of its class (the same place one period away in any direction) by
u_s − u_m = E (x_s − x_m), three *EQUATION rows per node, E the macro displacement gradient held
by three dummy nodes (dummy k's DOF i is E_ik). Six steps prescribe the unit strains ε11 … γ12
(engineering shear split over E_ij and E_ji); the dummy nodes' reactions over the volume are the
average stress, so the six columns are the stiffness C; its inverse gives the constants, the
fibres along the ply's axis 1 (z here), x and y its axes 2 and 3.
"""
import json
import os
import shutil
import tempfile

import h5py
import numpy as np

import ccx_cell
import common

# C3D15: corners 1–3 bottom, 4–6 top; mid-edges 7–9 bottom (1-2, 2-3, 3-1), 10–12 top; 13–15 the
# mid-height of the vertical edges 1-4, 2-5, 3-6. dualcell's p2 triangle: corners 0–2, then the
# mid-side nodes of (0,1), (1,2), (2,0), counter-clockwise. Numbers are written with 12
# significant digits: CalculiX reads fields of at most 20 characters.


def deck(mesh, periodic_points, point_of, fibre, matrix, h):
    used = [int(v) for v in mesh.used]
    corner = sorted({int(v) for tri in mesh.triangles for v in tri[:3]})
    index = {v: i for i, v in enumerate(used)}
    n2 = len(used)
    mid_index = {v: i for i, v in enumerate(corner)}
    bottom = lambda v: 1 + index[v]  # noqa: E731
    top = lambda v: 1 + n2 + index[v]  # noqa: E731
    middle = lambda v: 1 + 2 * n2 + mid_index[v]  # noqa: E731
    n3 = 2 * n2 + len(corner)
    xyz = {}
    for v in used:
        x, y = mesh.nodes[v]
        xyz[bottom(v)] = (x, y, 0.0)
        xyz[top(v)] = (x, y, h)
    for v in corner:
        x, y = mesh.nodes[v]
        xyz[middle(v)] = (x, y, h / 2)
    # Classes of periodic images: in-plane pairs (per layer) and bottom–top.
    parent = list(range(n3 + 1))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    def join(a, b):
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    node_of_point = {}
    for v in range(len(point_of)):
        node_of_point.setdefault(int(point_of[v]), int(mesh.rep[v]))
    for point, partner in periodic_points:
        a, b = node_of_point[point], node_of_point[partner]
        join(bottom(a), bottom(b))
        join(top(a), top(b))
        if a in mid_index and b in mid_index:
            join(middle(a), middle(b))
    for v in used:
        join(bottom(v), top(v))
    dummies = [n3 + 1, n3 + 2, n3 + 3]
    lines = ["*NODE"] + [f"{k}, {p[0]:.12g}, {p[1]:.12g}, {p[2]:.12g}" for k, p in sorted(xyz.items())]
    lines += [f"{d}, 0, 0, 0" for d in dummies]
    elements = {True: [], False: []}
    for e, tri in enumerate(mesh.triangles):
        t = [int(v) for v in tri]
        nodes = ([bottom(v) for v in t[:3]] + [top(v) for v in t[:3]] + [bottom(v) for v in t[3:]] +
                 [top(v) for v in t[3:]] + [middle(v) for v in t[:3]])
        elements[bool(mesh.is_fibre[e])].append(f"{e + 1}, " + ", ".join(map(str, nodes)))
    for name, fibre_set in (("FIBRE", True), ("MATRIX", False)):
        lines += [f"*ELEMENT, TYPE=C3D15, ELSET={name}"]
        for row in elements[fibre_set]:
            words = row.split(", ")
            lines += [", ".join(words[:10]) + ",", ", ".join(words[10:])]
    # CalculiX gives DOFs only to nodes of elements: each dummy DOF hangs on a grounded spring of
    # negligible stiffness (1e-12 of the matrix's E times the cell's size; its reaction is that
    # much of the stress).
    spring = 1e-12 * matrix[0] * h
    for i in range(3):
        lines += [f"*ELEMENT, TYPE=SPRING1, ELSET=SPRING{i + 1}"]
        lines += [f"{len(mesh.triangles) + 3 * k + i + 1}, {d}" for k, d in enumerate(dummies)]
        lines += [f"*SPRING, ELSET=SPRING{i + 1}", f"{i + 1}", f"{spring:.6g}"]
    for name, (E, nu) in (("FIBRE", fibre), ("MATRIX", matrix)):
        lines += [f"*MATERIAL, NAME={name}", "*ELASTIC", f"{E:.12g}, {nu:.12g}",
                  f"*SOLID SECTION, ELSET={name}, MATERIAL={name}"]
    lines += ["*EQUATION"]
    fixed = None
    for k in sorted(xyz):
        m = find(k)
        if m == k:
            fixed = fixed or k
            continue
        d = [xyz[k][c] - xyz[m][c] for c in range(3)]
        for i in range(3):
            terms = [(k, i + 1, 1.0), (m, i + 1, -1.0)] + [(dummies[c], i + 1, -d[c]) for c in range(3)
                                                           if abs(d[c]) > 1e-12]
            lines += [str(len(terms))] + [", ".join(f"{n}, {dof}, {a:.12g}" for n, dof, a in terms)]
    lines += ["*ELSET, ELSET=SOLID", "FIBRE, MATRIX"]
    for a, b in load_cases():
        E = strain(a) + (strain(b) if b != a else 0)
        lines += ["*STEP", "*STATIC", "*BOUNDARY, OP=NEW", f"{fixed}, 1, 3, 0."]
        lines += [f"{dummies[k]}, {i + 1}, {i + 1}, {E[i, k]:.12g}" for k in range(3) for i in range(3)]
        lines += ["*EL PRINT, ELSET=SOLID, TOTALS=ONLY", "ELSE", "*END STEP"]
    return "\n".join(lines) + "\n", dummies


VOIGT = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]


def strain(a):
    """The displacement gradient of unit Voigt strain a (engineering shear split over E_ij, E_ji)."""
    E = np.zeros((3, 3))
    i, j = VOIGT[a]
    E[i, j] += 0.5 if i != j else 1.0
    E[j, i] += 0.5 if i != j else 0.0
    return E


def load_cases():
    """Each unit strain, then each pair of them together: the stiffness from strain energies,
    C_aa = 2U_a/V and C_ab = (U_ab − U_a − U_b)/V (CalculiX's reaction forces leave out what the
    *EQUATION rows carry, so the dummy nodes' reactions do not give the stress)."""
    return [(a, a) for a in range(6)] + [(a, b) for a in range(6) for b in range(a + 1, 6)]


def read_energies(path):
    """Per step: the total internal energy of the solid elements."""
    energies, expect = [], False
    with open(path) as f:
        for line in f:
            if "internal energy" in line:
                expect = True
                continue
            words = line.split()
            if expect and words:
                energies.append(float(words[-1]))
                expect = False
    return energies


def constants(mesh_path, ccx="ccx", work=None):
    mesh = ccx_cell.Mesh(mesh_path, bonded=True)
    if not mesh.quadratic:
        raise ValueError(f"{mesh_path}: a p1 mesh; the 3D slab is built of quadratic wedges (element = \"p2\")")
    fibre, matrix = ccx_cell.scene_materials(mesh)
    with h5py.File(mesh_path, "r") as f:
        point_of = f["/mesh/point_of"][:]
        periodic = [(int(p), int(q)) for p, q, _ in f["/mesh/periodic_pairs"][:]]
    W = mesh.nodes[:, 0].max() - mesh.nodes[:, 0].min()
    H = mesh.nodes[:, 1].max() - mesh.nodes[:, 1].min()
    h = min(W, H) / 4
    text, dummies = deck(mesh, periodic, point_of, fibre, matrix, h)
    folder = work or tempfile.mkdtemp(prefix="ccx_ply.")
    try:
        with open(os.path.join(folder, "ply.inp"), "w") as out:
            out.write(text)
        common.run_ccx(ccx, folder, "ply")
        U = read_energies(os.path.join(folder, "ply.dat"))
    finally:
        if not work:
            shutil.rmtree(folder, ignore_errors=True)
    cases = load_cases()
    if len(U) != len(cases):
        raise RuntimeError(f"ccx printed {len(U)} energies, not {len(cases)}")
    V = W * H * h
    C = np.zeros((6, 6))
    for (a, b), u in zip(cases, U):
        if a == b:
            C[a, a] = 2 * u / V
    for (a, b), u in zip(cases, U):
        if a != b:
            C[a, b] = C[b, a] = (u - C[a, a] * V / 2 - C[b, b] * V / 2) / V
    S = np.linalg.inv(C)
    # axes: ply 1 = z (Voigt 2), 2 = x (0), 3 = y (1); shears: 12 = xz (4), 13 = yz (3), 23 = xy (5)
    return {"E1": 1 / S[2, 2], "E2": 1 / S[0, 0], "E3": 1 / S[1, 1], "nu12": -S[2, 0] / S[2, 2],
            "nu13": -S[2, 1] / S[2, 2], "nu23": -S[0, 1] / S[0, 0], "G12": 1 / S[4, 4], "G13": 1 / S[3, 3],
            "G23": 1 / S[5, 5]}


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("mesh")
    parser.add_argument("--ccx", default="ccx")
    parser.add_argument("--work")
    args = parser.parse_args(argv[1:])
    print(json.dumps(constants(args.mesh, args.ccx, args.work)))


if __name__ == "__main__":
    common.main_guard(main)
