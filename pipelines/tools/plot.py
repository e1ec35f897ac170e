#!/usr/bin/python3
"""Pictures of dualcell results with gnuplot (PNG and SVG).

usage:
  plot.py stress-strain SWEEP.h5 OUTBASE     s against N:ε per path, the fuse jump marked
  plot.py polar LAW.h5 OUTBASE               E_tension(θ), E_compression(θ), debond onset(θ)
  plot.py deformed SOLUTION.h5 OUTBASE [--mesh MESH.h5]
                                             the deformed mesh with its gaps (exaggerated); with
                                             the mesh the fibres by /mesh/triangle_is_fibre (any
                                             mesher), the rims whose bonds broke as red dots and
                                             the open gaps as orange segments
  plot.py work-precision TABLE.csv OUTBASE   error of E_t, E_c against seconds, log-log
  plot.py accuracy TABLE.csv OUTBASE         the accuracy study: error against seconds per code,
                                             element and sign, log-log (accuracy_table.py's CSV)
  plot.py structure STRUCTURE.h5 OUTBASE     a structure of homogeneous cells at its last step: the
                                             deformed mesh coloured by σxx, fused cells outlined
                                             in red; beside it the load factor against the watch
                                             node's displacement over the steps
  plot.py scaling MODEL.csv OUTBASE          one solve over MPI ranks, weak scaling (bench_mpi.py's
                                             model): seconds per solve by part and the efficiency,
                                             replicated lambda (dualcell) and partitioned (projected)
  plot.py cure SWEEP.h5 OUTBASE --warm WARM.h5
                                             the debond onset |s*| under uniaxial stress along θ
                                             from the onset surfaces of a sweep without and with
                                             the cure's temperature change, side by side
  plot.py lamina TABLE.csv OUTBASE           the bonded RVE against the measured lamina: the
                                             difference per constant and material system
                                             (lamina_table.py's CSV), the constants not compared
                                             and alpha1 (near zero for carbon) left out
  plot.py last-stress SWEEP.h5               prints "sxx,syy,sxy" of the last step of path 000

Writes OUTBASE.png and OUTBASE.svg, each to a temporary name first and renamed when complete.
Debian's python3-h5py reads the files; gnuplot draws.
"""
import csv
import math
import os
import sys
import tempfile

import h5py

import common


def gnuplot(script, outbase, data_files):
    """Runs the gnuplot script once per terminal; data_files maps names to text."""
    outbase = os.path.abspath(outbase)  # gnuplot runs in the data folder
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in data_files.items():
            with open(os.path.join(tmp, name), "w") as f:
                f.write(text)
        for ext, terminal in (("png", "pngcairo size 1000,750 font ',11'"), ("svg", "svg size 1000,750 dynamic")):
            target = f"{outbase}.{ext}"

            def draw(partial):
                full = f"set terminal {terminal}\nset output '{partial}'\n" + script
                run = common.run(["gnuplot"], check=False, input=full, cwd=tmp)
                if run.returncode != 0 or not os.path.exists(partial):
                    sys.exit(f"plot.py: gnuplot failed for {target}: {run.stderr.strip()}")
            common.write_atomic(target, draw)  # the partial file is removed when gnuplot fails


def along(n, e):
    return n[0] * e[0] + n[1] * e[1] + 2 * n[2] * e[2]


