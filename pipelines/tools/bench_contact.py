#!/usr/bin/python3
"""The contact solver's ladder: how many applications of F a solve costs as the problem grows,
bonded, in contact and past the first break, on random RVEs and resolved beams.

usage: bench_contact.py BIN_DIR MATERIAL CELL_SCENE OUT_DIR [--fibres 4 16 36 64 144]
                        [--seeds 1 2 3] [--depths 4 8 16] [--cut-fibres 16] [--cuts 3000 1500]
                        [--adhesion-depths 4]

Cases (each one whole dualcell-mesh + dualcell-solve, its files kept in OUT_DIR/contact/<case>/,
a finished case not run again):
- RVEs of N random fibres (the RVE study's scene: v_f 0.5, p2, periodic, realisation = seed):
  bonded (interface strengths 0.05 under sxx = BONDED_STRESS, far below them), contact (no
  adhesion, sxx = CONTACT_STRESS) and adhesion past the first break (strengths 0.05 under
  sxx = BREAK_STRESS, which breaks most bonds in a cascade of debond rounds).
- The same RVE (N = --cut-fibres, seed 1) with its matrix cut by METIS into subdomains of about
  --cuts DOFs (by default the matrix is one subdomain, subdomain_dofs = 0), bonded and in
  contact: the FETI claim is that the count does not depend on the cut.
- Resolved beams in bending (tools/structures.py's beam of depth H cells, length 8H, of the cell
  CELL_SCENE): bonded (its strengths raised to BEAM_BONDED_STRENGTH, never reached), contact, and
  for --adhesion-depths the cantilever with adhesion at the fuse load (STEP past the first break).
Per case: F applications, CG, expansion and proportioning steps, outer iterations, debond
rounds, the QP's seconds and the whole command's seconds, the final relative projected gradient,
|G l - e| and the primal check's penetration, and the exit code (4: written, not converged).
Writes OUT_DIR/contact.csv and contact.md (with the contact/bonded ratio per case) and
OUT_DIR/contact.png/.svg (applications against N and against H), atomically.
"""
import csv
import os
import statistics
import sys

import h5py

import common
import rve_study
import structures
from plot import gnuplot

BONDED_STRESS = "0.001,0,0"
CONTACT_STRESS = "0.01,0,0"
BREAK_STRESS = "0.05,0,0"
BEAM_BONDED_STRENGTH = 1e3
DEFAULT_SUBDOMAIN_DOFS = 0  # core/scene.hpp's SolverSettings::subdomain_dofs: the matrix whole
FIELDS = ("operator_applications", "cg_steps", "expansion_steps", "proportioning_steps", "face_solves", "face_steps",
          "outer_iterations", "debond_rounds", "newly_broken", "tightenings")
KKT = ("relative_projected_gradient", "relative_equality_residual", "max_penetration")


