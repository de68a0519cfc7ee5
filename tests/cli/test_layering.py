#!/usr/bin/env python3
"""The libraries depend one way (docs/architecture.md):
core <- hfts_db <- robot <- grasp, physics <- planner <- service, bench; preprocess uses
core and hfts_db only (its program also robot and grasp); the client no library but
core (the error type, the atomic file writer and base64); the Python module
(python/) any library. Checked on the sources' #include lines and on what
the built programs link. Within the libraries, no include circle between
files (x.h and x.cpp taken as one) and no file over 600 lines in planner/
and robot/ (the SIMD kernel aside)."""
import argparse
import pathlib
import re
import subprocess
import sys
import unittest
from collections import defaultdict

# What each folder may include of the project's folders (besides itself).
ALLOWED = {
    "core": set(),
    "hfts_db": {"core"},
    "robot": {"core", "hfts_db"},
    "grasp": {"core", "hfts_db", "robot"},
    "physics": {"core", "hfts_db", "robot"},  # MuJoCo: never grasp or planner
    "planner": {"core", "hfts_db", "robot", "grasp", "physics"},
    "preprocess": {"core", "hfts_db", "robot", "grasp"},  # robot and grasp: tools/ only
    "service": {"core", "hfts_db", "robot", "grasp", "physics", "planner"},
    "client": {"core"},
    # the in-process Python module (python/): a front end over every library
    "python": {"core", "hfts_db", "robot", "grasp", "physics", "planner", "preprocess", "service",
               "client"},
}
LIBRARY_FOLDERS = set(ALLOWED) | {"bench"}
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]+"([a-z_]+)/[^"]+"', re.MULTILINE)

ARGS = None

# Include circles still there: to be broken, never added to. A circle that
# is gone must leave this list (none is left).
KNOWN_CIRCLES = set()
LONG_FILE_LINES = 600
# Files allowed over LONG_FILE_LINES: the SIMD kernel (one function per
# lane width); and files still longer (to be split, never added to).
LONG_FILES_ALLOWED = {"robot/src/sphere_kernel.cpp"}
LONG_FILES_KNOWN = set()
QUOTED_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]+"([^"]+)"', re.MULTILINE)


def includes(folder):
    """(file, included folder, included path) for every project include."""
    root = pathlib.Path(ARGS.source_dir) / folder
    for path in sorted(list(root.rglob("*.h")) + list(root.rglob("*.cpp"))):
        if path.parent.name == "bench":
            continue  # benchmark programs (service/bench) may use any library
        text = path.read_text()
        for match in INCLUDE.finditer(text):
            target = match.group(1)
            if target in LIBRARY_FOLDERS:
                line = text[match.start():text.index("\n", match.start())]
                yield path.relative_to(ARGS.source_dir), target, line.strip()


def module_of(path):
    """"folder/stem" of a library file: x.h and x.cpp are one module."""
    rel = path.relative_to(ARGS.source_dir)
    return f"{rel.parts[0]}/{path.stem}"


def resolve(source, included, root):
    """The project file an #include "..." names, or None (a system header)."""
    beside = source.parent / included
    if beside.exists():
        return beside
    folder, _, rest = included.partition("/")
    if folder in LIBRARY_FOLDERS:
        for candidate in (root / folder / "include" / included, root / folder / rest,
                          root / folder / "src" / rest):
            if candidate.exists():
                return candidate
    own = root / source.relative_to(root).parts[0] / "src" / included
    return own if own.exists() else None


