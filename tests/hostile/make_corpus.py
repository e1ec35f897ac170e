#!/usr/bin/python3
"""Regenerates the hostile-input corpus in data/hostile/ (read by tests/hostile/hostile_test.cpp).

    /usr/bin/python3 tests/hostile/make_corpus.py [BIN_DIR]     (default BIN_DIR: build/bin)

Writes
  data/hostile/scenes/*.toml, aux/*   malformed and hostile scene files (and the files they name)
  data/hostile/scenes/expected.tsv    file, expected outcome, substring of the message, what it is
  data/hostile/h5/*                   truncated and corrupted mesh.h5, solution.h5, sweep.h5, law.h5,
                                      made from real outputs of the stages on a 1x1 degree-1 scene
  data/hostile/h5/expected.tsv        file, kind (which stages read it), outcome, substring, what
  data/hostile/README.md              both tables in words

Outcomes: `ok` the stage accepts the input (exit 0); `input` it refuses it with exit 1 and one
line "<stage>: error: ..." containing the substring; `mesh-input` dualcell-mesh refuses it so
(an RVE's fibres, which only the mesher places; the other stages read the mesh instead). Needs Debian's python3-h5py and numpy.
Everything is deterministic except the provenance inside the stage outputs (code version,
timings), so regenerating changes the .h5 bytes but not what the tests expect.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUT = os.path.join(ROOT, "data", "hostile")
SCENES = os.path.join(OUT, "scenes")
H5 = os.path.join(OUT, "h5")

# ---------------------------------------------------------------------------------------------
# Scene files

GEOMETRY = {"cells": "[1, 1]", "fibre_radius": "0.3", "degree": "1", "element": "\"p1\""}
FIBRE = {"E": "10.0", "nu": "0.2"}
MATRIX = {"E": "1.0", "nu": "0.3"}


def table(name, defaults, over):
    keys = dict(defaults)
    keys.update(over or {})
    lines = [f"[{name}]"] + [f"{k} = {v}" for k, v in keys.items() if v is not None]
    return "\n".join(lines) + "\n"


def scene(geometry=None, fibre=None, matrix=None, tail="", head=""):
    """The tiny valid scene with some keys replaced (value None drops the key)."""
    return (head + table("geometry", GEOMETRY, geometry) + "\n" + table("fibre", FIBRE, fibre) + "\n" +
            table("matrix", MATRIX, matrix) + tail)


VALID = scene()
SCENE_CASES = []  # (file, content, outcome, substring, what)


def case(name, content, outcome, substring, what):
    SCENE_CASES.append((name + ".toml", content, outcome, substring, what))


def nested(depth, open_, close, leaf):
    return open_ * depth + leaf + close * depth


def build_scene_cases():
    # Accepted: the reference and the valid oddities.
    case("valid", VALID, "ok", "", "the tiny reference scene itself")
    case("crlf", VALID.replace("\n", "\r\n"), "ok", "", "CRLF line endings (valid TOML)")
    case("bom", "\ufeff" + VALID, "ok", "", "a UTF-8 byte order mark before the first key")
    case("unicode-comments", "# Glasfaser in Epoxid, r = 0,3 — ½ · π · r²\n" + VALID +
         "# 繊維 ガラス\n", "ok", "", "comments in German, Japanese and with symbols")
    case("integral-floats-for-cells", scene(geometry={"cells": "[1.0, 1.0]"}), "ok", "",
         "cells as integral floats (accepted: the value is an integer)")
    case("inline-tables", "geometry = {cells = [1, 1], fibre_radius = 0.3}\nfibre = {E = 10.0, nu = 0.2}\n"
         "matrix = {E = 1.0, nu = 0.3}\nsolver = {tolerance = 1e-8}\n", "ok", "",
         "every table written inline")
    case("material-file", "material = \"../../../materials/glass-epoxy.toml\"\n" +
         table("geometry", GEOMETRY, {}), "ok", "", "a material file by relative path")
    case("underscores-hex", scene(geometry={"degree": "0x1"}, fibre={"E": "1_0.0"}), "ok", "",
         "TOML number spellings: hex integer, underscores")

    # TOML syntax
    case("syntax-unclosed-table", "[geometry\nfibre_radius = 0.3\n", "input", "TOML syntax error",
         "a table header without ]")
    case("syntax-missing-value", scene(geometry={"fibre_radius": ""}), "input", "TOML syntax error",
         "key = and nothing")
    case("syntax-unterminated-string", "material = \"glass-epoxy.toml\n" + VALID, "input", "TOML syntax error",
         "a string without its closing quote")
    case("syntax-bare-word", scene(geometry={"degree": "one"}), "input", "TOML syntax error",
         "an unquoted word as value")
    case("syntax-duplicate-key", scene(geometry={"degree": "1\ndegree = 2"}), "input", "TOML syntax error",
         "the same key twice in one table")
    case("syntax-duplicate-table", VALID + "\n[geometry]\ndegree = 2\n", "input", "TOML syntax error",
         "the same table twice")
    case("syntax-integer-overflow", scene(geometry={"degree": "99999999999999999999"}), "input",
         "TOML syntax error", "an integer beyond 64 bits")
    case("syntax-nul-byte", VALID.replace("fibre_radius", "fibre\0_radius"), "input", "TOML syntax error",
         "a NUL byte inside a key")
    case("syntax-nul-only", "\0" * 64, "input", "TOML syntax error", "64 NUL bytes")
    case("syntax-deep-arrays", scene(geometry={"cells": nested(1000, "[", "]", "1")}), "input",
         "TOML syntax error", "cells nested 1000 arrays deep")
    case("syntax-deep-inline-tables", scene(tail="[solver]\nx = " + nested(1000, "{a = ", "}", "1") + "\n"),
         "input", "TOML syntax error", "an inline table nested 1000 deep")
    rng = np.random.default_rng(20240607)
    case("binary-garbage", bytes(rng.integers(0, 256, 4096, dtype=np.uint8)), "input", "TOML syntax error",
         "4 KiB of random bytes")
    case("invalid-utf8", VALID.encode() + b"# \xff\xfe\xc0\x80 not UTF-8\n", "input", "TOML syntax error",
         "a comment that is not UTF-8")
    case("utf16", ("\ufeff" + VALID).encode("utf-16-le"), "input", "TOML syntax error",
         "the scene saved as UTF-16")

    # Empty and huge
    case("empty", "", "input", "missing table [geometry]", "an empty file")
    case("comments-only", "# nothing here\n\n   \n# still nothing\n", "input", "missing table [geometry]",
         "only comments and blank lines")
    case("long-comment-line", "# " + "x" * (1 << 20) + "\n" + VALID, "ok", "", "a 1 MiB comment line")
    case("long-string-value", scene(tail="[load]\nboundary = \"" + "x" * (1 << 20) + "\"\n"), "input",
         "[load] boundary = \"xxxx", "a 1 MiB string value (the message quotes it shortened)")
    case("long-key", scene(tail="[solver]\n" + "k" * (1 << 16) + " = 1\n"), "input", "unknown key",
         "a 64 KiB key")
    case("many-magnitudes", scene(tail="[sweep]\nmagnitudes = [" + ",".join(["1"] * 100001) + "]\n"), "input",
         "[sweep] magnitudes", "100001 magnitudes (at most 100000)")

    # Wrong types, one per key kind
    types = [
        ("cells-string", scene(geometry={"cells": "\"2x2\""}), "[geometry] cells = \"2x2\"", "cells as a string"),
        ("cells-float", scene(geometry={"cells": "[1.5, 1]"}), "[geometry] cells = [1.5, 1]", "a fractional cell count"),
        ("cells-table", scene(geometry={"cells": "{x = 1, y = 1}"}), "[geometry] cells", "cells as an inline table"),
        ("cells-nested", scene(geometry={"cells": "[[1], [1]]"}), "[geometry] cells", "cells as arrays of arrays"),
        ("cells-three", scene(geometry={"cells": "[1, 1, 1]"}), "[geometry] cells", "three cell counts"),
        ("cells-empty", scene(geometry={"cells": "[]"}), "[geometry] cells", "an empty cells array"),
        ("cell-size-string", scene(geometry={"cell_size": "\"1 mm\""}), "[geometry] cell_size", "a length with a unit"),
        ("radius-bool", scene(geometry={"fibre_radius": "true"}), "[geometry] fibre_radius = true", "a boolean radius"),
        ("radius-array", scene(geometry={"fibre_radius": "[0.3]"}), "[geometry] fibre_radius", "a radius in an array"),
        ("radius-date", scene(geometry={"fibre_radius": "1979-05-27"}), "[geometry] fibre_radius",
         "a date as radius"),
        ("offset-string", scene(geometry={"fibre_offset": "\"0, 0\""}), "[geometry] fibre_offset",
         "an offset as a string"),
        ("offset-one", scene(geometry={"fibre_offset": "[0.1]"}), "[geometry] fibre_offset", "one offset component"),
        ("degree-float", scene(geometry={"degree": "1.0"}), "[geometry] degree = 1.0", "a float degree"),
        ("degree-string", scene(geometry={"degree": "\"1\""}), "[geometry] degree = \"1\"", "a quoted degree"),
        ("E-string", scene(fibre={"E": "\"72 GPa\""}), "[fibre] E = \"72 GPa\"", "a modulus with its unit"),
        ("nu-array", scene(matrix={"nu": "[0.3]"}), "[matrix] nu", "Poisson's ratio in an array"),
        ("strength-datetime", scene(tail="[interface]\nnormal_strength = 1979-05-27T07:32:00Z\n"),
         "[interface] normal_strength", "a date-time as strength"),
        ("boundary-integer", scene(tail="[load]\nboundary = 1\n"), "[load] boundary = 1", "a boundary by number"),
        ("boundary-unknown", scene(tail="[load]\nboundary = \"clamped\"\n"), "must be one of",
         "a boundary that does not exist"),
        ("body-force-table", scene(tail="[load]\nbody_force = {x = 0, y = -1}\n"), "[load] body_force",
         "a body force as a table"),
        ("directions-string", scene(tail="[sweep]\ndirections_deg = \"0, 90\"\n"), "[sweep] directions_deg",
         "directions as a string"),
        ("directions-mixed", scene(tail="[sweep]\ndirections_deg = [0, \"90\"]\n"), "[sweep] directions_deg",
         "a number and a string in one array"),
        ("magnitudes-table", scene(tail="[sweep]\nmagnitudes = {a = 1}\n"), "[sweep] magnitudes",
         "magnitudes as a table"),
        ("stress-directions-flat", scene(tail="[load]\nboundary = \"periodic\"\n[sweep]\nstress_directions = [1, 0, 0]\n"),
         "[sweep] stress_directions", "a tensor not wrapped in an outer array"),
        ("stress-directions-pair", scene(tail="[load]\nboundary = \"periodic\"\n[sweep]\nstress_directions = [[1, 0]]\n"),
         "[sweep] stress_directions", "a tensor with two components"),
        ("stress-directions-strings", scene(tail="[load]\nboundary = \"periodic\"\n[sweep]\nstress_directions = [[\"1\", 0, 0]]\n"),
         "[sweep] stress_directions", "a tensor component as a string"),
        ("fuse-tolerance-string", scene(tail="[sweep]\nfuse_tolerance = \"1e-3\"\n"), "[sweep] fuse_tolerance",
         "a quoted tolerance"),
        ("tolerance-array", scene(tail="[solver]\ntolerance = [1e-8]\n"), "[solver] tolerance", "a tolerance in an array"),
        ("iterations-float", scene(tail="[solver]\nmax_outer_iterations = 200.0\n"), "[solver] max_outer_iterations",
         "a float iteration count"),
        ("applications-string", scene(tail="[solver]\nmax_operator_applications = \"many\"\n"),
         "[solver] max_operator_applications", "a word as a count"),
        ("rho-bool", scene(tail="[solver]\nrho_factor = false\n"), "[solver] rho_factor = false", "a boolean factor"),
        ("gamma-time", scene(tail="[solver]\nGamma = 07:32:00\n"), "[solver] Gamma", "a time of day as Gamma"),
        ("dual-operator-unknown", scene(tail="[solver]\ndual_operator = \"dense\"\n"),
         "dual_operator = \"dense\": must be one of", "a dual operator that does not exist"),
        ("dual-operator-bool", scene(tail="[solver]\ndual_operator = true\n"), "[solver] dual_operator",
         "a boolean as the dual operator"),
        ("material-integer", "material = 5\n" + table("geometry", GEOMETRY, {}), "[top level] material = 5",
         "material as a number"),
        ("geometry-not-table", "geometry = 5\n" + table("fibre", FIBRE, {}) + table("matrix", MATRIX, {}),
         "[geometry] must be a table", "geometry as a number"),
        ("fibre-array-of-tables", table("geometry", GEOMETRY, {}) + "[[fibre]]\nE = 10.0\nnu = 0.2\n" +
         table("matrix", MATRIX, {}), "[fibre] must be a table", "[[fibre]]: an array of tables"),
        ("solver-string", scene(head="solver = \"fast\"\n"), "[solver] must be a table", "solver as a string"),
    ]
    for name, content, substring, what in types:
        case("type-" + name, content, "input", substring, what)

    # Unknown keys and tables
    case("unknown-top-key", "foo = 1\n" + VALID, "input", "[top level] foo: unknown table or key", "an unknown top-level key")
    case("unknown-table", VALID + "[mesh]\nsize = 1\n", "input", "[top level] mesh: unknown table or key",
         "an unknown table")
    case("unknown-key", scene(geometry={"radius": "0.3"}), "input", "[geometry] radius = 0.3: unknown key",
         "a misspelt key in [geometry]")
    case("unknown-subtable", scene(tail="[geometry.extra]\na = 1\nb = 2\n"), "input",
         "[geometry] extra", "a sub-table [geometry.extra] (its text spans lines)")
    case("unknown-key-in-material", scene(fibre={"G": "30"}), "input", "[fibre] G = 30: unknown key",
         "a shear modulus the scene does not use")
    case("unicode-key", scene(geometry={"\"Faserradius\u00b2\"": "0.09"}), "input",
         "[geometry] \"Faserradius\u00b2\" = 0.09: unknown key", "a quoted key with a non-ASCII letter")
    case("unicode-bare-key", scene(geometry={"rädius": "0.3"}), "input", "TOML syntax error",
         "a bare key with a non-ASCII letter (not allowed bare in TOML 1.0)")
    case("unicode-table-header", scene(tail="[geometry.\"ν\"]\nE = 1\n"), "input", "[geometry] \"ν\"",
         "a sub-table with a Greek name")
    case("unicode-value", scene(tail="[load]\nboundary = \"symmétry\"\n"), "input",
         "[load] boundary = \"symmétry\": must be one of", "a value string with an accent")
    case("unicode-after-value", scene(fibre={"E": "10.0µ"}), "input", "TOML syntax error",
         "a micro sign glued to a number")
    case("toml-ub-line-ending-backslash", scene(tail="[load]\nboundary = \"\"\"\\\n§symmetry\"\"\"\n"),
         "input", "[load] boundary", "§ after a line-ending backslash (undefined behaviour in toml++ 3.3, "
         "tomlplusplus#190)")
    case("toml-ub-two-bytes", b"\xcc\xaa", "input", "TOML syntax error",
         "U+032A alone (undefined behaviour in toml++ 3.3, tomlplusplus#295)")
    case("material-unicode-path", "material = \"aux/matériau-ν.material\"\n" + table("geometry", GEOMETRY, {}),
         "ok", "", "a material file whose name has non-ASCII letters")
    case("material-unicode-missing", "material = \"aux/äöü.material\"\n" + table("geometry", GEOMETRY, {}),
         "input", "aux/äöü.material\": material file not found", "a missing material file with umlauts")
    case("newline-key", scene(geometry={"\"line\\nbreak\"": "1"}), "input", "unknown key",
         "a quoted key holding a newline (the message stays one line)")
    case("multiline-string", scene(tail="[load]\nboundary = \"\"\"\nsym\nmetry\"\"\"\n"), "input",
         "[load] boundary", "a multi-line string value (the message stays one line)")

    # Out of range
    ranges = [
        ("radius-negative", scene(geometry={"fibre_radius": "-0.1"}), "fibre_radius = -0.1: out of range"),
        ("radius-zero", scene(geometry={"fibre_radius": "0"}), "fibre_radius = 0: out of range"),
        ("radius-missing", scene(geometry={"fibre_radius": None}), "fibre_radius: missing"),
        ("fibre-touches-edge", scene(geometry={"fibre_radius": "0.5"}), "touches or crosses"),
        ("offset-touches-edge", scene(geometry={"fibre_offset": "[0.2, 0]"}), "touches or crosses"),
        ("offset-y-crosses-edge", scene(geometry={"fibre_offset": "[0, -0.7]"}), "fibre_offset[1]"),
        ("cell-size-zero", scene(geometry={"cell_size": "0"}), "cell_size = 0: out of range"),
        ("cell-size-negative", scene(geometry={"cell_size": "-1"}), "cell_size = -1: out of range"),
        ("nu-half", scene(matrix={"nu": "0.5"}), "[matrix] nu = 0.5: out of range"),
        ("nu-minus-one", scene(fibre={"nu": "-1"}), "[fibre] nu = -1: out of range"),
        ("E-zero", scene(fibre={"E": "0"}), "[fibre] E = 0: out of range"),
        ("E-negative", scene(matrix={"E": "-3.5"}), "[matrix] E = -3.5: out of range"),
        ("E-missing", scene(matrix={"E": None}), "[matrix] E: missing"),
        ("degree-zero", scene(geometry={"degree": "0"}), "degree = 0: out of range"),
        ("degree-negative", scene(geometry={"degree": "-3"}), "degree = -3: out of range"),
        ("degree-huge", scene(geometry={"degree": "100000"}), "degree = 100000: out of range"),
        ("cells-zero", scene(geometry={"cells": "[0, 1]"}), "cells = [0, 1]: out of range"),
        ("cells-negative", scene(geometry={"cells": "[1, -2]"}), "cells = [1, -2]: out of range"),
        ("cells-huge", scene(geometry={"cells": "[100000, 100000]"}), "cells = [100000, 100000]: out of range"),
        ("cells-4096-degree-256", scene(geometry={"cells": "[4096, 4096]", "degree": "256"}),
         "more than the limit"),
        ("cells-64-degree-64", scene(geometry={"cells": "[64, 64]", "degree": "64"}), "more than the limit"),
        ("strength-negative", scene(tail="[interface]\nnormal_strength = -1\n"), "normal_strength = -1: out of range"),
        ("tolerance-zero", scene(tail="[solver]\ntolerance = 0\n"), "tolerance = 0: out of range"),
        ("tolerance-one", scene(tail="[solver]\ntolerance = 1\n"), "tolerance = 1: out of range"),
        ("iterations-zero", scene(tail="[solver]\nmax_outer_iterations = 0\n"), "max_outer_iterations = 0: out of range"),
        ("applications-int64-max", scene(tail="[solver]\nmax_operator_applications = 9223372036854775807\n"),
         "max_operator_applications = 9223372036854775807: out of range"),
        ("debond-rounds-int64-min", scene(tail="[solver]\nmax_debond_rounds = -9223372036854775808\n"),
         "max_debond_rounds = -9223372036854775808: out of range"),
        ("rho-huge", scene(tail="[solver]\nrho_factor = 1e7\n"), "rho_factor = 1e7: out of range"),
        ("gamma-zero", scene(tail="[solver]\nGamma = 0.0\n"), "Gamma = 0.0: out of range"),
        ("magnitude-zero", scene(tail="[sweep]\nmagnitudes = [0]\n"), "magnitudes = [0]: out of range"),
        ("magnitudes-empty", scene(tail="[sweep]\nmagnitudes = []\n"), "magnitudes = []"),
        ("direction-720", scene(tail="[sweep]\ndirections_deg = [720]\n"), "directions_deg = [720]: out of range"),
        ("fuse-tolerance-one", scene(tail="[sweep]\nfuse_tolerance = 1\n"), "fuse_tolerance = 1: out of range"),
        ("stress-direction-zero", scene(tail="[load]\nboundary = \"periodic\"\n[sweep]\nstress_directions = [[0, 0, 0]]\n"),
         "not all zero"),
        ("body-force-with-traction", scene(tail="[load]\nboundary = \"traction\"\nbody_force = [0, -1]\n"),
         "needs boundary = \"symmetry\""),
        ("body-force-with-adhesion", scene(tail="[interface]\nnormal_strength = 1\n[load]\nbody_force = [0, -1]\n"),
         "cannot be combined with adhesion"),
        # Expansion per kelvin (a value in ppm is refused), and a temperature change only with it.
        ("alpha-in-ppm", scene(fibre={"alpha": "5"}), "[fibre] alpha = 5: out of range"),
        ("alpha-L-on-isotropic", scene(fibre={"alpha": "5e-6", "alpha_L": "1e-6"}),
         "alpha_L: only for a transversely isotropic phase"),
        ("delta-T-without-alpha", scene(tail="[load]\ndelta_T = -100\n"),
         "a temperature change needs both phases' expansion"),
        ("delta-T-huge", scene(fibre={"alpha": "5e-6"}, matrix={"alpha": "6e-5"}, tail="[load]\ndelta_T = 1e5\n"),
         "delta_T = 1e5: out of range"),
    ]
    for name, content, substring in ranges:
        case("range-" + name, content, "input", substring, "out of range: " + name.replace("-", " "))

    # NaN, infinities, huge exponents
    nonfinite = [
        ("radius-nan", scene(geometry={"fibre_radius": "nan"}), "fibre_radius = nan: out of range"),
        ("radius-minus-nan", scene(geometry={"fibre_radius": "-nan"}), "fibre_radius = -nan: out of range"),
        ("cell-size-inf", scene(geometry={"cell_size": "+inf", "fibre_radius": "1e300"}), "cell_size = +inf: out of range"),
        ("E-inf", scene(fibre={"E": "inf"}), "[fibre] E = inf: out of range"),
        ("nu-nan", scene(matrix={"nu": "nan"}), "[matrix] nu = nan: out of range"),
        ("offset-nan", scene(geometry={"fibre_offset": "[nan, 0]"}), "fibre_offset = [nan, 0]: out of range"),
        ("magnitudes-inf", scene(tail="[sweep]\nmagnitudes = [1, -inf]\n"), "magnitudes = [1, -inf]: out of range"),
        ("directions-nan", scene(tail="[sweep]\ndirections_deg = [nan]\n"), "directions_deg = [nan]: out of range"),
        ("stress-direction-inf", scene(tail="[load]\nboundary = \"periodic\"\n[sweep]\nstress_directions = [[inf, 0, 0]]\n"),
         "[sweep] stress_directions"),
        ("body-force-inf", scene(tail="[load]\nbody_force = [inf, 0]\n"), "body_force = [inf, 0]: out of range"),
        # over two lines the message prints the value itself, not the source text (fuzzer finding)
        ("body-force-inf-two-lines", scene(tail="[load]\nbody_force = [inf,3\n]\n"), "body_force = [inf, 3]: out of range"),
        ("strength-nan", scene(tail="[interface]\ntangential_strength = nan\n"), "tangential_strength = nan: out of range"),
        ("E-exponent-overflow", scene(fibre={"E": "1e400"}), "TOML syntax error"),
        ("radius-exponent-underflow", scene(geometry={"fibre_radius": "1e-400"}), "[geometry] fibre_radius"),
        ("tolerance-exponent-huge", scene(tail="[solver]\ntolerance = 1e-99999999999\n"), "[solver] tolerance"),
    ]
    for name, content, substring in nonfinite:
        case("nonfinite-" + name, content, "input", substring, "non-finite or extreme: " + name.replace("-", " "))

    # Extreme values that are valid and must be meshed without trouble
    case("extreme-small-cell", scene(geometry={"cell_size": "1e-50", "fibre_radius": "3e-51"}), "ok", "",
         "a cell of size 1e-50, the smallest (its area, the law's volume, 1e-100)")
    case("extreme-large-cell", scene(geometry={"cell_size": "1e50", "fibre_radius": "3e49"}), "ok", "",
         "a cell of size 1e50, the largest")
    case("extreme-tiny-cell", scene(geometry={"cell_size": "1e-300", "fibre_radius": "3e-301"}), "input",
         "cell_size in [1e-50, 1e50]", "a cell of size 1e-300 (its area underflows: no law)")
    case("extreme-huge-cell", scene(geometry={"cell_size": "1e300", "fibre_radius": "3e299"}), "input",
         "cell_size in [1e-50, 1e50]", "a cell of size 1e300 (its area overflows)")
    case("extreme-thin-ligament", scene(geometry={"fibre_radius": "0.4999999"}), "ok", "",
         "a fibre 1e-7 from its cell's edge")

    # Periodic RVEs: the scene's keys (every stage), then what only the mesher can see (mesh-input:
    # the fibres' positions, a jam, a gap too narrow to mesh; solve and sweep read the mesh instead).
    def rve(geometry, fibres=(), tail="[load]\nboundary = \"periodic\"\n"):
        text = "[geometry]\n" + "".join(f"{k} = {v}\n" for k, v in geometry.items()) + "\n"
        for x, y, r in fibres:
            text += f"[[fibres]]\ncentre = [{x}, {y}]\nradius = {r}\n\n"
        return text + table("fibre", FIBRE, {}) + "\n" + table("matrix", MATRIX, {}) + tail
    one = [(0.5, 0.5, 0.3)]
    case("rve-valid", rve({"size": "[1.0, 1.0]"}, one), "ok", "", "a periodic RVE of one listed fibre")
    case("rve-random-valid", rve({"size": "[1.0, 1.0]", "kind": "\"random\"", "volume_fraction": "0.4",
                                  "radius": "[0.2, 0.01]", "min_gap": "0.02", "seed": "4"}), "ok", "",
         "a periodic RVE of random fibres")
    case("rve-with-cells", rve({"size": "[1.0, 1.0]", "cells": "[1, 1]"}, one), "input",
         "[geometry] cells: not with size", "an RVE that also gives cells")
    case("rve-without-fibres", rve({"size": "[1.0, 1.0]"}), "input", "size without [[fibres]]",
         "an RVE of kind list without its [[fibres]]")
    case("rve-fibres-without-size", scene(tail="[[fibres]]\ncentre = [0.5, 0.5]\nradius = 0.3\n"), "input",
         "[[fibres]] only for a periodic RVE", "a fibre list in a block of cells")
    case("rve-symmetry", rve({"size": "[1.0, 1.0]"}, one, "[load]\nboundary = \"symmetry\"\n"), "input",
         "is periodic: boundary = \"periodic\"", "an RVE with the symmetry boundary")
    case("rve-vf-range", rve({"size": "[1.0, 1.0]", "kind": "\"random\"", "volume_fraction": "0.95",
                              "radius": "[0.1, 0]"}), "input", "[geometry] volume_fraction = 0.95: out of range",
         "a random volume fraction of 0.95")
    case("rve-overlap", rve({"size": "[1.0, 1.0]"}, [(0.3, 0.5, 0.2), (0.6, 0.5, 0.2)]), "mesh-input",
         "overlaps fibre 1", "two listed fibres that overlap")
    case("rve-corner", rve({"size": "[1.0, 1.0]"}, [(0.05, 0.05, 0.1)]), "mesh-input",
         "crosses two edges at a corner", "a fibre across a corner of the RVE")
    case("rve-jam", rve({"size": "[1.0, 1.0]", "kind": "\"random\"", "volume_fraction": "0.85",
                         "radius": "[0.1, 0]", "min_gap": "0.01"}), "mesh-input", "the fibres jam at volume fraction",
         "random fibres to a volume fraction that jams")
    case("rve-narrow-gap", rve({"size": "[1.0, 1.0]"}, [(0.3, 0.5, 0.15), (0.6000001, 0.5, 0.15)]), "mesh-input",
         "too narrow to mesh", "two fibres 1e-7 apart, no min_gap")
    case("rve-sliver", rve({"size": "[1.0, 1.0]"}, [(0.09999999, 0.5, 0.1), (0.6, 0.5, 0.3)]), "mesh-input",
         "too narrow to mesh", "a fibre the left edge cuts 1e-8 from its rim (a sliver), no min_gap")
    case("rve-tiny-fibre", rve({"size": "[1.0, 1.0]"}, [(0.5, 0.5, 0.3), (0.1, 0.5, 1e-7)]), "mesh-input",
         "below h/10", "a fibre of radius 1e-7 beside one of 0.3 (crashed gmsh inside its parallel meshing)")
    for vf in ("1e-05", "1e-09"):
        case(f"rve-vf-{vf}", rve({"size": "[1.0, 1.0]", "kind": "\"random\"", "volume_fraction": vf,
                                  "radius": "[0.05, 0]"}), "mesh-input", "is less than half of one fibre",
             f"random fibres to v_f {vf}, less than one fibre (meshed for minutes, 2.8 GB, without end)")
    case("rve-fibres-160000", rve({"size": "[1000.0, 1000.0]", "kind": "\"random\"", "volume_fraction": "0.5",
                                   "radius": "[1.0, 0]", "min_gap": "0.1"}), "input",
         "fibres, more than the limit 10000", "160 000 random fibres (over 5 min silent in a quadratic placement)")
    case("rve-size-huge", rve({"size": "[1e300, 1e300]", "kind": "\"random\"", "volume_fraction": "0.5",
                               "radius": "[0.05, 0]"}), "input", "each in [1e-50, 1e50]",
         "an RVE of size 1e300 (was called a jam)")
    case("rve-size-tiny", rve({"size": "[1e-300, 1e-300]"}, [(5e-301, 5e-301, 3e-301)]), "input",
         "each in [1e-50, 1e50]", "an RVE of size 1e-300 (a raw OpenCASCADE exception)")
    case("rve-radius-sd", rve({"size": "[1.0, 1.0]", "kind": "\"random\"", "volume_fraction": "0.4",
                               "radius": "[0.1, 0.03]"}), "input", "0 <= sd <= mean/4",
         "a radius standard deviation above mean/4 (the README's rule said mean - 2 sd > 0)")

    # Material files: missing, a folder, a device, the scene itself, foreign keys
    case("material-missing", "material = \"no-such-material.toml\"\n" + table("geometry", GEOMETRY, {}), "input",
         "material file not found", "a material file that does not exist")
    case("material-directory", "material = \"aux\"\n" + table("geometry", GEOMETRY, {}), "input",
         "is a directory", "material names a folder")
    case("material-dev-zero", "material = \"/dev/zero\"\n" + table("geometry", GEOMETRY, {}), "input",
         "not a regular file", "material names /dev/zero (endless)")
    case("material-dev-null", "material = \"/dev/null\"\n" + table("geometry", GEOMETRY, {}), "input",
         "not a regular file", "material names /dev/null")
    case("material-self", "material = \"material-self.toml\"\n" + table("geometry", GEOMETRY, {}), "input",
         "geometry: unknown key", "material names the scene file itself")
    case("material-unknown-keys", "material = \"aux/unknown-keys.material\"\n" + table("geometry", GEOMETRY, {}),
         "input", "density: unknown key", "a material file with a key it must not have")
    case("material-bad-nu", "material = \"aux/bad-nu.material\"\n" + table("geometry", GEOMETRY, {}), "input",
         "[matrix] nu = 0.5: out of range", "a material file with nu = 0.5 (the message names that file)")
    case("material-garbage", "material = \"aux/garbage.material\"\n" + table("geometry", GEOMETRY, {}), "input",
         "TOML syntax error", "a material file of random bytes")
    case("material-name-too-long", "material = \"aux/" + "k" * 5000 + ".material\"\n" +
         table("geometry", GEOMETRY, {}), "input", "cannot access material file",
         "a material name longer than the file system allows (found by the fuzzer)")
    case("material-and-tables", "material = \"../../../materials/glass-epoxy.toml\"\n" + VALID, "input",
         "not both", "a material file and inline [fibre]/[matrix]")
    case("material-empty-name", "material = \"\"\n" + table("geometry", GEOMETRY, {}), "input",
         "missing table [fibre]", "material = \"\" (no file, no tables)")
    return [
        ("aux/unknown-keys.material", "source = \"test\"\ndensity = 2.5\n" + table("fibre", FIBRE, {}) +
         table("matrix", MATRIX, {})),
        ("aux/bad-nu.material", "source = \"test\"\n" + table("fibre", FIBRE, {}) + table("matrix", MATRIX, {"nu": "0.5"})),
        ("aux/matériau-ν.material", "source = \"test éν\"\n" + table("fibre", FIBRE, {}) +
         table("matrix", MATRIX, {})),
        ("aux/garbage.material", bytes(np.random.default_rng(7).integers(0, 256, 512, dtype=np.uint8))),
    ]


def write_bytes(path, content):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(content if isinstance(content, bytes) else content.encode("utf-8"))


def tsv_field(text):
    assert "\t" not in text and "\n" not in text, text
    return text


def write_scenes():
    if os.path.isdir(SCENES):
        shutil.rmtree(SCENES)
    aux = build_scene_cases()
    for name, content in aux:
        write_bytes(os.path.join(SCENES, name), content)
    names = set()
    with open(os.path.join(SCENES, "expected.tsv"), "w", encoding="utf-8") as manifest:
        manifest.write("# file\toutcome\tsubstring of the one-line message\twhat\n")
        for name, content, outcome, substring, what in SCENE_CASES:
            assert name not in names, name
            names.add(name)
            write_bytes(os.path.join(SCENES, name), content)
            manifest.write("\t".join(tsv_field(x) for x in (name, outcome, substring, what)) + "\n")


# ---------------------------------------------------------------------------------------------
# HDF5 files

TINY = """# The scene of every file in data/hostile/h5 (a 1x1 cell at degree 1 of linear triangles, periodic boundary).
[geometry]
cells = [1, 1]
fibre_radius = 0.3
degree = 1
element = "p1"

