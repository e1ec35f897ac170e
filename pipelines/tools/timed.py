#!/usr/bin/python3
"""Runs a command and writes its wall seconds to a file: make's timed rules (common.run).

usage: timed.py SECONDS COMMAND [ARG...]

The command's output goes where this script's goes. When it succeeds, SECONDS gets its wall
seconds (common.write_seconds); when it fails, SECONDS is not written and this script exits 1.
Several commands are timed together as one `sh -c '... && ...'`.
"""
import argparse

import common


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("seconds", metavar="SECONDS")
    parser.add_argument("command", metavar="COMMAND [ARG...]", nargs=argparse.REMAINDER)
    args = parser.parse_args(argv[1:])
    if not args.command:
        raise ValueError("no command to time")
    done = common.run(args.command, stdout=None, stderr=None)
    common.write_seconds(args.seconds, done.seconds)


if __name__ == "__main__":
    common.main_guard(main)
