#!/usr/bin/env python3
"""The type stubs python/hfts/_hfts.pyi against the built module hfts._hfts.

Every public name of the module has a stub and every stub names something
the module has; each class has the same methods, static methods, read-only
properties and writable attributes in both; each function and method takes
the same arguments in the same order, with defaults in the same places (and
the same values where the stub writes one out). The arguments are read
from the first line of pybind11's docstrings.

Run: /usr/bin/python3 tests/python/test_stubs.py --python-dir build/python
     [--stub python/hfts/_hfts.pyi]
"""

import argparse
import ast
import copy
import os
import sys
import types
import unittest

STUB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python", "hfts",
                    "_hfts.pyi")
module = None  # hfts._hfts, imported in __main__ once sys.path has the build's python dir

# Dunders whose presence says nothing about the API.
IGNORED_DUNDERS = {"__repr__", "__str__"}


def is_dunder(name):
    return name.startswith("__") and name.endswith("__")


def is_public(name):
    return not name.startswith("_") or is_dunder(name)


# The stub side.

def stub_tree(text):
    return ast.parse(text)


def stub_top_level(tree):
    """Public classes and functions of the stub by name."""
    return {node.name: node for node in tree.body
            if isinstance(node, (ast.ClassDef, ast.FunctionDef)) and not node.name.startswith("_")}


def decorator_names(function):
    names = []
    for d in function.decorator_list:
        if isinstance(d, ast.Name):
            names.append(d.id)
        elif isinstance(d, ast.Attribute):
            names.append(d.attr)  # "setter" of @name.setter
    return names


def stub_members(classdef):
    """name -> "method", "static", "property" (read-only) or "attribute" (writable)."""
    members = {}
    for node in classdef.body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            members[node.target.id] = "attribute"
        elif isinstance(node, ast.FunctionDef):
            decorators = decorator_names(node)
            if "setter" in decorators:
                members[node.name] = "attribute"
            elif "property" in decorators:
                members.setdefault(node.name, "property")
            elif "staticmethod" in decorators:
                members[node.name] = "static"
            else:
                members[node.name] = "method"
    return {name: kind for name, kind in members.items()
            if is_public(name) and name not in IGNORED_DUNDERS}


def stub_methods(classdef):
    return {node.name: node for node in classdef.body if isinstance(node, ast.FunctionDef)
            and "property" not in decorator_names(node) and "setter" not in decorator_names(node)}


def stub_arguments(function, bound):
    """[(name, default source or None)] of a stub function; `bound` drops the first."""
    a = function.args
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    out = [(arg.arg, default) for arg, default in zip(positional, defaults)]
    out += [(arg.arg, default) for arg, default in zip(a.kwonlyargs, a.kw_defaults)]
    if bound:
        out = out[1:]
    return [(name, None if d is None else ast.unparse(d)) for name, d in out]


# The module side.

def runtime_members(cls):
    members = {}
    for name, value in vars(cls).items():
        if not is_public(name) or name in IGNORED_DUNDERS:
            continue
        if is_dunder(name) and type(value).__name__ != "instancemethod":
            continue  # not defined by the binding (pybind11's placeholder __init__, __doc__, ...)
        if isinstance(value, staticmethod):
            members[name] = "static"
        elif isinstance(value, property):
            members[name] = "attribute" if value.fset is not None else "property"
        elif callable(value):
            members[name] = "method"
    return members


