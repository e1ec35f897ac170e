#!/usr/bin/python3
"""Our solver figures for the thesis' section 7.1 cases beside the thesis' own (data/thesis-2001-solver.csv).

usage: thesis_table.py THESIS_CSV CASES_DIR OUT.md

Reads CASES_DIR/<case>/{compression,tension}.h5 written by dualcell-solve and the thesis'
figures from THESIS_CSV (data/thesis-2001-solver.csv); writes a Markdown table. The thesis
counted CG steps of its inner solver; our count is MPRGP steps (CG + expansion +
proportioning) and applications of F, the unit of work of a dual method.
"""
import csv
import os
import sys

import h5py

import common


def read_solution(path):
    with h5py.File(path, "r") as f:
        s = f["/solver"].attrs
        strain = f["/macro/strain"][:]
        stress = f["/macro/stress"][:]
        return {
            "status": common.text(s["status"]),
            "dim_u": int(s["dim_u"]), "dim_lambda": int(s["dim_lambda"]),
            "outer": int(s["outer_iterations"]), "applications": int(s["operator_applications"]),
            "steps": int(s["cg_steps"]) + int(s["expansion_steps"]) + int(s["proportioning_steps"]),
            "proportioning": int(s["proportioning_steps"]),
            "seconds": float(s["seconds_qp"]) + float(s["seconds_recovery"]) + float(s["seconds_dual_setup"]),
            "setup_seconds": float(s["seconds_assembly"]) + float(s["seconds_factorisation"]),
            "E": stress[1] / strain[1],
        }


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("thesis_csv", metavar="THESIS_CSV")
    parser.add_argument("cases_dir", metavar="CASES_DIR")
    parser.add_argument("out", metavar="OUT.md")
    args = parser.parse_args(argv[1:])
    csv_path, cases_dir, out_path = args.thesis_csv, args.cases_dir, args.out
    rows = [line for line in open(csv_path) if not line.startswith("#")]
    header = ("case,cells_x,cells_y,degree,dim_u,dim_lambda,cg_compression,cg_tension,seconds_compression,"
              "seconds_tension,rho_max,proportioning_compression,proportioning_tension,outer_compression,outer_tension")
    thesis = list(csv.DictReader([header] + rows))
    lines = [
        "# Thesis §7.1 cases: dualcell beside the thesis (2001)",
        "",
        "Each cell: compression / tension, load 10 on the top edge, material as printed. Ours: Total FETI +",
        "SMALBE/MPRGP, no tangential rows (no adhesion). Thesis: dim λ includes tangential rows, Dirichlet",
        "conditions edited into K; seconds are MATLAB on a 2001 PC. Our seconds are the solve only (dual",
        "setup + QP + recovery); the one-off setup (assembly + factorisation) is listed apart.",
        "",
        "| case | dim u (ours / thesis) | dim λ (ours / thesis) | outer (ours / thesis) | MPRGP steps (ours) | F applications (ours) | CG steps (thesis) | seconds (ours) | setup s (ours) | seconds (thesis) | E_c/E_t (ours) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for t in thesis:
        case = t["case"]
        c = read_solution(os.path.join(cases_dir, case, "compression.h5"))
        s = read_solution(os.path.join(cases_dir, case, "tension.h5"))
        for r in (c, s):
            if r["status"] != "converged":
                print(f"thesis_table.py: {case}: solver status {r['status']}", file=sys.stderr)
        lines.append(
            f"| {case} | {c['dim_u']} / {t['dim_u']} | {c['dim_lambda']} / {t['dim_lambda']} | "
            f"{c['outer']}/{s['outer']} / {t['outer_compression']}/{t['outer_tension']} | "
            f"{c['steps']}/{s['steps']} | {c['applications']}/{s['applications']} | "
            f"{t['cg_compression']}/{t['cg_tension']} | {c['seconds']:.3f}/{s['seconds']:.3f} | "
            f"{c['setup_seconds']:.3f} | {t['seconds_compression']}/{t['seconds_tension']} | "
            f"{c['E'] / s['E']:.3f} |")
    text = "\n".join(lines) + "\n"
    common.write_atomic(out_path, text)
    sys.stdout.write(text)


if __name__ == "__main__":
    common.main_guard(main)
