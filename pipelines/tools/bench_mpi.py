#!/usr/bin/python3
"""Strong scaling of a sweep over MPI ranks: the same dualcell-sweep run serially (no launcher)
and under mpiexec with P ranks, one thread each, the best of REPEAT runs per P.

usage: bench_mpi.py BIN SCENE.toml OUTDIR "P1 P2 ..." REPEAT CORES

Meshes SCENE once, then times each run of dualcell-sweep (the journal removed before each, so
every run computes every path) and checks that each run's sweep.h5 equals the serial one but for
the seconds columns (h5diff). Writes OUTDIR/sweep.md and OUTDIR/sweep.csv: P, seconds (min and
median), speed-up and efficiency against the serial run, and whether the run was oversubscribed
(P > CORES, the machine's cores: then the ranks share cores and the speed-up is capped).
"""
import os
import shutil
import statistics
import subprocess
import sys
import time


def run(command, env=None):
    start = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"bench_mpi.py: {' '.join(command)} failed:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    return seconds


def same_but_seconds(a, b):
    done = subprocess.run(["h5diff", a, b], capture_output=True, text=True)
    if done.returncode > 1:
        sys.exit(f"bench_mpi.py: h5diff failed: {done.stderr}")
    others = [l for l in done.stdout.splitlines()
              if (l.startswith("dataset:") or l.startswith("attribute:")) and "/seconds>" not in l]
    return not others


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    bindir, scene, outdir, ranks, repeat, cores = sys.argv[1:]
    ranks, repeat, cores = [int(p) for p in ranks.split()], int(repeat), int(cores)
    os.makedirs(outdir, exist_ok=True)
    mesh = os.path.join(outdir, "mesh.h5")
    run([os.path.join(bindir, "dualcell-mesh"), "--quiet", "--config", scene, "--out", mesh])
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    sweep = [os.path.join(bindir, "dualcell-sweep"), "--quiet", "--threads", "1", "--config", scene, "--mesh", mesh]

    def timed(prefix, out):
        times = []
        for _ in range(repeat):
            for stale in (out, out + ".parts"):
                if os.path.isdir(stale):
                    shutil.rmtree(stale)
                elif os.path.exists(stale):
                    os.remove(stale)
            times.append(run(prefix + sweep + ["--out", out], env))
            print(f"bench_mpi.py: {os.path.basename(out)}: {times[-1]:.2f} s", file=sys.stderr)
        return times

    serial_out = os.path.join(outdir, "serial.h5")
    rows = [("serial (no launcher)", 1, timed([], serial_out), True)]
    for p in ranks:
        out = os.path.join(outdir, f"ranks-{p}.h5")
        times = timed(["mpiexec", "-n", str(p), "--oversubscribe"], out)
        rows.append((f"mpiexec -n {p}", p, times, same_but_seconds(serial_out, out)))
    base = min(rows[0][2])
    csv = ["run,ranks,seconds_min,seconds_median,speedup,efficiency,oversubscribed,same_as_serial"]
    md = ["# Strong scaling of a sweep over MPI ranks", "",
          f"Scene {os.path.basename(scene)}, one thread per rank, best of {repeat} runs; the machine has {cores} cores.",
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
    for name, lines in (("sweep.csv", csv), ("sweep.md", md)):
        path = os.path.join(outdir, name)
        with open(path + ".tmp", "w") as f:
            f.write("\n".join(lines) + "\n")
        os.replace(path + ".tmp", path)
    print("\n".join(md))
    if not all(r[3] for r in rows):
        sys.exit("bench_mpi.py: a run under mpiexec did not write the serial sweep.h5")


if __name__ == "__main__":
    main()