def solve_case(bin_dir, folder, scene_text, stress):
    """mesh + solve of scene_text in folder; returns the row of the solve (kept: resume)."""
    os.makedirs(folder, exist_ok=True)
    scene = os.path.join(folder, "scene.toml")
    mesh = os.path.join(folder, "mesh.h5")
    out = os.path.join(folder, "solution.h5")
    if not os.path.exists(out):
        common.write_atomic(scene, scene_text)
        if not os.path.exists(mesh):
            common.run_stage([os.path.join(bin_dir, "dualcell-mesh"), "--quiet", "--config", scene, "--out", mesh], mesh)
        command = [os.path.join(bin_dir, "dualcell-solve"), "--quiet", "--config", scene, "--mesh", mesh, "--out", out]
        if stress:
            command += ["--stress", stress]
        done = common.run_stage(command, out, unconverged_kept=True)
        common.write_atomic(out + ".seconds", f"{done.seconds!r} {done.returncode}\n")
    with open(out + ".seconds") as f:  # the command's wall seconds and exit code
        seconds, code = f.read().split()
    row = {"seconds": float(seconds), "exit": int(code), "steps": 1}
    with h5py.File(out, "r") as f:
        solver, kkt = f["solver"].attrs, f["kkt"].attrs
        row.update({k: int(solver[k]) for k in FIELDS})
        if "steps" in f and len(f["steps/factor"]) > 1:
            # A resolved beam loaded in steps: /solver holds the last step's counts, /steps each
            # step's applications and breaks; the steps' kinds of MPRGP step are not kept.
            row["operator_applications"] = int(f["steps/operator_applications"][:].sum())
            row["newly_broken"] = int(f["steps/newly_broken"][:].sum())
            for k in ("cg_steps", "expansion_steps", "proportioning_steps", "face_solves", "face_steps",
                      "outer_iterations", "debond_rounds", "tightenings"):
                row[k] = ""
            row["steps"] = len(f["steps/factor"])
        row["seconds_qp"] = float(solver["seconds_qp"])
        row["rows"] = int(solver["dim_lambda"])
        row["subdomains"] = int(solver["subdomains"])
        row.update({k: float(kkt[k]) for k in KKT})
    return row


def progress(line):
    print(line, file=sys.stderr, flush=True)


def rve_cases(bin_dir, material, root, fibres, seeds, cut_fibres, cuts):
    rows = []
    for n in fibres:
        for seed in seeds:
            bonded = rve_study.scene_text(material, n, seed, 0.5, 2, True)
            contact = rve_study.scene_text(material, n, seed, 0.5, 2, False)
            base = os.path.join(root, f"rve-N{n}-s{seed}")
            for mode, text, stress in (("bonded", bonded, BONDED_STRESS), ("contact", contact, CONTACT_STRESS),
                                       ("break", bonded, BREAK_STRESS)):
                row = solve_case(bin_dir, os.path.join(base, mode), text, stress)
                rows.append({"problem": "rve", "size": n, "seed": seed, "cut": DEFAULT_SUBDOMAIN_DOFS, "mode": mode,
                             **row})
                progress(f"bench_contact: RVE N = {n}, seed {seed}, {mode}: "
                                f"{row['operator_applications']} F applications, {row['seconds']:.1f} s")
    if cut_fibres:
        for cut in cuts:
            for mode, bond, stress in (("bonded", True, BONDED_STRESS), ("contact", False, CONTACT_STRESS)):
                text = rve_study.with_solver(rve_study.scene_text(material, cut_fibres, 1, 0.5, 2, bond),
                                             subdomain_dofs=cut)
                row = solve_case(bin_dir, os.path.join(root, f"rve-N{cut_fibres}-s1-cut{cut}", mode), text, stress)
                rows.append({"problem": "rve", "size": cut_fibres, "seed": 1, "cut": cut, "mode": mode, **row})
                progress(f"bench_contact: RVE N = {cut_fibres}, subdomain_dofs {cut}, {mode}: "
                                f"{row['operator_applications']} F applications")
    return rows


def beam_text(cell_scene, bond, kind, H, folder, strength=None):
    """tools/structures.py's resolved beam (resolved.toml), its strengths replaced when given."""
    structures.scenes(cell_scene, bond, kind, H, folder)
    with open(os.path.join(folder, "resolved.toml")) as f:
        text = f.read()
    if strength is not None:
        lines = [f"{line.split('=')[0].strip()} = {strength!r}" if line.startswith(("normal_strength",
                                                                                 "tangential_strength")) else line
                 for line in text.splitlines()]
        text = "\n".join(lines) + "\n"
    return text


