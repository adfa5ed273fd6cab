#!/usr/bin/env python3
"""dynid.summarize_many on a Dask local cluster of 1 and of 2 single-threaded workers: the
speed-up of summarizing many logs (issue 70: at least 1.8 on two cores), and the same result.

    PYTHONPATH=build/python python3 bench/dask_summarize.py --dynid build/bin/dynid [--processes]

Simulates --logs Panda logs of --seconds each (fv, fc, fo; once, in a scratch folder), then times
summarize_many over them on dynid's default local cluster of 1 and of 2 workers (--repeats
runs each, the median). Each run is a fresh Python process with a fresh cluster (its start not
timed: the time is the work and its scheduling), so that nothing of an earlier run is kept (a
log's digest is remembered by the process that hashed it). The workers are threads of that process, as dynid's default local
cluster has them (dynid releases the GIL); --processes: worker processes under their nannies.
Each count is timed twice: with the workers cold, and warm (each has summarized another log
first, untimed: a fresh thread's first summary costs ~50 ms more, its memory touched for the
first time, which a long-lived worker has paid).
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import dynid


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--dynid", default="build/bin/dynid")
    parser.add_argument("--logs", type=int, default=32)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--per-task", type=int, default=4)
    parser.add_argument("--processes", action="store_true")
    parser.add_argument("--once", type=int, default=0)
    parser.add_argument("--plain", type=int, default=0)
    parser.add_argument("--warm")
    parser.add_argument("--out")
    parser.add_argument("files", nargs="*")
    args = parser.parse_args()
    if args.once:
        return once(args.once, args.files, args.out, args.per_task, args.processes, args.warm)
    if args.plain:
        return plain_threads(args.plain, args.files, args.warm)
    scratch = tempfile.mkdtemp(prefix="dynid_dask_bench_")
    logs = []
    for seed in range(args.logs + 1):  # seed 0: the warm-up's log, not timed
        path = os.path.join(scratch, f"log{seed}.csv")
        subprocess.run([args.dynid, "simulate", "--robot", "panda", "--drives", "--controller",
                        "fourier", "--duration", str(args.seconds), "--noise-tau", "0.1",
                        "--seed", str(seed + 1000 * (seed == 0)), "--out", path], check=True,
                       capture_output=True)
        logs.append(path)
    warm_log, logs = logs[0], logs[1:]
    for warm in (False, True):
        print("workers warm (each summarized another log first, as a long-lived cluster's have)"
              if warm else "workers cold (a fresh process and cluster)")
        medians, betas = {}, {}
        for workers in (1, 2):
            times = []
            for _ in range(args.repeats):
                out = os.path.join(scratch, f"beta{workers}.npy")
                done = subprocess.run(
                    [sys.executable, __file__, "--once", str(workers), "--out", out,
                     "--per-task", str(args.per_task)]
                    + (["--processes"] if args.processes else [])
                    + (["--warm", warm_log] if warm else []) + logs,
                    check=True, capture_output=True, text=True)
                times.append(float(done.stdout.split()[-1]))
            medians[workers] = statistics.median(times)
            betas[workers] = np.load(out)
            print(f"  {workers} worker(s): {medians[workers]:.2f} s for {args.logs} logs of "
                  f"{args.seconds:g} s ({args.logs / medians[workers]:.2f} logs/s; runs "
                  f"{min(times):.2f}-{max(times):.2f})")
        print(f"  speed-up: {medians[1] / medians[2]:.2f}; the same estimate: "
              f"{np.array_equal(betas[1], betas[2])}")
        # The ceiling: the same logs summarized by one and by two plain Python threads (half the
        # logs each, merged in order), no Dask; each a fresh process too.
        plain = {}
        for threads in (1, 2):
            times = [float(subprocess.run(
                [sys.executable, __file__, "--plain", str(threads)]
                + (["--warm", warm_log] if warm else []) + logs,
                check=True, capture_output=True, text=True).stdout.split()[-1])
                for _ in range(args.repeats)]
            plain[threads] = statistics.median(times)
        print(f"  without Dask, 1 and 2 threads: {plain[1]:.2f} s, {plain[2]:.2f} s "
              f"(speed-up {plain[1] / plain[2]:.2f})")


def plain_threads(threads, logs, warm_log):
    """Summarizes the logs on `threads` Python threads (every threads-th log each); prints the
    seconds (from when every thread has summarized `warm_log`, when given)."""
    import threading
    model = dynid.load_model("panda", drives=True)
    parts = [None] * threads
    ready = threading.Barrier(threads + 1)
    go = threading.Event()

    def run(i):
        if warm_log:
            dynid.summarize(model, warm_log, threads=1)
        ready.wait()
        go.wait()
        for log in logs[i::threads]:
            one = dynid.summarize(model, log, threads=1)
            parts[i] = one if parts[i] is None else parts[i] + one

    workers = [threading.Thread(target=run, args=(i,)) for i in range(threads)]
    for w in workers:
        w.start()
    ready.wait()
    start = time.perf_counter()
    go.set()
    for w in workers:
        w.join()
    print(time.perf_counter() - start)


def once(workers, logs, out, per_task, processes, warm_log):
    """One timed run in this fresh process on dynid's default local cluster of `workers` workers:
    prints the seconds, saves the OLS estimate. With `warm_log`, each worker summarizes it first
    (untimed): its thread's memory is then in use, as a long-lived worker's is."""
    from dynid_distributed import _local_client

    model = dynid.load_model("panda", drives=True)
    client, cluster = _local_client(workers, processes)
    with client:
        client.run(lambda: __import__("dynid"))
        if warm_log:
            client.gather([client.submit(lambda m, log: dynid.summarize(m, log, threads=1), model,
                                         warm_log, workers=[address], pure=False)
                           for address in client.scheduler_info()["workers"]])
        start = time.perf_counter()
        done = dynid.summarize_many(model, logs, client=client, logs_per_task=per_task)
        seconds = time.perf_counter() - start
    cluster.close()
    np.save(out, dynid.identify(model, done.summary, method="ols").beta)
    print(seconds)


if __name__ == "__main__":
    main()
