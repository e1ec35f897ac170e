#!/usr/bin/python3
"""The laws of the pipelines' cells and their self-checks, from their law.h5 files.

usage:
  law_table.py OUT.md LAW.h5...     one row per law (the scene is the law's folder name)

Per law: the exact law (the cell condensed onto its interface rows: rows, kB, seconds of the
condensation), its replay of the sweep it came from (points, largest relative strain error,
whether the broken bonds agree), and the compact cone-wise law against it over the dense set of
directions (/law/cone_check: largest and rms relative stress error, the worst direction; without
an exact law the same against the sweep's held-out directions, attribute `against`); with
adhesion a second table, the compact law past the fuse against the exact law past the fuse
(/law/cone_after_fuse_check). The small cell (/law/small_check), where the fit made one: its rows
and its largest and rms error against the exact law (or the held-out full solves), and with
adhesion the small cell with a fuse in the second table, along the exact law's cascade paths.
Writes OUT.md and OUT.csv beside it, atomically.
"""
import os

import h5py

import common

COLUMNS = ["scene", "interface_rows", "condense_s", "kB", "replay_points", "replay_max", "breaks_agree",
           "cone_against", "cone_directions", "cone_form", "cone_max", "cone_rms", "worst_sxx", "worst_syy", "worst_sxy",
           "sweep_fit_max", "sweep_fit_rms", "fuse_against", "fuse_directions", "fuse_form", "fuse_max", "fuse_rms",
           "fuse_worst_sxx", "fuse_worst_syy", "fuse_worst_sxy", "fuse_sweep_fit_max", "fuse_sweep_fit_rms",
           "small_rows", "small_against", "small_max", "small_rms"]


def row(path):
    scene = os.path.basename(os.path.dirname(os.path.abspath(path)))
    with h5py.File(path, "r") as f:
        g = f["law"]
        if "cell" not in g:
            r = {"scene": scene, "interface_rows": "none: " + common.text(g.attrs["cell_note"])}
        else:
            c = g["cell"]
            r = {"scene": scene, "interface_rows": len(c["pair"]), "condense_s": float(c["seconds"][0]),
                 "kB": int(c["bytes"][0]) / 1e3, "replay_points": int(g["cell_replay/points"][0]),
                 "replay_max": float(g["cell_replay/max_error"][0]),
                 "breaks_agree": "yes" if int(g["cell_replay/break_mismatches"][0]) == 0 else "no"}
        if "cone_check" in g:
            k = g["cone_check"]
            worst = k["worst"][:]
            r.update({"cone_against": common.text(k.attrs.get("against", "the exact law")),
                      "cone_directions": len(k["error"]), "cone_form": common.text(g["cone"].attrs["form"]),
                      "sweep_fit_max": float(k["sweep_fit_max_error"][0]),
                      "sweep_fit_rms": float(k["sweep_fit_rms_error"][0]), "cone_max": float(k["max_error"][0]),
                      "cone_rms": float(k["rms_error"][0]), "worst_sxx": worst[0], "worst_syy": worst[1],
                      "worst_sxy": worst[2]})
        if "cone_after_fuse_check" in g:
            k = g["cone_after_fuse_check"]
            worst = k["worst"][:]
            r.update({"fuse_against": common.text(k.attrs.get("against", "the exact law")),
                      "fuse_directions": len(k["error"]), "fuse_form": common.text(g["cone_after_fuse"].attrs["form"]),
                      "fuse_max": float(k["max_error"][0]), "fuse_rms": float(k["rms_error"][0]),
                      "fuse_worst_sxx": worst[0], "fuse_worst_syy": worst[1], "fuse_worst_sxy": worst[2],
                      "fuse_sweep_fit_max": float(k["sweep_fit_max_error"][0]),
                      "fuse_sweep_fit_rms": float(k["sweep_fit_rms_error"][0])})
        if "small_check" in g:
            k = g["small_check"]
            r.update({"small_rows": len(g["small/pair"]), "small_against": common.text(k.attrs["against"]),
                      "small_max": float(k["max_error"][0]), "small_rms": float(k["rms_error"][0])})
        return r


