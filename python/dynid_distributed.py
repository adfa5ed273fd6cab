"""dynid on a Dask cluster: least-squares summaries of many logs, computed where the workers are
and merged as a tree (docs/FLEET.md). The C++ library stays engine-free; this module is the Python
layer's, reached as dynid.summarize_many, dynid.fleet(client=) and dynid.batch (the extension
module imports it on first use).

A task summarizes a few consecutive logs (`dynid.summarize` with one thread, the worker's own) and
merges them; the summaries travel pickled (their summary.json, the factors bit for bit) and are
merged pairwise in a fixed tree by the logs' order, so that the result is the same bits whichever
worker ran what, in whatever order, and after a worker was lost and its tasks ran again. A log
that cannot be summarized (unreadable, another robot's, a bad row) is named with its error in
`failed`, and the rest go on. dynid.fleet(..., client=) summarizes every robot's logs so, then
learns the fleet from their summaries.
"""

import collections
import contextlib
import os

import dynid

SummarizeMany = collections.namedtuple("SummarizeMany", ["summary", "summarized", "failed"])
SummarizeMany.__doc__ = """What summarize_many returns: the merged Summary of every log summarized
(None when none was), the logs summarized in their given order, and {log: error} of the rest."""


def _tree(items, merge):
    """Pairwise merges in a fixed tree: (0 1) (2 3) ..., then their results the same way."""
    while len(items) > 1:
        items = [merge(items[i], items[i + 1]) if i + 1 < len(items) else items[i]
                 for i in range(0, len(items), 2)]
    return items[0] if items else None


def _summarize_group(model, logs, rest_velocity, torque_filter, robot_spec, shares):
    """A task: its logs' summaries merged pairwise, and the errors of those that could not be
    summarized (as text: a task that raised would be retried as if its worker had died, and the
    message is what the user needs). Its summary keeps at most a `shares`-th of the batches a
    summary keeps (neighbours joined here, in parallel with the other tasks), so that the merge
    tree above only appends them: its top, which runs when every task is done, joins nothing."""
    parts, failed = [], {}
    for log in logs:
        try:
            parts.append(dynid.summarize(model, log, rest_velocity=rest_velocity,
                                         torque_filter=torque_filter, threads=1,
                                         robot_spec=robot_spec))
        except Exception as e:  # noqa: BLE001 - every refusal is the log's, named in `failed`
            failed[log] = f"{type(e).__name__}: {e}"
    summary = _tree(parts, _merge)
    if summary is not None:
        summary._join_for(shares)
    return summary, failed


def _merge(a, b):
    if a is None or b is None:
        return b if a is None else a
    return a + b


def _merge_outcomes(a, b):
    """Two tasks' (summary, failed) as one: the summaries merged, the failures together."""
    return _merge(a[0], b[0]), {**a[1], **b[1]}


def _local_client(workers=None, processes=False):
    """dynid's default local cluster: `workers` single-threaded workers (None: one per core), as
    threads of this process unless `processes`; returns (client, cluster)."""
    try:
        import dask
        from distributed import Client, LocalCluster
    except ImportError as e:  # pragma: no cover - the installer provides it
        raise ImportError("summarize_many runs on Dask: install Debian's python3-distributed "
                          "(scripts/install-deps.sh does), or pass client=") from e
    # Workers as threads of this process: dynid releases the GIL while it computes, so they run
    # in parallel, and summaries pass between them without pickling (bench/dask_summarize.py: two
    # workers 1.83-1.95 times one on two cores, against 1.5 for worker processes, which Dask's
    # nannies also start with MALLOC_TRIM_THRESHOLD_=65536, under which dynid's allocations cost
    # 30 % more). A crash takes this process with it: pass a client of worker processes to
    # isolate them. A worker is sent a task when it has none left (worker-saturation 1.0, the
    # scheduler's default holding one more): a task of a few seconds queued behind another while
    # a worker idles waits for Dask's work stealing (~0.1 s, seen at the end of a run).
    with dask.config.set({"distributed.scheduler.worker-saturation": 1.0}):
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                               processes=processes, dashboard_address=None)
    return Client(cluster), cluster


@contextlib.contextmanager
def _cluster(client):
    """`client` as it is, or (None) a local cluster's, closed after."""
    if client is not None:
        yield client
        return
    own, cluster = _local_client()
    try:
        yield own
    finally:
        own.close()
        cluster.close()


def _submit(client, model, logs, rest_velocity, torque_filter, robot_spec, retries,
            logs_per_task):
    """The root of `logs`' tree (a task per `logs_per_task` logs, their (summary, failed) merged
    pairwise), every task submitted at once: a merge runs as soon as its two inputs are done,
    while later tasks still compute. The summaries stay on the workers until the root's (summary,
    failed) comes back, so the client holds one summary. None for no logs."""
    groups = [logs[i:i + logs_per_task] for i in range(0, len(logs), logs_per_task)]
    tasks = [client.submit(_summarize_group, model, group, rest_velocity, torque_filter,
                           robot_spec, len(groups), pure=False, retries=retries)
             for group in groups]
    return _tree(tasks, lambda a, b: client.submit(_merge_outcomes, a, b, pure=False,
                                                   retries=retries))