def module_graph():
    """module -> the modules its files include, over the library folders. A
    private header (in a library's src/) that only one module includes is
    that module's own part (a helper of its implementation), not a module
    of its own."""
    root = pathlib.Path(ARGS.source_dir)
    edges = []
    private = set()
    for folder in sorted(LIBRARY_FOLDERS):
        for path in sorted(list((root / folder).rglob("*.h")) +
                           list((root / folder).rglob("*.cpp"))):
            if path.suffix == ".h" and "include" not in path.relative_to(root).parts:
                private.add(module_of(path))
            for match in QUOTED_INCLUDE.finditer(path.read_text()):
                target = resolve(path, match.group(1), root)
                if target is not None and module_of(target) != module_of(path):
                    edges.append((module_of(path), module_of(target)))
    includers = defaultdict(set)
    for source, target in edges:
        includers[target].add(source)
    owner = {helper: next(iter(users)) for helper, users in includers.items()
             if helper in private and len(users) == 1}

    def merged(module):
        seen = set()
        while module in owner and module not in seen:
            seen.add(module)
            module = owner[module]
        return module

    graph = defaultdict(set)
    for source, target in edges:
        if merged(source) != merged(target):
            graph[merged(source)].add(merged(target))
    return graph


def circles(graph):
    """The strongly connected components with more than one module (Tarjan)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(frozenset(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


class Layering(unittest.TestCase):
    def test_each_folder_includes_only_the_folders_below_it(self):
        for folder, allowed in ALLOWED.items():
            for path, target, line in includes(folder):
                if target == folder:
                    continue
                with self.subTest(file=str(path), include=line):
                    self.assertIn(target, allowed)

    def test_no_include_circle_between_files(self):
        found = set(circles(module_graph()))
        for circle in sorted(found - KNOWN_CIRCLES, key=sorted):
            with self.subTest(circle=sorted(circle)):
                self.fail("a new include circle between " + ", ".join(sorted(circle)))
        for circle in sorted(KNOWN_CIRCLES - found, key=sorted):
            with self.subTest(circle=sorted(circle)):
                self.fail("gone (or changed): remove it from KNOWN_CIRCLES: " +
                          ", ".join(sorted(circle)))

    def test_the_circle_finder_finds_a_circle(self):
        self.assertEqual(circles({"a/x": {"a/y"}, "a/y": {"a/z"}, "a/z": {"a/x"}, "a/w": {"a/x"}}),
                         [frozenset({"a/x", "a/y", "a/z"})])
        self.assertEqual(circles({"a/x": {"a/y"}, "a/y": set()}), [])

    def test_no_long_file_in_planner_and_robot(self):
        root = pathlib.Path(ARGS.source_dir)
        for folder in ("planner", "robot"):
            for path in sorted(list((root / folder).rglob("*.h")) +
                               list((root / folder).rglob("*.cpp"))):
                name = str(path.relative_to(root))
                if name in LONG_FILES_ALLOWED:
                    continue
                lines = len(path.read_text().splitlines())
                with self.subTest(file=name, lines=lines):
                    if name in LONG_FILES_KNOWN:
                        self.assertGreater(lines, LONG_FILE_LINES,
                                           "now short enough: remove it from LONG_FILES_KNOWN")
                    else:
                        self.assertLessEqual(lines, LONG_FILE_LINES)

    def test_the_preprocess_library_needs_only_hfts_db(self):
        for path, target, line in includes("preprocess"):
            if path.parts[1] != "tools":
                with self.subTest(file=str(path)):
                    self.assertIn(target, {"preprocess", "hfts_db", "core"}, line)

    def test_the_service_includes_no_file_format(self):
        # The error type, the atomic writer and base64 are core's: the
        # service reads requests and writes answers without hfts_db (the
        # databases reach it through the planner's PlanningWorld).
        for path, target, line in includes("service"):
            with self.subTest(file=str(path), include=line):
                self.assertNotEqual(target, "hfts_db")

    def test_hfts_preprocess_links_no_ompl(self):
        libs = subprocess.run(["ldd", ARGS.preprocess], capture_output=True, text=True,
                              check=True).stdout
        self.assertIn("liburdfdom", libs)  # the robot model is linked ...
        self.assertNotIn("libompl", libs)  # ... but not the planner's OMPL

    def test_hfts_client_links_no_library_of_the_planner(self):
        libs = subprocess.run(["ldd", ARGS.client], capture_output=True, text=True,
                              check=True).stdout
        for lib in ("libompl", "libfcl", "libhdf5", "libassimp", "liburdfdom"):
            self.assertNotIn(lib, libs)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--preprocess", required=True)
    parser.add_argument("--client", required=True)
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