def split_top_level(text):
    """`text` split at the commas outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{<":
            depth += 1
        elif c in ")]}>" and not (c == ">" and text[i - 1] == "-"):
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:])
    return [p.strip() for p in parts]


def runtime_arguments(function, bound):
    """[(name, default text or None)] from pybind11's signature line, or None
    for an overloaded function."""
    line = (function.__doc__ or "").splitlines()[0] if function.__doc__ else ""
    open_at = line.find("(")
    if open_at < 0 or line.endswith("(*args, **kwargs)"):
        return None
    depth = 0
    for close_at in range(open_at, len(line)):
        depth += {"(": 1, ")": -1}.get(line[close_at], 0)
        if depth == 0:
            break
    out = []
    for part in split_top_level(line[open_at + 1:close_at]):
        name, _, rest = part.partition(":")
        _, eq, default = rest.partition(" = ")
        out.append((name.strip(), default.strip() if eq else None))
    return out[1:] if bound else out


def literal(text):
    try:
        return True, ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return False, None


def compare_arguments(where, stub_args, runtime_args):
    if runtime_args is None:
        return []
    problems = []
    stub_names = [n for n, _ in stub_args]
    runtime_names = [n for n, _ in runtime_args]
    if stub_names != runtime_names:
        return [f"{where}: arguments {stub_names} in the stub, {runtime_names} in the module"]
    for (name, stub_default), (_, runtime_default) in zip(stub_args, runtime_args):
        if (stub_default is None) != (runtime_default is None):
            problems.append(f"{where}({name}): default {stub_default} in the stub, "
                            f"{runtime_default} in the module")
        elif stub_default is not None and stub_default != "...":
            ok_stub, stub_value = literal(stub_default)
            ok_runtime, runtime_value = literal(runtime_default)
            if ok_stub and ok_runtime and stub_value != runtime_value:
                problems.append(f"{where}({name}): default {stub_default} in the stub, "
                                f"{runtime_default} in the module")
    return problems


# The comparison.

def compare_class(name, classdef, cls):
    problems = []
    if issubclass(cls, BaseException):
        stub_bases = [ast.unparse(b) for b in classdef.bases]
        runtime_bases = [b.__name__ for b in cls.__bases__]
        if stub_bases != runtime_bases:
            problems.append(f"{name}: bases {stub_bases} in the stub, "
                            f"{runtime_bases} in the module")
        return problems  # attributes of exceptions are set per instance (test below)
    stub, runtime = stub_members(classdef), runtime_members(cls)
    for member in sorted(set(stub) | set(runtime)):
        if member not in stub:
            problems.append(f"{name}.{member}: {runtime[member]} in the module, not in the stub")
        elif member not in runtime:
            problems.append(f"{name}.{member}: in the stub, not in the module")
        elif stub[member] != runtime[member]:
            problems.append(f"{name}.{member}: {stub[member]} in the stub, "
                            f"{runtime[member]} in the module")
    for member, node in stub_methods(classdef).items():
        if runtime.get(member) not in ("method", "static"):
            continue
        static = runtime[member] == "static"
        problems += compare_arguments(f"{name}.{member}", stub_arguments(node, bound=not static),
                                      runtime_arguments(getattr(cls, member), bound=not static))
    return problems


def compare(stub_text, mod):
    """Every difference between a stub's text and a module, as sentences."""
    stubbed = stub_top_level(stub_tree(stub_text))
    public = {name for name in dir(mod) if not name.startswith("_")}
    problems = [f"{n}: in the module, not in the stub" for n in sorted(public - set(stubbed))]
    problems += [f"{n}: in the stub, not in the module" for n in sorted(set(stubbed) - public)]
    for name in sorted(public & set(stubbed)):
        node, value = stubbed[name], getattr(mod, name)
        if isinstance(node, ast.ClassDef) != isinstance(value, type):
            problems.append(f"{name}: a {type(node).__name__} in the stub, {value!r} in the module")
        elif isinstance(node, ast.ClassDef):
            problems += compare_class(name, node, value)
        else:
            problems += compare_arguments(name, stub_arguments(node, bound=False),
                                          runtime_arguments(value, bound=False))
    return problems


def read_stub():
    with open(STUB, encoding="utf-8") as f:
        return f.read()


