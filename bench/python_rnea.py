#!/usr/bin/env python3
"""The Python module's speed: batched rnea over 1e6 states against the C++ loop that does the
same (bench_core's BM_RneaBatch), and the per-call overhead of the single-state functions.

    PYTHONPATH=build/python python3 bench/python_rnea.py --bench-core build/bench/bench_core

Prints medians of --repeats runs. Single thread unless --threads says otherwise.
"""
import argparse
import json
import statistics
import subprocess
import time

import numpy as np

import dynid


def median_seconds(call, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bench-core", help="bench_core, to run BM_RneaBatch beside")
    parser.add_argument("--states", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()

    model = dynid.load_model("puma560")
    rng = np.random.default_rng(42)
    q, dq, ddq = (rng.uniform(-2, 2, (args.states, 6)) for _ in range(3))
    batch = median_seconds(lambda: dynid.rnea(model, q, dq, ddq, threads=args.threads),
                           args.repeats)
    print(f"python batched rnea, {args.states} states, {args.threads} thread(s): "
          f"{batch * 1e3:.1f} ms ({batch / args.states * 1e9:.0f} ns/state)")
    if args.bench_core:
        done = subprocess.run([args.bench_core, "--benchmark_filter=BM_RneaBatch",
                               f"--benchmark_repetitions={args.repeats}",
                               "--benchmark_report_aggregates_only", "--benchmark_format=json"],
                              capture_output=True, text=True, check=True)
        runs = json.loads(done.stdout)["benchmarks"]
        median = next(r for r in runs if r["aggregate_name"] == "median")
        cpp = median["real_time"] / 1e3  # ms -> s
        print(f"C++ loop (BM_RneaBatch, 1e6 states): {cpp * 1e3:.1f} ms "
              f"({cpp / 1e6 * 1e9:.0f} ns/state); python / C++ per state: "
              f"{(batch / args.states) / (cpp / 1e6):.2f}")

    one = (np.zeros(6), np.zeros(6), np.zeros(6))
    calls = 20000
    for name, call in [("rnea", lambda: dynid.rnea(model, *one)),
                       ("aba", lambda: dynid.aba(model, *one)),
                       ("crba", lambda: dynid.crba(model, one[0])),
                       ("regressor", lambda: dynid.regressor(model, *one))]:
        def loop():
            for _ in range(calls):
                call()
        t = median_seconds(loop, args.repeats)
        print(f"single-state {name}: {t / calls * 1e6:.2f} us per call")


if __name__ == "__main__":
    main()