[fibre]
E = 10.0
nu = 0.2

[matrix]
E = 1.0
nu = 0.3

[interface]
normal_strength = 0.05

[load]
boundary = "periodic"

[sweep]
directions_deg = [0, 45, 90]
magnitudes = [-0.02, 0.02]
"""

H5_CASES = []  # (file, kind, outcome, substring, what)


def run(bin_dir, *args, cwd):
    subprocess.run([os.path.join(bin_dir, args[0]), "--quiet", *args[1:]], cwd=cwd, check=True)


def copy_with(src, dst, edit):
    """Copies an HDF5 file object by object (h5py), letting `edit` change the copy."""
    shutil.copyfile(src, dst)
    with h5py.File(dst, "r+") as f:
        edit(f)


def replace(f, name, data, dtype=None):
    attrs = dict(f[name].attrs) if isinstance(f[name], h5py.Dataset) else {}
    del f[name]
    d = f.create_dataset(name, data=np.asarray(data, dtype=dtype) if dtype else data)
    for k, v in attrs.items():
        d.attrs[k] = v


def h5case(kind, name, outcome, substring, what, make=None):
    H5_CASES.append((name, kind, outcome, substring, what, make))


def bytes_of(path):
    with open(path, "rb") as f:
        return f.read()


def truncated(src, size):
    def make(dst):
        write_bytes(dst, bytes_of(src)[:size])
    return make


def flipped(src, offsets):
    def make(dst):
        data = bytearray(bytes_of(src))
        for o in offsets:
            data[o] ^= 0xFF
        write_bytes(dst, bytes(data))
    return make


def dataset_offset(path, name):
    with h5py.File(path, "r") as f:
        return f[name].id.get_offset()


def edited(src, edit):
    def make(dst):
        copy_with(src, dst, edit)
    return make


def copied(src):
    def make(dst):
        shutil.copyfile(src, dst)
    return make


def unallocated(src, name, shape, dtype):
    """`name` replaced by a dataset declaring `shape` with no data stored (a few bytes on disk)."""
    def edit(f):
        del f[name]
        f.create_dataset(name, shape=shape, dtype=dtype)
    return edited(src, edit)


# A dataset each stage reads, and where its object header lies.
READ = {"mesh": "/mesh/triangles", "solution": "/interface/bonded", "sweep": "/paths/000/strain",
        "law": "/law/S_tension"}


def object_header(path, name):
    with h5py.File(path, "r") as f:
        info = h5py.h5o.get_info(f[name].id)
        return info.addr, info.hdr.space.total


def write_h5(bin_dir):
    if os.path.isdir(H5):
        shutil.rmtree(H5)
    os.makedirs(H5)
    write_bytes(os.path.join(H5, "tiny.toml"), TINY)
    # Real outputs, with relative paths so that no machine's folders end up in the files.
    run(bin_dir, "dualcell-mesh", "--config", "tiny.toml", "--out", "mesh.h5", cwd=H5)
    run(bin_dir, "dualcell-solve", "--config", "tiny.toml", "--mesh", "mesh.h5", "--stress", "0.02,0,0",
        "--out", "solution.h5", cwd=H5)
    run(bin_dir, "dualcell-sweep", "--config", "tiny.toml", "--mesh", "mesh.h5", "--out", "sweep.h5", cwd=H5)
    run(bin_dir, "dualcell-fit", "--sweep", "sweep.h5", "--out", "law.h5", cwd=H5)
    for extra in ("mesh.xdmf", "solution.xdmf"):
        os.remove(os.path.join(H5, extra))
    src = {k: os.path.join(H5, k + ".h5") for k in ("mesh", "solution", "sweep", "law")}
    others = {"mesh": "sweep", "solution": "mesh", "sweep": "law", "law": "solution"}

    for kind in ("mesh", "solution", "sweep", "law"):
        s = src[kind]
        size = os.path.getsize(s)
        h5case(kind, f"{kind}.h5", "ok", "", f"the valid {kind}.h5 itself")
        h5case(kind, f"{kind}-empty.h5", "input", "corrupt", "an empty file", truncated(s, 0))
        for cut in (7, 512, 2048):
            h5case(kind, f"{kind}-truncated-{cut}.h5", "input", "corrupt",
                   f"the first {cut} bytes", truncated(s, cut))
        h5case(kind, f"{kind}-truncated-half.h5", "input", "corrupt", "the first half",
               truncated(s, size // 2))
        h5case(kind, f"{kind}-truncated-last-byte.h5", "input", "corrupt", "all but the last byte",
               truncated(s, size - 1))
        h5case(kind, f"{kind}-flip-signature.h5", "input", "corrupt",
               "a byte of the HDF5 signature flipped", flipped(s, [1]))
        h5case(kind, f"{kind}-flip-superblock.h5", "input", "corrupt",
               "bytes flipped in the superblock (its sizes and addresses)", flipped(s, [13, 14, 40, 41, 42]))
        header, length = object_header(s, READ[kind])
        h5case(kind, f"{kind}-flip-header.h5", "input", READ[kind],
               f"16 bytes flipped in the middle of the object header of {READ[kind]} (its checksum fails)",
               flipped(s, range(header + length // 2 - 8, header + length // 2 + 8)))
        h5case(kind, f"{kind}-wrong-kind.h5", "input", f"not a dualcell {kind} file"
               if kind != "law" else "expected 'dualcell law 4'",
               f"a valid {others[kind]}.h5 in its place", copied(src[others[kind]]))
        h5case(kind, f"{kind}-no-format.h5", "input", "format", "the root attribute format deleted",
               edited(s, lambda f: f.attrs.__delitem__("format")))
        h5case(kind, f"{kind}-format-number.h5", "input", "format", "the root attribute format is a number",
               edited(s, lambda f: f.attrs.__setitem__("format", 1.0)))
        h5case(kind, f"{kind}-directory.h5", "input", "directory", "a folder named like the file", None)

    # mesh.h5, read by dualcell-solve and dualcell-sweep
    m = src["mesh"]
    nodes_at = dataset_offset(m, "/mesh/nodes")
    h5case("mesh", "mesh-nodes-nan.h5", "input", "/mesh/nodes: non-finite coordinate",
           "a coordinate overwritten with NaN bytes in place", lambda dst: patch(m, dst, nodes_at + 8,
                                                                               np.array([np.nan]).tobytes()))
    h5case("mesh", "mesh-nodes-inf.h5", "input", "/mesh/nodes: non-finite coordinate", "an infinite coordinate",
           edited(m, lambda f: f["/mesh/nodes"].__setitem__((3, 1), np.inf)))
    h5case("mesh", "mesh-nodes-shape.h5", "input", "/mesh/nodes: expected shape", "nodes N×3",
           edited(m, lambda f: replace(f, "/mesh/nodes", np.zeros((33, 3)))))
    h5case("mesh", "mesh-nodes-1d.h5", "input", "/mesh/nodes: expected shape", "nodes flattened to 2N",
           edited(m, lambda f: replace(f, "/mesh/nodes", np.asarray(f["/mesh/nodes"]).ravel())))
    h5case("mesh", "mesh-nodes-strings.h5", "input", "/mesh/nodes: expected floating-point data",
           "nodes as strings", edited(m, lambda f: replace(f, "/mesh/nodes", np.full((33, 2), b"x", dtype="S8"))))
    h5case("mesh", "mesh-nodes-group.h5", "input", "/mesh/nodes: not a dataset", "nodes a group",
           edited(m, lambda f: (f.__delitem__("/mesh/nodes"), f.create_group("/mesh/nodes"))))
    h5case("mesh", "mesh-nodes-huge.h5", "input", "/mesh/nodes", "nodes declaring 2^40×2 values, none stored",
           unallocated(m, "/mesh/nodes", (1 << 40, 2), "f8"))
    h5case("mesh", "mesh-triangles-float.h5", "input", "/mesh/triangles: expected integer data",
           "triangles as floats",
           edited(m, lambda f: replace(f, "/mesh/triangles", np.asarray(f["/mesh/triangles"], dtype="f8"))))
    h5case("mesh", "mesh-triangles-missing.h5", "input", "/mesh/triangles: missing dataset", "no triangles",
           edited(m, lambda f: f.__delitem__("/mesh/triangles")))
    h5case("mesh", "mesh-triangle-index-high.h5", "input", "/mesh/triangles: node index 33 out of range",
           "a triangle naming node N", edited(m, lambda f: f["/mesh/triangles"].__setitem__((5, 1), 33)))
    h5case("mesh", "mesh-triangle-index-negative.h5", "input", "/mesh/triangles: node index -1 out of range",
           "a triangle naming node -1", edited(m, lambda f: f["/mesh/triangles"].__setitem__((0, 0), -1)))
    h5case("mesh", "mesh-triangle-index-int64-max.h5", "input", "out of range", "node index 2^63-1",
           edited(m, lambda f: f["/mesh/triangles"].__setitem__((0, 2), np.iinfo(np.int64).max)))
    h5case("mesh", "mesh-triangle-other-subdomain.h5", "input", "/mesh/triangles",
           "a fibre triangle naming a matrix node", edited(m, lambda f: f["/mesh/triangles"].__setitem__(
               (int(np.flatnonzero(np.asarray(f["/mesh/triangle_subdomain"]) == 1)[0]), 0), 0)))
    h5case("mesh", "mesh-interface-wrong-subdomain.h5", "input", "/mesh/interface_pairs",
           "an interface pair whose fibre node is a matrix node",
           edited(m, lambda f: f["/mesh/interface_pairs"].__setitem__((0, 0), f["/mesh/interface_pairs"][0, 1])))
    h5case("mesh", "mesh-glue-self.h5", "input", "/mesh/glue_pairs", "a glue pair gluing a node to itself",
           edited(m, lambda f: replace(f, "/mesh/glue_pairs", np.array([[1, 1]], dtype="i8"))))
    h5case("mesh", "mesh-boundary-fibre-node.h5", "input", "/mesh/boundary/left",
           "a boundary edge through fibre nodes", edited(m, lambda f: f["/mesh/boundary/left"].__setitem__(
               0, [int(f["/mesh/subdomain_nodes"][1, 0]) + i for i in range(f["/mesh/boundary/left"].shape[1])])))
    h5case("mesh", "mesh-element-unknown.h5", "input", "/mesh attribute element = \"p3\"",
           "an element order that does not exist", edited(m, lambda f: f["/mesh"].attrs.__setitem__("element", "p3")))
    h5case("mesh", "mesh-element-p2-on-p1.h5", "input", "/mesh/triangles: expected shape",
           "a p1 mesh (T×3 triangles) that claims 6-node triangles",
           edited(m, lambda f: f["/mesh"].attrs.__setitem__("element", "p2")))
    # The physical points and periodic pairs (mesh::Mesh::point_of, point_sides, periodic_pairs).
    def swap_partners(f):
        pairs = np.asarray(f["/mesh/periodic_pairs"])
        pairs[[1, 2], 1] = pairs[[2, 1], 1]
        replace(f, "/mesh/periodic_pairs", pairs)

    def left_point_off_its_side(f):
        sides = np.asarray(f["/mesh/point_sides"])
        point = int(np.flatnonzero(sides == 1)[0])  # on the left side only
        node = int(np.flatnonzero(np.asarray(f["/mesh/point_of"]) == point)[-1])
        f["/mesh/nodes"][node, 0] = 1e-3
        sides[point] = 0
        replace(f, "/mesh/point_sides", sides)
        # and the boundary edges through it left out, so that only the sides' points disagree
        edges = np.asarray(f["/mesh/boundary/left"])
        replace(f, "/mesh/boundary/left", edges[~(edges == node).any(axis=1)])

    h5case("mesh", "mesh-periodic-partner-swapped.h5", "input",
           "/mesh/periodic_pairs: pair 1: the partner of a point on the right side is not its copy",
           "two right points' partners on the left side swapped", edited(m, swap_partners))
    h5case("mesh", "mesh-periodic-pairs-short.h5", "input", "side is not in exactly one pair",
           "the last periodic pair (top-right corner to bottom-right) left out",
           edited(m, lambda f: replace(f, "/mesh/periodic_pairs", np.asarray(f["/mesh/periodic_pairs"])[:-1])))
    h5case("mesh", "mesh-periodic-pairs-missing.h5", "input", "/mesh/periodic_pairs: missing dataset",
           "no periodic pairs (a mesh.h5 of an earlier format, its format attribute edited)",
           edited(m, lambda f: f.__delitem__("/mesh/periodic_pairs")))
    h5case("mesh", "mesh-periodic-pairs-side.h5", "input", "/mesh/periodic_pairs: pair 0 has side 0",
           "a periodic pair from the left side",
           edited(m, lambda f: f["/mesh/periodic_pairs"].__setitem__((0, 2), 0)))
    h5case("mesh", "mesh-point-of-high.h5", "input", "/mesh/point_of: point",
           "a node whose point is past the last point",
           edited(m, lambda f: f["/mesh/point_of"].__setitem__(0, f["/mesh/point_sides"].shape[0])))
    h5case("mesh", "mesh-unequal-sides.h5", "input", "/mesh/point_sides: the right side has",
           "a left point moved off its side, its side mark and boundary edges with it: unequal sides",
           edited(m, left_point_off_its_side))
    h5case("mesh", "mesh-subdomain-cell-high.h5", "input", "/mesh/subdomain_cell", "a subdomain of cell 7 of 1",
           edited(m, lambda f: f["/mesh/subdomain_cell"].__setitem__(0, 7)))
    h5case("mesh", "mesh-subdomain-fibre-flags.h5", "input", "/mesh/subdomain_is_fibre",
           "both subdomains claim to be fibres", edited(m, lambda f: f["/mesh/subdomain_is_fibre"].__setitem__(
               slice(None), 1)))
    h5case("mesh", "mesh-subdomain-ranges.h5", "input", "not contiguous", "node ranges overlapping",
           edited(m, lambda f: f["/mesh/subdomain_nodes"].__setitem__((1, 0), 3)))
    h5case("mesh", "mesh-triangle-subdomain-high.h5", "input", "/mesh/triangle_subdomain",
           "a triangle of subdomain 9", edited(m, lambda f: f["/mesh/triangle_subdomain"].__setitem__(0, 9)))
    h5case("mesh", "mesh-interface-cell-high.h5", "input", "/mesh/interface_cell: index out of range",
           "an interface pair of cell 5", edited(m, lambda f: f["/mesh/interface_cell"].__setitem__(0, 5)))
    h5case("mesh", "mesh-centres-nan.h5", "input", "/mesh/fibre_centres", "a NaN fibre centre",
           edited(m, lambda f: f["/mesh/fibre_centres"].__setitem__((0, 0), np.nan)))
    h5case("mesh", "mesh-nodes-collapsed.h5", "input", "degenerate or clockwise", "every node at the origin",
           edited(m, lambda f: f["/mesh/nodes"].__setitem__(slice(None), 0.0)))
    h5case("mesh", "mesh-nodes-mirrored.h5", "input", "degenerate or clockwise", "x mirrored: clockwise triangles",
           edited(m, lambda f: f["/mesh/nodes"].__setitem__((slice(None), 0), 1 - np.asarray(f["/mesh/nodes"])[:, 0])))
    h5case("mesh", "mesh-node-outside.h5", "input", "outside the block", "a node at x = 1e300",
           edited(m, lambda f: f["/mesh/nodes"].__setitem__((4, 0), 1e300)))
    h5case("mesh", "mesh-subdomain-scalar.h5", "input", "/mesh/subdomain_is_fibre", "subdomain flags as a scalar",
           edited(m, lambda f: replace(f, "/mesh/subdomain_is_fibre", np.int64(1))))
    h5case("mesh", "mesh-cells-attribute-one.h5", "input", "attribute cells: expected 2 values, found 1", "attribute cells with one entry",
           edited(m, lambda f: f["/mesh"].attrs.__setitem__("cells", np.array([1], dtype="i8"))))
    h5case("mesh", "mesh-degree-string.h5", "input", "degree", "attribute degree as a string",
           edited(m, lambda f: f["/mesh"].attrs.__setitem__("degree", "one")))
    h5case("mesh", "mesh-degree-empty.h5", "input", "degree", "attribute degree with no values",
           edited(m, lambda f: f["/mesh"].attrs.__setitem__("degree", np.zeros(0, dtype="i8"))))
    h5case("mesh", "mesh-other-scene.h5", "input", "made from a different scene", "a mesh of another radius",
           edited(m, lambda f: f["/mesh"].attrs.__setitem__("fibre_radius", 0.25)))

    # solution.h5, read by dualcell-solve --bonds
    s = src["solution"]
    h5case("solution", "solution-other-mesh.h5", "input", "computed on another mesh", "another mesh_hash",
           edited(s, lambda f: f.attrs.__setitem__("mesh_hash", "0123456789abcdef")))
    h5case("solution", "solution-bonded-missing.h5", "input", "/interface/bonded: missing dataset",
           "no bond state", edited(s, lambda f: f.__delitem__("/interface/bonded")))
    h5case("solution", "solution-bonded-short.h5", "input", "/interface/bonded: expected shape (8) (one per interface pair of the mesh), found (7)",
           "7 bonds for 8 pairs", edited(s, lambda f: replace(f, "/interface/bonded", np.ones(7, dtype="i8"))))
    h5case("solution", "solution-bonded-2d.h5", "input", "/interface/bonded", "bonds as 8×1",
           edited(s, lambda f: replace(f, "/interface/bonded", np.ones((8, 1), dtype="i8"))))
    h5case("solution", "solution-bonded-two.h5", "input", "entries must be 0 or 1", "a bond state of 2",
           edited(s, lambda f: f["/interface/bonded"].__setitem__(3, 2)))
    h5case("solution", "solution-bonded-float.h5", "input", "expected integer data", "bond states as floats",
           edited(s, lambda f: replace(f, "/interface/bonded", np.ones(8))))
    h5case("solution", "solution-bonded-huge.h5", "input", "/interface/bonded",
           "bonds declaring 2^40 entries, none stored", unallocated(s, "/interface/bonded", (1 << 40,), "i8"))
    h5case("solution", "solution-hash-number.h5", "input", "mesh_hash", "mesh_hash as a number",
           edited(s, lambda f: f.attrs.__setitem__("mesh_hash", 42)))

    # sweep.h5, read by dualcell-fit
    w = src["sweep"]
    strain_at = dataset_offset(w, "/paths/000/strain")
    h5case("sweep", "sweep-strain-nan.h5", "input", "/paths/000/strain: non-finite",
           "a strain overwritten with NaN bytes in place",
           lambda dst: patch(w, dst, strain_at, np.array([np.nan]).tobytes()))
    h5case("sweep", "sweep-load-inf.h5", "input", "/paths/001/load: non-finite", "an infinite load",
           edited(w, lambda f: f["/paths/001/load"].__setitem__(0, -np.inf)))
    h5case("sweep", "sweep-n-paths-more.h5", "input", "/paths/006: missing", "n_paths = 7 for 6 paths",
           edited(w, lambda f: f.attrs.__setitem__("n_paths", np.int64(7))))
    h5case("sweep", "sweep-n-paths-negative.h5", "input", "n_paths", "n_paths = -1",
           edited(w, lambda f: f.attrs.__setitem__("n_paths", np.int64(-1))))
    h5case("sweep", "sweep-n-paths-zero.h5", "input", "n_paths", "n_paths = 0",
           edited(w, lambda f: f.attrs.__setitem__("n_paths", np.int64(0))))
    h5case("sweep", "sweep-n-paths-huge.h5", "input", "n_paths", "n_paths = 2^62",
           edited(w, lambda f: f.attrs.__setitem__("n_paths", np.int64(1 << 62))))
    h5case("sweep", "sweep-path-missing.h5", "input", "/paths/003: missing", "one path deleted",
           edited(w, lambda f: f.__delitem__("/paths/003")))
    h5case("sweep", "sweep-strain-shape.h5", "input", "/paths/000/strain: expected", "strains n×2",
           edited(w, lambda f: replace(f, "/paths/000/strain", np.asarray(f["/paths/000/strain"])[:, :2])))
    h5case("sweep", "sweep-strain-rows.h5", "input", "/paths/002/strain: expected", "one strain row missing",
           edited(w, lambda f: replace(f, "/paths/002/strain", np.asarray(f["/paths/002/strain"])[:-1])))
    h5case("sweep", "sweep-stress-strings.h5", "input", "/paths/000/stress: expected floating-point data",
           "stresses as strings", edited(w, lambda f: replace(f, "/paths/000/stress",
                                                              np.full((2, 3), b"s", dtype="S4"))))
    h5case("sweep", "sweep-converged-missing.h5", "input", "/paths/000/converged: missing dataset",
           "no converged flags", edited(w, lambda f: f.__delitem__("/paths/000/converged")))
    h5case("sweep", "sweep-load-huge.h5", "input", "/paths/000/load", "loads declaring 2^40 entries, none stored",
           unallocated(w, "/paths/000/load", (1 << 40,), "f8"))
    h5case("sweep", "sweep-unit-stress-two.h5", "input", "attribute unit_stress: expected 3 values, found 2",
           "unit_stress with 2 entries", edited(w, lambda f: f["/paths/000"].attrs.__setitem__(
               "unit_stress", np.array([1.0, 0.0]))))
    h5case("sweep", "sweep-direction-inf.h5", "input", "direction_deg", "a path whose direction is infinite",
           edited(w, lambda f: f["/paths/000"].attrs.__setitem__("direction_deg", np.inf)))
    h5case("sweep", "sweep-sign-zero.h5", "input", "sign", "a path of sign 0",
           edited(w, lambda f: f["/paths/000"].attrs.__setitem__("sign", np.int64(0))))
    h5case("sweep", "sweep-fuse-partial.h5", "input", "/fuse", "a fuse group with its strains missing",
           edited(w, lambda f: (f.create_group("/paths/000/fuse"),
                                f.create_dataset("/paths/000/fuse/onset_load", data=np.array([0.01])))))
    h5case("sweep", "sweep-single-path.h5", "ok", "", "only the first path (one point: fewer equations than "
           "compliance unknowns)", edited(w, lambda f: ([f.__delitem__(f"/paths/{i:03d}") for i in range(1, 6)],
                                                       f.attrs.__setitem__("n_paths", np.int64(1)))))
    h5case("sweep", "sweep-only-stress-directions.h5", "input", "direction", "every path marked as a "
           "stress_directions path (direction NaN): no uniaxial direction to fit",
           edited(w, lambda f: [g.attrs.__setitem__("direction_deg", np.nan) for g in f["/paths"].values()]))
    h5case("sweep", "sweep-fibre-E-missing.h5", "input", "missing attribute fibre_E",
           "no constituent fibre_E", edited(w, lambda f: f.attrs.__delitem__("fibre_E")))

    h5case("sweep", "sweep-onset-missing.h5", "input", "/onset: missing group", "no /onset group",
           edited(w, lambda f: f.__delitem__("/onset")))

    # law.h5, read by dualcell-export
    l = src["law"]
    h5case("law-calculix", "law-S-nan.h5", "input", "S_tension", "a NaN compliance (calculix refuses; json/csv write null)",
           edited(l, lambda f: f["/law/S_tension"].__setitem__((0, 0), np.nan)))
    h5case("law", "law-S-shape.h5", "input", "/law/S_tension", "S_tension 2×2",
           edited(l, lambda f: replace(f, "/law/S_tension", np.eye(2))))
    h5case("law", "law-S-ints.h5", "input", "/law/S_compression", "S_compression of strings",
           edited(l, lambda f: replace(f, "/law/S_compression", np.full((3, 3), b"S", dtype="S2"))))
    h5case("law", "law-directions-empty.h5", "input", "/law/direction_deg", "no directions",
           edited(l, lambda f: replace(f, "/law/direction_deg", np.zeros(0))))
    h5case("law", "law-directions-nan.h5", "input", "/law/direction_deg: a direction is not finite",
           "a NaN direction", edited(l, lambda f: f["/law/direction_deg"].__setitem__(1, np.nan)))
    h5case("law", "law-directions-huge.h5", "input", "/law/direction_deg",
           "directions declaring 2^40 entries, none stored", unallocated(l, "/law/direction_deg", (1 << 40,), "f8"))
    h5case("law", "law-column-short.h5", "input", "/law/E_tension", "E_tension one entry short",
           edited(l, lambda f: replace(f, "/law/E_tension", np.asarray(f["/law/E_tension"])[:-1])))
    h5case("law", "law-count-negative.h5", "input", "is not a count", "n_tension = -1",
           edited(l, lambda f: f["/law/n_tension"].__setitem__(0, -1)))
    h5case("law", "law-rank-seven.h5", "input", "S_tension_rank", "a rank of 7 for 6 unknowns",
           edited(l, lambda f: f["/law/S_tension_rank"].__setitem__(0, 7)))
    h5case("law", "law-stress-state.h5", "input", "expected 'plane strain'", "stress_state = plane stress",
           edited(l, lambda f: f["/law"].attrs.__setitem__("stress_state", "plane stress")))
    h5case("law", "law-constituent-missing.h5", "input", "missing attribute matrix_E", "no matrix_E",
           edited(l, lambda f: f["/law"].attrs.__delitem__("matrix_E")))
    h5case("law-calculix", "law-nu-unphysical.h5", "input", "nu", "matrix_nu = 0.7 (calculix refuses; json/csv write it)",
           edited(l, lambda f: f["/law"].attrs.__setitem__("matrix_nu", 0.7)))
    h5case("law", "law-group-missing.h5", "input", "/law: missing group", "no /law group",
           edited(l, lambda f: f.__delitem__("/law")))
    h5case("law", "law-onset-facet-nan.h5", "input", "/law/onset/facets: row 2 is not finite",
           "a NaN in an onset facet", edited(l, lambda f: f["/law/onset/facets"].__setitem__((2, 1), np.nan)))
    h5case("law", "law-onset-linear-two.h5", "input", "/law/onset: attribute linear = 2",
           "the onset surface's attribute linear = 2", edited(l, lambda f: f["/law/onset"].attrs.__setitem__(
               "linear", np.int64(2))))
    h5case("law", "law-onset-pair-short.h5", "input", "/law/onset/pair: expected shape",
           "one facet's pair missing", edited(l, lambda f: replace(f, "/law/onset/pair",
                                                                   np.asarray(f["/law/onset/pair"])[:-1])))
    h5case("law", "law-cell-H-asymmetric.h5", "input", "/law/cell: H is not symmetric",
           "the exact law's interface flexibility made asymmetric",
           edited(l, lambda f: f["/law/cell/H"].__setitem__((0, 1), f["/law/cell/H"][0, 1] * 2 + 1)))
    h5case("law", "law-cell-pair-high.h5", "input", "/law/cell/pair: 100000 is not a pair index",
           "an interface row of the exact law naming a pair that does not exist",
           edited(l, lambda f: f["/law/cell/pair"].__setitem__(0, 100000)))
    h5case("law", "law-cell-Y-nan.h5", "input", "/law/cell: non-finite entries",
           "a NaN in the exact law's openings per unit stress",
           edited(l, lambda f: f["/law/cell/Y"].__setitem__((0, 0), np.nan)))
    h5case("law", "law-cell-H-zero.h5", "input", "the law is not convex",
           "the exact law's interface flexibility all zero (an internal error in dualcell-structure)",
           edited(l, lambda f: f["/law/cell/H"].__setitem__(slice(None), 0.0)))
    h5case("law", "law-cell-H-negated.h5", "input", "the law is not convex",
           "the exact law's interface flexibility negated (Newton for minutes on a non-convex law)",
           edited(l, lambda f: replace(f, "/law/cell/H", -np.asarray(f["/law/cell/H"]))))
    h5case("law", "law-cell-S0-shrunk.h5", "input", "is not positive definite on G p = 0",
           "the open cell's compliance scaled by 1e-5: every block definite, the energy not",
           edited(l, lambda f: replace(f, "/law/cell/S0", 1e-5 * np.asarray(f["/law/cell/S0"]))))
    h5case("law", "law-cell-S0-huge.h5", "input", "/law/cell/S0: its largest entry is",
           "the open cell's compliance at 1e300", edited(l, lambda f: replace(
               f, "/law/cell/S0", 1e300 * np.asarray(f["/law/cell/S0"]))))
    h5case("law", "law-cell-volume-tiny.h5", "input", "volume is 1e-308, not within",
           "the cell's volume 1e-308 (a Cholesky failure, internal error)",
           edited(l, lambda f: f["/law/cell/volume"].__setitem__(0, 1e-308)))

    def declared_rows(n):
        def edit(f):
            g = f["/law/cell"]
            for k in ("Y", "H", "G", "tangential", "pair", "lower_bonded", "upper_bonded", "lower_broken",
                      "upper_broken"):
                shape = list(g[k].shape)
                if k == "H":
                    shape = [n, n]
                elif k == "G":
                    shape[1] = n
                else:
                    shape[0] = n
                dtype = g[k].dtype
                del g[k]
                g.create_dataset(k, shape=shape, dtype=dtype, compression="gzip", fillvalue=0)
        return edited(l, edit)
    for n in (16000, 40000):
        h5case("law", f"law-cell-rows-{n}.h5", "input", f"declares {n} n_rows, at most 3000",
               f"an exact law declaring {n} interface rows, stored compressed (allocated past 6 GB)",
               declared_rows(n))
    h5case("law", "law-cell-bounds-open.h5", "input", "its bounds do not hold 0",
           "an interface row whose bonded bounds exclude zero",
           edited(l, lambda f: f["/law/cell/lower_bonded"].__setitem__(0, 1.0)))

    with open(os.path.join(H5, "expected.tsv"), "w", encoding="utf-8") as manifest:
        manifest.write("# file\tkind\toutcome\tsubstring of the one-line message\twhat\n")
        for name, kind, outcome, substring, what, make in H5_CASES:
            path = os.path.join(H5, name)
            if make:
                make(path)
            elif name.endswith("-directory.h5"):
                os.makedirs(path)
                write_bytes(os.path.join(path, "README"), "a folder where a file is expected\n")
            manifest.write("\t".join(tsv_field(x) for x in (name, kind, outcome, substring, what)) + "\n")


def patch(src, dst, offset, data):
    raw = bytearray(bytes_of(src))
    raw[offset:offset + len(data)] = data
    write_bytes(dst, bytes(raw))


# ---------------------------------------------------------------------------------------------

README_HEAD = """# data/hostile: malformed scene files and corrupt HDF5 inputs

