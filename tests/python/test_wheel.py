"""`pip install .` as the README gives it, offline: a venv that sees Debian's packages, the wheel
built by setup.py's CMake backend (in this build's tree: DYNID_CMAKE_BUILD_DIR, so CI does not
build dynid twice), then the module and the program used from the venv alone."""

import os
import re
import subprocess
import sys

import pytest

SOURCE = os.environ.get("DYNID_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.environ.get("DYNID_BUILD_DIR")


def run(args, **kwargs):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "DYNID_CLI")}
    env.update(kwargs.pop("env", {}))
    done = subprocess.run(args, capture_output=True, text=True, env=env, **kwargs)
    assert done.returncode == 0, f"{args}: {done.stdout}\n{done.stderr}"
    return done.stdout


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    if not BUILD:
        pytest.skip("DYNID_BUILD_DIR is not set (CTest sets it)")
    root = tmp_path_factory.mktemp("wheel")
    env_dir = root / "v"
    # The interpreter the module was built for (CMake's Python_EXECUTABLE: Debian's python3).
    run([sys.executable, "-m", "venv", "--system-site-packages", str(env_dir)])
    run([str(env_dir / "bin" / "pip"), "install", "--no-build-isolation", "--no-index", SOURCE],
        cwd=root, env={"DYNID_CMAKE_BUILD_DIR": BUILD})
    return env_dir


def cmake_version():
    with open(os.path.join(SOURCE, "CMakeLists.txt")) as f:
        return re.search(r"project\(dynid VERSION ([0-9.]+)", f.read()).group(1)


def test_the_program_is_a_script_of_the_venv(venv, tmp_path):
    out = run([str(venv / "bin" / "dynid"), "--version"], cwd=tmp_path)
    assert out.startswith("dynid " + cmake_version()), out


def test_the_module_is_the_venvs_and_runs_the_readmes_lines(venv, tmp_path):
    with open(os.path.join(SOURCE, "README.md")) as f:
        readme = f.read()
    code = readme.split("## Six lines of Python", 1)[1].split("```python\n", 1)[1]
    code = code.split("```", 1)[0]
    out = run([str(venv / "bin" / "python"), "-c",
               "import dynid; print(dynid.__file__); print(dynid.__version__)\n" + code],
              cwd=tmp_path)
    where, version = out.splitlines()[:2]
    assert where.startswith(str(venv)), where
    assert version == cmake_version()
    assert '"kind": "dynid.estimate"' in out


def test_the_wheel_has_no_run_path_into_the_build(venv):
    """Relocatable: neither binary looks for libraries in the build tree (readelf's dynamic
    section names no RPATH or RUNPATH there)."""
    module = next((venv / "lib").glob("python3*/site-packages/dynid*.so"))
    for binary in (module, venv / "bin" / "dynid"):
        dynamic = run(["readelf", "-d", str(binary)])
        paths = [line for line in dynamic.splitlines() if "RPATH" in line or "RUNPATH" in line]
        assert not [p for p in paths if BUILD in p or SOURCE in p], paths


def test_the_dask_layer_is_beside_the_module(venv, tmp_path):
    out = run([str(venv / "bin" / "python"), "-c",
               "import dynid, dynid_distributed, os; "
               "print(os.path.dirname(dynid.__file__) == "
               "os.path.dirname(dynid_distributed.__file__))"], cwd=tmp_path)
    assert out.strip() == "True", out
