#!/usr/bin/python3
"""One rung of the accuracy study for dualcell: mesh and solve a scene in tension and compression.

usage: accuracy_dualcell.py BIN_DIR SCENE.toml SIGMA REPEAT OUT.csv

Runs `dualcell-mesh` once and `dualcell-solve --stress ±SIGMA,0,0` for each sign, REPEAT times
each, and keeps the fastest wall time of mesh + solve (the machine is shared: the minimum is
the least disturbed run). The apparent modulus is E = σ̄xx / ε̄xx with ε̄ the boundary-average
strain dualcell writes to /macro/strain. Writes OUT.csv atomically, one row per sign:
code,element,degree,nodes,dofs,load,E,seconds. Errors: one line on stderr, exit 1.
"""
import os
import subprocess
import sys
import time
import tomllib

import h5py

HEADER = "code,element,degree,nodes,dofs,load,E,seconds"


def run(command):
    start = time.perf_counter()
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)}: exit {done.returncode}: {done.stderr.strip()}")
    return seconds


def main(argv):
    if len(argv) != 6:
        raise ValueError("usage: accuracy_dualcell.py BIN_DIR SCENE.toml SIGMA REPEAT OUT.csv")
    bin_dir, scene, sigma, repeat, out = argv[1], argv[2], float(argv[3]), int(argv[4]), argv[5]
    if not sigma > 0 or repeat < 1:
        raise ValueError(f"SIGMA {argv[3]} must be > 0 and REPEAT {argv[4]} >= 1")
    with open(scene, "rb") as f:
        geometry = tomllib.load(f).get("geometry", {})
    element, degree = geometry.get("element", "p1"), geometry["degree"]
    work = os.path.dirname(os.path.abspath(out))
    mesh = os.path.join(work, "mesh.h5")
    mesh_seconds = min(run([os.path.join(bin_dir, "dualcell-mesh"), "--quiet", "--config", scene, "--out", mesh])
                       for _ in range(repeat))
    with h5py.File(mesh, "r") as f:
        nodes = f["/mesh/nodes"].shape[0]
    rows = [HEADER]
    for load in (sigma, -sigma):
        solution = os.path.join(work, f"solution{'+' if load > 0 else '-'}.h5")
        command = [os.path.join(bin_dir, "dualcell-solve"), "--quiet", "--config", scene, "--mesh", mesh, "--stress",
                   f"{load!r},0,0", "--out", solution]
        seconds = min(run(command) for _ in range(repeat))
        with h5py.File(solution, "r") as f:
            strain = f["/macro/strain"][:]
        rows.append(f"dualcell,{element},{degree},{nodes},{2 * nodes},{load!r},{load / strain[0]!r},"
                    f"{mesh_seconds + seconds:.6f}")
    tmp = f"{out}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        f.write("\n".join(rows) + "\n")
    os.replace(tmp, out)


if __name__ == "__main__":
    try:
        main(sys.argv)
    except (OSError, ValueError, KeyError, RuntimeError, tomllib.TOMLDecodeError) as e:
        sys.stderr.write(f"accuracy_dualcell.py: error: {e}\n")
        sys.exit(1)
