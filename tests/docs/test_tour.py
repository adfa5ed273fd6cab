"""docs/TOUR.md runs as written: its "Commands" shell block top to bottom (bash -e), then its
Python block in the folder the commands wrote, with this build's dynid on PATH and its module on
PYTHONPATH. The block starts with `repo=$PWD` (the repository root): here the root is a scratch
folder holding links to the repository's tests/ and examples/, so the tour's files stay out of
the source tree."""

import os
import re
import subprocess
import sys

SOURCE = os.environ.get("DYNID_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def tour_blocks():
    with open(os.path.join(SOURCE, "docs", "TOUR.md")) as f:
        text = f.read()
    commands = text.split("## Commands\n", 1)[1]
    shell = re.search(r"```sh\n(.*?)```", commands, re.S).group(1)
    python = re.search(r"```python\n(.*?)```", commands, re.S).group(1)
    return shell, python


def test_the_tours_commands_and_python_run_as_written(tmp_path):
    shell, python = tour_blocks()
    for shared in ("tests", "examples"):
        os.symlink(os.path.join(os.path.abspath(SOURCE), shared), tmp_path / shared)
    env = os.environ.copy()
    env["PATH"] = os.path.dirname(env["DYNID_CLI"]) + os.pathsep + env["PATH"]
    done = subprocess.run(["bash", "-e", "-c", shell], cwd=tmp_path, env=env,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-4000:]
    tour = tmp_path / "tour"
    for made in ("est/estimate.json", "pred/prediction.json", "payload/payload.json",
                 "watch/monitor.json", "study/study.json", "demo/summary.json",
                 "batch/results.csv", "puma.xml", "fleet/fleet.json"):
        assert (tour / made).exists(), made
    done = subprocess.run([sys.executable, "-c", python], cwd=tour, env=env,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-4000:]
    assert '"kind": "dynid.estimate"' in done.stdout
