#!/usr/bin/python3
"""The RVE-size study: random fibre RVEs of N fibres, several realisations each, their transverse
law against N (docs/results/rve.md).

usage:
  rve_study.py BIN_DIR OUT_DIR MATERIAL [--fibres 1 4 9 16 36 64] [--realisations 5]
               [--volume-fraction 0.5] [--extra 0.6] [--extra-fibres 36] [--degree 2]

Per RVE (mean radius 1, standard deviation 0.05, min_gap 0.05, the square of side
sqrt(N pi / v_f), seed = realisation + 1, p2 at the degree), two sweeps and their fits:
  bonded   interface strengths 0.05, uniaxial stress 1e-3 along 0, 45, 90, 135 deg (below the
           onset): the compliance S (/law/S_tension), E(theta) = 1/(v.S.v) with
           v = (c^2, s^2, cs), nu = -S_xy/S_xx, G = 1/S_shear, the anisotropy max/min E(theta),
           and the debond onset stress along 0 deg from the onset surface;
  contact  no adhesion, +-1e-2 along 0 and 90 deg: E_t and E_c (their mean over the two).
Each RVE's files stay in OUT_DIR/N<n>-r<k>/ and a finished RVE is not run again (resume).
Writes OUT_DIR/table.md (with the exact law of the contact RVEs against N: kept or why not, and
what the compact law was checked against), table.csv (per N: mean and standard deviation over the realisations;
`extra`: one realisation set at the extra volume fraction), convergence.png/svg (each figure's
mean +- sd against N, relative to the largest N's mean), microstructures.png/svg (one
realisation per N, fibres on their mesh) and debonded-N<n>.png/svg (that realisation, bonded,
under sxx = 1.2 x its onset along 0 deg: the broken rims and open gaps on the deformed mesh;
its solution in N<n>-r0/debonded/).
"""
import io
import math
import os
import statistics
import sys

import h5py

import common
import plot

FIGURES = [("E", "E (bonded, mean over theta)"), ("nu", "nu xy (bonded)"), ("G", "G (bonded)"),
           ("anisotropy", "max/min E(theta) (bonded)"), ("E_t", "E_t (contact)"), ("E_c", "E_c (contact)"),
           ("onset", "debond onset stress at 0 deg")]


def scene_text(material, n, seed, vf, degree, bonded):
    side = math.sqrt(n * math.pi / vf)
    text = (f'material = "{material}"\n\n[geometry]\nsize = [{side!r}, {side!r}]\nkind = "random"\n'
            f"volume_fraction = {vf}\nradius = [1.0, 0.05]\nmin_gap = 0.05\nseed = {seed}\ndegree = {degree}\n\n"
            '[load]\nboundary = "periodic"\n\n')
    if bonded:
        return text + ("[interface]\nnormal_strength = 0.05\ntangential_strength = 0.05\n\n"
                       "[sweep]\ndirections_deg = [0, 45, 90, 135]\nmagnitudes = [1e-3]\n")
    return text + "[sweep]\ndirections_deg = [0, 90]\nmagnitudes = [-1e-2, 1e-2]\n"


def with_solver(text, **settings):
    """The scene text with a [solver] table of the given settings (tolerance=1e-5, ...) appended."""
    return text + "\n[solver]\n" + "".join(f"{k} = {v!r}\n" for k, v in settings.items())


# The load of the debonded pictures, over the onset along 0 deg.
DEBOND_LOAD = 1.2


def debond(bin_dir, folder, load):
    """The bonded RVE in folder under sxx = load: debonded/solution.h5 (kept: resume)."""
    out = os.path.join(folder, "debonded", "solution.h5")
    if not os.path.exists(out):
        os.makedirs(os.path.dirname(out), exist_ok=True)
        bonded = os.path.join(folder, "bonded")
        # Exit 4 (the QP stopped short of its tolerance, stagnated near it) is good enough for a
        # picture: kept, and said on stderr.
        common.run_stage([os.path.join(bin_dir, "dualcell-solve"), "--quiet", "--config",
                          os.path.join(bonded, "scene.toml"), "--mesh", os.path.join(bonded, "mesh.h5"),
                          "--stress", f"{load!r},0,0", "--out", out], out, unconverged_kept=True)
    return out


def run_case(bin_dir, folder, text):
    """The scene `text` through mesh -> sweep -> fit in folder (common.law_chain); skipped when
    law.h5 is there (a finished case)."""
    law = os.path.join(folder, "law.h5")
    if os.path.exists(law):
        return law
    os.makedirs(folder, exist_ok=True)
    scene = os.path.join(folder, "scene.toml")
    common.write_atomic(scene, text)
    common.law_chain(bin_dir, scene, folder)
    return law


