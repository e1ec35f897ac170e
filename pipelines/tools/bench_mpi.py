#!/usr/bin/python3
"""dualcell over MPI ranks: strong scaling of a sweep and of one solve, and a performance model.

usage:
  bench_mpi.py sweep BIN SCENE.toml OUTDIR "P1 P2 ..." REPEAT CORES
  bench_mpi.py solve BIN SCENE.toml STRESS OUTDIR "P1 P2 ..." REPEAT CORES
  bench_mpi.py model OUTDIR

sweep: meshes SCENE once, then times dualcell-sweep run serially (no launcher) and under
mpiexec with P ranks, one thread each (and once more on as many ranks as cores over TCP with
OpenMPI's pt2pt one-sided component, a transport without hardware atomics), the best of REPEAT
runs per P (the journal removed before each, so every run computes every path), and checks that
each run's sweep.h5 equals the serial one but for the seconds columns (h5diff). Writes
OUTDIR/sweep.md and OUTDIR/sweep.csv: P, seconds (min and median), speed-up and efficiency
against the serial run, and whether the run was oversubscribed (P > CORES, the machine's cores:
then the ranks share cores and the speed-up is capped).

solve: the same for one dualcell-solve of SCENE at STRESS ("sxx,syy,sxy"); each run's
solution must equal the serial one to 1e-12 of its largest entry with the same iteration
counts. From the /ranks table of each best run: per rank its DOFs, subdomain data and peak
memory, and per application of F or M^-1 the seconds of its own subdomains, the seconds in the
exchange, the bytes received and the exchanges. Writes OUTDIR/solve.md, solve.csv, ranks.csv.

model: from OUTDIR/solve-serial.h5 (the serial solve's unit costs) and the measured runs,
projects one solve per rank count (docs/method.md §16): validated against the measured strong
scaling, then weak scaling (the subdomains per rank fixed) to 64-1024 ranks on an assumed
cluster interconnect. Writes OUTDIR/model.md and OUTDIR/model.csv.
"""
import math
import os
import shutil
import statistics
import sys

import h5py

import common


def write(outdir, name, lines):
    common.write_atomic(os.path.join(outdir, name), "\n".join(lines) + "\n")


def same_but_seconds(a, b):
    done = common.run(["h5diff", a, b], check=False)
    if done.returncode > 1:
        sys.exit(f"bench_mpi.py: h5diff failed: {done.stderr}")
    others = [l for l in done.stdout.splitlines()
              if (l.startswith("dataset:") or l.startswith("attribute:")) and "/seconds>" not in l]
    return not others