def stress_strain(sweep, outbase):
    data, plots, fuses = {}, [], []
    with h5py.File(sweep, "r") as f:
        for i, name in enumerate(sorted(f["paths"])):
            g = f["paths"][name]
            n = g.attrs["unit_stress"]
            direction = g.attrs["direction_deg"]
            label = ("{:g} deg".format(direction) if not math.isnan(direction) else "N = ({:.2g}, {:.2g}, {:.2g})".format(*n))
            label += " tension" if g.attrs["sign"] > 0 else " compression"
            if "eps33" in g.attrs:
                label += " e33 = {:g}".format(float(g.attrs["eps33"]))
            if "gamma" in g.attrs:
                label += " gamma = ({:g}, {:g})".format(*[float(v) for v in g.attrs["gamma"]])
            rows = ["0 0"] + ["{:.10g} {:.10g}".format(along(n, e), s) for s, e in zip(g["load"][:], g["strain"][:])]
            data[f"path{i}.dat"] = "\n".join(rows) + "\n"
            plots.append(f"'path{i}.dat' using 1:2 with linespoints pt 7 ps 0.6 title '{label}'")
            if "fuse" in g:
                z = g["fuse"]
                fuses.append("{:.10g} {:.10g}\n{:.10g} {:.10g}\n\n".format(
                    along(n, z["strain_before"][:]), z["load_before"][0], along(n, z["strain_after"][:]), z["load_after"][0]))
    if fuses:
        data["fuse.dat"] = "".join(fuses)
        plots.append("'fuse.dat' using 1:2 with linespoints lw 3 lc rgb 'red' pt 6 ps 2 title 'fuse jump'")
    script = ("set title 'Macroscopic stress against strain along the load'\nset xlabel 'strain along the load N:ε'\n"
              "set ylabel 'load s (macro stress σ̄ = s·N)'\nset grid\nset key outside right\nset xzeroaxis\nset yzeroaxis\n"
              "plot " + ", \\\n  ".join(plots) + "\n")
    gnuplot(script, outbase, data)


def onset_surface_curve(facets, sign):
    """|s*| of uniaxial stress sign·n⊗n along θ = 0 … 180° from an onset surface's facets
    (s* = 1/max_k g_k·N), as data rows; NaN where no facet is reached."""
    rows = []
    for t in range(0, 181):
        c, s_ = math.cos(math.radians(t)), math.sin(math.radians(t))
        reach = max(sign * (g[0] * c * c + g[1] * s_ * s_ + g[2] * c * s_) for g in facets)
        rows.append("{} {:.10g}\n".format(t, 1 / reach if reach > 0 else float("nan")))
    return "".join(rows)


def cure(sweep, outbase, warm):
    """The onset surfaces of `warm` (no temperature change) and `sweep` (with the scene's
    delta_T, from the cool-down) side by side, on the same axes."""
    panels, data, top = [], {}, 0.0
    for tag, path in (("warm", warm), ("cooled", sweep)):
        with h5py.File(path, "r") as f:
            if int(f["onset"].attrs["linear"]) != 1:
                sys.exit(f"plot.py: {path}: no onset surface ({common.text(f['onset'].attrs.get('message', ''))})")
            facets = f["onset/facets"][:]
            delta_T = float(f.attrs["delta_T"]) if "delta_T" in f.attrs else 0.0
        for sign, name in ((1, "t"), (-1, "c")):
            text = onset_surface_curve(facets, sign)
            data[f"{tag}_{name}.dat"] = text
            top = max([top] + [float(r.split()[1]) for r in text.splitlines() if r.split()[1] != "nan"])
        panels.append((tag, delta_T))
    script = ("set multiplot layout 1,2 title 'Debond onset |s*| under uniaxial stress along θ' noenhanced\n"
              "set grid\nset xrange [0:180]\nset xlabel 'θ (deg)'\nset ylabel '|s*|' noenhanced\n")
    script += f"set yrange [0:{1.1 * top:.6g}]\nset key below vertical maxrows 2 font ',9'\n"
    for tag, delta_T in panels:
        title = "no temperature change" if delta_T == 0 else f"cured: ΔT = {delta_T:g} K, from the cool-down"
        script += (f"set title '{title}' noenhanced\n"
                   f"plot '{tag}_t.dat' using 1:2 with lines lw 2 lc rgb '#009060' title 'tension', \\\n"
                   f"  '{tag}_c.dat' using 1:2 with lines lw 2 lc rgb '#8000c0' title 'compression'\n")
    gnuplot(script + "unset multiplot\n", outbase, data)


def lamina(table, outbase):
    """Bars of the difference (%) of the RVE from the measured lamina, clustered by constant, one
    colour per material system; only the rows the table compares, and not alpha1 (near zero for
    carbon: its relative difference says nothing)."""
    with open(table, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["compared"] == "yes" and r["constant"] != "alpha1"]
    if not rows:
        sys.exit(f"plot.py: {table}: no compared constant")
    systems = list(dict.fromkeys(r["system"] for r in rows))
    constants = list(dict.fromkeys(r["constant"] for r in rows))
    value = {(r["system"], r["constant"]): r["difference_percent"] for r in rows}
    text = "constant " + " ".join(f'"{s}"' for s in systems) + "\n"
    for c in constants:
        text += f'"{c}" ' + " ".join(value.get((s, c), "NaN").lstrip("+") for s in systems) + "\n"
    script = ("set title 'Bonded RVE from the constituents against the measured lamina' noenhanced\n"
              "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
              "set ylabel 'difference from the measured lamina (%)'\nset grid ytics\nset xzeroaxis lt -1\n"
              "set key below noenhanced\n")
    script += "plot " + ", ".join(f"'lamina.dat' using {i + 2}:xtic(1) title columnheader({i + 2})"
                                  for i in range(len(systems))) + "\n"
    gnuplot(script, outbase, {"lamina.dat": text})


