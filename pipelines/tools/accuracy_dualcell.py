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
import tomllib

import h5py

import common

HEADER = "code,element,degree,nodes,dofs,load,E,seconds"


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("bin_dir", metavar="BIN_DIR")
    parser.add_argument("scene", metavar="SCENE.toml")
    parser.add_argument("sigma", metavar="SIGMA", type=float)
    parser.add_argument("repeat", metavar="REPEAT", type=int)
    parser.add_argument("out", metavar="OUT.csv")
    args = parser.parse_args(argv[1:])
    bin_dir, scene, sigma, repeat, out = args.bin_dir, args.scene, args.sigma, args.repeat, args.out
    if not sigma > 0 or repeat < 1:
        raise ValueError(f"SIGMA {sigma!r} must be > 0 and REPEAT {repeat} >= 1")
    with open(scene, "rb") as f:
        geometry = tomllib.load(f).get("geometry", {})
    element, degree = geometry.get("element", "p1"), geometry["degree"]
    work = os.path.dirname(os.path.abspath(out))
    mesh = os.path.join(work, "mesh.h5")
    mesh_command = [os.path.join(bin_dir, "dualcell-mesh"), "--quiet", "--config", scene, "--out", mesh]
    mesh_seconds = min(common.run(mesh_command).seconds for _ in range(repeat))
    with h5py.File(mesh, "r") as f:
        nodes = f["/mesh/nodes"].shape[0]
    rows = [HEADER]
    for load in (sigma, -sigma):
        solution = os.path.join(work, f"solution{'+' if load > 0 else '-'}.h5")
        command = [os.path.join(bin_dir, "dualcell-solve"), "--quiet", "--config", scene, "--mesh", mesh, "--stress",
                   f"{load!r},0,0", "--out", solution]
        seconds = min(common.run(command).seconds for _ in range(repeat))
        with h5py.File(solution, "r") as f:
            strain = f["/macro/strain"][:]
        rows.append(f"dualcell,{element},{degree},{nodes},{2 * nodes},{load!r},{load / strain[0]!r},"
                    f"{mesh_seconds + seconds:.6f}")
    common.write_atomic(out, "\n".join(rows) + "\n")


if __name__ == "__main__":
    common.main_guard(main)
