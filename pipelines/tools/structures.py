#!/usr/bin/python3
"""The structures validation: homogenised cells (dualcell-structure) against the resolved block
(dualcell-solve with boundary = "edges") for beams of depth H cells and length 8H.

usage:
  structures.py scenes CELL_SCENE BOND KIND H OUTDIR
      writes OUTDIR/resolved.toml and OUTDIR/structure.toml: the same beam, edge conditions and
      load, once with every cell resolved as in CELL_SCENE and once of homogeneous cells (and
      OUTDIR/structure-point.toml, that with the exact law's bonds per quadrature point).
      KIND: bending (a moment at the free end; the left end a roller, one point held in y),
      cantilever (end shear, left end fixed), threepoint (supports at the lower corners, a point
      load at the top midspan), fuse (the cantilever in steps FUSE_STEPS, well past its first
      break, then unloaded; adhesion only). BOND: contact (no adhesion: the cell scene's
      strengths are dropped) or adhesion (the cell scene's strengths; a small step, below the
      first break).
  structures.py table OUTROOT CASE...
      CASE = BOND/KIND-H<H>: reads OUTROOT/CASE/{solution.h5, structure.h5, structure-cell.h5,
      seconds_*} and writes OUTROOT/table.csv and OUTROOT/table.md (errors of the homogenised
      models, cone-wise and exact law, against the resolved one, first break against first fuse,
      time ratio).
  structures.py fuse OUTROOT CASE...
      CASE = adhesion/fuse-H<H>: the tip deflection per step of the models (resolved, cone-wise
      law, exact law with the bonds per cell, and per point where structure-point.h5 exists):
      OUTROOT/fuse.csv, fuse.md (per H the largest error over the steps past the first break, and
      the first break) and fuse.{png,svg} (load against deflection).
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
# The fuse cases: up to three times the load, past the resolved cantilever's first break (about
# 1.07 at H = 2), and back to half of it.
FUSE_STEPS = [0.5, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 1.5]


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
    steps = [1.0] if bond == "contact" else [STEP_ADHESION]
    if kind == "fuse":
        if bond != "adhesion":
            sys.exit("structures.py: the fuse case needs adhesion (BOND adhesion)")
        steps, kind = FUSE_STEPS, "cantilever"
    factors = "[steps]\nfactors = [" + ", ".join(f"{t:g}" for t in steps) + "]\n"
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
                "[load]\nboundary = \"edges\"\n" + edges + factors)
    structure = (f"# {kind}, H = {H}, {bond}: homogeneous cells with the fitted law\n"
                 f"[structure]\ncells = [{L}, {H}]\nelements_per_cell = 2\nelement = \"p2\"\n" + edges + factors)
    common.write_atomic(os.path.join(outdir, "resolved.toml"), resolved)
    common.write_atomic(os.path.join(outdir, "structure.toml"), structure)
    # The same with the exact law's bonds per quadrature point instead of per cell.
    common.write_atomic(os.path.join(outdir, "structure-point.toml"),
                        structure.replace("element = \"p2\"\n", "element = \"p2\"\nbonds = \"point\"\n", 1))


def line_fit(y, ux):
    """ux = s·y + b by least squares: returns (rotation −s, neutral axis −b/s)."""
    A = np.column_stack([y, np.ones_like(y)])
    (s, b), *_ = np.linalg.lstsq(A, ux, rcond=None)
    return -s, -b / s


MODELS = (("resolved", "solution.h5"), ("cone", "structure.h5"), ("cell", "structure-cell.h5"))


def read_model(path, kind, step=-1):
    """One model's measures at load step `step`: the case's quantity per unit load factor, the
    neutral axis at the loaded end (bending), the first break/fuse factor, bonds broken or cells
    fused over the run, convergence."""
    with h5py.File(path, "r") as f:
        nodes, factor = f["/mesh/nodes"][:], f["/steps/factor"][:]
        watch = f["/steps/watch_displacement"][:]
        converged = f["/steps/converged"][:]
        if "/solution" in f:  # dualcell-solve: the last step's field only
            u = f["/solution/u"][:]
            m = {"first": float(f["/steps"].attrs["first_break_factor"]), "broken": int(f["/steps/broken"][-1])}
        else:
            last = sorted(k for k in f["/steps"].keys() if k.isdigit())[step]
            u = f[f"/steps/{last}/displacement"][:]
            broken = "/steps/newly_broken" if common.text(f.attrs.get("law_form", "")) == "cell" else "/steps/newly_fused_cells"
            m = {"first": float(f["/steps"].attrs["first_fuse_factor"]), "broken": int(f[broken][:].sum())}
    m["converged"] = int(converged.min())
    m.update(per_model(kind, nodes, u, factor[step], watch[step]))
    m["factors"], m["deflection"] = factor, -watch[:, 1]
    return m


def measures(case_dir, kind):
    """Per model (resolved, cone, cell): read_model at the last step, and its seconds."""
    out = {}
    for name, file in MODELS:
        out[name] = read_model(os.path.join(case_dir, file), kind)
        seconds = {"resolved": "seconds_resolved", "cone": "seconds_homogenised", "cell": "seconds_homogenised_cell"}
        with open(os.path.join(case_dir, seconds[name])) as f:
            out[name]["seconds"] = float(f.read())
    return out


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


def write_rows_csv(path, rows):
    """rows (dicts with the same keys) as a CSV with a header, floats to 9 digits, atomically."""
    def write(temporary):
        with open(temporary, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.9g}" if isinstance(v, float) else v) for k, v in r.items()})
    common.write_atomic(path, write)


def relative(a, b):
    return (a - b) / b if math.isfinite(b) and b != 0 else float("nan")


def table(outroot, cases):
    rows = []
    for case in cases:
        bond, rest = case.split("/")
        kind, H = rest.rsplit("-H", 1)
        m = measures(os.path.join(outroot, case), kind)
        res, cone, cell = m["resolved"], m["cone"], m["cell"]
        rows.append({
            "bond": bond, "kind": kind, "H": int(H), "quantity": QUANTITY[kind],
            "resolved": res["value"], "homogenised": cone["value"], "error": relative(cone["value"], res["value"]),
            "exact": cell["value"], "exact_error": relative(cell["value"], res["value"]),
            "axis_resolved": res["axis"], "axis_homogenised": cone["axis"], "axis_exact": cell["axis"],
            "first_break_resolved": res["first"], "first_fuse_homogenised": cone["first"],
            "first_error": relative(cone["first"], res["first"]),
            "first_break_exact": cell["first"], "first_exact_error": relative(cell["first"], res["first"]),
            "broken_in_step": res["broken"], "fused_in_step": cone["broken"], "broken_exact": cell["broken"],
            "converged": min(res["converged"], cone["converged"], cell["converged"]),
            "seconds_resolved": res["seconds"], "seconds_homogenised": cone["seconds"],
            "seconds_exact": cell["seconds"], "time_ratio": res["seconds"] / cone["seconds"],
            "time_ratio_exact": res["seconds"] / cell["seconds"]})
    rows.sort(key=lambda r: (r["bond"], r["kind"], r["H"]))
    write_rows_csv(os.path.join(outroot, "table.csv"), rows)

    md = ["# Homogenised cells against the resolved structure",
          "",
          "Beams of depth H cells and length 8H; per unit load factor: bending the end rotation (right",
          "end, least-squares line through the section), cantilever the tip deflection −u_y(L, 0),",
          "three-point bend the midspan deflection −u_y(L/2, 0). Homogenised twice: with the cone-wise",
          "law (the fuse per cell) and with the exact law (every quadrature point the condensed cell,",
          "the bonds of its cell). Neutral axis y_n/H from the bending section (0 = bottom; the bottom",
          "is in tension). First break: the load factor at which the first bond breaks (resolved, exact",
          "law) or the first cell leaves the onset surface (cone-wise law), all exact. Seconds: mesh +",
          "solve (resolved), the structure stage (homogenised); the law's sweep and fit are done once",
          "for all cases and not counted.",
          "",
          "| bond | case | H | resolved | cone-wise | error | exact law | error | y_n/H res. / cone / exact | "
          "first break res. | first fuse cone | error | first break exact | error | broken res. / fused cone / "
          "broken exact | s res. | s cone | s exact | ratio cone / exact |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        axes = " / ".join(g(r[k]) for k in ("axis_resolved", "axis_homogenised", "axis_exact"))
        md.append(f"| {r['bond']} | {r['quantity']} | {r['H']} | {r['resolved']:.5g} | {r['homogenised']:.5g} | "
                  f"{pct(r['error'])} | {r['exact']:.5g} | {pct(r['exact_error'])} | {axes} | "
                  f"{g(r['first_break_resolved'])} | {g(r['first_fuse_homogenised'])} | {pct(r['first_error'])} | "
                  f"{g(r['first_break_exact'])} | {pct(r['first_exact_error'])} | "
                  f"{r['broken_in_step']} / {r['fused_in_step']} / {r['broken_exact']} | {r['seconds_resolved']:.2f} | "
                  f"{r['seconds_homogenised']:.3f} | {r['seconds_exact']:.3f} | "
                  f"{r['time_ratio']:.0f} / {r['time_ratio_exact']:.0f} |" + ("" if r["converged"] else " NOT converged"))
    common.write_atomic(os.path.join(outroot, "table.md"), "\n".join(md) + "\n")


def pct(x):
    return "–" if not math.isfinite(x) else f"{100 * x:+.2f} %"


def g(x):
    return "–" if not math.isfinite(x) else f"{x:.4g}"


def fuse(outroot, cases):
    """Load–deflection past the first break: per H and step the tip deflection of the three models."""
    rows, summary, data, plots = [], [], {}, []
    for colour, case in enumerate(sorted(cases, key=lambda c: int(c.rsplit("-H", 1)[1])), start=1):
        H = int(case.rsplit("-H", 1)[1])
        m = {name: read_model(os.path.join(outroot, case, file), "cantilever")
             for name, file in MODELS + (("point", "structure-point.h5"),)}
        res = m["resolved"]
        if not all(len(m[k]["factors"]) == len(res["factors"]) for k in m):
            sys.exit(f"structures.py: {case}: the models have different load steps")
        first = res["first"]
        worst = {"cone": 0.0, "cell": 0.0, "point": 0.0}
        past = False
        lines = ""
        for k, t in enumerate(res["factors"]):
            past = past or t > first
            row = {"H": H, "step": k, "factor": float(t), "past_first_break": int(past)}
            for name in ("resolved", "cone", "cell", "point"):
                row[name] = float(m[name]["deflection"][k])
            for name in ("cone", "cell", "point"):
                row[f"{name}_error"] = relative(row[name], row["resolved"])
                if past:
                    worst[name] = max(worst[name], abs(row[f"{name}_error"]))
            rows.append(row)
            lines += f"{row['resolved']} {row['cone']} {row['cell']} {t} {row['point']}\n"
        peak = int(np.argmax(res["factors"]))
        at_peak = {name: relative(float(m[name]["deflection"][peak]), float(res["deflection"][peak]))
                   for name in ("cone", "cell", "point")}
        summary.append({"H": H, "first_resolved": first, "first_cone": m["cone"]["first"],
                        "peak_cone": at_peak["cone"], "peak_cell": at_peak["cell"], "peak_point": at_peak["point"],
                        "first_cell": m["cell"]["first"], "first_point": m["point"]["first"],
                        "worst_cone": worst["cone"], "worst_cell": worst["cell"], "worst_point": worst["point"],
                        "converged": min(m[k]["converged"] for k in m)})
        name = f"fuse_H{H}.dat"
        data[name] = lines
        plots.append(f"'{name}' using 1:4 with linespoints pt 7 dt 1 lc {colour} title 'H = {H}: resolved'")
        plots.append(f"'{name}' using 3:4 with linespoints pt 5 dt 2 lc {colour} title 'H = {H}: exact law'")
        plots.append(f"'{name}' using 2:4 with linespoints pt 4 dt 3 lc {colour} title 'H = {H}: cone-wise law'")
        plots.append(f"'{name}' using 5:4 with linespoints pt 6 dt 4 lc {colour} title 'H = {H}: exact law, bonds per point'")

    write_rows_csv(os.path.join(outroot, "fuse.csv"), rows)
    md = ["# The cantilever past the first break: load against tip deflection",
          "",
          f"Cantilevers of depth H cells and length 8H (adhesion), the end shear in steps {FUSE_STEPS} (load",
          "factors; the last unloads), bond history carried through the steps. Per H: the first break of",
          "each model and the largest relative error of the tip deflection over the steps from the",
          "resolved first break on (fuse.csv has every step).",
          "",
          "Exact law: bonds per cell (the default) and per quadrature point (`bonds = \"point\"`). The",
          "error at the largest load is the tip deflection's at the step of the largest factor.",
          "",
          "| H | first break res. | first fuse cone | first break exact, per cell | per point | "
          "max error past it: cone | exact, per cell | per point | at the largest load: cone | exact, per cell | "
          "per point |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in summary:
        md.append(f"| {r['H']} | {g(r['first_resolved'])} | {g(r['first_cone'])} | {g(r['first_cell'])} | "
                  f"{g(r['first_point'])} | {100 * r['worst_cone']:.1f} % | {100 * r['worst_cell']:.1f} % | "
                  f"{100 * r['worst_point']:.1f} % | {pct(r['peak_cone'])} | {pct(r['peak_cell'])} | "
                  f"{pct(r['peak_point'])} |" +
                  ("" if r["converged"] else " NOT converged"))
    common.write_atomic(os.path.join(outroot, "fuse.md"), "\n".join(md) + "\n")
    script = ("set title 'Cantilevers of depth H cells past the first break: resolved and homogenised'\n"
              "set xlabel 'tip deflection −u_y(L, 0) (cell sizes)'\nset ylabel 'load factor'\nset logscale x\n"
              "set grid\nset key outside below\nplot " + ", \\\n  ".join(plots) + "\n")
    gnuplot(script, os.path.join(outroot, "fuse"), data)


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
        data[name] = "".join(f"{r['H']} {float(r['resolved']) / ref} {float(r['homogenised']) / ref} "
                             f"{float(r['exact']) / ref}\n" for r in rs)
        plots.append(f"'{name}' using 1:2 with linespoints pt 7 dt 1 lc {colour} title '{bond}, {QUANTITY[kind]}: resolved'")
        plots.append(f"'{name}' using 1:3 with linespoints pt 4 dt 3 lc {colour} title '{bond}, {QUANTITY[kind]}: cone-wise law'")
        plots.append(f"'{name}' using 1:4 with linespoints pt 5 dt 2 lc {colour} title '{bond}, {QUANTITY[kind]}: exact law'")
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
    p = modes.add_parser("fuse")
    p.add_argument("outroot", metavar="OUTROOT")
    p.add_argument("cases", metavar="CASE", nargs="+")
    args = vars(parser.parse_args(argv[1:]))
    {"scenes": scenes, "table": table, "plot": plot, "fuse": fuse}[args.pop("mode")](**args)


if __name__ == "__main__":
    common.main_guard(main)
