#!/usr/bin/python3
"""The CalculiX half of the accuracy study: one dualcell mesh solved by ccx, apparent modulus out.

usage: ccx_cell.py MESH.h5 LOAD OUT.csv [--penalty F] [--bonded] [--fibre E NU] [--matrix E NU]
                   [--regularisation R] [--load-scale S] [--continuation C] [--repeat N]
                   [--ccx PATH] [--work DIR] [--label TEXT]

Reads a `mesh.h5` of dualcell-mesh (p1: T×3 triangles -> CPE3; p2: T×6 -> CPE6, whose node
order, corners counter-clockwise then the mid-side nodes of edges (0,1), (1,2), (2,0), is
CalculiX's) and solves the `symmetry` load case of docs/method.md §12 under σ̄ = (LOAD, 0, 0):

- element sets of fibre and matrix, isotropic elastic, plane strain of thickness 1; materials
  from the mesh's own scene (its `scene` and `material` attributes) unless --fibre/--matrix;
- u_x = 0 on x = x_min, u_y = 0 on y = y_min (nodes found by coordinate);
- σ̄·n on the right edge as *DLOAD P<face> = −σ̄xx on the faces with both corners on x = x_max
  (a CalculiX pressure pushes into the element: tension is a negative pressure); the top edge
  carries σ̄·n = 0; coincident matrix nodes of neighbouring cells (glue pairs) are merged;
- per cell a face-to-face penalty contact pair (*CONTACT PAIR, TYPE=SURFACE TO SURFACE), slave
  the matrix faces on the hole, master the fibre faces on the rim (faces whose nodes are
  consecutive interface nodes), frictionless (no *FRICTION), linear pressure-overclosure of
  slope K = F·E_m/h (--penalty F, default 1e5; h = cell_size/(4·degree), /(8·degree) for p2: the
  node spacing on the cell edge). F = 1e5 moves E by at most 2.4e-5 relative against F = 1e7
  (compression at degree 4; 1e-5 at degree 16; tension < 1e-6). --bonded merges every interface
  pair instead: the linear bonded problem, no contact.

How ccx is made to solve the same problem as dualcell (all measured on scenes/accuracy.toml):

- Small load. ccx searches contact in the current (deformed) geometry at the start of every
  increment and step even without NLGEOM; at σ̄ = 0.01 the fibre slides along the hole by up to
  ~40 % of an element at degree 32, so re-matching changes E by up to 2e-3 and slows the
  iterations. dualcell's model is geometrically linear, E does not depend on |σ̄|, and the
  bulk is linear in ccx too, so ccx runs at σ̄·S (--load-scale S, default 1e-4): E changes by
  < 2e-7 between S = 1e-4 and 1e-6 (4e-6 tension, 2e-5 compression at S = 1e-2). The CSV
  reports LOAD and E = σ̄xx/ε̄xx of the scaled run.
- Penalty continuation. A single step with the final slope often cycles (the set of active
  contact points repeats without converging; ccx then cuts back and scales the penalty down by
  100, and the result is wrong). The deck instead runs steps F = 1e3, 1e3·C, ... up to F, each
  *CHANGE SURFACE BEHAVIOR starting from the last solution (--continuation C, default 10 for
  CPE3 and √10 for CPE6, whose quadratic faces cycled with 10 at degree 8). A cut-back attempt
  in the .sta file gives a warning on stderr. Limit: CPE6 at degree 16 still cycles in tension
  (also with C = 10^(1/4)) and ends in "increment size smaller than minimum".
- Regularisation: the fibre is held by frictionless contact alone, and a face-to-face element
  carries force only where it penetrates, so an iterate with too few active points would leave
  the fibre floating (singular). Three one-node springs (SPRING1) tie the fibre to the ground:
  u_x and u_y at its node nearest the centre and u_y at its rim node at angle 0 (translations
  and rotation), each R·E_m (force per length at thickness 1; --regularisation R, default
  1e-8). Between R = 0 and 1e-8 E changes by < 5e-9 relative (degree 8; 1e-6: 4e-7,
  1e-4: 4e-5); in practice ccx starts with every contact point active, and R = 0 also ran.
  *SURFACE BEHAVIOR's tension value σ∞ would be no help: CalculiX uses it only for node-to-face
  contact.
- Tight iterations: *CONTROLS FIELD R_n = C_n = 1e-9 (average force estimated as |σ̄|·h),
  CONTACT delcon = 0 (convergence needs an unchanged set of contact elements), at most 200
  iterations per increment; no NLGEOM; automatic increments towards time 1 in every step.

ccx runs in a scratch folder (--work DIR keeps it, with cell.log; default a temporary folder
beside OUT.csv, removed after) with OMP_NUM_THREADS=1 and CCX_NPROC_*=1; only its wall time is
measured, the fastest of --repeat N runs (default 1). The displacements of the left and right
edge nodes come from *NODE PRINT (.dat, 7 significant digits, which limits E to about 1e-8
relative) at the end of the last step, and

    ε̄xx = (1/|Ω|) (∫_right u_x dy − ∫_left u_x dy),   E = σ̄xx / ε̄xx

integrated exactly with the edges' shape functions (trapezoid on 2-node edges, weights 1/6,
4/6, 1/6 on 3-node edges), |Ω| the bounding box of the nodes: the boundary average strain of
docs/method.md §12 (on dualcell's own u it reproduces /macro/strain to 1e-15).

Writes OUT.csv atomically (temporary + rename): a header and one row
code,element,degree,nodes,dofs,load,E,seconds,iterations,penalty
(code `ccx` or `ccx-bonded`, element CPE3/CPE6, nodes of the 2D model after merging and
dofs = 2·nodes, iterations: ccx's ITRS summed over every attempt, increment and step of the .sta
file; penalty: the final slope K, empty when bonded), and prints the row. Errors: one line on
stderr, exit 1.
"""
import math
import os
import shutil
import sys
import tempfile
import tomllib