def bonded_figures(law):
    with h5py.File(law, "r") as f:
        S = f["law/S_tension"][:]
        facets = f["law/onset/facets"][:] if "law/onset/facets" in f else None
    moduli = []
    for deg in range(180):
        t = math.radians(deg)
        v = (math.cos(t) ** 2, math.sin(t) ** 2, math.cos(t) * math.sin(t))
        moduli.append(1 / sum(v[i] * S[i][j] * v[j] for i in range(3) for j in range(3)))
    onset = math.nan
    if facets is not None and len(facets):
        onset = 1 / max(g[0] for g in facets)
    return {"E": statistics.fmean(moduli), "anisotropy": max(moduli) / min(moduli), "nu": -S[0][1] / S[0][0],
            "G": 1 / S[2][2], "onset": onset}


def contact_figures(law):
    with h5py.File(law, "r") as f:
        return {"E_t": float(f["law/E_tension"][:].mean()), "E_c": float(f["law/E_compression"][:].mean())}


def law_checks(law):
    """The exact law of a law.h5 (its interface rows, or why it has none) and its compact law's
    check (against what, largest error)."""
    with h5py.File(law, "r") as f:
        g = f["law"]
        out = {"rows": len(g["cell/pair"]) if "cell" in g else None, "note": common.text(g.attrs["cell_note"]),
               "against": None, "max_error": math.nan}
        if "cone_check" in g:
            out["against"] = common.text(g["cone_check"].attrs.get("against", "the exact law"))
            out["max_error"] = float(g["cone_check/max_error"][0])
    return out


def exact_law_lines(checks):
    """The exact law against N: checks maps (v_f, N) to the law_checks of each realisation's
    contact law."""
    lines = ["| v_f | N | exact law kept | interface rows | why not (first realisation without) | "
             "compact law checked against: max error (mean) |", "|---|---|---|---|---|---|"]
    for (vf, n), cs in checks.items():
        kept = [c for c in cs if c["rows"] is not None]
        rows = f"{statistics.fmean(c['rows'] for c in kept):.0f}" if kept else ""
        why = next((c["note"] for c in cs if c["rows"] is None), "")
        against = sorted({c["against"] for c in cs if c["against"]})
        errors = [c["max_error"] for c in cs if math.isfinite(c["max_error"])]
        if errors:
            checked = ", ".join(against) + f": {100 * statistics.fmean(errors):.1f} %"
        else:  # a held-out check whose refits all failed is unbounded; no check at all is none
            checked = ", ".join(against) + ": unbounded (no law fits the other directions alone)" if against else "none"
        lines.append(f"| {vf} | {n} | {len(kept)} of {len(cs)} | {rows} | {why} | {checked} |")
    return lines


def microstructure_data(mesh_file):
    """Fibre triangles as gnuplot polygons (corner nodes), and the RVE's size."""
    with h5py.File(mesh_file, "r") as f:
        nodes, triangles = f["mesh/nodes"][:], f["mesh/triangles"][:]
        fibre = f["mesh/triangle_is_fibre"][:]
        size = f["mesh"].attrs["size"]
    out = io.StringIO()
    for t, is_fibre in zip(triangles, fibre):
        if is_fibre:
            for v in list(t[:3]) + [t[0]]:
                out.write(f"{nodes[v][0]} {nodes[v][1]}\n")
            out.write("\n")
    return out.getvalue(), size


