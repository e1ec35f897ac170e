#!/usr/bin/python3
"""The whole ply's law in a beam of 3D elements in CalculiX, loaded past the fuse, against
dualcell-structure's transverse solution of the same beam (docs/method.md §16a, docs/results/ply.md "How a 3D
model uses the ply").

usage:
  ccx_solid_beam.py CCX CARD.inp STRUCTURE.h5 SCENE.toml OUT.md

CARD.inp is a layout-3 card (dualcell-export --format umat of a law with [load] macro = "full",
the cell's file beside it). STRUCTURE.h5 is dualcell-structure's solution of SCENE.toml with the
same law.h5: a roller left edge, one point held in y, a traction linear along the right edge,
load factors as its steps. Its p2 mesh is extruded along the fibres (z) into one layer
of C3D15 wedges of unit thickness; every node is held at w = 0, so the 3D elements are in plane
strain and the umat takes (ε11, ε22, γ12) with ε33 = γ13 = γ23 = 0: the transverse law, which is
the full law's in-plane part. The right face carries the consistent nodal forces of the traction
(the 8-node face, 3 × 3 Gauss points). ccx takes the scene's steps as fixed increments (*STATIC,
DIRECT, one increment per step): each starts from the last one's bonds, as dualcell-structure's
steps do. With a card whose bonds break between increments (dualcell-export --breaks between:
held within an increment, what each point's cascade breaks at its end broken at the start of the
next) each load level is repeated once per debond round dualcell-structure took there, and once
more: the rounds of its debond loop (equilibrium with the bonds held, then each point's cascade).

Compared at the last step: the end rotation and the largest nodal displacement difference (the
bottom layer against dualcell-structure's nodes; the top layer must equal the bottom), and the
watched point's deflection at every step. Bound 1e-5 on the end rotation and on each load level's
deflection, as for the plane beam (ccx_umat_check.py beam): both solve the same discrete problem
to their Newton tolerances; with bonds breaking between increments the last two rounds of every
level must agree to 1e-12 of the largest displacement (the rounds asked finished the cascade).
Writes OUT.md atomically; exit 1 where the bound is missed.
"""
import os
import shutil
import sys
import tempfile
import tomllib

import numpy as np

import common
from ccx_umat_check import card_constants, end_rotation, material_cards, run_ccx


def quad8(xi, zeta):
    """The 8-node face's shape functions at (ξ, ζ): corners (−1,−1), (1,−1), (1,1), (−1,1), then
    the mid-sides (0,−1), (1,0), (0,1), (−1,0)."""
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    N = [0.25 * (1 + a * xi) * (1 + b * zeta) * (a * xi + b * zeta - 1) for a, b in corners]
    N += [0.5 * (1 - xi * xi) * (1 - zeta), 0.5 * (1 + xi) * (1 - zeta * zeta), 0.5 * (1 - xi * xi) * (1 + zeta),
          0.5 * (1 - xi) * (1 - zeta * zeta)]
    return N


def face_forces(nodes, edge, layer, t_start, t_end):
    """Consistent nodal forces (node id → 3-vector) of a traction linear from t_start to t_end along
    the right edge (p2 node list ordered along it: corner, mid, ..., corner), constant through the
    unit thickness, on the faces of the extruded wedges. layer(i, k): the 3D id of 2D node i at
    z = k/2 (k = 0, 1, 2)."""
    f = {}
    first, last = nodes[edge[0]], nodes[edge[-1]]
    length = np.linalg.norm(last - first)
    g = [(-np.sqrt(0.6), 5 / 9), (0.0, 8 / 9), (np.sqrt(0.6), 5 / 9)]
    for k in range(0, len(edge) - 2, 2):
        a, m, b = edge[k], edge[k + 1], edge[k + 2]
        ids = [layer(a, 0), layer(b, 0), layer(b, 2), layer(a, 2), layer(m, 0), layer(b, 1), layer(m, 2),
               layer(a, 1)]
        h = np.linalg.norm(nodes[b] - nodes[a])
        for xi, wx in g:
            for zeta, wz in g:
                x = nodes[a] + (xi + 1) / 2 * (nodes[b] - nodes[a])
                s = np.linalg.norm(x - first) / length
                t = np.array(t_start) + s * (np.array(t_end) - np.array(t_start))
                for n, N in zip(ids, quad8(xi, zeta)):
                    f[n] = f.get(n, np.zeros(2)) + wx * wz * (h / 2) * 0.5 * N * t
    return f


def displacement_blocks(dat, nodes):
    """Every node's displacement (nodes × 3) per block of ccx's .dat, in order."""
    blocks = []
    for line in dat.splitlines():
        if line.strip().startswith("displacements"):
            blocks.append(np.zeros((nodes, 3)))
        elif blocks and line.split():
            r = line.split()
            blocks[-1][int(r[0]) - 1] = [float(v) for v in r[1:4]]
    return blocks