Every stage that reads one of these files must answer with exactly one line on stderr,
`<stage>: error: ...`, exit code 1, within seconds (never a crash, a hang or an internal error),
and leave nothing in its output folder: no output, no temporary (`tests/hostile/hostile_test.cpp`).
The exceptions are marked `ok`: such a scene is meshed by dualcell-mesh (solve and sweep are not
run on it, its geometry need not match `h5/mesh.h5`), such an HDF5 file is accepted by every stage
that reads it. The machine-readable expectations are `scenes/expected.tsv` and `h5/expected.tsv`:
the file, the outcome (`ok` or `input`) and a substring the message must contain. The scene files
also seed the parser's fuzzer (`make -C pipelines fuzz`).

Generated, not written by hand: `/usr/bin/python3 tests/hostile/make_corpus.py build/bin`
rewrites both folders and this file (needs a release build and Debian's python3-h5py and
python3-numpy). The HDF5 files are real outputs of the stages on `h5/tiny.toml` (1×1 cell,
degree 1), then truncated, flipped or edited with h5py; regenerating changes their provenance
bytes (code version, timings) but not the expectations. An input the fuzzer crashes on goes into
`build_scene_cases()` there, with the message it must now give.

"""


def write_readme():
    lines = [README_HEAD, "## scenes/ (read by dualcell-mesh, dualcell-solve, dualcell-sweep)\n\n",
             "| file | what | outcome |\n|---|---|---|\n"]
    for name, _content, outcome, substring, what in SCENE_CASES:
        expect = "accepted" if outcome == "ok" else "refused: `" + substring.replace("|", "\\|") + "`"
        if outcome == "mesh-input":
            expect += " (by dualcell-mesh)"
        lines.append(f"| `{name}` | {what} | {expect} |\n")
    lines.append("\n`scenes/aux/` holds the material files some scenes name.\n\n")
    lines.append("## h5/ (mesh: dualcell-solve and dualcell-sweep; solution: dualcell-solve --bonds; "
                 "sweep: dualcell-fit; law: dualcell-export in all three formats)\n\n")
    lines.append("| file | what | outcome |\n|---|---|---|\n")
    for name, kind, outcome, substring, what, _make in H5_CASES:
        expect = "accepted" if outcome == "ok" else "refused: `" + substring + "`"
        lines.append(f"| `{name}` | {what} | {expect} |\n")
    with open(os.path.join(OUT, "README.md"), "w", encoding="utf-8") as f:
        f.write("".join(lines))


def main():
    bin_dir = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin"))
    write_scenes()
    write_h5(bin_dir)
    write_readme()
    with open(os.path.join(OUT, ".gitattributes"), "w") as f:
        f.write("# Byte-exact: CRLF, BOM, NUL and binary files are the point of this corpus.\n* -text\n*.h5 binary\n")


if __name__ == "__main__":
    main()
