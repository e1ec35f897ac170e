#!/usr/bin/python3
"""The cost of a large random RVE: mesh, one solve and a sphere sweep, at the solver tolerance
that gives the bonded modulus to a stated accuracy.

usage: bench_rve.py BIN_DIR MATERIAL OUT_DIR [--fibres 64] [--volume-fraction 0.5] [--degree 2]
                    [--accuracy 1e-3] [--sphere 12]

The RVE is the RVE study's first realisation of that size (rve_study.scene_text, seed 1, p2).
1. dualcell-mesh: seconds and peak memory.
2. The tolerance: the bonded RVE (interface strengths 0.05, far above this load) under
   sxx = 1e-3, solved at [solver] tolerance 1e-10 (the reference) and at 1e-4 ... 1e-8; E = sxx /
   exx at each, its relative error against the reference and the seconds: the loosest tolerance
   within --accuracy is the bench's.
3. At that tolerance: one bonded solve and one contact solve (no adhesion, sxx = 1e-2; its E
   against the same solve at tolerance 1e-8, the scenes' default), and a
   `dualcell-sweep` of the contact RVE over --sphere directions of the stress sphere (magnitude
   1e-2): seconds and peak memory of each whole command.
Each command is measured by common.run: its wall seconds and, as its peak memory, its resident set
(os.wait4's ru_maxrss). Writes OUT_DIR/rve.md and rve.csv atomically; the RVE's files stay in
OUT_DIR/rve-N<n>/.
"""
import os

import h5py

import common
import rve_study

TOLERANCES = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
REFERENCE_TOLERANCE = 1e-10
# Contact: the scenes' default (below it the 64-fibre QP stagnates at its attainable accuracy).
CONTACT_REFERENCE_TOLERANCE = 1e-8


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("bin_dir")
    parser.add_argument("material")
    parser.add_argument("out_dir")
    parser.add_argument("--fibres", type=int, default=64)
    parser.add_argument("--volume-fraction", type=float, default=0.5)
    parser.add_argument("--degree", type=int, default=2)
    parser.add_argument("--accuracy", type=float, default=1e-3)
    parser.add_argument("--sphere", type=int, default=12)
    args = parser.parse_args(argv[1:])
    material = os.path.abspath(args.material)
    folder = os.path.join(args.out_dir, f"rve-N{args.fibres}")
    os.makedirs(folder, exist_ok=True)
    stage = lambda name: os.path.join(args.bin_dir, name)  # noqa: E731
    bonded = rve_study.scene_text(material, args.fibres, 1, args.volume_fraction, args.degree, True)
    contact = rve_study.scene_text(material, args.fibres, 1, args.volume_fraction, args.degree, False)
    rows = []

    def scene(name, text):
        path = os.path.join(folder, name)
        common.write_atomic(path, text)
        return path

    mesh = os.path.join(folder, "mesh.h5")
    meshed = common.run_stage([stage("dualcell-mesh"), "--quiet", "--config", scene("mesh.toml", bonded),
                               "--out", mesh], mesh)
    with h5py.File(mesh, "r") as f:
        nodes = len(f["mesh/nodes"])
        subdomains = len(f["mesh/subdomain_nodes"])
    rows.append({"step": "mesh", "tolerance": "", "seconds": meshed.seconds, "peak_MiB": meshed.peak_mib,
                 "note": f"{nodes} nodes, {subdomains} subdomains"})

    def solve(text, stress, tag, tolerance):
        out = os.path.join(folder, f"{tag}.h5")
        # Exit 4 (a solve written whose QP stagnated just short of its tolerance) is measured too.
        solved = common.run_stage([stage("dualcell-solve"), "--quiet", "--config",
                                   scene(f"{tag}.toml", rve_study.with_solver(text, tolerance=tolerance)), "--mesh", mesh,
                                   "--stress", stress, "--out", out], out, unconverged_kept=True)
        with h5py.File(out, "r") as f:
            strain = f["macro/strain"][:]
            status = common.text(f["solver"].attrs["status"])
            applications = f"{int(f['solver'].attrs['operator_applications'])} F applications" + (
                "" if status == "converged" else f", {status}")
        return solved.seconds, solved.peak_mib, strain, applications

    # The tolerance: E = sxx / exx of the bonded RVE against the reference.
    load = 1e-3
    _, _, reference, _ = solve(bonded, f"{load},0,0", "bonded-reference", REFERENCE_TOLERANCE)
    E_reference = load / reference[0]
    chosen = None
    for tolerance in TOLERANCES:
        seconds, peak, strain, applications = solve(bonded, f"{load},0,0", f"bonded-{tolerance:g}", tolerance)
        error = abs(load / strain[0] - E_reference) / E_reference
        rows.append({"step": "bonded solve", "tolerance": tolerance, "seconds": seconds, "peak_MiB": peak,
                     "E_error": error, "note": applications})
        if chosen is None and error <= args.accuracy:
            chosen = tolerance
    if chosen is None:
        raise SystemExit(f"bench_rve: no tolerance down to {TOLERANCES[-1]:g} gives E to {args.accuracy:g}")

    # The contact solve at that tolerance, its E against the scenes' default tolerance.
    _, _, contact_reference, _ = solve(contact, "0.01,0,0", "contact-reference", CONTACT_REFERENCE_TOLERANCE)
    seconds, peak, strain, applications = solve(contact, "0.01,0,0", "contact", chosen)
    rows.append({"step": "contact solve", "tolerance": chosen, "seconds": seconds, "peak_MiB": peak,
                 "E_error": abs(contact_reference[0] / strain[0] - 1), "note": applications})
    sweep_scene = scene("sweep.toml", rve_study.with_solver(contact.replace(
        "[sweep]\ndirections_deg = [0, 90]\nmagnitudes = [-1e-2, 1e-2]\n",
        f"[sweep]\nsphere = {args.sphere}\nmagnitudes = [1e-2]\n"), tolerance=chosen))
    sweep = os.path.join(folder, "sweep.h5")
    if os.path.exists(sweep):
        os.remove(sweep)  # a fresh sweep, not a resumed one
    swept = common.run_stage([stage("dualcell-sweep"), "--quiet", "--config", sweep_scene, "--mesh", mesh,
                              "--out", sweep], sweep, unconverged_kept=True)
    rows.append({"step": f"contact sphere sweep ({args.sphere} paths)", "tolerance": chosen, "seconds": swept.seconds,
                 "peak_MiB": swept.peak_mib, "note": ""})

    lines = [f"{args.fibres} fibres, v_f {args.volume_fraction}, p2 at degree {args.degree}; E of the bonded RVE "
             f"to {args.accuracy:g} from tolerance {chosen:g} (reference: tolerance {REFERENCE_TOLERANCE:g})", "",
             "| step | tolerance | seconds | peak MiB | relative error of E | note |", "|---|---|---|---|---|---|"]
    for r in rows:
        error = f"{r['E_error']:.1e}" if "E_error" in r else ""
        tolerance = f"{r['tolerance']:g}" if r["tolerance"] != "" else ""
        lines.append(f"| {r['step']} | {tolerance} | {r['seconds']:.1f} | {r['peak_MiB']:.0f} | {error} | {r['note']} |")
    common.write_atomic(os.path.join(args.out_dir, "rve.md"), "\n".join(lines) + "\n")
    common.write_csv(os.path.join(args.out_dir, "rve.csv"), ["step", "tolerance", "seconds", "peak_MiB", "E_error", "note"],
                     rows)
    print("\n".join(lines))


if __name__ == "__main__":
    common.main_guard(main)