def polar(law, outbase):
    with h5py.File(law, "r") as f:
        g = f["law"]
        theta = list(g["direction_deg"][:])
        Et, Ec, onset = list(g["E_tension"][:]), list(g["E_compression"][:]), list(g["onset_stress"][:])
        after = list(g["E_after_fuse"][:])
        # The fitted cone-wise law's moduli around the circle, as dualcell-fit wrote them.
        cone = None
        if "cone" in g and int(g["cone/ok"][0]) == 1 and "cone/polar_deg" in g:
            cone = (list(g["cone/polar_deg"][:]), list(g["cone/polar_E_tension"][:]),
                    list(g["cone/polar_E_compression"][:]))
        # The exact law's moduli (the cell condensed onto its interface rows) and the cone-wise
        # law's error against it, as dualcell-fit measured them.
        # Without an exact law the check is against the sweep's held-out directions (no polar).
        exact, cone_error = None, None
        if "cone_check" in g:
            if "cone_check/polar_deg" in g:
                exact = (list(g["cone_check/polar_deg"][:]), list(g["cone_check/polar_E_tension"][:]),
                         list(g["cone_check/polar_E_compression"][:]))
            against = common.text(g["cone_check"].attrs.get("against", "the exact law"))
            cone_error = (float(g["cone_check/max_error"][0]), float(g["cone_check/rms_error"][0]), against)
        facets, swept = None, []
        if "onset" in g and int(g["onset"].attrs["linear"]) == 1:
            facets = g["onset/facets"][:]
            if "onset/path_stress" in g:
                swept = list(zip(g["onset/path_stress"][:], g["onset/sweep_onset"][:]))
    # E(θ + 180°) = E(θ) exactly (n⊗n is the same tensor): the measured directions are drawn
    # again half a turn on, as a separate block, so that no line crosses unmeasured directions.
    def curve(values, shift):
        return "".join("{:.10g} {:.10g}\n".format(t + shift, v) for t, v in sorted(zip(theta, values))
                       if not math.isnan(v))
    def both(values):
        return curve(values, 0) + "\n\n" + curve(values, 180)
    data = {"Et.dat": both(Et), "Ec.dat": both(Ec)}
    # With adhesion the moduli before any break are the bonded (linear) ones; the tangent
    # modulus past the tension fuse is where tension and compression part.
    after_fuse = ""
    if any(not math.isnan(v) for v in after):
        data["after.dat"] = both(after)
        after_fuse = (", \\\n  'after.dat' using 1:2 with linespoints lw 2 pt 9 lc rgb '#d02020' "
                      "title 'E tension past the fuse'")
    # The fitted cone-wise law's E(θ) over the whole circle, as thin lines beside the points.
    cone_curves = ""
    if cone is not None:
        polar_theta, polar_t, polar_c = cone
        for name, values in (("cone_c.dat", polar_c), ("cone_t.dat", polar_t)):
            data[name] = "".join("{:.10g} {:.10g}\n".format(t, v) for t, v in zip(polar_theta, values))
        cone_curves = (", \\\n  'cone_c.dat' using 1:2 with lines lw 1 dt 2 lc rgb '#8000c0' "
                       "title 'cone-wise law, compression', \\\n  'cone_t.dat' using 1:2 with lines lw 1 dt 2 "
                       "lc rgb '#009060' title 'cone-wise law, tension'")
    # The exact law's E(θ) as solid lines (θ and θ + 180°: n⊗n repeats).
    exact_curves = ""
    if exact is not None:
        polar_theta, polar_t, polar_c = exact
        for name, values in (("exact_c.dat", polar_c), ("exact_t.dat", polar_t)):
            data[name] = "".join("{:.10g} {:.10g}\n".format(t + shift, v) for shift in (0, 180)
                                 for t, v in zip(polar_theta, values) if not math.isnan(v))
        exact_curves = (", \\\n  'exact_c.dat' using 1:2 with lines lw 1 lc rgb '#8000c0' "
                        "title 'exact law, compression', \\\n  'exact_t.dat' using 1:2 with lines lw 1 "
                        "lc rgb '#009060' title 'exact law, tension'")
    title = "Moduli by load direction θ"
    if cone_error is not None:
        title += "\\ncone-wise vs {}: max {:.1f} %, rms {:.1f} %".format(
            cone_error[2], 100 * cone_error[0], 100 * cone_error[1])
    polar_plot = ('set title "' + title + '"\nset polar\nset angles degrees\n'
                  "set grid polar 30\nset size square\nunset border\nunset xtics\nunset ytics\nset rtics\n"
                  "set key below vertical maxrows 4 font ',8'\n"
                  "plot 'Ec.dat' using 1:2 with linespoints lw 2 pt 7 lc rgb '#8000c0' title 'E compression', \\\n"
                  "  'Et.dat' using 1:2 with linespoints lw 2 pt 5 lc rgb '#009060' title 'E tension'" + after_fuse
                  + cone_curves + exact_curves + "\n")
    if any(not math.isnan(v) for v in onset):
        # The onset of uniaxial tension and compression along θ, from the onset surface over
        # every θ (s* = 1/max_k g_k·N, N = ±n⊗n) and as the sweep's paths solved it.
        plots = []
        if facets is not None:
            for name, sign in (("surface_t.dat", 1.0), ("surface_c.dat", -1.0)):
                data[name] = onset_surface_curve(facets, sign)
            plots += ["'surface_t.dat' using 1:2 with lines lw 1 dt 2 lc rgb '#009060' title 'onset surface, tension'",
                      "'surface_c.dat' using 1:2 with lines lw 1 dt 2 lc rgb '#8000c0' "
                      "title 'onset surface, compression'"]
        points = {1: [], -1: []}
        for N, s_star in swept:
            # Uniaxial paths only: N = ±n⊗n has a zero determinant.
            if math.isnan(s_star) or abs(N[0] * N[1] - N[2] * N[2]) > 1e-12:
                continue
            sign = 1 if N[0] + N[1] > 0 else -1
            theta_deg = math.degrees(0.5 * math.atan2(2 * sign * N[2], sign * (N[0] - N[1]))) % 180
            points[sign].append("{:.10g} {:.10g}\n".format(theta_deg, s_star))
        for name, sign, colour, title in (("swept_t.dat", 1, "#009060", "tension"),
                                          ("swept_c.dat", -1, "#8000c0", "compression")):
            if points[sign]:
                data[name] = "".join(sorted(points[sign], key=lambda r: float(r.split()[0])))
                plots.append(f"'{name}' using 1:2 with points pt 7 ps 1.2 lc rgb '{colour}' title 'swept, {title}'")
        if not plots:
            data["onset.dat"] = curve(onset, 0)
            plots = ["'onset.dat' using 1:2 with linespoints lw 2 pt 9 title 'onset'"]
        script = ("set multiplot layout 1,2\n" + polar_plot +
                  "unset polar\nset size nosquare\nset border\nset xtics\nset ytics\nset grid\n"
                  "set key below vertical maxrows 2 font ',9'\nset xrange [0:180]\n"
                  "set title 'Debond onset |s*| under uniaxial stress along θ'\nset xlabel 'θ (deg)'\n"
                  "set ylabel '|s*|'\nplot " + ", \\\n  ".join(plots) + "\nunset multiplot\n")
    else:
        script = polar_plot
    gnuplot(script, outbase, data)


