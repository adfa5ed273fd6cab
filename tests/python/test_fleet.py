"""dynid.fleet: robots of one model at once, from Summaries or logs, here and on a Dask local
cluster (the logs summarized on the workers): the same fleet, a robot carrying an undeclared mass
outside it, a corrupt log named and its robot going on with the rest."""
import os

import numpy as np
import pytest

import dynid
from conftest import run_cli


@pytest.fixture(scope="module")
def fleet_logs(tmp_path_factory):
    """Seven robots, two 2 s logs each: six PUMAs with drive terms and one with 3 kg more at link
    3's origin ("heavy"); and a copy of arm1's first log whose 50th row is not a number. (Six
    others: a fleet's spread learnt from fewer is too uncertain to call 3 kg odd at this noise.)"""
    d = tmp_path_factory.mktemp("fleet")
    model = d / "heavy.json"
    run_cli("model", "export", "--robot", "puma560", "--drives", "--format", "json", "--out",
            model)
    import json
    doc = json.loads(model.read_text())
    doc["bodies"][2]["inertial"]["m"] += 3.0
    model.write_text(json.dumps(doc))
    robots = {}
    for r, name in enumerate(["arm1", "arm2", "arm3", "arm4", "arm5", "arm6", "heavy"]):
        (d / name).mkdir()
        robots[name] = []
        for part in (1, 2):
            path = d / name / f"log{part}.csv"
            spec = [os.fspath(model)] if name == "heavy" else ["puma560", "--drives"]
            run_cli("simulate", "--robot", *spec, "--controller", "fourier", "--duration", 2,
                    "--noise-tau", 0.1, "--seed", 10 * r + part, "--out", path)
            robots[name].append(path)
    rows = robots["arm1"][0].read_text().splitlines()
    rows[50] = "0.05,x" + rows[50].split(",", 1)[1]
    bad = d / "arm1" / "bad.csv"
    bad.write_text("\n".join(rows) + "\n")
    return robots, bad


def test_a_fleet_of_summaries_is_the_fleet_of_their_logs(fleet_logs):
    robots, _ = fleet_logs
    model = dynid.load_model("puma560", drives=True)
    from_logs = dynid.fleet(model, robots)
    summaries = {name: sum(dynid.summarize(model, log) for log in logs)
                 for name, logs in robots.items()}
    from_summaries = dynid.fleet(model, summaries)
    assert from_logs["kind"] == "dynid.fleet"
    assert [r["name"] for r in from_logs["robots"]] == list(robots)
    assert [r["outside"] for r in from_logs["robots"]] == [False] * 6 + [True]
    assert "heavy" in from_logs["verdict"]
    for a, b in zip(from_logs["robots"], from_summaries["robots"]):
        # sum() merges from 0 as the run merges its logs: the same bits.
        assert a["estimate"] == b["estimate"]
        assert a["posterior"] == b["posterior"]
    assert from_logs["provenance"]["interface"] == "python"


def test_a_fleet_refuses_two_robots_and_other_methods(fleet_logs):
    robots, _ = fleet_logs
    model = dynid.load_model("puma560", drives=True)
    two = {k: robots[k] for k in ["arm1", "arm2"]}
    with pytest.raises(ValueError, match="three robots or more"):
        dynid.fleet(model, two)
    with pytest.raises(ValueError, match=r"'pc' \(expected ols or wls\)"):
        dynid.fleet(model, robots, method="pc")
    with pytest.raises(TypeError, match="arm1"):
        dynid.fleet(model, {**robots, "arm1": 3})


def test_on_a_dask_cluster_the_fleet_is_the_same_and_a_corrupt_log_is_named(fleet_logs):
    distributed = pytest.importorskip("distributed")
    robots, bad = fleet_logs
    model = dynid.load_model("puma560", drives=True)
    here = dynid.fleet(model, robots)
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    with distributed.Client(cluster) as client:
        there = dynid.fleet(model, {**robots, "arm1": [*robots["arm1"], bad]}, client=client)
    cluster.close()
    assert list(there["failed"]) == [os.fspath(bad)]
    assert "bad.csv:51" in there["failed"][os.fspath(bad)]
    assert there["robots_left_out"] == []
    for a, b in zip(here["robots"], there["robots"]):
        np.testing.assert_allclose(b["estimate"], a["estimate"], rtol=1e-12, atol=0)
        assert a["outside"] == b["outside"]
    assert here["verdict"] == there["verdict"]
