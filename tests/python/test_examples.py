"""The Python examples run (quick mode) and write their tables."""
import csv
import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.environ.get("DYNID_SOURCE_DIR", os.path.join(
    os.path.dirname(__file__), "..", "..")), "examples", "python")


def run_example(name, out):
    done = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), "--quick", "--out",
                           str(out)], capture_output=True, text=True, env=os.environ.copy())
    assert done.returncode == 0, done.stderr
    return done.stdout


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def test_noise_study_error_grows_with_the_noise(tmp_path):
    run_example("noise_study.py", tmp_path)
    rows = read_rows(tmp_path / "noise_study.csv")
    assert len(rows) == 3 * 2 * 2  # levels x seeds x methods
    def mean_error(level):
        values = [float(r["base_error"]) for r in rows
                  if float(r["noise_tau"]) == level and r["method"] == "ols"]
        return sum(values) / len(values)
    # Least squares is linear in the noise: 100x the noise, far more than 10x the error.
    assert mean_error(1.0) > 10 * mean_error(0.01)


def test_regressor_vs_search_scores_three_estimates(tmp_path):
    output = run_example("regressor_vs_search.py", tmp_path)
    rows = read_rows(tmp_path / "comparison.csv")
    assert [r["method"] for r in rows] == ["least squares (ols)", "GC search (nlo)",
                                           "search + Ceres refine"]
    for r in rows:
        assert float(r["base_error"]) > 0 and float(r["held_out_gc"]) > 0
    assert "comparison.csv" in output
    try:
        import matplotlib  # noqa: F401
        assert (tmp_path / "comparison.png").exists()
    except ImportError:
        assert "matplotlib is not installed" in output


def test_the_readmes_python_lines_run(tmp_path):
    """The README's "Six lines of Python", as printed there, in a fresh interpreter."""
    source = os.environ.get("DYNID_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
    with open(os.path.join(source, "README.md")) as f:
        readme = f.read()
    block = readme.split("## Six lines of Python", 1)[1].split("```python\n", 1)[1]
    code = block.split("```", 1)[0]
    assert len([line for line in code.splitlines() if line.strip()]) == 6
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, env=os.environ.copy())
    assert done.returncode == 0, done.stderr
    assert '"kind": "dynid.estimate"' in done.stdout
