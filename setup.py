"""`pip install .`: builds dynid with CMake and packs the Python module and the `dynid` program.

pyproject.toml says why the backend is setuptools. The wheel holds the extension module `dynid`
(with its type stubs, when python3-mypy made them, and dynid_distributed.py, its Dask layer) and the `dynid` program as a script: pip puts it
in the environment's bin/. Both link dynid's own libraries statically and Debian's shared ones
(Ceres, NLopt, urdfdom, ...) from the system, with no run path into the build tree: the wheel is
relocatable. Settings, from the environment:
  DYNID_CMAKE_BUILD_DIR  an existing CMake build tree to build the two targets in (CI reuses its
                         release build); by default a fresh Release build under build-pip/.
  DYNID_BUILD_JOBS       parallel jobs (default: the CPU count).
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

# setuptools (66 on Debian 12) has no build_scripts of its own: distutils' (setuptools provides it).
from distutils.command.build_scripts import build_scripts  # noqa: E402  (after setuptools)

ROOT = Path(__file__).resolve().parent


def project_version():
    """The one version: CMakeLists.txt's project(dynid VERSION x.y.z)."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    match = re.search(r"project\(\s*dynid\s+VERSION\s+([0-9]+\.[0-9]+\.[0-9]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no project(dynid VERSION x.y.z)")
    return match.group(1)


def cmake_build_dir():
    """Where CMake builds: DYNID_CMAKE_BUILD_DIR, else build-pip/cmake in the source tree."""
    given = os.environ.get("DYNID_CMAKE_BUILD_DIR")
    return Path(given).resolve() if given else ROOT / "build-pip" / "cmake"


def run_cmake():
    """Configures (a new tree only) and builds the program and the module; the build tree."""
    tree = cmake_build_dir()
    if not (tree / "CMakeCache.txt").exists():
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        subprocess.check_call(
            ["cmake", "-S", str(ROOT), "-B", str(tree), *generator,
             "-DCMAKE_BUILD_TYPE=Release", "-DDYNID_PYTHON=ON", "-DDYNID_BUILD_TESTS=OFF",
             "-DDYNID_BUILD_BENCH=OFF", "-DCMAKE_UNITY_BUILD=ON",
             f"-DPython_EXECUTABLE={sys.executable}"])
    jobs = os.environ.get("DYNID_BUILD_JOBS") or str(os.cpu_count() or 1)
    subprocess.check_call(["cmake", "--build", str(tree), "--target", "dynid", "dynid_python",
                           "-j", jobs])
    return tree


class CMakeBuildExt(build_ext):
    """The extension `dynid` is CMake's target dynid_python: built there, copied here."""

    def run(self):
        tree = run_cmake()
        for ext in self.extensions:
            built = sorted((tree / "python").glob("dynid*.so"))
            if not built:
                raise RuntimeError(f"{tree / 'python'}: CMake built no dynid*.so")
            target = Path(self.get_ext_fullpath(ext.name))
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(built[0], target)
            stubs = tree / "python" / "dynid.pyi"
            if stubs.exists():
                shutil.copy2(stubs, target.parent / "dynid.pyi")
            # The Dask layer, pure Python beside the module (dynid.summarize_many imports it).
            shutil.copy2(tree / "python" / "dynid_distributed.py",
                         target.parent / "dynid_distributed.py")


class ProgramScripts(build_scripts):
    """The `dynid` program as the wheel's script, copied as it is (a binary, not Python)."""

    def run(self):
        tree = run_cmake()
        program = tree / "bin" / "dynid"
        Path(self.build_dir).mkdir(parents=True, exist_ok=True)
        shutil.copy2(program, Path(self.build_dir) / "dynid")
        os.chmod(Path(self.build_dir) / "dynid", 0o755)


# setuptools' own scratch (build/, *.egg-info) under build-pip/, away from CMake's build/.
(ROOT / "build-pip").mkdir(exist_ok=True)
setup(
    version=project_version(),
    ext_modules=[Extension("dynid", sources=[])],
    scripts=["bin-placeholder/dynid"],
    cmdclass={"build_ext": CMakeBuildExt, "build_scripts": ProgramScripts},
    options={"build": {"build_base": "build-pip"}, "egg_info": {"egg_base": "build-pip"}},
    zip_safe=False,
)