import h5py
import numpy as np

import common

HEADER = "code,element,degree,nodes,dofs,load,E,seconds,iterations,penalty"
# Local edges of a triangle in CalculiX's face numbering (faces 1, 2, 3 = corners 1-2, 2-3, 3-1)
# with the index of the mid-side node of each edge in a 6-node triangle.
EDGES = ((0, 1, 3), (1, 2, 4), (2, 0, 5))


class Mesh:
    """What the deck needs from mesh.h5, with glue pairs (and, bonded, interface pairs) merged."""

    def __init__(self, path, bonded):
        try:
            f = h5py.File(path, "r")
        except OSError as e:
            raise ValueError(f"{path}: cannot open as HDF5 ({e})")
        with f:
            if "mesh" not in f or "nodes" not in f["mesh"] or "triangles" not in f["mesh"]:
                raise ValueError(f"{path}: no /mesh/nodes and /mesh/triangles: not a dualcell mesh.h5")
            g = f["mesh"]
            self.nodes = g["nodes"][:]
            triangles = g["triangles"][:].astype(np.int64)
            self.is_fibre = g["triangle_is_fibre"][:].astype(bool)
            self.pairs = g["interface_pairs"][:].astype(np.int64)
            self.pair_cell = g["interface_cell"][:].astype(np.int64)
            glue = g["glue_pairs"][:].astype(np.int64).reshape(-1, 2)
            self.centres = g["fibre_centres"][:]
            self.degree = int(g.attrs["degree"])
            self.cell_size = float(g.attrs["cell_size"])
            element = g.attrs.get("element", "p1")
            self.order = common.text(element)
            self.scene = common.text(f.attrs.get("scene", ""))
            self.material = common.text(f.attrs.get("material", ""))
        if self.nodes.ndim != 2 or self.nodes.shape[1] != 2:
            raise ValueError(f"{path}: /mesh/nodes has shape {self.nodes.shape}, expected N×2")
        width = triangles.shape[1] if triangles.ndim == 2 else 0
        if width not in (3, 6):
            raise ValueError(f"{path}: /mesh/triangles has shape {triangles.shape}, expected T×3 or T×6")
        if (width == 6) != (self.order == "p2"):
            raise ValueError(f"{path}: element attribute {self.order!r} but triangles of {width} nodes")
        if len(self.is_fibre) != len(triangles):
            raise ValueError(f"{path}: /mesh/triangle_is_fibre has {len(self.is_fibre)} rows, "
                             f"/mesh/triangles {len(triangles)}")
        self.quadratic = width == 6
        # Merging: every node maps to a representative; the rim is found before merging.
        rep = np.arange(len(self.nodes))
        merged = [glue] + ([self.pairs] if bonded else [])  # the lower index represents each set
        for pairs in merged:
            for a, b in pairs:
                ra, rb = _find(rep, a), _find(rep, b)
                if ra != rb:
                    rep[max(ra, rb)] = min(ra, rb)
        self.rep = np.array([_find(rep, i) for i in range(len(rep))])
        self.rim_faces = None if bonded else self._rim_faces(triangles)
        self.triangles = self.rep[triangles]
        self.used = np.unique(self.triangles)  # the nodes of the model (representatives that elements use)

    def _rim_faces(self, triangles):
        """Per cell: (matrix faces, fibre faces) on the interface, each face (element, face 1..3)."""
        position = {}  # node -> (cell, position along the rim, rim length)
        for cell in np.unique(self.pair_cell):
            rows = self.pairs[self.pair_cell == cell]
            for side in (0, 1):
                for i, node in enumerate(rows[:, side]):
                    position[int(node)] = (int(cell), i, len(rows))
        step = 2 if self.quadratic else 1
        faces = {}
        for e, tri in enumerate(triangles):
            for face, (i, j, m) in enumerate(EDGES, start=1):
                a, b = int(tri[i]), int(tri[j])
                if a not in position or b not in position:
                    continue
                (ca, pa, n), (cb, pb, _) = position[a], position[b]
                if ca != cb or (pb - pa) % n not in (step, n - step):
                    continue
                if self.quadratic:
                    mid = position.get(int(tri[m]))
                    if mid is None or mid[0] != ca or {(mid[1] - pa) % n, (pb - mid[1]) % n} - {1, n - 1}:
                        continue
                side = 1 if self.is_fibre[e] else 0
                faces.setdefault(ca, ([], []))[side].append((e + 1, face))
        for cell, (matrix, fibre) in faces.items():
            count = len(self.pairs[self.pair_cell == cell]) // step
            if len(matrix) != count or len(fibre) != count:
                raise ValueError(f"cell {cell}: found {len(matrix)} hole and {len(fibre)} rim faces, "
                                 f"expected {count} each")
        return faces