def beam_cases(bin_dir, cell_scene, root, depths, adhesion_depths):
    rows = []
    for H in depths:
        for mode, bond, kind, strength in (("bonded", "adhesion", "bending", BEAM_BONDED_STRENGTH),
                                           ("contact", "contact", "bending", None)):
            folder = os.path.join(root, f"beam-H{H}", mode)
            os.makedirs(folder, exist_ok=True)
            text = beam_text(cell_scene, bond, kind, H, folder, strength)
            row = solve_case(bin_dir, folder, text, None)
            rows.append({"problem": "beam", "size": H, "seed": 0, "cut": DEFAULT_SUBDOMAIN_DOFS, "mode": mode, **row})
            progress(f"bench_contact: beam H = {H}, {mode}: {row['operator_applications']} F applications, "
                            f"{row['seconds']:.1f} s")
    for H in adhesion_depths:
        folder = os.path.join(root, f"beam-H{H}", "break")
        os.makedirs(folder, exist_ok=True)
        text = beam_text(cell_scene, "adhesion", "fuse", H, folder)
        row = solve_case(bin_dir, folder, text, None)
        rows.append({"problem": "beam", "size": H, "seed": 0, "cut": DEFAULT_SUBDOMAIN_DOFS, "mode": "break", **row})
        progress(f"bench_contact: beam H = {H}, past the break: {row['operator_applications']} F "
                        f"applications, {row['seconds']:.1f} s")
    return rows


COLUMNS = ("problem", "size", "seed", "cut", "mode", "rows", "subdomains", "steps", "operator_applications", "ratio",
           "cg_steps", "expansion_steps", "proportioning_steps", "face_solves", "face_steps", "outer_iterations",
           "debond_rounds", "newly_broken",
           "tightenings", "seconds_qp", "seconds", "exit") + KKT


def with_ratios(rows):
    """Each row's applications over its bonded twin's (same problem, size, seed, cut)."""
    bonded = {(r["problem"], r["size"], r["seed"], r["cut"]): r["operator_applications"] for r in rows
              if r["mode"] == "bonded"}
    for r in rows:
        twin = bonded.get((r["problem"], r["size"], r["seed"], r["cut"]))
        r["ratio"] = r["operator_applications"] / twin if twin else float("nan")
    return rows


def markdown(rows):
    md = ["# The contact solver's ladder (tools/bench_contact.py)", "",
          "F applications of one solve (all included: norm estimates, CG, expansion (2 each) and "
          "proportioning steps, the face solves' CG steps (docs/method.md §7b), every debond round and "
          "tightening); ratio: over the bonded solve of the "
          "same problem; exit 4: written, not converged. RVE: sxx = 1e-3 bonded, 1e-2 in contact, 5e-2 "
          "past the first break (most bonds break); beam: bending (bonded and contact) and the "
          "cantilever's fuse steps (break: the applications of all its load steps, whose kinds of "
          "step are not kept).", "",
          "| problem | size | seed | subdomain_dofs (0: matrix whole) | mode | rows | F applications | ratio | load steps | CG | expansion | "
          "proportioning | faces | face CG | outer | debond rounds | QP s | command s | exit | rel. gP | rel. Gl-e |",
          "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        md.append(f"| {r['problem']} | {r['size']} | {r['seed'] or ''} | {r['cut']} | {r['mode']} | {r['rows']} | "
                  f"{r['operator_applications']} | {r['ratio']:.2f} | {r['steps']} | {r['cg_steps']} | {r['expansion_steps']} | "
                  f"{r['proportioning_steps']} | {r['face_solves']} | {r['face_steps']} | {r['outer_iterations']} | "
                  f"{r['debond_rounds']} | "
                  f"{r['seconds_qp']:.2f} | {r['seconds']:.2f} | {r['exit']} | "
                  f"{r['relative_projected_gradient']:.1e} | {r['relative_equality_residual']:.1e} |")
    summary = ["", "Median over the realisations (default cut):", "",
               "| problem | size | bonded | contact | ratio | break | ratio |", "|---|---:|---:|---:|---:|---:|---:|"]
    for problem, size in sorted({(r["problem"], r["size"]) for r in rows}):
        def median(mode, key):
            values = [r[key] for r in rows if (r["problem"], r["size"], r["mode"], r["cut"]) ==
                      (problem, size, mode, DEFAULT_SUBDOMAIN_DOFS)]
            return statistics.median(values) if values else float("nan")
        summary.append(f"| {problem} | {size} | {median('bonded', 'operator_applications'):.0f} | "
                       f"{median('contact', 'operator_applications'):.0f} | {median('contact', 'ratio'):.2f} | "
                       f"{median('break', 'operator_applications'):.0f} | {median('break', 'ratio'):.2f} |")
    return "\n".join(md + summary) + "\n"


