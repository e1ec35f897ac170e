#!/usr/bin/python3
"""The structures validation: homogenised cells (dualcell-structure) against the resolved block
(dualcell-solve with boundary = "edges") for beams of depth H cells and length 8H.

usage:
  structures.py scenes CELL_SCENE BOND KIND H OUTDIR
      writes OUTDIR/resolved.toml and OUTDIR/structure.toml: the same beam, edge conditions and
      load, once with every cell resolved as in CELL_SCENE and once of homogeneous cells.
      KIND: bending (a moment at the free end; the left end a roller, one point held in y),
      cantilever (end shear, left end fixed), threepoint (supports at the lower corners, a point
      load at the top midspan). BOND: contact (no adhesion: the cell scene's strengths are
      dropped) or adhesion (the cell scene's strengths; a small step, below the first break).
  structures.py table OUTROOT CASE...
      CASE = BOND/KIND-H<H>: reads OUTROOT/CASE/{solution.h5, structure.h5, seconds_*} and
      writes OUTROOT/table.csv and OUTROOT/table.md (errors of the homogenised model against the
      resolved one, first break against first fuse, time ratio).
  structures.py plot OUTROOT
      OUTROOT/deflection.{png,svg}: the end rotation or deflection per unit load against H, both
      models, per case (from table.csv).

Every number is read from the stage outputs; nothing is typed in.
"""
import csv
import math
import os
import sys
import tomllib

import h5py
import numpy as np

import common
from plot import gnuplot

# Load levels: the largest bending stress about 0.01 (stress units of the cell scene) at t = 1
# whatever H (cantilever: M = τH·L at the root, σ = 6M/H² = 48τ; three-point: M = P·L/4,
# σ = 12P/H); with adhesion the step is t = STEP_ADHESION, meant to stay below the first break
# (the table says whether it did).
SIGMA = 0.01
STEP_ADHESION = 0.1


def edges_text(kind, L, H):
    if kind == "bending":
        return (f"[edges.left]\ntype = \"roller\"\n[edges.right]\ntype = \"traction\"\n"
                f"traction = [{SIGMA}, 0]\ntraction_end = [{-SIGMA}, 0]\n"
                f"[[support]]\nat = [0, 0]\nfix = \"y\"\n[output]\nwatch = [{L}, 0]\n")
    if kind == "cantilever":
        tau = SIGMA / 48
        return (f"[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\ntraction = [0, {-tau:.12g}]\n"
                f"[output]\nwatch = [{L}, 0]\n")
    if kind == "threepoint":
        P = SIGMA * H / 12
        return (f"[[support]]\nat = [0, 0]\nfix = \"xy\"\n[[support]]\nat = [{L}, 0]\nfix = \"y\"\n"
                f"[[point_load]]\nat = [{L / 2:g}, {H}]\nforce = [0, {-P:.12g}]\n[output]\nwatch = [{L / 2:g}, 0]\n")
    sys.exit(f"structures.py: unknown kind '{kind}' (bending, cantilever, threepoint)")


def scenes(cell_scene, bond, kind, H, outdir):
    with open(cell_scene, "rb") as f:
        cell = tomllib.load(f)
    H = int(H)
    L = 8 * H
    geometry = cell["geometry"]
    a = geometry.get("cell_size", 1.0)
    material = cell.get("material")
    head = ""
    if material:
        head = f"material = \"{os.path.abspath(os.path.join(os.path.dirname(cell_scene), material))}\"\n"
    else:
        for name in ("fibre", "matrix"):
            head += f"[{name}]\nE = {cell[name]['E']}\nnu = {cell[name]['nu']}\n"
    step = 1.0 if bond == "contact" else STEP_ADHESION
    interface = ""
    if bond == "adhesion":
        i = cell.get("interface", {})
        if not (i.get("normal_strength", 0) > 0 or i.get("tangential_strength", 0) > 0):
            sys.exit(f"structures.py: {cell_scene} has no adhesion, so no 'adhesion' case can be made from it")
        interface = (f"[interface]\nnormal_strength = {i.get('normal_strength', 0)}\n"
                     f"tangential_strength = {i.get('tangential_strength', 0)}\n")
    elif bond != "contact":
        sys.exit(f"structures.py: unknown bond '{bond}' (contact, adhesion)")
    edges = edges_text(kind, L * a, H * a)
    os.makedirs(outdir, exist_ok=True)
    resolved = (f"# {kind}, H = {H}, {bond}: every cell resolved as in {os.path.basename(cell_scene)}\n" + head +
                f"[geometry]\ncells = [{L}, {H}]\ncell_size = {a}\nfibre_radius = {geometry['fibre_radius']}\n"
                f"degree = {geometry.get('degree', 1)}\nelement = \"{geometry.get('element', 'p2')}\"\n" + interface +
                "[load]\nboundary = \"edges\"\n" + edges + f"[steps]\nfactors = [{step}]\n")
    structure = (f"# {kind}, H = {H}, {bond}: homogeneous cells with the fitted law\n"
                 f"[structure]\ncells = [{L}, {H}]\nelements_per_cell = 2\nelement = \"p2\"\n" + edges +
                 f"[steps]\nfactors = [{step}]\n")
    common.write_atomic(os.path.join(outdir, "resolved.toml"), resolved)
    common.write_atomic(os.path.join(outdir, "structure.toml"), structure)