def sweep(bindir, scene, outdir, ranks, repeat, cores):
    os.makedirs(outdir, exist_ok=True)
    mesh = os.path.join(outdir, "mesh.h5")
    common.run([os.path.join(bindir, "dualcell-mesh"), "--quiet", "--config", scene, "--out", mesh])
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    sweep = [os.path.join(bindir, "dualcell-sweep"), "--quiet", "--threads", "1", "--config", scene, "--mesh", mesh]

    def repeated(prefix, out):
        """The wall seconds (common.run) of REPEAT fresh sweeps under the launcher `prefix`."""
        times = []
        for _ in range(repeat):
            for stale in (out, out + ".parts"):
                if os.path.isdir(stale):
                    shutil.rmtree(stale)
                elif os.path.exists(stale):
                    os.remove(stale)
            times.append(common.run(prefix + sweep + ["--out", out], env).seconds)
            print(f"bench_mpi.py: {os.path.basename(out)}: {times[-1]:.2f} s", file=sys.stderr)
        return times

    serial_out = os.path.join(outdir, "serial.h5")
    rows = [("serial (no launcher)", 1, repeated([], serial_out), True)]
    for p in ranks:
        out = os.path.join(outdir, f"ranks-{p}.h5")
        times = repeated(["mpiexec", "-n", str(p), "--oversubscribe"], out)
        rows.append((f"mpiexec -n {p}", p, times, same_but_seconds(serial_out, out)))
    # Over TCP with OpenMPI's pt2pt one-sided component, as on a cluster without RDMA: the path
    # counter's fetch-and-add is served only when rank 0 enters MPI (SharedCounter::serve).
    p = min(cores, max(ranks))
    out = os.path.join(outdir, f"ranks-{p}-tcp.h5")
    times = repeated(["mpiexec", "-n", str(p), "--oversubscribe", "--mca", "osc", "pt2pt", "--mca", "btl", "tcp,self"],
                     out)
    rows.append((f"mpiexec -n {p}, TCP (osc pt2pt)", p, times, same_but_seconds(serial_out, out)))
    base = min(rows[0][2])
    with h5py.File(serial_out, "r") as f:
        paths = len(f["/paths"])
        fuses = sum(1 for name in f["/paths"] if "fuse" in f["/paths"][name])
    csv = ["run,ranks,seconds_min,seconds_median,speedup,efficiency,oversubscribed,same_as_serial"]
    md = ["# Strong scaling of a sweep over MPI ranks", "",
          f"Scene {os.path.basename(scene)}: {paths} paths, {fuses} of them with a fuse; one thread per rank, best of "
          f"{repeat} runs; the machine has {cores} cores.",
          "Speed-up and efficiency against the serial run (no launcher); oversubscribed runs share cores.", "",
          "| run | ranks | seconds (min) | seconds (median) | speed-up | efficiency | oversubscribed | sweep.h5 = serial but seconds |",
          "|---|---|---|---|---|---|---|---|"]
    for label, p, times, same in rows:
        best, median = min(times), statistics.median(times)
        speedup = base / best
        over = p > cores
        csv.append(f"{label},{p},{best:.4f},{median:.4f},{speedup:.3f},{speedup / p:.3f},{int(over)},{int(same)}")
        md.append(f"| {label} | {p} | {best:.2f} | {median:.2f} | {speedup:.2f} | {speedup / p:.2f} | "
                  f"{'yes' if over else 'no'} | {'yes' if same else 'NO'} |")
    write(outdir, "sweep.csv", csv)
    write(outdir, "sweep.md", md)
    print("\n".join(md))
    if not all(r[3] for r in rows):
        sys.exit("bench_mpi.py: a run under mpiexec did not write the serial sweep.h5")


# The solver's counters: every number of ranks must give the serial ones.
COUNTERS = ("operator_applications", "preconditioner_applications", "outer_iterations", "cg_steps",
            "expansion_steps", "proportioning_steps", "debond_rounds", "newly_broken", "tightenings")


def differs_from_serial(serial, other):
    """'' when `other` holds the serial solution to 1e-12 of its largest entry with the same
    counters, else what differs."""
    with h5py.File(serial, "r") as a, h5py.File(other, "r") as b:
        for name in ("/solution/u", "/interface/lambda"):
            x, y = a[name][()], b[name][()]
            worst, scale = float(abs(x - y).max()), float(abs(x).max())
            if worst > 1e-12 * scale:
                return f"{name} differs by {worst:.3g} of {scale:.3g}"
        for c in COUNTERS:
            if a["/solver"].attrs[c] != b["/solver"].attrs[c]:
                return f"{c}: {b['/solver'].attrs[c]}, serial {a['/solver'].attrs[c]}"
    return ""


