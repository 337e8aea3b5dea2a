"""Builds visfield's Python extension and its `visfield` program with CMake for pip (pyproject.toml).

pip calls this through setuptools; a user runs `pip install --no-build-isolation .`. The build is
Release and portable (x86-64-v3, AVX-512 kernels chosen at run time), in the build's temporary
folder, or in VISFIELD_BUILD_DIR when that names an existing CMake build of this checkout (CI reuses
its build there). CMake, Ninja and the libraries come from Debian (scripts/install-deps.sh --all).
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    """The version in CMakeLists.txt's project() line: one place says it."""
    match = re.search(r"project\(visfield VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not match:
        sys.exit("setup.py: error: no 'project(visfield VERSION ...)' in CMakeLists.txt")
    return match.group(1)


class CMakeBuild(build_ext):
    """Configures and builds the CMake targets visfield_python and visfield, then copies the module
    and the program into the package."""

    def build_extension(self, ext):
        build = Path(os.environ.get("VISFIELD_BUILD_DIR") or Path(self.build_temp).resolve() / "cmake")
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 2)
        if not (build / "CMakeCache.txt").exists():
            generator = ["-G", "Ninja"] if shutil.which("ninja") else []
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), *generator, "-DCMAKE_BUILD_TYPE=Release",
                            "-DVISFIELD_PYTHON=ON", "-DVISFIELD_TESTS=OFF", "-DVISFIELD_BENCH=OFF",
                            f"-DPYTHON_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build), "-j", jobs, "--target", "visfield_python", "visfield"], check=True)
        module = next((build / "python" / "visfield").glob("_visfield*.so"), None)
        if module is None:
            sys.exit(f"setup.py: error: the build made no python/visfield/_visfield*.so in {build}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, target)
        # The program beside the module: visfield.command runs it for the `visfield` command.
        program = target.parent / "bin" / "visfield"
        program.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(build / "bin" / "visfield", program)


setup(
    version=project_version(),
    # Not build/: that is the README's CMake build folder.
    options={"build": {"build_base": "build-python"}},
    ext_modules=[Extension("visfield._visfield", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
)
