"""Shared fixtures of the Python tests: the module under test, the CLI it is compared with, and
small simulated datasets written by the CLI itself."""
import json
import os
import subprocess

import pytest

import dynid  # noqa: F401  (fails here, once, when PYTHONPATH does not reach the build)


def cli_path():
    path = os.environ.get("DYNID_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("DYNID_CLI is not set (run through ctest)")
    return path


def run_cli(*args, check=True):
    """Runs `dynid args...` and returns the CompletedProcess (stdout and stderr as text)."""
    done = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"dynid {' '.join(map(str, args))} exited {done.returncode}:\n"
                             f"{done.stderr}")
    return done


def read_json(path):
    with open(path) as f:
        return json.load(f)


def less_provenance(document):
    """A document without its `provenance`: what made it (a command or a Python call, when, from
    which working directory) differs between the two front ends; the rest is the same."""
    return {k: v for k, v in document.items() if k != "provenance"}


@pytest.fixture(scope="session")
def puma_csv(tmp_path_factory):
    """4 s of the rigid PUMA 560 under the default sinusoids, torque noise 0.05 N m."""
    path = tmp_path_factory.mktemp("data") / "puma.csv"
    run_cli("simulate", "--robot", "puma560", "--duration", 4, "--noise-tau", 0.05, "--seed", 7,
            "--out", path)
    return path


@pytest.fixture(scope="session")
def puma_validate_csv(tmp_path_factory):
    """Another 2 s with other noise, held out."""
    path = tmp_path_factory.mktemp("data") / "validate.csv"
    run_cli("simulate", "--robot", "puma560", "--duration", 2, "--noise-tau", 0.05, "--seed", 8,
            "--controller", "fourier", "--out", path)
    return path
