"""What the pipeline's Python tools share: the command line, running and timing a command, the
mesh -> sweep -> fit chain, atomic writes and a script's error convention (one line on stderr,
exit 1).

The tools import it as a sibling (`import common`): a script run as `python3 tools/x.py` has its
own folder first on sys.path, so no sys.path edit is needed.
"""
import argparse
import contextlib
import csv
import io
import os
import re
import subprocess
import sys
import tempfile
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


class Finished(subprocess.CompletedProcess):
    """A command that ran (subprocess.CompletedProcess) and what it cost: `seconds`, its wall time
    (time.perf_counter), and `peak_mib`, its peak resident memory in MiB (os.wait4's ru_maxrss of
    that child and the children it waited for, not of this process)."""

    def __init__(self, command, returncode, stdout, stderr, seconds, peak_mib):
        super().__init__(command, returncode, stdout, stderr)
        self.seconds = seconds
        self.peak_mib = peak_mib


def run(command, env=None, check=True, input=None, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **options):
    """Runs `command` (a list of words) and returns its Finished: the exit status, its stdout and
    stderr as text, its wall seconds and peak memory. The one way the tools run and time a command.
    stdout and stderr are captured unless given (None: this process's, subprocess.DEVNULL,
    stderr=subprocess.STDOUT); `input` is text for its stdin; `options` go to subprocess.Popen
    (cwd, ...). A non-zero exit raises CommandFailed ('<command>: exit <status>: <its stderr>')
    unless `check` is false: then the caller judges the result."""
    # Captured output goes to files, not pipes: the child is reaped by os.wait4 (its own peak
    # memory, which subprocess.run's wait does not give), so nothing may wait on full pipes.
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        start = time.perf_counter()
        process = subprocess.Popen(command, env=env, stdin=subprocess.PIPE if input is not None else None,
                                   stdout=out if stdout == subprocess.PIPE else stdout,
                                   stderr=err if stderr == subprocess.PIPE else stderr, text=True, **options)
        if input is not None:
            # A child that exits without reading all of it (gnuplot on an error) is judged by its
            # exit status, as subprocess.run does.
            with contextlib.suppress(BrokenPipeError):
                with process.stdin:
                    process.stdin.write(input)
        _, status, usage = os.wait4(process.pid, 0)
        seconds = time.perf_counter() - start
        process.returncode = os.waitstatus_to_exitcode(status)  # reaped: Popen must not wait again
        out.seek(0)
        err.seek(0)
        done = Finished(command, process.returncode, out.read() if stdout == subprocess.PIPE else None,
                        err.read() if stderr == subprocess.PIPE else None, seconds, usage.ru_maxrss / 1024)
    if check and done.returncode != 0:
        raise CommandFailed(command, done)
    return done


# The exit status of a stage that wrote its output without converging everywhere: a sweep's
# steps marked as not converged (the fit uses the converged ones), a solve whose QP stagnated
# just short of its tolerance. It says so on stderr.
NOT_CONVERGED = 4


def run_stage(command, out, unconverged_kept=False, **options):
    """Runs a dualcell stage `command` writing `out` (run's Finished, its output captured). With
    `unconverged_kept`, exit NOT_CONVERGED is no failure: `out` is kept (what make would delete
    with a failed rule). What the stage said on stderr (that note, a scene's warnings: the callers
    run stages --quiet, so nothing else) is passed on after the file it concerns. Any other
    non-zero exit raises CommandFailed."""
    done = run(command, check=False, **options)
    if done.returncode != 0 and not (unconverged_kept and done.returncode == NOT_CONVERGED):
        raise CommandFailed(command, done)
    if done.stderr and done.stderr.strip():
        print(f"{os.path.basename(sys.argv[0])}: {out}: {done.stderr.strip()}", file=sys.stderr)
    return done


def run_ccx(ccx, folder, job, env=None):
    """Runs CalculiX `ccx` on `job`.inp in `folder` (one thread unless `env` says otherwise) and
    returns its Finished (stdout with stderr); a non-zero exit or an *ERROR line in its output
    raises RuntimeError with the first such line."""
    env = env or dict(os.environ, OMP_NUM_THREADS="1")
    done = run([ccx, "-i", job], env, check=False, cwd=folder, stderr=subprocess.STDOUT)
    errors = [line.strip() for line in done.stdout.splitlines() if "*ERROR" in line]
    if done.returncode != 0 or errors:
        raise RuntimeError(f"ccx exit {done.returncode}: {errors[0] if errors else done.stdout.strip()[-300:]}")
    return done


def law_chain(bin_dir, scene, folder, fit_options=()):
    """mesh -> sweep -> fit of `scene` (a scene file) into `folder`: mesh.h5, sweep.h5 and law.h5,
    the stages run --quiet from `bin_dir`, a sweep that did not converge everywhere kept
    (run_stage), `fit_options` passed to dualcell-fit. The one spelling of the chain (make's
    law_chain, the RVE study, the lamina table). Returns the stages' Finished by name: mesh,
    sweep, fit."""
    stage = lambda name: os.path.join(bin_dir, f"dualcell-{name}")  # noqa: E731
    mesh, sweep, law = (os.path.join(folder, name) for name in ("mesh.h5", "sweep.h5", "law.h5"))
    return {"mesh": run_stage([stage("mesh"), "--quiet", "--config", scene, "--out", mesh], mesh),
            "sweep": run_stage([stage("sweep"), "--quiet", "--config", scene, "--mesh", mesh, "--out", sweep], sweep,
                               unconverged_kept=True),
            "fit": run_stage([stage("fit"), "--quiet", *fit_options, "--sweep", sweep, "--out", law], law)}


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


def write_csv(path, columns, rows):
    """Writes the dicts `rows` as CSV with the header `columns` (missing keys empty, others
    ignored), atomically (write_atomic)."""
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns, extrasaction="ignore", restval="", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    write_atomic(path, text.getvalue())


def write_table(path, markdown, columns, rows):
    """A study's table: the Markdown text `markdown` to `path` and the dicts `rows` as CSV beside
    it (the same name, .csv; write_csv), both atomically."""
    write_atomic(path, markdown)
    write_csv(os.path.splitext(path)[0] + ".csv", columns, rows)


def write_seconds(path, seconds):
    """Writes a measured wall time to `path` as the tables read it (tools/convergence_table.py,
    tools/structures.py): the seconds on one line, to six significant digits."""
    write_atomic(path, f"{seconds:.6g}\n")
