#!/usr/bin/python3
"""The floor against both BLAS libraries, side by side (make -C pipelines bench).

usage: floor_table.py REFERENCE/floor.json OPENBLAS/floor.json OUT.md

Each floor.json is written by `dualcell-bench --floor-only` run on one BLAS (chosen by
LD_LIBRARY_PATH; the file names the library the process loaded). Writes OUT.md atomically: per
case the contact solve's seconds and CHOLMOD's (analyse + factorise + solve of the bonded
problem as one body) on each BLAS, and the two ratios contact / CHOLMOD. Errors: one line on
stderr, exit 1.
"""
import json
import sys

import common


def load(path):
    with open(path) as f:
        data = json.load(f)
    return data["blas"], data["floor"]


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("reference", metavar="REFERENCE/floor.json")
    parser.add_argument("openblas", metavar="OPENBLAS/floor.json")
    parser.add_argument("out", metavar="OUT.md")
    args = parser.parse_args(argv[1:])
    (ref_blas, ref), (fast_blas, fast) = load(args.reference), load(args.openblas)
    if [(r["element"], r["dofs"]) for r in ref] != [(r["element"], r["dofs"]) for r in fast]:
        raise ValueError("the two floor.json files hold different cases")
    lines = ["# The floor on two BLAS libraries", "",
             f"Reference BLAS: `{ref_blas}`; optimised: `{fast_blas}`. Contact: setup + solve of the contact "
             "problem (dualcell, its own threads); CHOLMOD: analyse, factorise and solve of the bonded problem as "
             "one body (supernodal). Ratio = contact / CHOLMOD; target ≤ 2 at ~1e6 DOF against the optimised BLAS.",
             "",
             "| element | DOF | contact s (ref. run) | CHOLMOD s, reference BLAS | ratio | contact s (opt. run) "
             "| CHOLMOD s, OpenBLAS | ratio |",
             "|---|---|---|---|---|---|---|---|"]
    for r, f in zip(ref, fast):
        lines.append(f"| {r['element']} | {r['dofs']} | {r['contact_seconds']:.2f} | {r['cholesky_seconds']:.2f} | "
                     f"{r['contact_seconds'] / r['cholesky_seconds']:.2f} | {f['contact_seconds']:.2f} | "
                     f"{f['cholesky_seconds']:.2f} | {f['contact_seconds'] / f['cholesky_seconds']:.2f} |")
    text = "\n".join(lines) + "\n"
    common.write_atomic(args.out, text)
    sys.stdout.write(text)


if __name__ == "__main__":
    common.main_guard(main)
