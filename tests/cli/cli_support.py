"""What the command-line tests share: running a program and building the
databases of bundled objects (standard library only)."""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import unittest


def sanitizer_slowdown():
    """How much slower the programs run under the sanitizer of HFTS_SANITIZER
    (scripts/sanitize.sh), as tests/support/plan_checks.h scales plan time."""
    return {"address": 4.0, "thread": 10.0, "undefined": 2.0}.get(
        os.environ.get("HFTS_SANITIZER", ""), 1.0)


def run(binary, *args, check=None, timeout=240):
    """Runs `binary` with `args` (stdin closed, output captured); with
    `check`, asserts that it exits with that status."""
    result = subprocess.run([binary, *map(str, args)], capture_output=True, text=True,
                            timeout=timeout, stdin=subprocess.DEVNULL)
    if check is not None:
        assert result.returncode == check, (result.returncode, result.stdout, result.stderr)
    return result


def bundled_meshes(source_dir):
    """The file names of the bundled meshes (objects/meshes), sorted; not
    their sidecars (<mesh stem>.json, which hfts-preprocess reads beside a
    mesh)."""
    meshes = os.path.join(source_dir, "objects", "meshes")
    return sorted(f for f in os.listdir(meshes) if not f.endswith(".json"))


def build_databases(preprocess, source_dir, out_dir, objects, robots=("kr5_sdh",)):
    """The databases of the named bundled objects and the hand maps of the
    named bundled robots (default the KR5 + SDH), written into `out_dir` with
    hfts-preprocess (what hfts-bench and hfts-server read)."""
    meshes = os.path.join(source_dir, "objects", "meshes")
    for mesh in bundled_meshes(source_dir):
        if os.path.splitext(mesh)[0] in objects:
            run(preprocess, os.path.join(meshes, mesh), "-o", out_dir, "-q", check=0)
    for robot in robots:
        config = os.path.join(source_dir, "robots", robot, robot + ".json")
        run(preprocess, "--hand", config, "-o", out_dir, check=0)


def run_tests_with_databases(preprocess, source_dir, objects, rest, use_folder):
    """Builds the named objects' databases and the KR5 + SDH hand map into a
    temporary folder, hands the folder to use_folder, runs the __main__
    module's tests (arguments `rest`), removes the folder and exits with
    the tests' verdict."""
    folder = tempfile.mkdtemp(prefix="hfts-test-db-")
    try:
        use_folder(folder)
        build_databases(preprocess, source_dir, folder, objects)
        program = unittest.main(argv=[sys.argv[0], *rest], verbosity=2, exit=False)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    sys.exit(0 if program.result.wasSuccessful() else 1)


def bench_options():
    """--binary, --preprocess and --source-dir of the hfts-bench tests, and
    the remaining arguments for unittest."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", required=True)
    parser.add_argument("--preprocess", required=True)
    parser.add_argument("--source-dir", required=True)
    args, rest = parser.parse_known_args()
    return args.binary, args.preprocess, args.source_dir, rest