def representative(samples, key, tol):
    """The smallest N from which every N's mean of `key` stays within tol of the largest N's mean
    and its scatter (sd/mean, where there is one) stays below tol; None when no N does.
    samples: N -> {key_mean, key_sd}."""
    ns = sorted(samples)
    reference = samples[ns[-1]][key + "_mean"]

    def holds(n):
        mean, sd = samples[n][key + "_mean"], samples[n][key + "_sd"]
        return abs(mean / reference - 1) <= tol and (not math.isfinite(sd) or sd / abs(mean) <= tol)

    for i, n in enumerate(ns):
        if all(holds(m) for m in ns[i:]):
            return n
    return None


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("bin_dir")
    parser.add_argument("out_dir")
    parser.add_argument("material")
    parser.add_argument("--fibres", type=int, nargs="+", default=[1, 4, 9, 16, 36, 64])
    parser.add_argument("--realisations", type=int, default=5)
    parser.add_argument("--volume-fraction", type=float, default=0.5)
    parser.add_argument("--extra", type=float, default=0.6, help="one more set at this volume fraction (0: none)")
    parser.add_argument("--extra-fibres", type=int, default=36, help="the fibres of the RVEs of that set")
    parser.add_argument("--degree", type=int, default=2)
    args = parser.parse_args(argv[1:])
    material = os.path.abspath(args.material)
    sets = [(args.volume_fraction, n) for n in args.fibres]
    if args.extra > 0:
        sets.append((args.extra, args.extra_fibres))
    rows, samples, checks = [], {}, {}
    for vf, n in sets:
        values = {key: [] for key, _ in FIGURES}
        for k in range(args.realisations):
            tag = f"N{n}-r{k}" + ("" if vf == args.volume_fraction else f"-vf{vf}")
            folder = os.path.join(args.out_dir, tag)
            print(f"rve_study: {tag}", file=sys.stderr, flush=True)
            bonded = run_case(args.bin_dir, os.path.join(folder, "bonded"),
                              scene_text(material, n, k + 1, vf, args.degree, True))
            contact = run_case(args.bin_dir, os.path.join(folder, "contact"),
                               scene_text(material, n, k + 1, vf, args.degree, False))
            figures = {**bonded_figures(bonded), **contact_figures(contact)}
            checks.setdefault((vf, n), []).append(law_checks(contact))
            for key in values:
                values[key].append(figures[key])
        row = {"volume_fraction": vf, "fibres": n, "realisations": args.realisations}
        for key, _ in FIGURES:
            v = [x for x in values[key] if math.isfinite(x)]
            row[key + "_mean"] = statistics.fmean(v) if v else math.nan
            row[key + "_sd"] = statistics.stdev(v) if len(v) > 1 else math.nan
        rows.append(row)
        if vf == args.volume_fraction:
            samples[n] = row

    # The table: mean +- sd per N; the last columns judge representativeness against the largest N.
    largest = samples[max(samples)]
    lines = ["| v_f | N | " + " | ".join(label for _, label in FIGURES) + " |",
             "|---|---|" + "---|" * len(FIGURES)]
    for r in rows:
        cells = [f"{r[k + '_mean']:.4g} ± {r[k + '_sd']:.2g}" for k, _ in FIGURES]
        lines.append(f"| {r['volume_fraction']} | {r['fibres']} | " + " | ".join(cells) + " |")
    lines += ["", "Representative to 1 % and 5 % (the smallest N from which the mean stays within that of the "
              "largest N's and the scatter, sd/mean, stays below it):", ""]
    for key, label in FIGURES:
        judged = [representative(samples, key, tol) for tol in (0.01, 0.05)]
        lines.append(f"- {label}: 1 % from N = {judged[0] or 'none'}, 5 % from N = {judged[1] or 'none'}")
    lines += ["", "The exact law of the contact RVEs (the cell condensed onto its rims) and what their compact law "
              "was checked against:", ""] + exact_law_lines(checks)
    os.makedirs(args.out_dir, exist_ok=True)
    common.write_atomic(os.path.join(args.out_dir, "table.md"), "\n".join(lines) + "\n")
    common.write_csv(os.path.join(args.out_dir, "table.csv"), list(rows[0].keys()), rows)

    # Convergence: each figure relative to the largest N's mean.
    data = io.StringIO()
    for n in sorted(samples):
        r = samples[n]
        data.write(f"{n} " + " ".join(f"{r[k + '_mean'] / largest[k + '_mean']} "
                                      f"{(r[k + '_sd'] if math.isfinite(r[k + '_sd']) else 0) / abs(largest[k + '_mean'])}"
                                      for k, _ in FIGURES) + "\n")
    curves = ", ".join(f"'conv.dat' using ($1*{1 + 0.03 * i}):{2 + 2 * i}:{3 + 2 * i} with yerrorlines title '{label}'"
                       for i, (_, label) in enumerate(FIGURES))
    plot.gnuplot("set termoption noenhanced\nset logscale x\nset xlabel 'fibres N'\nset ylabel 'mean / mean at the largest N'\n"
                 "set key outside right\nset grid\nplot " + curves + "\n",
                 os.path.join(args.out_dir, "convergence"), {"conv.dat": data.getvalue()})

    # Microstructures: the first realisation of each N, side by side.
    panels, files = [], {}
    ns = sorted(samples)
    for i, n in enumerate(ns):
        polygons, size = microstructure_data(os.path.join(args.out_dir, f"N{n}-r0", "bonded", "mesh.h5"))
        files[f"m{n}.dat"] = polygons
        panels.append(f"set title 'N = {n}'\nset xrange [0:{size[0]}]\nset yrange [0:{size[1]}]\n"
                      f"plot 'm{n}.dat' with filledcurves closed lc rgb '#4477aa' notitle\n")
    layout = f"set multiplot layout 1,{len(ns)}\nset size ratio -1\nunset key\nunset tics\n"
    plot.gnuplot(layout + "".join(panels) + "unset multiplot\n", os.path.join(args.out_dir, "microstructures"), files)

    # Debonded: the first realisation of each N, bonded, loaded along 0 deg to DEBOND_LOAD times
    # its onset: the cascade, the broken rims and the open gaps on the deformed mesh.
    for n in ns:
        folder = os.path.join(args.out_dir, f"N{n}-r0")
        onset = bonded_figures(os.path.join(folder, "bonded", "law.h5"))["onset"]
        if not math.isfinite(onset):
            continue
        solution = debond(args.bin_dir, folder, DEBOND_LOAD * onset)
        plot.deformed(solution, os.path.join(args.out_dir, f"debonded-N{n}"),
                      os.path.join(folder, "bonded", "mesh.h5"))
    print("\n".join(lines))


if __name__ == "__main__":
    common.main_guard(main)