def line_fit(y, ux):
    """ux = s·y + b by least squares: returns (rotation −s, neutral axis −b/s)."""
    A = np.column_stack([y, np.ones_like(y)])
    (s, b), *_ = np.linalg.lstsq(A, ux, rcond=None)
    return -s, -b / s


def measures(case_dir, kind):
    """Per model: the case's quantity per unit load factor, the neutral axis at the loaded end
    (bending), the first break/fuse factor, seconds."""
    out = {}
    with h5py.File(os.path.join(case_dir, "solution.h5"), "r") as f:
        nodes, u = f["/mesh/nodes"][:], f["/solution/u"][:]
        t = f["/steps/factor"][-1]
        watch = f["/steps/watch_displacement"][-1]
        res = {"first": float(f["/steps"].attrs["first_break_factor"]), "broken": int(f["/steps/broken"][-1]),
               "converged": int(f["/steps/converged"][-1])}
    res.update(per_model(kind, nodes, u, t, watch))
    with h5py.File(os.path.join(case_dir, "structure.h5"), "r") as f:
        nodes, t = f["/mesh/nodes"][:], f["/steps/factor"][-1]
        last = sorted(k for k in f["/steps"].keys() if k.isdigit())[-1]
        u = f[f"/steps/{last}/displacement"][:]
        watch = f["/steps/watch_displacement"][-1]
        hom = {"first": float(f["/steps"].attrs["first_fuse_factor"]), "broken": int(f["/steps/newly_fused_cells"][:].sum()),
               "converged": int(f["/steps/converged"][-1])}
    hom.update(per_model(kind, nodes, u, t, watch))
    for name, model in (("resolved", res), ("homogenised", hom)):
        with open(os.path.join(case_dir, f"seconds_{name}")) as f:
            model["seconds"] = float(f.read())
    return res, hom


def per_model(kind, nodes, u, t, watch):
    L = nodes[:, 0].max()
    m = {}
    if kind == "bending":
        right = np.abs(nodes[:, 0] - L) < 1e-9 * L
        rotation, axis = line_fit(nodes[right, 1], u[right, 0])
        m["value"], m["axis"] = rotation / t, axis / nodes[:, 1].max()
    else:
        m["value"], m["axis"] = -watch[1] / t, float("nan")
    return m


QUANTITY = {"bending": "end rotation", "cantilever": "tip deflection", "threepoint": "midspan deflection"}