def _find(rep, i):
    while rep[i] != i:
        rep[i] = rep[rep[i]]
        i = rep[i]
    return i


def scene_materials(mesh):
    """(fibre (E, nu), matrix (E, nu)) from the mesh's scene: inline tables or its material file."""
    try:
        scene = tomllib.loads(mesh.scene) if mesh.scene else {}
        source = tomllib.loads(mesh.material) if "material" in scene and mesh.material else scene
        return tuple((float(source[t]["E"]), float(source[t]["nu"])) for t in ("fibre", "matrix"))
    except (tomllib.TOMLDecodeError, KeyError, TypeError, ValueError) as e:
        raise ValueError(f"cannot read the materials from the mesh's scene ({e}); give --fibre and --matrix")


def boundary_faces(mesh, axis, value, tol):
    """Element faces with both corners on the line x_axis = value: [(element, face, (a, b, mid))]."""
    on = np.abs(mesh.nodes[:, axis] - value) <= tol
    out = []
    for e, tri in enumerate(mesh.triangles):
        for face, (i, j, m) in enumerate(EDGES, start=1):
            if on[tri[i]] and on[tri[j]]:
                out.append((e + 1, face, (tri[i], tri[j], tri[m] if mesh.quadratic else -1)))
    return out


def edge_integral(faces, nodes, u):
    """∫ u ds along the faces (straight edges): trapezoid, or 1/6, 4/6, 1/6 with the mid-side node."""
    total = 0.0
    for _, _, (a, b, m) in faces:
        length = math.dist(nodes[a], nodes[b])
        if m < 0:
            total += length * (u[a] + u[b]) / 2
        else:
            total += length * (u[a] + 4 * u[m] + u[b]) / 6
    return total


def real(x):
    """A real for the deck: 13 digits, a decimal point (CalculiX tells reals from integers by it) and
    at most 19 characters (ccx reads numeric fields of 20 characters and cuts longer ones)."""
    return f"{x:.12e}"


def _lines(values, per_line=8):
    values = list(values)
    return "\n".join(", ".join(str(v) for v in values[i:i + per_line]) for i in range(0, len(values), per_line))