def summarize_many(model, logs, client=None, rest_velocity=None, torque_filter="auto",
                   robot_spec="", retries=2, logs_per_task=4):
    """The least-squares summary of many logs on a Dask cluster: a task per `logs_per_task`
    consecutive logs (dynid.summarize on a worker, one thread, merged pairwise there, its batches
    joined down to its share of the 256 a summary keeps), then the tasks' summaries merged
    pairwise as a tree on the workers. The tasks and the tree follow from the logs' order alone:
    the same bits however many workers ran the tasks, in whatever order, and after a worker died
    and its tasks ran again (`retries` times at most); where no batch needs joining, with
    `logs_per_task` a power of two, the same bits as the logs' own pairwise tree, (0 1) (2 3) ...,
    merged with + in one process. `client`: a distributed.Client (any cluster: local,
    Slurm through dask-jobqueue, ...); None starts a local cluster of one worker thread per core
    and closes it after. Returns SummarizeMany(summary, summarized, failed): a log that
    cannot be summarized is named with its error in `failed` and left out; the rest go on."""
    logs = [os.fspath(log) for log in logs]
    if logs_per_task < 1:
        raise ValueError("logs_per_task must be >= 1")
    with _cluster(client) as client:
        root = _submit(client, model, logs, rest_velocity, torque_filter, robot_spec, retries,
                       logs_per_task)
        summary, failed = root.result() if root is not None else (None, {})
        summarized = [log for log in logs if log not in failed]
        return SummarizeMany(summary, summarized, failed)


def fleet(model, robots, client=None, method="ols", covariance="hac", flag_level=0.01,
          rest_velocity=None, torque_filter="auto", robot_spec="", retries=2, logs_per_task=4):
    """dynid.fleet with every robot's logs summarized on a Dask cluster: `robots` is {name: a
    Summary, a log path or a list of log paths}; each robot's logs are summarized and merged on
    the workers as summarize_many does (every robot's tasks submitted at once), then the fleet
    is learnt here from the robots' summaries (dynid.fleet). `client`: a distributed.Client;
    None starts a local cluster of one worker thread per core and closes it after.
    Returns fleet.json as a dict, with "failed": {log: error} for the logs that could not be
    summarized (left out, their robot goes on with the rest; a robot none of whose logs could be
    is left out of the fleet and named in "robots_left_out")."""
    if logs_per_task < 1:
        raise ValueError("logs_per_task must be >= 1")
    with _cluster(client) as client:
        given, submitted = {}, {}
        for name, value in robots.items():
            if isinstance(value, dynid.Summary):
                given[name] = value
                continue
            logs = ([os.fspath(value)] if isinstance(value, (str, os.PathLike))
                    else [os.fspath(v) for v in value])
            submitted[name] = _submit(client, model, logs, rest_velocity, torque_filter,
                                      robot_spec, retries, logs_per_task)
        names = [name for name in submitted if submitted[name] is not None]
        outcomes = dict(zip(names, client.gather([submitted[name] for name in names])))
        summaries, left_out, failed = {}, [], {}
        for name in robots:
            if name in given:
                summaries[name] = given[name]
                continue
            summary, errors = outcomes.get(name, (None, {}))
            failed.update(errors)
            if summary is None:
                left_out.append(name)
            else:
                summaries[name] = summary
        out = dynid.fleet(model, summaries, method=method, covariance=covariance,
                          flag_level=flag_level, robot_spec=robot_spec)
        out["failed"] = failed
        out["robots_left_out"] = left_out
        return out


def _batch_run(spec):
    """A batch task: one run of the grid (its Study and method, measured), its record's text."""
    return dynid._batch_run(spec)


def batch(manifest, out, client=None, quick=False, retries=2):
    """dynid batch on a Dask cluster: every run of the manifest's grid not yet stored in `out` is
    a task (retried `retries` times when its worker dies); each run's record is stored in
    out/runs/<run>.json here as it comes back, so that a batch stopped resumes where it was;
    then results.csv and results.json are written, as `dynid batch` writes them. A run that
    raised is named in "failed" with its error (the rest go on). `client`: a distributed.Client;
    None starts a local cluster of one worker thread per core and closes it after.
    Returns results.json as a dict, with "failed": {run: error}."""
    from distributed import as_completed

    manifest, out = os.fspath(manifest), os.fspath(out)
    todo = dynid._batch_plan(manifest, out, quick)
    with _cluster(client) as client:
        names = {}
        for name, spec in todo:
            names[client.submit(_batch_run, spec, pure=False, retries=retries)] = name
        failed = {}
        for future in as_completed(list(names)):
            name = names[future]
            try:
                dynid._batch_store(out, name, future.result())
            except Exception as e:  # noqa: BLE001 - the run's, named in `failed`
                failed[name] = f"{type(e).__name__}: {e}"
        results = dynid._batch_finish(manifest, out, quick)
        results["failed"] = failed
        return results