def solve(bindir, scene, stress, outdir, ranks, repeat, cores):
    os.makedirs(outdir, exist_ok=True)
    mesh = os.path.join(outdir, "solve-mesh.h5")
    common.run([os.path.join(bindir, "dualcell-mesh"), "--quiet", "--config", scene, "--out", mesh])
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    command = [os.path.join(bindir, "dualcell-solve"), "--quiet", "--threads", "1", "--config", scene, "--mesh", mesh,
               "--stress", stress]

    def repeated(prefix, out):
        """The wall seconds (common.run) of REPEAT solves under the launcher `prefix`; `out` is the
        fastest run's solution."""
        times = []
        for k in range(repeat):
            times.append(common.run(prefix + command + ["--out", f"{out}.{k}.h5"], env).seconds)
            print(f"bench_mpi.py: {os.path.basename(out)} run {k + 1}: {times[-1]:.2f} s", file=sys.stderr)
        best = times.index(min(times))
        for k in range(repeat):
            for ext in (".h5", ".xdmf"):
                name = f"{out}.{k}{ext}"
                if k == best:
                    os.replace(name, out[:-3] + ext)
                elif os.path.exists(name):
                    os.remove(name)
        return times

    serial_out = os.path.join(outdir, "solve-serial.h5")
    runs = [("serial (no launcher)", 1, serial_out, repeated([], serial_out))]
    for p in ranks:
        out = os.path.join(outdir, f"solve-ranks-{p}.h5")
        runs.append((f"mpiexec -n {p}", p, out, repeated(["mpiexec", "-n", str(p), "--oversubscribe"], out)))
    base = min(runs[0][3])
    with h5py.File(serial_out, "r") as f:
        dofs, m = int(f["/solver"].attrs["dim_u"]), int(f["/solver"].attrs["dim_lambda"])
        S = int(f["/ranks/subdomains"][0])
        base_qp = float(f["/solver"].attrs["seconds_qp"])
    csv = ["run,ranks,seconds_min,seconds_median,speedup,efficiency,seconds_qp,speedup_qp,oversubscribed,cores,"
           "same_as_serial"]
    md = ["# Strong scaling of one solve over MPI ranks", "",
          f"Scene {os.path.basename(scene)} at stress ({stress}): {dofs} DOFs in {S} subdomains, dim lambda {m}; "
          f"one thread per rank, best of {repeat} runs; the machine has {cores} cores (oversubscribed runs share "
          "them). Wall: the whole dualcell-solve (start-up, reading, setup, QP, writing); QP: rank 0's QP seconds.", "",
          "| run | ranks | wall s (min) | wall s (median) | speed-up | efficiency | QP s | QP speed-up | "
          "oversubscribed | solution = serial (1e-12, same iterations) |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    ranks_csv = ["run,ranks,rank,subdomains,dofs,data_MiB,peak_MiB,seconds_setup,apply_s_per_application,"
                 "exchange_s_per_exchange,bytes_per_exchange,exchanges_per_application"]
    ranks_md = ["", "Per rank (the fastest run of each): its subdomains' data and the process's peak memory; per "
                "application of F or M^-1 its own subdomains' seconds (K^+, the preconditioner), and per exchange "
                "(one MPI_Allgatherv of the row sums) its seconds and the bytes it received.", "",
                "| run | rank | subdomains | DOFs | data MiB | peak MiB | setup s | apply ms / appl. | exchange ms | "
                "KiB / exchange | exchanges / appl. |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    failures = []
    for label, p, out, times in runs:
        best, median = min(times), statistics.median(times)
        speedup = base / best
        differs = differs_from_serial(serial_out, out) if out != serial_out else ""
        if differs:
            failures.append(f"{label}: {differs}")
        with h5py.File(out, "r") as f:
            solver = f["/solver"].attrs
            qp = float(solver["seconds_qp"])
            applications = int(solver["operator_applications"]) + int(solver["preconditioner_applications"])
            r = {k: f["/ranks/" + k][()] for k in f["/ranks"]}
        over = p > cores
        csv.append(f"{label},{p},{best:.4f},{median:.4f},{speedup:.3f},{speedup / p:.3f},{qp:.4f},{base_qp / qp:.3f},"
                   f"{int(over)},{cores},{int(not differs)}")
        md.append(f"| {label} | {p} | {best:.2f} | {median:.2f} | {speedup:.2f} | {speedup / p:.2f} | {qp:.2f} | "
                  f"{base_qp / qp:.2f} | {'yes' if over else 'no'} | {'yes' if not differs else 'NO'} |")
        for k in range(len(r["dofs"])):
            ex = int(r["exchanges"][k])
            per_exchange = (float(r["seconds_communication"][k]) / ex, float(r["bytes_received"][k]) / ex) if ex else (0, 0)
            row = (label, p, k, int(r["subdomains"][k]), int(r["dofs"][k]), r["subdomain_bytes"][k] / 2**20,
                   r["peak_rss_bytes"][k] / 2**20, float(r["seconds_setup"][k]),
                   float(r["seconds_apply"][k]) / applications, per_exchange[0], per_exchange[1], ex / applications)
            ranks_csv.append("{},{},{},{},{},{:.1f},{:.1f},{:.4f},{:.6f},{:.6f},{:.0f},{:.4f}".format(*row))
            ranks_md.append("| {} | {} | {} | {} | {:.0f} | {:.0f} | {:.2f} | {:.3f} | {:.3f} | {:.0f} | {:.3f} |".format(
                label, k, *row[3:8], row[8] * 1e3, row[9] * 1e3, row[10] / 1024, row[11]))
    write(outdir, "solve.csv", csv)
    write(outdir, "ranks.csv", ranks_csv)
    write(outdir, "solve.md", md + ranks_md)
    print("\n".join(md + ranks_md))
    if failures:
        sys.exit("bench_mpi.py: a run under mpiexec did not give the serial solution: " + "; ".join(failures))


# ---- the performance model (docs/method.md §16) -------------------------------------------
# An assumed cluster interconnect, typical of HDR InfiniBand: latency per message and bandwidth
# per link (100 Gb/s).
LATENCY_S = 1.5e-6
BANDWIDTH_B_PER_S = 12.5e9
# Reductions of one scalar per MPRGP step a λ partitioned by owner would need (the step length,
# the CG coefficient, the norms of the projected gradient's parts): an assumption.
DOTS_PER_STEP = 4
WEAK_RANKS = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]