def table(outroot, cases):
    rows = []
    for case in cases:
        bond, rest = case.split("/")
        kind, H = rest.rsplit("-H", 1)
        res, hom = measures(os.path.join(outroot, case), kind)
        error = (hom["value"] - res["value"]) / res["value"]
        first_error = (hom["first"] - res["first"]) / res["first"] if math.isfinite(res["first"]) else float("nan")
        rows.append({
            "bond": bond, "kind": kind, "H": int(H), "quantity": QUANTITY[kind],
            "resolved": res["value"], "homogenised": hom["value"], "error": error,
            "axis_resolved": res["axis"], "axis_homogenised": hom["axis"],
            "first_break_resolved": res["first"], "first_fuse_homogenised": hom["first"], "first_error": first_error,
            "broken_in_step": res["broken"], "fused_in_step": hom["broken"],
            "converged": min(res["converged"], hom["converged"]),
            "seconds_resolved": res["seconds"], "seconds_homogenised": hom["seconds"],
            "time_ratio": res["seconds"] / hom["seconds"]})
    rows.sort(key=lambda r: (r["bond"], r["kind"], r["H"]))
    fields = list(rows[0].keys())

    def write_csv(path):
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.9g}" if isinstance(v, float) else v) for k, v in r.items()})
    common.write_atomic(os.path.join(outroot, "table.csv"), write_csv)

    def pct(x):
        return "–" if not math.isfinite(x) else f"{100 * x:+.2f} %"

    def g(x):
        return "–" if not math.isfinite(x) else f"{x:.4g}"

    md = ["# Homogenised cells against the resolved structure",
          "",
          "Beams of depth H cells and length 8H; per unit load factor: bending the end rotation (right",
          "end, least-squares line through the section), cantilever the tip deflection −u_y(L, 0),",
          "three-point bend the midspan deflection −u_y(L/2, 0). Neutral axis y_n/H from the bending",
          "section (0 = bottom; the bottom is in tension). First break: the load factor at which the first",
          "bond breaks (resolved) or the first cell leaves the onset surface (homogenised), both exact.",
          "Seconds: mesh + solve (resolved), the structure stage (homogenised); the law's sweep and fit",
          "are done once for all cases and not counted.",
          "",
          "| bond | case | H | resolved | homogenised | error | y_n/H res. | y_n/H hom. | first break res. | "
          "first fuse hom. | error | broken / fused in step | s res. | s hom. | ratio |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['bond']} | {r['quantity']} | {r['H']} | {r['resolved']:.5g} | {r['homogenised']:.5g} | "
                  f"{pct(r['error'])} | {g(r['axis_resolved'])} | {g(r['axis_homogenised'])} | "
                  f"{g(r['first_break_resolved'])} | {g(r['first_fuse_homogenised'])} | {pct(r['first_error'])} | "
                  f"{r['broken_in_step']} / {r['fused_in_step']} | {r['seconds_resolved']:.2f} | "
                  f"{r['seconds_homogenised']:.3f} | {r['time_ratio']:.0f} |" +
                  ("" if r["converged"] else " NOT converged"))
    common.write_atomic(os.path.join(outroot, "table.md"), "\n".join(md) + "\n")


def plot(outroot):
    with open(os.path.join(outroot, "table.csv")) as f:
        rows = list(csv.DictReader(f))
    data, plots = {}, []
    series = {}
    for r in rows:
        series.setdefault((r["bond"], r["kind"]), []).append(r)
    for colour, ((bond, kind), rs) in enumerate(sorted(series.items()), start=1):
        rs.sort(key=lambda r: int(r["H"]))
        name = f"{bond}_{kind}.dat"
        # Normalised by the resolved value at the largest H, so that every case shares one axis.
        ref = float(rs[-1]["resolved"])
        data[name] = "".join(f"{r['H']} {float(r['resolved']) / ref} {float(r['homogenised']) / ref}\n" for r in rs)
        plots.append(f"'{name}' using 1:2 with linespoints pt 7 dt 1 lc {colour} title '{bond}, {QUANTITY[kind]}: resolved'")
        plots.append(f"'{name}' using 1:3 with linespoints pt 5 dt 2 lc {colour} title '{bond}, {QUANTITY[kind]}: homogenised'")
    script = ("set title 'Beams of depth H cells, length 8H: homogenised cells against the resolved structure'\n"
              "set logscale x 2\nset xlabel 'H (cells through the depth)'\n"
              "set ylabel 'rotation or deflection / resolved value at the largest H'\nset grid\n"
              "set key outside below\nplot " + ", \\\n  ".join(plots) + "\n")
    gnuplot(script, os.path.join(outroot, "deflection"), data)


def main(argv):
    parser = common.Parser(__doc__)
    modes = parser.add_subparsers(dest="mode", metavar="MODE", required=True)
    p = modes.add_parser("scenes")
    p.add_argument("cell_scene", metavar="CELL_SCENE")
    p.add_argument("bond", metavar="BOND")
    p.add_argument("kind", metavar="KIND")
    p.add_argument("H")
    p.add_argument("outdir", metavar="OUTDIR")
    p = modes.add_parser("table")
    p.add_argument("outroot", metavar="OUTROOT")
    p.add_argument("cases", metavar="CASE", nargs="+")
    modes.add_parser("plot").add_argument("outroot", metavar="OUTROOT")
    args = vars(parser.parse_args(argv[1:]))
    {"scenes": scenes, "table": table, "plot": plot}[args.pop("mode")](**args)


if __name__ == "__main__":
    common.main_guard(main)
