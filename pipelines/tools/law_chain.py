#!/usr/bin/python3
"""mesh -> sweep -> fit of one scene into a folder, the stages run --quiet (common.law_chain).

usage: law_chain.py SCENE.toml FOLDER --bin BIN_DIR [--seconds FILE]

Writes FOLDER/mesh.h5, sweep.h5 and law.h5 (FOLDER is created). A sweep that exits 4 (steps
marked as not converged; the fit uses the converged ones) is kept, its note on stderr. --seconds:
also writes the wall seconds of mesh + sweep to FILE (the cost of the cell's solutions, which the
convergence study reports; the fit is not part of it). Errors: one line on stderr, exit 1.
"""
import os

import common


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("scene", metavar="SCENE.toml")
    parser.add_argument("folder", metavar="FOLDER")
    parser.add_argument("--bin", required=True, metavar="BIN_DIR")
    parser.add_argument("--seconds", metavar="FILE")
    args = parser.parse_args(argv[1:])
    os.makedirs(args.folder, exist_ok=True)
    stages = common.law_chain(args.bin, args.scene, args.folder)
    if args.seconds:
        common.write_seconds(args.seconds, stages["mesh"].seconds + stages["sweep"].seconds)


if __name__ == "__main__":
    common.main_guard(main)