def penalty_ladder(final, ratio=10.0, first=1e3):
    """Penalty factors of the continuation: first, ratio·first, ... below final, then final itself."""
    ladder = []
    factor = min(first, final)
    while factor < final * (1 - 1e-9):
        ladder.append(factor)
        factor *= ratio
    return ladder + [final]


def regularising_springs(mesh):
    """Per fibre: (node, dof) of u_x and u_y at its node nearest the centre and u_y at its rim node
    at angle 0 (the two translations and the rotation of a floating fibre)."""
    fibre_nodes = np.unique(mesh.triangles[mesh.is_fibre].ravel())
    springs = []
    for cell, centre in enumerate(mesh.centres):
        rim = mesh.pairs[mesh.pair_cell == cell][:, 0]
        if len(rim) == 0:
            continue
        middle = fibre_nodes[np.argmin(np.linalg.norm(mesh.nodes[fibre_nodes] - centre, axis=1))]
        rel = mesh.nodes[rim] - centre
        zero = mesh.rep[rim[np.argmin(np.abs(np.arctan2(rel[:, 1], rel[:, 0])))]]
        springs += [(middle, 1), (middle, 2), (zero, 2)]
    return springs


def write_deck(mesh, load, fibre, matrix, slopes, spring, right, left_nodes, bottom_nodes, print_nodes, h):
    """The deck: model, then one step per penalty slope of the continuation (one step when bonded)."""
    element = "CPE6" if mesh.quadratic else "CPE3"
    out = ["*HEADING", f"ccx_cell.py: dualcell mesh, degree {mesh.degree} {mesh.order}, sxx = {load!r}",
           "*NODE, NSET=NALL"]
    out += [f"{i + 1}, {real(mesh.nodes[i, 0])}, {real(mesh.nodes[i, 1])}" for i in mesh.used]
    for name, mask in (("EFIBRE", mesh.is_fibre), ("EMATRIX", ~mesh.is_fibre)):
        out.append(f"*ELEMENT, TYPE={element}, ELSET={name}")
        out += [f"{e + 1}, " + ", ".join(str(n + 1) for n in mesh.triangles[e]) for e in np.flatnonzero(mask)]
    out += ["*NSET, NSET=NLEFT", _lines(n + 1 for n in left_nodes),
            "*NSET, NSET=NBOTTOM", _lines(n + 1 for n in bottom_nodes),
            "*NSET, NSET=NPRINT", _lines(n + 1 for n in print_nodes)]
    for name, (E, nu) in (("FIBRE", fibre), ("MATRIX", matrix)):
        out += [f"*MATERIAL, NAME={name}", "*ELASTIC", f"{real(E)}, {real(nu)}",
                f"*SOLID SECTION, ELSET=E{name}, MATERIAL={name}", "1."]
    contact = mesh.rim_faces is not None
    if contact:
        out += ["*SURFACE INTERACTION, NAME=RIM", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", real(slopes[0])]
        for cell, (hole, rim) in sorted(mesh.rim_faces.items()):
            out.append(f"*SURFACE, NAME=HOLE{cell}, TYPE=ELEMENT")
            out += [f"{e}, S{face}" for e, face in hole]
            out.append(f"*SURFACE, NAME=RIM{cell}, TYPE=ELEMENT")
            out += [f"{e}, S{face}" for e, face in rim]
            out += ["*CONTACT PAIR, INTERACTION=RIM, TYPE=SURFACE TO SURFACE", f"HOLE{cell}, RIM{cell}"]
        springs = regularising_springs(mesh) if spring > 0 else []
        first = len(mesh.triangles) + 1
        for dof in (1, 2):
            ids = [(first + i, n) for i, (n, d) in enumerate(springs) if d == dof]
            if ids:
                out.append(f"*ELEMENT, TYPE=SPRING1, ELSET=SPRING{dof}")
                out += [f"{e}, {n + 1}" for e, n in ids]
                out += [f"*SPRING, ELSET=SPRING{dof}", f"{dof}", real(spring)]  # the real needs its decimal point
    out += ["*BOUNDARY", "NLEFT, 1, 1", "NBOTTOM, 2, 2"]
    # Tight convergence: residual and correction 1e-9 relative (the average force estimated as
    # |σ̄| h, so that a small load is not taken for zero flux), and with contact every change in
    # the set of contact elements counts (delcon = 0), at most 200 iterations per increment.
    controls = ["*CONTROLS, PARAMETERS=FIELD", f"1e-9, 1e-9, {real(abs(load) * h)}, , 1e-9, 1e-5, 1e-9, 1e-12"]
    if contact:
        controls += ["*CONTROLS, PARAMETERS=CONTACT", "0., 0.1, 100, 200"]
    for j, slope in enumerate(slopes if contact else [None]):
        out += ["*STEP, INC=1000", "*STATIC", "1., 1., 1e-6, 1."] + controls
        if j == 0:
            out.append("*DLOAD")
            out += [f"{e}, P{face}, {real(-load)}" for e, face, _ in right]
        else:
            out += ["*CHANGE SURFACE BEHAVIOR, INTERACTION=RIM", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
                    real(slope)]
        if j == (len(slopes) - 1 if contact else 0):
            out += ["*NODE PRINT, NSET=NPRINT", "U"]
        out.append("*END STEP")
    return "\n".join(out) + "\n"


def read_displacements(dat_path):
    """{node id: (ux, uy)} of the last *NODE PRINT block of U (the end of the last step) in the .dat file."""
    blocks, current = [], None
    with open(dat_path) as f:
        for line in f:
            if line.lstrip().startswith("displacements (vx,vy,vz)"):
                current = {}
                blocks.append((float(line.split()[-1]), current))
                continue
            fields = line.split()
            if current is not None and len(fields) == 4:
                try:
                    current[int(fields[0])] = (float(fields[1]), float(fields[2]))
                except ValueError:
                    current = None
            elif current is not None and fields:
                current = None
    if not blocks or not blocks[-1][1]:
        raise RuntimeError(f"{dat_path}: no displacements printed (did ccx converge?)")
    return blocks[-1][1]


def read_status(sta_path):
    """(iterations, failed attempts) from the .sta file: ITRS summed over every attempt of every
    increment of every step, and the attempts marked U (not converged, cut back)."""
    iterations = failed = 0
    if not os.path.exists(sta_path):
        return 0, 0
    with open(sta_path) as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 4 and fields[0].isdigit() and fields[1].isdigit() and fields[3].isdigit():
                iterations += int(fields[3])
                failed += fields[2].endswith("U")
    return iterations, failed


def parse_args(argv):
    """The command line (a negative LOAD such as -1e-2 is a value, not an option: common.Parser)."""
    parser = common.Parser(__doc__)
    parser.add_argument("mesh", metavar="MESH.h5")
    parser.add_argument("load", metavar="LOAD", type=float)
    parser.add_argument("out", metavar="OUT.csv")
    parser.add_argument("--penalty", metavar="F", type=float, default=1e5)
    parser.add_argument("--bonded", action="store_true")
    parser.add_argument("--fibre", metavar=("E", "NU"), type=float, nargs=2)
    parser.add_argument("--matrix", metavar=("E", "NU"), type=float, nargs=2)
    parser.add_argument("--regularisation", metavar="R", type=float, default=1e-8)
    parser.add_argument("--load-scale", metavar="S", type=float, default=1e-4)
    parser.add_argument("--continuation", metavar="C", type=float)
    parser.add_argument("--repeat", metavar="N", type=int, default=1)
    parser.add_argument("--ccx", metavar="PATH", default="ccx")
    parser.add_argument("--work", metavar="DIR")
    parser.add_argument("--label", metavar="TEXT")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        raise ValueError(f"--repeat {args.repeat}: expected an integer >= 1")
    return args


def main(argv):
    args = parse_args(argv[1:])
    if not (math.isfinite(args.load) and args.load != 0):
        raise ValueError(f"LOAD {args.load!r}: expected a finite non-zero number")
    mesh = Mesh(args.mesh, args.bonded)
    if args.continuation is None:  # the default ratio (module docstring)
        args.continuation = math.sqrt(10.0) if mesh.quadratic else 10.0
    if not (args.penalty > 0 and args.regularisation >= 0 and args.load_scale > 0 and args.continuation > 1):
        raise ValueError("--penalty and --load-scale must be > 0, --regularisation >= 0, --continuation > 1")
    fibre, matrix = scene_materials(mesh) if args.fibre is None or args.matrix is None else (None, None)
    fibre = tuple(args.fibre) if args.fibre else fibre
    matrix = tuple(args.matrix) if args.matrix else matrix
    for name, (E, nu) in (("fibre", fibre), ("matrix", matrix)):
        if not (E > 0 and -1 < nu < 0.5):
            raise ValueError(f"{name} E = {E!r}, nu = {nu!r}: expected E > 0 and -1 < nu < 0.5")

    used = mesh.nodes[mesh.used]
    lo, hi = used.min(axis=0), used.max(axis=0)
    tol = 1e-9 * float(np.max(hi - lo))
    right = boundary_faces(mesh, 0, hi[0], tol)
    left = boundary_faces(mesh, 0, lo[0], tol)
    bottom = boundary_faces(mesh, 1, lo[1], tol)
    if not right or not left or not bottom:
        raise ValueError(f"{args.mesh}: no element faces on one of the edges x = {lo[0]}, x = {hi[0]}, y = {lo[1]}")
    edge_nodes = lambda faces: sorted({int(n) for _, _, f in faces for n in f if n >= 0})  # noqa: E731
    left_nodes, bottom_nodes = edge_nodes(left), edge_nodes(bottom)
    print_nodes = sorted(set(left_nodes) | set(edge_nodes(right)))
    h = mesh.cell_size / (4 * mesh.degree * (2 if mesh.quadratic else 1))
    slopes = [factor * matrix[0] / h for factor in penalty_ladder(args.penalty, args.continuation)]
    load = args.load * args.load_scale  # what ccx applies (module docstring)
    deck = write_deck(mesh, load, fibre, matrix, slopes, args.regularisation * matrix[0], right, left_nodes,
                      bottom_nodes, print_nodes, h)

    out_dir = os.path.dirname(os.path.abspath(args.out))
    work = args.work or tempfile.mkdtemp(prefix="ccx_cell.", dir=out_dir)
    os.makedirs(work, exist_ok=True)
    try:
        job = "cell"
        with open(os.path.join(work, job + ".inp"), "w") as f:
            f.write(deck)
        env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1", CCX_NPROC_STIFFNESS="1",
                   CCX_NPROC_RESULTS="1")
        seconds, u = math.inf, None
        for _ in range(args.repeat):  # the same deterministic run; the fastest is the least disturbed
            for stale in (".dat", ".sta", ".frd", ".cvg"):
                if os.path.exists(os.path.join(work, job + stale)):
                    os.remove(os.path.join(work, job + stale))
            done = common.run_ccx(args.ccx, work, job, env)
            seconds = min(seconds, done.seconds)
            with open(os.path.join(work, job + ".log"), "w") as f:
                f.write(done.stdout)
            run = read_displacements(os.path.join(work, job + ".dat"))
            if u is not None and run != u:
                raise RuntimeError("two runs of the same deck gave different displacements")
            u = run
        iterations, failed = read_status(os.path.join(work, job + ".sta"))
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
    missing = [n for n in print_nodes if n + 1 not in u]
    if missing:
        raise RuntimeError(f"ccx printed no displacement of node {missing[0] + 1}")
    ux = np.zeros(len(mesh.nodes))
    for n in print_nodes:
        ux[n] = u[n + 1][0]
    area = float(np.prod(hi - lo))
    strain = (edge_integral(right, mesh.nodes, ux) - edge_integral(left, mesh.nodes, ux)) / area
    if strain == 0:
        raise RuntimeError("the boundary strain is zero")
    if failed:
        sys.stderr.write(f"ccx_cell.py: warning: {args.mesh}, load {args.load!r}: {failed} increment attempt(s) "
                         "did not converge and were cut back (the penalty may have been scaled down meanwhile)\n")
    code = args.label or ("ccx-bonded" if args.bonded else "ccx")
    element = "CPE6" if mesh.quadratic else "CPE3"
    row = (f"{code},{element},{mesh.degree},{len(mesh.used)},{2 * len(mesh.used)},{args.load!r},"
           f"{load / strain!r},{seconds:.6f},{iterations},{'' if args.bonded else repr(slopes[-1])}")
    common.write_atomic(args.out, HEADER + "\n" + row + "\n")
    print(row)


if __name__ == "__main__":
    common.main_guard(main)