def solid_deck(nodes, tri, scene, text, name, factors, repeats):
    """The ccx deck of the beam: the p2 mesh extruded into one layer of C3D15 (2D node i at z = 0,
    1 and, for corners, 0.5), w = 0 everywhere, the scene's roller edge and supports, the right
    face's consistent forces, and `repeats[k]` one-increment steps at load factor `factors[k]`.
    Returns the deck, layer(i, level) (the 3D id of 2D node i at z = level/2), the right edge's
    nodes in order and the watched node."""
    N = len(nodes)
    corners = sorted(set(tri[:, :3].ravel()))
    mid_layer = {c: 2 * N + j + 1 for j, c in enumerate(corners)}

    def layer(i, level):
        return i + 1 if level == 0 else N + i + 1 if level == 2 else mid_layer[i]

    L, H = nodes[:, 0].max(), nodes[:, 1].max()
    tol = 1e-9 * max(L, H)
    left = [i for i in range(N) if abs(nodes[i, 0]) < tol]
    right = sorted((i for i in range(N) if abs(nodes[i, 0] - L) < tol), key=lambda i: nodes[i, 1])
    edges = scene["edges"]
    t0 = edges["right"]["traction"]
    t1 = edges["right"].get("traction_end", t0)
    forces = face_forces(nodes, right, layer, t0, t1)  # at load factor 1
    deck = "*NODE, NSET=NALL\n"
    deck += "".join(f"{layer(i, 0)}, {x:.13e}, {y:.13e}, 0\n" for i, (x, y) in enumerate(nodes))
    deck += "".join(f"{layer(i, 2)}, {x:.13e}, {y:.13e}, 1\n" for i, (x, y) in enumerate(nodes))
    deck += "".join(f"{mid_layer[c]}, {nodes[c, 0]:.13e}, {nodes[c, 1]:.13e}, 0.5\n" for c in corners)
    deck += "*ELEMENT, TYPE=C3D15, ELSET=E\n"
    for e, row in enumerate(tri):
        c, m = row[:3], row[3:]
        ids = [layer(i, 0) for i in c] + [layer(i, 2) for i in c] + [layer(i, 0) for i in m] + \
              [layer(i, 2) for i in m] + [layer(i, 1) for i in c]
        deck += f"{e + 1}, " + ", ".join(str(i) for i in ids[:10]) + ",\n" + ", ".join(str(i) for i in ids[10:]) + "\n"
    deck += material_cards(text[text.index("*MATERIAL"):])
    deck += f"*SOLID SECTION, ELSET=E, MATERIAL={name}\n*BOUNDARY\nNALL, 3, 3, 0.\n"
    for i in left:
        deck += "".join(f"{layer(i, lv)}, 1, 1, 0.\n" for lv in range(3) if lv != 1 or i in mid_layer)
    for s in scene.get("support", []):
        i = int(np.argmin(np.linalg.norm(nodes - np.array(s["at"], dtype=float), axis=1)))
        for c, axis in (("x", 1), ("y", 2)):
            if c in s.get("fix", "xy"):
                deck += "".join(f"{layer(i, lv)}, {axis}, {axis}, 0.\n" for lv in range(3) if lv != 1 or i in mid_layer)
    watch = np.array(scene.get("output", {}).get("watch", [L, 0]), dtype=float)
    w = int(np.argmin(np.linalg.norm(nodes - watch, axis=1)))
    # One ccx step (one increment) per load level and round, the loads at the level's factor;
    # Newton with the umat's tangent to a tight residual.
    for t, repeat in zip(factors, repeats):
        for _ in range(repeat):
            deck += ("*STEP, INC=1000\n*STATIC, DIRECT\n1., 1.\n*CONTROLS, PARAMETERS=FIELD\n1e-10, 1e-10\n"
                     "*CONTROLS, PARAMETERS=TIME INCREMENTATION\n4, 8, 9, 200, 10, 4, , 200\n*CLOAD\n")
            for i, fv in sorted(forces.items()):
                deck += f"{i}, 1, {t * fv[0]:.13e}\n{i}, 2, {t * fv[1]:.13e}\n"
            deck += "*NODE PRINT, NSET=NALL\nU\n*END STEP\n"
    return deck, layer, right, w