def allgather_seconds(P, rows):
    """MPI_Allgatherv of `rows` doubles in all over P ranks: log2(P) latencies (recursive
    doubling / Bruck) and each rank receiving what the others hold."""
    return 0.0 if P == 1 else math.ceil(math.log2(P)) * LATENCY_S + 8 * rows * (P - 1) / P / BANDWIDTH_B_PER_S


def allreduce_seconds(P, values):
    return 0.0 if P == 1 else math.ceil(math.log2(P)) * LATENCY_S + 2 * 8 * values / BANDWIDTH_B_PER_S


class UnitCosts:
    """Seconds per subdomain and per row of lambda, from the serial solve's own profile."""

    def __init__(self, h5):
        with h5py.File(h5, "r") as f:
            a = f["/solver"].attrs
            self.S = int(f["/ranks/subdomains"][0])
            self.m = int(a["dim_lambda"])
            self.n_F = int(a["operator_applications"])
            self.n_M = int(a["preconditioner_applications"])
            t_F, t_M, t_Q = float(a["seconds_qp_F"]), float(a["seconds_qp_preconditioner"]), float(a["seconds_qp_Q"])
            t_vector = float(a["seconds_qp"]) - t_F - t_M - t_Q
            self.F_per_subdomain = t_F / self.n_F / self.S
            self.M_per_subdomain = t_M / self.n_M / self.S if self.n_M else 0.0
            # Per F application (one MPRGP step): the QP's vector work and the coarse problem Q,
            # per row of lambda.
            self.vector_per_row = t_vector / self.n_F / self.m
            self.Q_per_row = t_Q / self.n_F / self.m
            self.setup_per_subdomain = (float(a["seconds_assembly"]) + float(a["seconds_factorisation"])) / self.S
            self.dual_setup = float(a["seconds_dual_setup"])
        self.rows_per_subdomain = self.m / self.S

    def solve_seconds(self, P, subdomains, partitioned=False, exchange=None):
        """One solve of `subdomains` subdomains (the measured kind) over P ranks, the iteration
        counts measured (TFETI with the Dirichlet preconditioner: bounded for a fixed H/h, an
        assumption for the larger problems). `exchange`: measured seconds per exchange instead
        of the interconnect's."""
        s = subdomains / P
        m = self.rows_per_subdomain * subdomains
        compute = self.n_F * s * self.F_per_subdomain + self.n_M * s * self.M_per_subdomain
        # B, G and GGᵀ are built on every rank for every subdomain: linear in the subdomains
        # (GGᵀ's sparse factor grows a little faster; at these sizes it is a small part).
        setup = s * self.setup_per_subdomain + self.dual_setup * subdomains / self.S
        coarse = self.n_F * self.Q_per_row * m  # replicated in both arrangements
        if not partitioned:
            vector = self.n_F * self.vector_per_row * m
            per_exchange = exchange if exchange is not None else allgather_seconds(P, m)
            communication = (self.n_F + self.n_M) * per_exchange
        else:
            vector = self.n_F * (self.vector_per_row * m / P + DOTS_PER_STEP * allreduce_seconds(P, 1))
            # Rows shared with neighbour ranks: a square patch of s subdomains has about 4√s
            # subdomain edges on its boundary, each with a quarter of a subdomain's rows.
            shared = math.sqrt(s) * self.rows_per_subdomain if P > 1 else 0.0
            neighbour = 0.0 if P == 1 else 4 * LATENCY_S + 8 * shared / BANDWIDTH_B_PER_S
            communication = (self.n_F + self.n_M) * neighbour + self.n_F * allreduce_seconds(P, 3 * subdomains)
        return {"setup": setup, "compute": compute, "vector": vector, "coarse": coarse, "communication": communication,
                "total": setup + compute + vector + coarse + communication}


