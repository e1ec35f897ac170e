"""What the pipeline's Python tools share: the command line, running a stage, atomic writes and
a script's error convention (one line on stderr, exit 1).

The tools import it as a sibling (`import common`): a script run as `python3 tools/x.py` has its
own folder first on sys.path, so no sys.path edit is needed.
"""
import argparse
import contextlib
import os
import re
import subprocess
import sys
import time

# What a script's main raises for a bad input, a missing file or a failed command: main_guard
# reports it as one line. Anything else is a bug and keeps its traceback.
ERRORS = (OSError, ValueError, KeyError, RuntimeError)


def main_guard(main):
    """Runs main(sys.argv); an error of ERRORS ends the script with one line on stderr,
    '<script>: error: <message>', and exit 1."""
    try:
        main(sys.argv)
    except ERRORS as e:
        sys.exit(f"{os.path.basename(sys.argv[0])}: error: {e}")


class Parser(argparse.ArgumentParser):
    """argparse as the tools use it: --help prints the description (the script's docstring) as
    written; a usage error raises ValueError, one line with the usage (main_guard: exit 1, not
    argparse's 2); long options are not abbreviated; and a word starting with - and a digit
    (-1e-2, -0.02,0,0) is a value, not an option (Python 3.11's argparse takes only -5 and -0.5
    for numbers; newer versions match any such word, as here)."""

    def __init__(self, description=None, **options):
        options.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        options.setdefault("allow_abbrev", False)
        super().__init__(description=description, **options)
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message):
        raise ValueError(f"{message}; {' '.join(self.format_usage().split())}")


class CommandFailed(RuntimeError):
    """A command that exited with a non-zero status; `done` is its subprocess.CompletedProcess."""

    def __init__(self, command, done):
        detail = (done.stderr or "").strip() or (done.stdout or "").strip()[-2000:]
        super().__init__(f"{' '.join(command)}: exit {done.returncode}: {detail}")
        self.done = done


def text(value):
    """An HDF5 string attribute as str (h5py gives fixed-length strings as bytes)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def run(command, env=None, check=True, **options):
    """Runs `command` (a list of words) and returns (its subprocess.CompletedProcess, its wall
    seconds by time.perf_counter). Its stdout and stderr are captured as text; `options` go to
    subprocess.run (cwd, input, stderr=subprocess.STDOUT, ...). A non-zero exit raises
    CommandFailed ('<command>: exit <status>: <its stderr>') unless `check` is false: then the
    caller judges the result."""
    options = {"stdout": subprocess.PIPE, "stderr": subprocess.PIPE, "text": True, **options}
    start = time.perf_counter()
    done = subprocess.run(command, env=env, **options)
    seconds = time.perf_counter() - start
    if check and done.returncode != 0:
        raise CommandFailed(command, done)
    return done, seconds


def write_atomic(path, content):
    """Writes `path` so that no reader sees it half written: into `<path>.tmp.<pid>` beside it,
    then os.replace. `content` is the text, or a function that writes the file whose path it is
    given (a CSV writer, gnuplot). On failure the temporary is removed and the error goes on."""
    tmp = f"{path}.tmp.{os.getpid()}"
    try:
        if callable(content):
            content(tmp)
        else:
            with open(tmp, "w") as f:
                f.write(content)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp)
        raise
