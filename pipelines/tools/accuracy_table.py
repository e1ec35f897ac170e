#!/usr/bin/python3
"""The accuracy study's table: error against seconds for dualcell (p1, p2) and CalculiX.

usage: accuracy_table.py OUT_DIR ROWS.csv...

Each ROWS.csv has a header with at least code, element, dofs, load, E, seconds (dualcell's rows
from accuracy_dualcell.py, CalculiX's from ccx_cell.py; a column E_app is read as E). The
reference modulus per load sign is the Richardson limit of the three finest dualcell p2 rungs
(E(h) = E* + C h^p, h = 1/degree, p solved for: convergence_table.richardson); the observed
order of every dualcell ladder comes from its three finest rungs the same way. Per code,
element and sign it reports the time to reach a relative error of 1e-4 (the fastest row at or
below it) or, when no row gets there, the best error reached and its time. Writes atomically
OUT_DIR/table.csv (every row with its error) and OUT_DIR/table.md (the summary, the targets and
every row). Errors: one line on stderr, exit 1.
"""
import csv
import math
import os
import sys

import common
from convergence_table import richardson

TARGET = 1e-4


def read_rows(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(row for row in f if not row.startswith("#")):
                if "E" not in r and "E_app" in r:
                    r["E"] = r["E_app"]
                for key in ("code", "element", "dofs", "load", "E", "seconds"):
                    if key not in r or r[key] in (None, ""):
                        raise ValueError(f"{path}: a row without {key}")
                rows.append({"code": r["code"], "element": r["element"],
                             "degree": int(r["degree"]) if r.get("degree") not in (None, "") else None,
                             "dofs": int(r["dofs"]), "load": float(r["load"]), "E": float(r["E"]),
                             "seconds": float(r["seconds"])})
    return rows


def sign(load):
    return "tension" if load > 0 else "compression"


def ladder(rows, code, element, which):
    return sorted((r for r in rows if r["code"] == code and r["element"] == element and sign(r["load"]) == which),
                  key=lambda r: r["dofs"])


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("out_dir", metavar="OUT_DIR")
    parser.add_argument("rows", metavar="ROWS.csv", nargs="+")
    args = parser.parse_args(argv[1:])
    out_dir, rows = args.out_dir, read_rows(args.rows)
    reference, orders = {}, {}
    for which in ("tension", "compression"):
        finest = [r for r in ladder(rows, "dualcell", "p2", which) if r["degree"]][-3:]
        if len(finest) < 3:
            raise ValueError(f"{which}: need three dualcell p2 rungs for the reference, found {len(finest)}")
        reference[which], orders[("p2", which)] = richardson([(1.0 / r["degree"], r["E"]) for r in finest])
        if not math.isfinite(orders[("p2", which)]):
            raise ValueError(f"{which}: the finest p2 rungs are not in the asymptotic range")
        p1 = [r for r in ladder(rows, "dualcell", "p1", which) if r["degree"]][-3:]
        if len(p1) == 3:
            orders[("p1", which)] = richardson([(1.0 / r["degree"], r["E"]) for r in p1])[1]
    for r in rows:
        r["error"] = abs(r["E"] - reference[sign(r["load"])]) / abs(reference[sign(r["load"])])

    series = sorted({(r["code"], r["element"]) for r in rows})
    best = {}
    for code, element in series:
        for which in ("tension", "compression"):
            ladder_rows = ladder(rows, code, element, which)
            if not ladder_rows:
                continue
            reached = [r for r in ladder_rows if r["error"] <= TARGET]
            best[(code, element, which)] = (min(reached, key=lambda r: r["seconds"]), True) if reached else \
                (min(ladder_rows, key=lambda r: r["error"]), False)

    csv_lines = ["code,element,degree,dofs,load,E,relative_error,seconds"]
    for r in sorted(rows, key=lambda r: (r["code"], r["element"], -r["load"], r["dofs"])):
        csv_lines.append(f"{r['code']},{r['element']},{r['degree'] if r['degree'] else ''},{r['dofs']},"
                         f"{r['load']!r},{r['E']!r},{r['error']:.4e},{r['seconds']:.4f}")
    common.write_atomic(os.path.join(out_dir, "table.csv"), "\n".join(csv_lines) + "\n")

    md = ["# Accuracy per second: dualcell and CalculiX on one cell", "",
          "Reference (Richardson limit of the three finest dualcell p2 rungs): "
          + ", ".join(f"E_{w} = {reference[w]:.10g}" for w in ("tension", "compression")) + ".",
          "Observed orders in h = 1/degree (three finest rungs): "
          + ", ".join(f"{el} {w} {p:.2f}" for (el, w), p in sorted(orders.items())) + ".", "",
          f"## Time to a relative error of {TARGET:g}", "",
          "| code | element | load | reached | error | DOF | seconds |", "|---|---|---|---|---|---|---|"]
    for (code, element, which), (r, reached) in sorted(best.items()):
        md.append(f"| {code} | {element} | {which} | {'yes' if reached else 'no (best)'} | {r['error']:.2e} | "
                  f"{r['dofs']} | {r['seconds']:.3f} |")
    md.append("")
    for which in ("tension", "compression"):
        ours = best.get(("dualcell", "p2", which))
        theirs = [v for (code, _, w), v in best.items() if code != "dualcell" and w == which]
        if ours and theirs:
            their_best = min(theirs, key=lambda v: (not v[1], v[0]["seconds"] if v[1] else v[0]["error"]))
            ratio = their_best[0]["seconds"] / ours[0]["seconds"]
            md.append(f"{which}: dualcell p2 {'reaches' if ours[1] else 'does not reach'} {TARGET:g} in "
                      f"{ours[0]['seconds']:.3f} s; the best CalculiX row "
                      f"{'reaches it' if their_best[1] else 'gets to ' + format(their_best[0]['error'], '.1e')} in "
                      f"{their_best[0]['seconds']:.3f} s: ratio {ratio:.0f} (target ≥ 100).")
    md += ["", "## Every row", "", "| code | element | degree | DOF | load | E | relative error | seconds |",
           "|---|---|---|---|---|---|---|---|"]
    for line in csv_lines[1:]:
        c = line.split(",")
        md.append(f"| {' | '.join(c[:4])} | {float(c[4]):+g} | {float(c[5]):.8f} | {c[6]} | {c[7]} |")
    text = "\n".join(md) + "\n"
    common.write_atomic(os.path.join(out_dir, "table.md"), text)
    sys.stdout.write(text)


if __name__ == "__main__":
    common.main_guard(main)