def deformed(solution, outbase, mesh=None):
    with h5py.File(solution, "r") as f:
        nodes = f["/mesh/nodes"][:]
        u = f["/solution/u"][:]
        tri = f["/mesh/triangles"][:]
        sub = f["/mesh/triangle_subdomain"][:]
        stress = f["/macro/stress"][:]
        bonded = f["/interface/bonded"][:]
        opening = f["/interface/opening"][:]
        newly_broken = int(f["/solver"].attrs["newly_broken"])
    # Without the mesh: the mapped mesher's alternation of matrix and fibre subdomains.
    is_fibre, pairs = [int(s) % 2 for s in sub], None
    if mesh is not None:
        with h5py.File(mesh, "r") as f:
            is_fibre = f["/mesh/triangle_is_fibre"][:]
            pairs = f["/mesh/interface_pairs"][:]
    # Exaggerated so that the largest displacement is 12 % of the block: gaps become visible.
    size = max(nodes[:, 0].max() - nodes[:, 0].min(), nodes[:, 1].max() - nodes[:, 1].min())
    largest = abs(u).max()
    scale = 0.12 * size / largest if largest > 0 else 1.0
    x = nodes + scale * u
    # The outline of each triangle: corners for 3-node triangles; for 6-node ones corner, mid-side
    # node, corner, ... (rows: corners 0, 1, 2, then the middles of (0,1), (1,2), (2,0)), so that
    # curved rim edges show as two chords.
    outline = [0, 1, 2, 0] if tri.shape[1] == 3 else [0, 3, 1, 4, 2, 5, 0]
    lines = {0: [], 1: []}
    for t, fibre in zip(tri, is_fibre):
        lines[int(fibre)].append("".join("{:.8g} {:.8g}\n".format(*x[t[k]]) for k in outline) + "\n")
    data = {"matrix.dat": "".join(lines[0]), "fibre.dat": "".join(lines[1])}
    plots = ["'matrix.dat' with lines lw 0.6 lc rgb '#404040' title 'matrix'",
             "'fibre.dat' with lines lw 0.6 lc rgb '#c02080' title 'fibres'"]
    if pairs is not None and len(pairs) == len(bonded):
        # Bonds exist where some pair is bonded or this load broke some (else: no adhesion, no
        # red). Pair rows are (fibre node, matrix node). An open gap: opening above 1e-9 of the
        # block (the solver's complementarity is ~1e-8 relative).
        adhesion = bool(bonded.any()) or newly_broken > 0
        broken = "".join("{:.8g} {:.8g}\n".format(*x[p[1]]) for p, b in zip(pairs, bonded) if adhesion and not b)
        gaps = "".join("{:.8g} {:.8g}\n{:.8g} {:.8g}\n\n".format(*x[p[0]], *x[p[1]])
                       for p, g in zip(pairs, opening) if g > 1e-9 * size)
        if gaps:
            data["gaps.dat"] = gaps
            plots.append("'gaps.dat' with lines lw 2 lc rgb '#ff9900' title 'open gap'")
        if broken:
            data["broken.dat"] = broken
            plots.append("'broken.dat' with points pt 7 ps 0.3 lc rgb '#e00000' title 'broken bond'")
    script = ("set title 'Deformed mesh at σ̄ = ({:.3g}, {:.3g}, {:.3g}), displacements × {:.3g}'\n".format(*stress, scale) +
              "set size ratio -1\nset key outside bottom horizontal\nset xlabel 'x'\nset ylabel 'y'\nplot " +
              ", ".join(plots) + "\n")
    gnuplot(script, outbase, data)


