#!/usr/bin/env python3
"""The libraries depend one way (docs/architecture.md):
hfts_db <- robot <- grasp, physics <- planner <- service, bench; preprocess uses
hfts_db only (its program also robot and grasp); the client no library but
the atomic file writer and base64 (hfts::atomic_file). Checked on the sources' #include lines and on what
the built programs link."""
import argparse
import pathlib
import re
import subprocess
import sys
import unittest

# What each folder may include of the project's folders (besides itself).
ALLOWED = {
    "hfts_db": set(),
    "robot": {"hfts_db"},
    "grasp": {"hfts_db", "robot"},
    "physics": {"hfts_db", "robot"},  # MuJoCo: never grasp or planner
    "planner": {"hfts_db", "robot", "grasp", "physics"},
    "preprocess": {"hfts_db", "robot", "grasp"},  # robot and grasp: tools/ only
    "service": {"hfts_db", "robot", "grasp", "physics", "planner"},
    "client": {"hfts_db"},  # atomic_file.h only
}
LIBRARY_FOLDERS = set(ALLOWED) | {"bench"}
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]+"([a-z_]+)/[^"]+"', re.MULTILINE)

ARGS = None


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


class Layering(unittest.TestCase):
    def test_each_folder_includes_only_the_folders_below_it(self):
        for folder, allowed in ALLOWED.items():
            for path, target, line in includes(folder):
                if target == folder:
                    continue
                with self.subTest(file=str(path), include=line):
                    self.assertIn(target, allowed)

    def test_the_preprocess_library_needs_only_hfts_db(self):
        for path, target, line in includes("preprocess"):
            if path.parts[1] != "tools":
                with self.subTest(file=str(path)):
                    self.assertIn(target, {"preprocess", "hfts_db"}, line)

    def test_the_client_includes_only_the_standard_library_utilities(self):
        # hfts::atomic_file: the atomic file writer and base64, no HDF5 or assimp.
        for path, target, line in includes("client"):
            if target == "hfts_db":
                self.assertRegex(line, r'"hfts_db/(atomic_file|base64)\.h"', path)

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
