#!/usr/bin/python3
"""Tests of the tools' shared running and timing (common.py, law_chain.py, timed.py; run by ctest
with the stages' folder as argument): common.run gives a child's own wall seconds and peak memory,
the chain keeps a sweep that exits 4 with its note, and the make rules' CLIs write what the tables
read.

The chain runs the real stages on a tiny cell whose solver budget leaves some steps unconverged:
the exit status and its note come from dualcell-sweep itself, not from a stand-in.
"""
import contextlib
import io
import os
import subprocess
import sys
import tempfile
import unittest

import common

BIN = None  # the stages' folder, the first argument
HERE = os.path.dirname(os.path.abspath(__file__))

# A 1x1 periodic cell, p1: F applied at most 50 times per step leaves some of its steps short of
# the tolerance (the sweep exits 4) and enough converged for the fit.
SCENE = """[geometry]
cells = [1, 1]
fibre_radius = 0.3
degree = 1
[fibre]
E = 10.0
nu = 0.2
[matrix]
E = 1.0
nu = 0.3
[load]
boundary = "periodic"
[sweep]
directions_deg = [0, 90]
magnitudes = [-0.01, 0.01]
[solver]
max_operator_applications = 50
"""

# A child that holds 64 MiB (written, so resident) for a moment.
ALLOCATES = [sys.executable, "-c", "import time; b = b'x' * (64 << 20); time.sleep(0.2)"]


class Run(unittest.TestCase):
    def test_seconds_and_the_childs_own_peak_memory(self):
        done = common.run(ALLOCATES)
        self.assertEqual(done.returncode, 0)
        self.assertGreaterEqual(done.seconds, 0.2)
        self.assertGreater(done.peak_mib, 64)
        # A child run after it reports its own peak, not the largest of this process's children.
        small = common.run([sys.executable, "-c", "pass"])
        self.assertLess(small.peak_mib, 50)

    def test_output_input_and_failure(self):
        done = common.run([sys.executable, "-c", "import sys; print(sys.stdin.read().upper()); "
                                                  "print('note', file=sys.stderr)"], input="abc")
        self.assertEqual((done.stdout, done.stderr), ("ABC\n", "note\n"))
        merged = common.run([sys.executable, "-c", "import sys; print('to err', file=sys.stderr)"],
                            stderr=subprocess.STDOUT)
        self.assertEqual(merged.stdout, "to err\n")
        with self.assertRaisesRegex(common.CommandFailed, "exit 3: why"):
            common.run([sys.executable, "-c", "import sys; print('why', file=sys.stderr); sys.exit(3)"])
        self.assertEqual(common.run([sys.executable, "-c", "raise SystemExit(5)"], check=False).returncode, 5)
        # A child that exits without reading its input is judged by its status alone.
        self.assertEqual(common.run(["true"], input="x" * (1 << 20)).returncode, 0)

    def test_a_stage_exiting_4_is_kept_only_where_asked(self):
        stage = [sys.executable, "-c", "import sys; print('short of the tolerance', file=sys.stderr); sys.exit(4)"]
        with self.assertRaisesRegex(common.CommandFailed, "exit 4"):
            common.run_stage(stage, "out.h5")
        note = io.StringIO()
        with contextlib.redirect_stderr(note):
            self.assertEqual(common.run_stage(stage, "out.h5", unconverged_kept=True).returncode, 4)
        self.assertIn("out.h5: short of the tolerance", note.getvalue())


class Chain(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.scene = os.path.join(self.tmp.name, "scene.toml")
        common.write_atomic(self.scene, SCENE)

    def tearDown(self):
        self.tmp.cleanup()

    def test_keeps_a_sweep_that_exits_4_with_its_note(self):
        folder = os.path.join(self.tmp.name, "cell")
        os.makedirs(folder)
        note = io.StringIO()
        with contextlib.redirect_stderr(note):
            stages = common.law_chain(BIN, self.scene, folder)
        self.assertEqual([stages[s].returncode for s in ("mesh", "sweep", "fit")], [0, common.NOT_CONVERGED, 0])
        for name in ("mesh.h5", "sweep.h5", "law.h5"):
            self.assertTrue(os.path.exists(os.path.join(folder, name)), name)
        self.assertIn(os.path.join(folder, "sweep.h5") + ": dualcell-sweep: warning:", note.getvalue())
        self.assertIn("did not converge", note.getvalue())

    def test_a_failed_stage_stops_the_chain(self):
        common.write_atomic(self.scene, "[geometry]\ncells = [0, 1]\n")
        with self.assertRaisesRegex(common.CommandFailed, "dualcell-mesh"):
            common.law_chain(BIN, self.scene, self.tmp.name)
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "sweep.h5")))

    def test_the_make_rule_writes_the_chain_and_its_seconds(self):
        folder = os.path.join(self.tmp.name, "case") + "/"  # as make's $(dir ...) gives it
        seconds = os.path.join(folder, "seconds")
        done = subprocess.run([sys.executable, os.path.join(HERE, "law_chain.py"), self.scene, folder, "--bin", BIN,
                               "--seconds", seconds], capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("did not converge", done.stderr)
        self.assertTrue(os.path.exists(os.path.join(folder, "law.h5")))
        with open(seconds) as f:
            self.assertGreater(float(f.read()), 0)


class Timed(unittest.TestCase):
    def test_writes_the_seconds_of_a_command_that_succeeds_only(self):
        with tempfile.TemporaryDirectory() as tmp:
            seconds = os.path.join(tmp, "seconds")
            timed = [sys.executable, os.path.join(HERE, "timed.py"), seconds]
            subprocess.run(timed + ["sh", "-c", "sleep 0.2 && true"], check=True)
            with open(seconds) as f:
                text = f.read()
            self.assertRegex(text, r"^[0-9.e+-]+\n$")
            self.assertGreaterEqual(float(text), 0.2)
            os.remove(seconds)
            failed = subprocess.run(timed + ["sh", "-c", "echo broken >&2; exit 2"], capture_output=True, text=True)
            self.assertEqual(failed.returncode, 1)
            self.assertIn("broken", failed.stderr)  # the command's own stderr, passed through
            self.assertFalse(os.path.exists(seconds))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: test_common.py BIN_DIR")
    BIN = sys.argv.pop(1)
    unittest.main()
