"""Builds the wheel of the module hfts: CMake builds the extension
(target hfts_python) from the repository this file is in, and the wheel
takes it with the package's Python files, its type stubs and the web
viewer (for Plan pages). Settings in pyproject.toml; run through
scripts/build_wheel.sh.

Environment:
  HFTS_SOURCE_ROOT      the repository (default: the folder above this
                        file's; scripts/build_wheel.sh builds a copy)
  HFTS_CMAKE_BUILD_DIR  a CMake build folder to build the extension in
                        (default: a folder of its own under build/wheel in
                        the repository, configured Release without tests)
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = pathlib.Path(__file__).resolve().parent
ROOT = pathlib.Path(os.environ.get("HFTS_SOURCE_ROOT") or HERE.parent).resolve()


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class BuildWithCMake(build_ext):
    """The extension from CMake; the viewer copied beside the package."""

    def build_extension(self, ext):
        build_dir = pathlib.Path(os.environ.get("HFTS_CMAKE_BUILD_DIR") or ROOT / "build" / "wheel")
        if not build_dir.is_absolute():
            raise RuntimeError(f"HFTS_CMAKE_BUILD_DIR must be an absolute path, got {build_dir}")
        if not (build_dir / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir),
                            "-DCMAKE_BUILD_TYPE=Release", "-DHFTS_BUILD_TESTS=OFF",
                            "-DHFTS_BUILD_BENCHMARKS=OFF", "-DHFTS_BUILD_PYTHON=ON",
                            f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "hfts_python", "-j",
                        str(os.cpu_count() or 1)], check=True)
        built = sorted((build_dir / "python" / "hfts").glob("_hfts*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one built extension in {build_dir}/python/hfts, "
                               f"found {[str(b) for b in built]}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)
        self.copy_viewer(target.parent)

    @staticmethod
    def copy_viewer(package):
        viewer = ROOT / "viewer"
        script = viewer / "dist" / "viewer.js"
        if not script.exists():
            raise RuntimeError(f"{script} is missing: run scripts/setup.sh (it bundles the viewer)")
        for source, name in ((viewer / "src" / "page.html", "src/page.html"),
                             (script, "dist/viewer.js")):
            destination = package / "viewer" / name
            destination.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, destination)


setup(ext_modules=[CMakeExtension("hfts._hfts")], cmdclass={"build_ext": BuildWithCMake})