def small(r):
    """The small cell's cell of a table row: rows, largest and rms error (and against what, when it
    is not the table's)."""
    if "small_max" not in r:
        return ""
    against = "" if r["small_against"] in ("the exact law", "the exact law past the fuse") else \
        f" against {r['small_against']}"
    return f"{r['small_rows']} rows, {100 * r['small_max']:.1f} %, {100 * r['small_rms']:.1f} %{against}"


def markdown(rows):
    lines = ["| scene | exact law: interface rows | condensation | replay of its sweep: points, max error | "
             "breaks agree | cone-wise law kept | against the exact law: directions, max, rms | worst direction "
             "(σxx, σyy, σxy) | the form fitted to the sweep: max, rms | small cell: rows, max, rms |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        form = cone = worst = sweep_fit = ""
        if "cone_max" in r:
            form = r["cone_form"]
            cone = f"{r['cone_directions']}, {100 * r['cone_max']:.1f} %, {100 * r['cone_rms']:.1f} %"
            worst = f"({r['worst_sxx']:.2f}, {r['worst_syy']:.2f}, {r['worst_sxy']:.2f})"
            if r["cone_against"] != "the exact law":
                cone = f"against {r['cone_against']} (no exact law): " + cone
            else:
                sweep_fit = f"{100 * r['sweep_fit_max']:.1f} %, {100 * r['sweep_fit_rms']:.1f} %"
        bonded_small = "" if r.get("small_against") == "the exact law past the fuse" else small(r)
        if "replay_points" not in r:
            lines.append(f"| {r['scene']} | {r['interface_rows']} | | | | {form} | {cone} | {worst} | | {bonded_small} |")
            continue
        lines.append(f"| {r['scene']} | {r['interface_rows']} | {r['condense_s']:.2f} s, {r['kB']:.0f} kB | "
                     f"{r['replay_points']}, {r['replay_max']:.1e} | {r['breaks_agree']} | {form} | {cone} | {worst} | "
                     f"{sweep_fit} | {bonded_small} |")
    fused = [r for r in rows if "fuse_max" in r]
    if fused:
        lines += ["", "Past the fuse (each direction loaded through its cascade to twice its onset):", "",
                  "| scene | cone-wise law after the fuse kept | against the exact law: directions, max, rms | worst "
                  "direction (σxx, σyy, σxy) | the form fitted to the sweep: max, rms | small cell with a fuse along "
                  "the cascade paths: rows, max, rms |", "|---|---|---|---|---|---|"]
        for r in fused:
            against = "" if r["fuse_against"] == "the exact law" else f"against {r['fuse_against']} (no exact law): "
            lines.append(f"| {r['scene']} | {r['fuse_form']} | {against}{r['fuse_directions']}, {100 * r['fuse_max']:.1f} %, "
                         f"{100 * r['fuse_rms']:.1f} % | ({r['fuse_worst_sxx']:.2f}, {r['fuse_worst_syy']:.2f}, "
                         f"{r['fuse_worst_sxy']:.2f}) | "
                         + ("" if against else f"{100 * r['fuse_sweep_fit_max']:.1f} %, "
                            f"{100 * r['fuse_sweep_fit_rms']:.1f} %") + f" | {small(r)} |")
    return "\n".join(lines) + "\n"


def main(argv):
    parser = common.Parser(description=__doc__)
    parser.add_argument("out")
    parser.add_argument("laws", nargs="+")
    args = parser.parse_args(argv[1:])
    rows = [row(p) for p in args.laws]
    common.write_table(args.out, markdown(rows), COLUMNS, rows)


if __name__ == "__main__":
    common.main_guard(main)