class Stubs(unittest.TestCase):
    def test_the_stub_matches_the_module(self):
        problems = compare(read_stub(), module)
        self.assertEqual(problems, [], "\n" + "\n".join(problems))

    def test_every_class_and_function_is_compared(self):
        stubbed = stub_top_level(stub_tree(read_stub()))
        self.assertIn("World", stubbed)
        self.assertIn("grasp_quality_batch", stubbed)
        self.assertGreater(len(stub_members(stubbed["World"])), 10)

    def test_errors_carry_field_and_problem(self):
        with self.assertRaises(module.InvalidArgument) as caught:
            module.grasp_quality([[0.0, 0.0]], [[0.0, 0.0]])
        self.assertEqual(caught.exception.field, "positions")
        self.assertIsInstance(caught.exception.problem, str)
        error = stub_top_level(stub_tree(read_stub()))["Error"]
        self.assertEqual(stub_members(error), {"field": "attribute", "problem": "attribute"})


class TheComparisonFails(unittest.TestCase):
    """The comparison finds what a stub that has fallen behind gets wrong."""

    def edited(self, edit):
        tree = stub_tree(read_stub())
        edit(stub_top_level(tree))
        return compare(ast.unparse(tree), module)

    def test_a_method_missing_from_the_stub(self):
        def drop_clearance(top):
            checker = top["CollisionChecker"]
            checker.body = [n for n in checker.body if getattr(n, "name", "") != "clearance"]
        self.assertIn("CollisionChecker.clearance: method in the module, not in the stub",
                      self.edited(drop_clearance))

    def test_a_method_added_to_the_module(self):
        def reset(self):
            """reset(self: hfts._hfts.Cancel) -> None"""
        cancel = type("Cancel", (), {**vars(module.Cancel), "reset": reset})
        grown = types.ModuleType("grown")
        grown.__dict__.update({n: getattr(module, n) for n in dir(module)}, Cancel=cancel)
        self.assertIn("Cancel.reset: method in the module, not in the stub",
                      compare(read_stub(), grown))

    def test_a_function_missing_from_the_stub(self):
        def drop(top):
            top["time_parameterize"].name = "_gone"
        self.assertIn("time_parameterize: in the module, not in the stub", self.edited(drop))

    def test_a_method_the_module_does_not_have(self):
        def add(top):
            method = copy.deepcopy(stub_methods(top["Plan"])["glb"])
            method.name = "gltf"
            top["Plan"].body.append(method)
        self.assertIn("Plan.gltf: in the stub, not in the module", self.edited(add))

    def test_a_writable_attribute_stubbed_as_a_property(self):
        def make_read_only(top):
            settings = top["PlanSettings"]
            settings.body = [n for n in settings.body
                             if not (isinstance(n, ast.AnnAssign) and n.target.id == "paper")]
            settings.body.append(ast.parse("@property\ndef paper(self) -> int: ...").body[0])
        self.assertIn("PlanSettings.paper: property in the stub, attribute in the module",
                      self.edited(make_read_only))

    def test_a_renamed_argument(self):
        def rename(top):
            friction = [a for a in top["grasp_quality"].args.args if a.arg == "friction"][0]
            friction.arg = "mu"
        problems = self.edited(rename)
        self.assertTrue(any(p.startswith("grasp_quality: arguments") for p in problems), problems)

    def test_a_wrong_default(self):
        def change(top):
            plan = stub_methods(top["World"])["plan"].args
            seed = [a.arg for a in plan.args].index("seed")
            plan.defaults[seed - (len(plan.args) - len(plan.defaults))] = ast.Constant(2)
        self.assertIn("World.plan(seed): default 2 in the stub, 1 in the module",
                      self.edited(change))

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--python-dir", required=True,
                        help="the build's python folder (build/python), put first on sys.path")
    parser.add_argument("--stub", default=STUB, help="the stub file (default: %(default)s)")
    args, rest = parser.parse_known_args()
    sys.path.insert(0, os.path.abspath(args.python_dir))
    STUB = args.stub
    import hfts._hfts as module  # noqa: E402
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
