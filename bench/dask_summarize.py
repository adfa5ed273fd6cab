#!/usr/bin/env python3
"""dynid.summarize_many on a Dask local cluster of 1 and of 2 single-threaded workers: the
speed-up of summarizing many logs (issue 70: at least 1.8 on two cores), and the same result.

    PYTHONPATH=build/python python3 bench/dask_summarize.py --dynid build/bin/dynid

Simulates --logs Panda logs of --seconds each (fv, fc, fo; once, in a scratch folder), then times
summarize_many over them on each cluster (--repeats runs each, the median; each run on freshly
fresh workers, the cluster's start not timed: the time is the work and its scheduling).
"""
import argparse
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np

import dynid
from distributed import Client, LocalCluster


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--dynid", default="build/bin/dynid")
    parser.add_argument("--logs", type=int, default=32)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--per-task", type=int, default=4)
    args = parser.parse_args()
    scratch = tempfile.mkdtemp(prefix="dynid_dask_bench_")
    logs = []
    for seed in range(1, args.logs + 1):
        path = os.path.join(scratch, f"log{seed}.csv")
        subprocess.run([args.dynid, "simulate", "--robot", "panda", "--drives", "--controller",
                        "fourier", "--duration", str(args.seconds), "--noise-tau", "0.1",
                        "--seed", str(seed), "--out", path], check=True, capture_output=True)
        logs.append(path)
    model = dynid.load_model("panda", drives=True)
    medians, betas = {}, {}
    for workers in (1, 2):
        times = []
        for _ in range(args.repeats):
            # A fresh cluster each run (its start not timed): nothing of an earlier run kept (a
            # log's digest is remembered by the process that hashed it).
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            with Client(cluster) as client:
                client.run(lambda: __import__("dynid"))
                start = time.perf_counter()
                done = dynid.summarize_many(model, logs, client=client,
                                            logs_per_task=args.per_task)
                times.append(time.perf_counter() - start)
            cluster.close()
        medians[workers] = statistics.median(times)
        betas[workers] = dynid.identify(model, done.summary, method="ols").beta
        print(f"{workers} worker(s): {medians[workers]:.2f} s for {args.logs} logs of "
              f"{args.seconds:g} s ({args.logs / medians[workers]:.2f} logs/s)")
    print(f"speed-up: {medians[1] / medians[2]:.2f}; the same estimate: "
          f"{np.array_equal(betas[1], betas[2])}")


if __name__ == "__main__":
    main()
