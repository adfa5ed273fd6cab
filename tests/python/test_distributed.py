"""dynid.summarize_many on a Dask local cluster: the merged summary is the same bits as merging
in this process, a corrupt log is named and the rest go on, and a worker killed mid-run costs
nothing but time (its tasks run again)."""
import os
import threading
import time

import numpy as np
import pytest

import dynid
from conftest import run_cli

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Eight 2 s PUMA logs with its drive terms, and one whose 50th row is not a number."""
    d = tmp_path_factory.mktemp("many")
    paths = []
    for seed in range(1, 9):
        path = d / f"s{seed}.csv"
        run_cli("simulate", "--robot", "puma560", "--drives", "--duration", 2, "--noise-tau",
                0.1, "--seed", seed, "--out", path)
        paths.append(path)
    rows = paths[0].read_text().splitlines()
    rows[50] = "0.05,x" + rows[50].split(",", 1)[1]
    bad = d / "bad.csv"
    bad.write_text("\n".join(rows) + "\n")
    return paths, bad


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def serial(model, paths):
    """The same tree of merges in this process: (0 1) (2 3) ..., then their results."""
    parts = [dynid.summarize(model, p, threads=1) for p in paths]
    while len(parts) > 1:
        parts = [parts[i] + parts[i + 1] if i + 1 < len(parts) else parts[i]
                 for i in range(0, len(parts), 2)]
    return parts[0]


def test_the_clusters_summary_is_this_processs_and_a_corrupt_log_is_named(logs, client):
    paths, bad = logs
    model = dynid.load_model("puma560", drives=True)
    done = dynid.summarize_many(model, [*paths[:3], bad, *paths[3:]], client=client)
    assert done.summarized == [os.fspath(p) for p in paths]
    assert list(done.failed) == [os.fspath(bad)]
    assert "bad.csv:51" in done.failed[os.fspath(bad)]  # the file and its line
    here = serial(model, paths)
    assert done.summary.samples == here.samples
    e_cluster = dynid.identify(model, done.summary, method="wls")
    e_here = dynid.identify(model, here, method="wls")
    # The corrupt log leaves its group of four with three: another tree of merges than the eight
    # good logs' own, so round-off apart (1e-12: a stacked QR's).
    assert np.linalg.norm(e_cluster.beta - e_here.beta) < 1e-12 * np.linalg.norm(e_here.beta)


def test_a_worker_killed_mid_run_changes_nothing(logs, client):
    paths, _ = logs
    model = dynid.load_model("puma560", drives=True)
    many = paths * 3  # 24 logs, 6 tasks
    result = {}
    runner = threading.Thread(
        target=lambda: result.update(done=dynid.summarize_many(model, many, client=client)))
    runner.start()
    # A worker that holds tasks it has not finished: killed, they must run again elsewhere.
    victim = None
    deadline = time.monotonic() + 60
    while victim is None and time.monotonic() < deadline and runner.is_alive():
        busy = [w for w, keys in client.processing().items()
                if any(k.startswith("_summarize_group") for k in keys)]
        victim = busy[0] if busy else None
        time.sleep(0.01)
    assert victim is not None, "no worker was summarizing: nothing to kill mid-run"
    # The worker's process ends mid-call (so the call cannot answer); its nanny starts another.
    client.run(os._exit, 1, workers=[victim], on_error="ignore")
    runner.join(timeout=240)
    assert not runner.is_alive()
    done = result["done"]
    assert not done.failed
    assert len(done.summarized) == len(many)
    assert victim not in set(client.scheduler_info()["workers"])  # it did die
    e_cluster = dynid.identify(model, done.summary, method="ols")
    e_here = dynid.identify(model, serial(model, many), method="ols")
    # Groups of four: the logs' own pairwise tree, whichever worker ran what: the same bits.
    assert np.array_equal(e_cluster.beta, e_here.beta)


def test_the_tasks_join_their_batches_and_the_tree_only_appends(logs, client):
    paths, _ = logs
    model = dynid.load_model("puma560", drives=True)
    many = paths * 8  # 64 logs of 8 batches, a task each: each keeps 256 / 64 = 4 batches
    done = dynid.summarize_many(model, many, client=client, logs_per_task=1)
    here = serial(model, many)  # 512 batches merged here, joined to 256 at the top
    assert done.summary.num_batches == 256 == here.num_batches
    assert done.summary.samples == here.samples
    e_cluster = dynid.identify(model, done.summary, method="ols")
    e_here = dynid.identify(model, here, method="ols")
    # The same rows' QR, joined in the tasks rather than at the top: round-off apart.
    assert np.linalg.norm(e_cluster.beta - e_here.beta) < 1e-12 * np.linalg.norm(e_here.beta)


def test_a_batch_on_the_cluster_is_the_clis_and_resumes(tmp_path, client):
    manifest = tmp_path / "manifest.json"
    manifest.write_text('{"schema_version": 1, "grid": {"method": ["ols", "wls"], "seed": [1, 2]},'
                        ' "fixed": {"train_seconds": 1, "test_seconds": 1, "segments": 5}}\n')
    run_cli("batch", manifest, "--quick", "--jobs", 1, "--out", tmp_path / "cli")
    import json
    cli = json.loads((tmp_path / "cli" / "results.json").read_text())
    there = dynid.batch(manifest, tmp_path / "dask", client=client, quick=True)
    assert there["failed"] == {}
    assert there["runs_done"] == cli["runs_done"] == 4

    def metrics(results):
        # Every column but the wall time: the same bits on any worker.
        return [{k: v for k, v in run.items() if k != "seconds"} for run in results["rows"]]

    assert metrics(there) == metrics(cli)
    # Stored as they came: a second call finds every run done and only writes the tables.
    stored = sorted(p.name for p in (tmp_path / "dask" / "runs").iterdir())
    assert len(stored) == 4
    again = dynid.batch(manifest, tmp_path / "dask", client=client, quick=True)
    assert metrics(again) == metrics(there)