def picture(rows, outbase):
    """F applications against N (RVEs) and against H (beams), one panel for each that has rows."""
    data, panels = {}, []
    for problem, label in (("rve", "random fibres N"), ("beam", "beam depth H (cells)")):
        plots = []
        for mode, colour in (("bonded", 1), ("contact", 2), ("break", 3)):
            points = sorted((r["size"], r["operator_applications"]) for r in rows
                            if (r["problem"], r["mode"], r["cut"]) == (problem, mode, DEFAULT_SUBDOMAIN_DOFS))
            if points:
                # Every realisation a point, their median per size the line.
                name = f"{problem}-{mode}.dat"
                data[name] = "".join(f"{s} {a}\n" for s, a in points)
                sizes = sorted({s for s, _ in points})
                data[f"{problem}-{mode}-median.dat"] = "".join(
                    f"{z} {statistics.median(a for s, a in points if s == z)}\n" for z in sizes)
                plots.append(f"'{name}' using 1:2 with points pt 7 ps 0.8 lc {colour} notitle")
                plots.append(f"'{problem}-{mode}-median.dat' using 1:2 with lines lw 2 lc {colour} "
                             f"title '{mode} (median)'")
        if plots:
            panels.append(f"set xlabel '{label}'\nset ylabel 'F applications'\nplot " + ", ".join(plots) + "\n")
    script = (f"set multiplot layout 1,{len(panels)} title 'F applications per solve'\nset logscale xy\n"
              "set offsets graph 0.05, graph 0.05, 0, 0\nset grid\n" + "".join(panels) + "unset multiplot\n")
    gnuplot(script, outbase, data)


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("bin_dir")
    parser.add_argument("material")
    parser.add_argument("cell_scene")
    parser.add_argument("out_dir")
    parser.add_argument("--fibres", type=int, nargs="*", default=[4, 16, 36, 64, 144])
    parser.add_argument("--seeds", type=int, nargs="*", default=[1, 2, 3])
    parser.add_argument("--depths", type=int, nargs="*", default=[4, 8, 16])
    parser.add_argument("--cut-fibres", type=int, default=16)
    parser.add_argument("--cuts", type=int, nargs="*", default=[3000, 1500])
    parser.add_argument("--adhesion-depths", type=int, nargs="*", default=[4])
    args = parser.parse_args(argv[1:])
    root = os.path.join(args.out_dir, "contact")
    material = os.path.abspath(args.material)
    rows = rve_cases(args.bin_dir, material, root, args.fibres, args.seeds, args.cut_fibres, args.cuts)
    rows += beam_cases(args.bin_dir, os.path.abspath(args.cell_scene), root, args.depths, args.adhesion_depths)
    rows = with_ratios(rows)

    def write_csv(path):
        with open(path, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
            writer.writeheader()
            writer.writerows(rows)
    common.write_atomic(os.path.join(args.out_dir, "contact.csv"), write_csv)
    common.write_atomic(os.path.join(args.out_dir, "contact.md"), markdown(rows))
    picture(rows, os.path.join(args.out_dir, "contact"))
    print(f"bench_contact.py: {len(rows)} cases into {args.out_dir}/contact.md, contact.csv, contact.png")


if __name__ == "__main__":
    common.main_guard(main)