def model(outdir):
    serial = os.path.join(outdir, "solve-serial.h5")
    if not os.path.exists(serial):
        sys.exit(f"bench_mpi.py: {serial} is missing: run `bench_mpi.py solve` first")
    u = UnitCosts(serial)
    md = ["# Performance model of one solve over MPI ranks", "",
          f"Unit costs from the serial solve ({u.S} subdomains, dim lambda {u.m}, {u.n_F} F and {u.n_M} M^-1 "
          "applications):", "",
          f"- F: {u.F_per_subdomain * 1e3:.3f} ms per subdomain per application; M^-1: "
          f"{u.M_per_subdomain * 1e3:.3f} ms",
          f"- the QP's vector work: {u.vector_per_row * 1e9:.1f} ns per row of lambda per F application; the "
          f"coarse problem (Q): {u.Q_per_row * 1e9:.1f} ns per row",
          f"- setup (assembly, factorisation): {u.setup_per_subdomain * 1e3:.1f} ms per subdomain; "
          f"{u.rows_per_subdomain:.0f} rows of lambda per subdomain",
          f"- assumed interconnect: latency {LATENCY_S * 1e6:.1f} us, bandwidth {BANDWIDTH_B_PER_S / 1e9:.1f} GB/s "
          "(HDR InfiniBand); iteration counts as measured (bounded for a fixed H/h)", ""]
    # Validation: the measured strong scaling, with the measured exchange seconds.
    md += ["## The model against the measured runs (strong scaling, this machine)", "",
           "With the exchange seconds measured here (shared memory) and, oversubscribed, the ranks' own work "
           "stretched by ranks/cores.", "",
           "| ranks | measured QP s | model QP s | model / measured | oversubscribed |", "|---|---|---|---|---|"]
    csv = ["kind,ranks,subdomains,setup,compute,vector,coarse,communication,total,efficiency"]
    with open(os.path.join(outdir, "solve.csv")) as f:
        measured = [line.strip().split(",") for line in f]
    col = {name: i for i, name in enumerate(measured[0])}
    measured = measured[1:]
    for row in measured[1:]:
        P = int(row[1])
        with h5py.File(os.path.join(outdir, f"solve-ranks-{P}.h5"), "r") as f:
            exchanges = f["/ranks/exchanges"][()]
            per_exchange = max(f["/ranks/seconds_communication"][()] / exchanges) if exchanges.min() > 0 else 0.0
        t = u.solve_seconds(P, u.S, exchange=per_exchange)
        # Oversubscribed, the ranks share the cores: their own work takes P/cores as long.
        cores = int(row[col["cores"]])
        qp = t["total"] - t["setup"] + t["compute"] * (max(1.0, P / cores) - 1)
        measured_qp = float(row[col["seconds_qp"]])
        md.append(f"| {P} | {measured_qp:.2f} | {qp:.2f} | {qp / measured_qp:.2f} | "
                  f"{'yes' if row[col['oversubscribed']] == '1' else 'no'} |")
    s = u.S // 2  # the subdomains per rank of the 2-rank run
    md += ["", f"## Weak scaling: {s} subdomains per rank (as on 2 ranks here), {s * u.m // u.S} rows of lambda per rank",
           "", "Seconds per solve, and the efficiency T(1 rank) / T(P ranks); the replicated arrangement is what "
           "dualcell does, the partitioned one is projected for comparison (not implemented).", "",
           "| ranks | DOFs | replicated: s | compute | vector + coarse | exchange | efficiency | "
           "partitioned: s | efficiency |", "|---|---|---|---|---|---|---|---|---|"]
    with h5py.File(serial, "r") as f:
        dofs_per_subdomain = int(f["/solver"].attrs["dim_u"]) / u.S
    one = u.solve_seconds(1, s)
    one_p = u.solve_seconds(1, s, partitioned=True)
    for P in WEAK_RANKS:
        r = u.solve_seconds(P, s * P)
        q = u.solve_seconds(P, s * P, partitioned=True)
        e, e_p = one["total"] / r["total"], one_p["total"] / q["total"]
        for kind, t, eff in (("replicated", r, e), ("partitioned", q, e_p)):
            csv.append(f"{kind},{P},{s * P},{t['setup']:.4f},{t['compute']:.4f},{t['vector']:.4f},{t['coarse']:.4f},"
                       f"{t['communication']:.4f},{t['total']:.4f},{eff:.4f}")
        md.append(f"| {P} | {dofs_per_subdomain * s * P:.3g} | {r['total']:.1f} | {r['compute']:.1f} | "
                  f"{r['vector'] + r['coarse']:.1f} | {r['communication']:.2f} | {e:.2f} | {q['total']:.1f} | "
                  f"{e_p:.2f} |")
    write(outdir, "model.csv", csv)
    write(outdir, "model.md", md)
    print("\n".join(md))


def rank_counts(text):
    """The rank counts of "P1 P2 ..." (one word on the command line)."""
    return [int(p) for p in text.split()]


def main(argv):
    parser = common.Parser(__doc__)
    modes = parser.add_subparsers(dest="mode", metavar="MODE", required=True)
    for mode in ("sweep", "solve"):
        p = modes.add_parser(mode)
        p.add_argument("bindir", metavar="BIN")
        p.add_argument("scene", metavar="SCENE.toml")
        if mode == "solve":
            p.add_argument("stress", metavar="STRESS")
        p.add_argument("outdir", metavar="OUTDIR")
        p.add_argument("ranks", metavar='"P1 P2 ..."', type=rank_counts)
        p.add_argument("repeat", metavar="REPEAT", type=int)
        p.add_argument("cores", metavar="CORES", type=int)
    modes.add_parser("model").add_argument("outdir", metavar="OUTDIR")
    args = vars(parser.parse_args(argv[1:]))
    {"sweep": sweep, "solve": solve, "model": model}[args.pop("mode")](**args)


if __name__ == "__main__":
    common.main_guard(main)