def work_precision(table, outbase):
    rows = [line.strip().split(",") for line in open(table) if line.strip() and not line.startswith("#")]
    header, rows = rows[0], rows[1:]
    col = {name: i for i, name in enumerate(header)}
    series = {}
    for r in rows:
        series.setdefault(r[col["degree"]], []).append(r)
    data, plots = {}, []
    # One colour per degree; tension solid with discs, compression dashed with squares.
    for colour, (k, rs) in enumerate(sorted(series.items(), key=lambda kv: int(kv[0])), start=1):
        rs.sort(key=lambda r: float(r[col["seconds"]]))
        for which in ("tension", "compression"):
            name = f"k{k}_{which}.dat"
            data[name] = "".join(f"{r[col['seconds']]} {r[col['error_' + which]]}\n" for r in rs
                                 if float(r[col["error_" + which]]) > 0)
            style = "pt 7 dt 1" if which == "tension" else "pt 5 dt 2"
            plots.append(f"'{name}' using 1:2 with linespoints {style} lc {colour} title 'degree {k}, E {which}'")
    script = ("set title 'Error of the moduli against run time (reference: Richardson extrapolation)'\n"
              "set logscale xy\nset xlabel 'seconds (mesh + sweep)'\nset ylabel 'relative error'\nset grid\n"
              "set key outside right\nset format y '10^{%L}'\nplot " + ", \\\n  ".join(plots) + "\n")
    gnuplot(script, outbase, data)


