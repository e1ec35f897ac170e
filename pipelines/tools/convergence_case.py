#!/usr/bin/python3
"""Writes one case scene of the convergence study from its template.

usage: convergence_case.py TEMPLATE.toml DEGREE TOLERANCE OUT.toml [ELEMENT]

Reads the template (TOML, Python's tomllib), sets [geometry] degree (and element, p1 or p2, when
given) and [solver] tolerance,
makes a relative `material` path absolute (so that it resolves from the case folder), and
writes OUT.toml atomically (temporary + rename). Errors: one line on stderr, exit 1.
"""
import math
import os
import tomllib

import common


def toml_value(value, where):
    """The TOML text of the value types scenes use: strings, booleans, numbers, arrays."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{where}: non-finite number {value}")
        return repr(value)  # shortest text that reads back to the same double
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v, where) for v in value) + "]"
    raise ValueError(f"{where}: cannot write a value of type {type(value).__name__}")


def toml_text(scene):
    """Top-level keys first, then one [table] each (the layout of every scene file)."""
    lines = [f"{key} = {toml_value(value, key)}" for key, value in scene.items() if not isinstance(value, dict)]
    for name, table in scene.items():
        if isinstance(table, dict):
            lines += ["", f"[{name}]"]
            for key, value in table.items():
                if isinstance(value, dict):
                    raise ValueError(f"[{name}] {key}: nested tables are not part of a scene")
                lines.append(f"{key} = {toml_value(value, f'[{name}] {key}')}")
    return "\n".join(lines) + "\n"


def case_scene(template_path, degree, tolerance, element=None):
    with open(template_path, "rb") as f:
        scene = tomllib.load(f)
    scene.setdefault("geometry", {})["degree"] = degree
    if element is not None:
        scene["geometry"]["element"] = element
    scene.setdefault("solver", {})["tolerance"] = tolerance
    if "material" in scene and not os.path.isabs(scene["material"]):
        scene["material"] = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(template_path)),
                                                          scene["material"]))
    return "# written by convergence_case.py from " + template_path + "\n" + toml_text(scene)


def main(argv):
    parser = common.Parser(__doc__)
    parser.add_argument("template", metavar="TEMPLATE.toml")
    parser.add_argument("degree", metavar="DEGREE", type=int)
    parser.add_argument("tolerance", metavar="TOLERANCE", type=float)
    parser.add_argument("out", metavar="OUT.toml")
    parser.add_argument("element", metavar="ELEMENT", nargs="?", choices=("p1", "p2"))
    args = parser.parse_args(argv[1:])
    common.write_atomic(args.out, case_scene(args.template, args.degree, args.tolerance, args.element))


if __name__ == "__main__":
    common.main_guard(main)
