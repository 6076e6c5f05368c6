#!/usr/bin/python3
"""Writes the decoder's tunables, defined once in cfg/DecoderParams.cfg, into its documentation.

    gen_param_docs.py           rewrite the generated blocks of README.md and launch/decoder.launch
    gen_param_docs.py --check   only compare; exit status 1 (with a diff) when a block is out of date
    gen_param_docs.py --check --xunit RESULT.xml   also write a JUnit result file (catkin's tests)

The .cfg is run as it is, with a stand-in for dynamic_reconfigure's ParameterGenerator that records
every gen.add(...) (so whatever Python the .cfg uses to compute a value, the table gets the value).
Each generated block lies between a BEGIN and an END marker comment; text outside them is kept.
Standard library only: it runs without ROS.
"""
import argparse
import difflib
import os
import sys
import types
import xml.etree.ElementTree as ET

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CFG = "cfg/DecoderParams.cfg"
BEGIN = "BEGIN generated from %s by scripts/gen_param_docs.py: edit the .cfg, then run the script" % CFG
END = "END generated"
COMMENT = "<!-- %s -->"  # the markers in Markdown and XML alike


class Param:
    """One gen.add(...) of the .cfg."""

    def __init__(self, name, paramtype, level, description, default=None, min=None, max=None, edit_method=""):
        self.name = name
        self.type = paramtype
        self.description = description
        self.default = default
        self.min = min
        self.max = max


class StubGenerator:
    """Records what dynamic_reconfigure's ParameterGenerator would generate code for."""

    generated = None  # the generator whose generate() the .cfg called

    def __init__(self):
        self.params = []

    def add(self, *args, **kwargs):
        self.params.append(Param(*args, **kwargs))

    def add_group(self, *args, **kwargs):
        return self  # one table: a group's parameters are listed with the others

    def const(self, name, paramtype, value, description):
        return {"name": name, "type": paramtype, "value": value, "description": description}

    def enum(self, constants, description):
        return repr({"enum": constants, "enum_description": description})

    def generate(self, pkg, node, name):
        StubGenerator.generated = self
        return 0


def read_cfg(path):
    """The parameters the .cfg at @p path adds, in order."""
    stub = types.ModuleType("dynamic_reconfigure.parameter_generator_catkin")
    stub.ParameterGenerator = StubGenerator
    for t in ("int", "double", "str", "bool"):
        setattr(stub, t + "_t", t)
    names = ("dynamic_reconfigure", "dynamic_reconfigure.parameter_generator_catkin")
    saved = {n: sys.modules.get(n) for n in names}
    sys.modules["dynamic_reconfigure"] = types.ModuleType("dynamic_reconfigure")
    sys.modules[names[1]] = stub
    StubGenerator.generated = None
    try:
        with open(path) as f:
            code = compile(f.read(), path, "exec")
        try:
            exec(code, {"__name__": "__main__", "__file__": path})
        except SystemExit:
            pass  # the .cfg ends with exit(gen.generate(...))
    finally:
        for n, module in saved.items():
            if module is None:
                sys.modules.pop(n, None)
            else:
                sys.modules[n] = module
    if StubGenerator.generated is None:
        raise RuntimeError("%s: gen.generate(...) was never called" % path)
    return StubGenerator.generated.params


def value_text(p, value):
    if p.type == "bool":
        return "true" if value else "false"
    return str(value)


def range_text(p):
    return "" if p.type in ("bool", "str") else "[%s, %s]" % (value_text(p, p.min), value_text(p, p.max))


def readme_block(params):
    lines = ["| parameter | type | default | range | meaning |", "|---|---|---|---|---|"]
    for p in params:
        cells = (p.name, p.type, value_text(p, p.default), range_text(p), p.description.replace("|", "\\|"))
        lines.append("| `%s` | %s | %s | %s | %s |" % cells)
    return lines


def launch_block(params, indent):
    lines = []
    for p in params:
        kind = p.type + (" in " + range_text(p) if range_text(p) else "")
        text = p.description.replace("--", "- -")  # "--" ends an XML comment
        lines.append("%s<!-- %s: %s (%s). -->" % (indent, p.name, text, kind))
        lines.append('%s<param name="%s" value="%s"/>' % (indent, p.name, value_text(p, p.default)))
    return lines


def replace_block(path, text, make_lines):
    """@p text with the lines between its marker comments replaced by make_lines(indent)."""
    lines = text.split("\n")
    begin = [i for i, line in enumerate(lines) if line.strip() == COMMENT % BEGIN]
    end = [i for i, line in enumerate(lines) if line.strip() == COMMENT % END]
    if len(begin) != 1 or len(end) != 1 or end[0] < begin[0]:
        raise RuntimeError("%s: needs one line '%s' and, after it, one line '%s'" %
                           (path, COMMENT % BEGIN, COMMENT % END))
    first = lines[begin[0]]
    indent = first[:len(first) - len(first.lstrip())]
    return "\n".join(lines[:begin[0] + 1] + make_lines(indent) + lines[end[0]:])


def targets(params):
    """(file, function from the block's indentation to its lines) for every generated block."""
    return [("README.md", lambda indent: readme_block(params)),
            ("launch/decoder.launch", lambda indent: launch_block(params, indent))]


def write_xunit(path, results):
    suite = ET.Element("testsuite", name="gen_param_docs", tests=str(len(results)),
                       failures=str(sum(1 for _, problem in results if problem)), errors="0")
    for name, problem in results:
        case = ET.SubElement(suite, "testcase", classname="sl_decoder.gen_param_docs", name=name)
        if problem:
            ET.SubElement(case, "failure", message=problem.splitlines()[0]).text = problem
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare only; exit 1 when out of date")
    parser.add_argument("--xunit", help="with --check: write a JUnit result file here")
    parser.add_argument("--package-dir", default=PACKAGE_DIR, help="the sl_decoder package (default: this one)")
    args = parser.parse_args()

    results = []
    try:
        params = read_cfg(os.path.join(args.package_dir, CFG))
        jobs = targets(params)
    except Exception as e:  # a broken .cfg is a failed check, reported like the others
        results.append((CFG, "%s" % e))
        jobs = []
    for name, make_lines in jobs:
        path = os.path.join(args.package_dir, name)
        try:
            with open(path) as f:
                text = f.read()
            wanted = replace_block(path, text, make_lines)
        except (OSError, RuntimeError) as e:
            results.append((name, str(e)))
            continue
        if wanted == text:
            results.append((name, ""))
        elif args.check:
            diff = "".join(difflib.unified_diff(text.splitlines(True), wanted.splitlines(True), name, name + " (wanted)"))
            results.append((name, "%s is out of date with %s: run sl_decoder/scripts/gen_param_docs.py\n%s" %
                            (name, CFG, diff)))
        else:
            with open(path, "w") as f:
                f.write(wanted)
            print("wrote %s" % path)
            results.append((name, ""))
    for _, problem in results:
        if problem:
            sys.stderr.write(problem + "\n")
    if args.xunit:
        write_xunit(args.xunit, results)
    return 1 if any(problem for _, problem in results) else 0


if __name__ == "__main__":
    sys.exit(main())