def last_stress(sweep):
    with h5py.File(sweep, "r") as f:
        s = f["paths"]["000"]["stress"][-1]
    print("{:.17g},{:.17g},{:.17g}".format(*s))


def accuracy(table, outbase):
    rows = [line.strip().split(",") for line in open(table) if line.strip() and not line.startswith("#")]
    header, rows = rows[0], rows[1:]
    col = {name: i for i, name in enumerate(header)}
    series = {}
    for r in rows:
        which = "tension" if float(r[col["load"]]) > 0 else "compression"
        series.setdefault((r[col["code"]], r[col["element"]], which), []).append(r)
    data, plots = {}, []
    colours = {}
    for (code, element, which), rs in sorted(series.items()):
        rs.sort(key=lambda r: float(r[col["seconds"]]))
        name = f"{code}_{element}_{which}.dat"
        data[name] = "".join(f"{r[col['seconds']]} {r[col['relative_error']]}\n" for r in rs
                             if float(r[col["relative_error"]]) > 0)
        colour = colours.setdefault((code, element), len(colours) + 1)
        style = "pt 7 dt 1" if which == "tension" else "pt 5 dt 2"
        plots.append(f"'{name}' using 1:2 with linespoints {style} lc {colour} lw 1.5 title '{code} {element}, {which}'")
    script = ("set title 'Apparent modulus of one cell: relative error against run time'\n"
              "set logscale xy\nset xlabel 'seconds (whole commands, best of repeats)'\nset ylabel 'relative error'\n"
              "set grid\nset key outside right\nset format y '10^{%L}'\n"
              "set arrow from graph 0, first 1e-4 to graph 1, first 1e-4 nohead dt 3 lc rgb '#808080'\nplot "
              + ", \\\n  ".join(plots) + "\n")
    gnuplot(script, outbase, data)


def structure(h5, outbase):
    with h5py.File(h5, "r") as f:
        nodes, tri, cell = f["/mesh/nodes"][:], f["/mesh/triangles"][:], f["/mesh/cell"][:]
        factor, watch = f["/steps/factor"][:], f["/steps/watch_displacement"][:]
        last = sorted(k for k in f["/steps"].keys() if k.isdigit())[-1]
        u, stress, fused = f[f"/steps/{last}/displacement"][:], f[f"/steps/{last}/stress"][:], f[f"/steps/{last}/fused"][:]
        # The exact law marks the triangles whose bonds (of their cell, or of a point) broke.
        unit = common.text(f.attrs["bond_unit"]) if common.text(f.attrs.get("law_form", "")) == "cell" else None
    outlined = {None: "fused cells", "cell": "cells with broken bonds", "point": "cells with a broken point"}[unit]
    size = max(nodes[:, 0].max() - nodes[:, 0].min(), nodes[:, 1].max() - nodes[:, 1].min())
    largest = abs(u).max()
    scale = 0.1 * size / largest if largest > 0 else 1.0
    x = nodes + scale * u
    # Each triangle filled with its σxx (corners only: the picture, not the field, is linear),
    # the outline of every fused cell's triangles in red.
    faces, outlines = [], []
    for t, s_t, fz in zip(tri, stress, fused):
        corners = [x[t[k]] for k in (0, 1, 2)]
        faces.append("".join(f"{p[0]:.8g} {p[1]:.8g} {s_t[0]:.8g}\n" for p in corners + corners[:1]) + "\n")
        if fz:
            outlines.append("".join(f"{p[0]:.8g} {p[1]:.8g}\n" for p in corners + corners[:1]) + "\n")
    n_fused = len({int(c) for c, z in zip(cell, fused) if z})
    data = {"faces.dat": "".join(faces), "fused.dat": "".join(outlines) or "nan nan\n",
            "steps.dat": "0 0 0\n" + "".join(f"{w[0]:.10g} {w[1]:.10g} {t:.10g}\n" for w, t in zip(watch, factor))}
    script = ("set multiplot layout 2,1\n"
              f"set title 'Structure at load factor {factor[-1]:.4g}: σxx per element, displacements × {scale:.3g}; "
              f"{n_fused} {outlined} outlined'\n"
              "set size ratio -1\nunset key\nset palette defined (-1 '#2040c0', 0 '#f0f0f0', 1 '#c02020')\n"
              "stats 'faces.dat' using 3 nooutput\nlim = (abs(STATS_min) > abs(STATS_max) ? abs(STATS_min) : abs(STATS_max))\n"
              "set cbrange [-lim:lim]\nset cblabel 'σxx'\n"
              "plot 'faces.dat' using 1:2:3 with filledcurves closed fillcolor palette z, "
              "'fused.dat' using 1:2 with lines lw 1.5 lc rgb '#e00000'\n"
              "set size noratio\nset title 'Load factor against the watch node displacement'\n"
              "set xlabel 'displacement'\nset ylabel 'load factor'\nset key top left\nset grid\nunset colorbox\n"
              "plot 'steps.dat' using 2:3 with linespoints pt 7 title 'u_y', 'steps.dat' using 1:3 with linespoints "
              "pt 5 dt 2 title 'u_x'\nunset multiplot\n")
    gnuplot(script, outbase, data)