def main(argv):
    parser = common.Parser(__doc__)
    for name in ("ccx", "card", "structure_h5", "scene_file", "out"):
        parser.add_argument(name)
    args = parser.parse_args(argv[1:])
    import h5py
    name, k, text = card_constants(args.card)
    if k[0] != 3:
        sys.exit("ccx_solid_beam.py: the card must be the whole ply's law (layout 3: [load] macro = \"full\")")
    with open(args.scene_file, "rb") as f:
        scene = tomllib.load(f)
    edges = scene.get("edges", {})
    if edges.get("left", {}).get("type") != "roller" or edges.get("right", {}).get("type") != "traction":
        sys.exit("ccx_solid_beam.py: the scene must have a roller left edge and a traction right edge")
    factors = scene.get("steps", {}).get("factors", [1.0])
    between = len(k) >= 5 and k[4] != 0
    with h5py.File(args.structure_h5, "r") as f:
        nodes, tri = f["/mesh/nodes"][:], f["/mesh/triangles"][:]
        steps = sorted(key for key in f["/steps"].keys() if key.isdigit())
        u_ref = f[f"/steps/{steps[-1]}/displacement"][:]
        watch_ref = f["/steps/watch_displacement"][:]
        rounds_ref = [int(r) for r in f["/steps/fuse_rounds"][:]]
        law_file = common.text(f.attrs.get("law_file", ""))
    if len(rounds_ref) != len(factors):
        sys.exit(f"ccx_solid_beam.py: {args.structure_h5} has {len(rounds_ref)} steps, the scene {len(factors)}")
    # Per load level, the ccx steps at it: one; with bonds breaking between increments (the card's
    # 5th constant) one more per debond round dualcell-structure took there, and one to see that
    # nothing more breaks.
    repeats = [1 + (r + 1 if between else 0) for r in rounds_ref]
    if tri.shape[1] != 6:
        sys.exit("ccx_solid_beam.py: the structure must be meshed with p2 triangles")
    N = len(nodes)
    deck, layer, right, w = solid_deck(nodes, tri, scene, text, name, factors, repeats)
    work = tempfile.mkdtemp(prefix="ccx-solid-beam-", dir=os.path.dirname(os.path.abspath(args.out)))
    try:
        dat, seconds = run_ccx(args.ccx, work, deck, args.card)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    blocks = displacement_blocks(dat, 3 * N)
    if len(blocks) != sum(repeats):
        sys.exit(f"ccx_solid_beam.py: ccx printed {len(blocks)} increments, not the {sum(repeats)} asked")
    # Each load level's last round; with breaks between increments, the last two rounds must agree
    # (nothing more broke).
    ends = np.cumsum(repeats) - 1
    watch_ccx = [blocks[e][layer(w, 0) - 1] for e in ends]
    settled = max((np.abs(blocks[e] - blocks[e - 1]).max() for e, r in zip(ends, repeats) if r > 1), default=0.0)
    settled /= max(np.abs(b).max() for b in blocks)
    u3 = blocks[-1]
    bottom = u3[:N, :2]
    top = u3[N:2 * N, :2]
    H = nodes[:, 1].max()
    rot_ccx, axis_ccx = end_rotation(nodes, right, bottom, H)
    rot_ref, axis_ref = end_rotation(nodes, right, u_ref, H)
    error = (rot_ccx - rot_ref) / rot_ref
    scale = np.abs(u_ref).max()
    nodal = np.abs(bottom - u_ref).max() / scale
    layers = np.abs(top - bottom).max() / scale
    md = ["# The whole ply's law in a beam of 3D elements past the fuse (CalculiX)", "",
          f"{os.path.basename(args.structure_h5)}'s mesh ({len(tri)} p2 triangles) extruded along the fibres into "
          f"{len(tri)} C3D15 (one layer, w = 0: plane strain), the edges and steps of "
          f"{os.path.basename(args.scene_file)}, material {name} (layout 3) of {law_file or 'the law'}; against "
          "dualcell-structure on the same law and mesh. "
          + (f"Bonds break between increments (the card's 5th constant): each load level is repeated once "
             f"per debond round of dualcell-structure's and once more ({sum(repeats)} ccx steps); the last two "
             f"rounds of a level differ by {settled:.1e} of the largest displacement."
             if between else "One ccx step per load level; bonds break within it."), "",
          "| load factor | deflection, dualcell-structure | deflection, CalculiX C3D15 | relative difference |",
          "|---|---|---|---|"]
    for t, ref, got in zip(factors, watch_ref, watch_ccx):
        md.append(f"| {t:g} | {-ref[1]:.7e} | {-got[1]:.7e} | {(got[1] - ref[1]) / ref[1]:.1e} |")
    md += ["", "| last step | end rotation | neutral axis y_n/H |", "|---|---|---|",
           f"| dualcell-structure | {rot_ref:.7e} | {axis_ref:.5f} |",
           f"| CalculiX C3D15 with the umat ({seconds:.1f} s) | {rot_ccx:.7e} | {axis_ccx:.5f} |", "",
           f"End rotation: relative difference {error:.2e} (bound 1e-5); largest nodal displacement difference "
           f"{nodal:.2e} of the largest displacement; top layer against bottom {layers:.1e}."]
    common.write_atomic(args.out, "\n".join(md) + "\n")
    print("\n".join(md))
    worst_level = max(abs((got[1] - ref[1]) / ref[1]) for ref, got in zip(watch_ref, watch_ccx))
    if abs(error) > 1e-5:
        sys.exit(f"ccx_solid_beam.py: end rotation differs by {error:.2e} > 1e-5")
    if worst_level > 1e-5:
        sys.exit(f"ccx_solid_beam.py: a load level's deflection differs by {worst_level:.2e} > 1e-5")
    # The rounds asked must have finished the cascade: the last two of a level agree to round-off.
    if settled > 1e-12:
        sys.exit(f"ccx_solid_beam.py: the last two rounds of a level differ by {settled:.1e}: the cascade was "
                 "still breaking bonds")


if __name__ == "__main__":
    common.main_guard(main)