def scaling(table, outbase):
    rows = [line.strip().split(",") for line in open(table) if line.strip()]
    header, rows = rows[0], rows[1:]
    col = {name: i for i, name in enumerate(header)}
    data, plots = {}, []
    parts = ("setup", "compute", "vector", "coarse", "communication", "total")
    for kind, dt in (("replicated", 1), ("partitioned", 2)):
        rs = [r for r in rows if r[col["kind"]] == kind]
        data[f"{kind}.dat"] = "".join(" ".join([r[col["ranks"]]] + [r[col[p]] for p in parts] + [r[col["efficiency"]]])
                                      + "\n" for r in rs)
        for i, part in enumerate(parts):
            if kind == "partitioned" and part != "total":
                continue
            plots.append(f"'{kind}.dat' using 1:{i + 2} axes x1y1 with linespoints dt {dt} pt {i + 4} lc {i + 1} "
                         f"title '{kind}: {part}'")
        plots.append(f"'{kind}.dat' using 1:8 axes x1y2 with linespoints dt {dt} lw 3 pt 7 lc 8 "
                     f"title '{kind}: efficiency (right)'")
    script = ("set title 'One solve over MPI ranks, weak scaling (model from measured unit costs)'\n"
              "set logscale x 2\nset logscale y\nset xlabel 'ranks (subdomains per rank fixed)'\n"
              "set ylabel 'seconds per solve'\nset y2label 'efficiency T(1)/T(P)'\nset y2range [0:1.05]\n"
              "set y2tics\nset ytics nomirror\nset grid\nset key outside right\nplot "
              + ", \\\n  ".join(plots) + "\n")
    gnuplot(script, outbase, data)


# Each picture: its function and the metavar of its input.
PICTURES = {"stress-strain": (stress_strain, "SWEEP.h5"), "polar": (polar, "LAW.h5"),
            "deformed": (deformed, "SOLUTION.h5"), "work-precision": (work_precision, "TABLE.csv"),
            "accuracy": (accuracy, "TABLE.csv"), "structure": (structure, "STRUCTURE.h5"),
            "scaling": (scaling, "MODEL.csv"), "cure": (cure, "SWEEP.h5"),
            "lamina": (lamina, "TABLE.csv")}


def main(argv):
    parser = common.Parser(__doc__)
    kinds = parser.add_subparsers(dest="kind", metavar="KIND", required=True)
    for kind, (_, source) in PICTURES.items():
        p = kinds.add_parser(kind)
        p.add_argument("source", metavar=source)
        p.add_argument("outbase", metavar="OUTBASE")
        if kind == "deformed":
            p.add_argument("--mesh", metavar="MESH.h5", help="the mesh.h5 of the solution (fibres, rim pairs)")
        if kind == "cure":
            p.add_argument("--warm", metavar="WARM.h5", required=True,
                           help="the sweep of the same cell without the temperature change")
    kinds.add_parser("last-stress").add_argument("source", metavar="SWEEP.h5")
    args = parser.parse_args(argv[1:])
    if args.kind == "last-stress":
        return last_stress(args.source)
    if args.kind == "deformed":
        return deformed(args.source, args.outbase, args.mesh)
    if args.kind == "cure":
        return cure(args.source, args.outbase, args.warm)
    PICTURES[args.kind][0](args.source, args.outbase)


if __name__ == "__main__":
    common.main_guard(main)
