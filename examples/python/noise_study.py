#!/usr/bin/env python3
"""How torque noise degrades least-squares estimates of the PUMA 560's base parameters.

For each noise level, several seeded simulations of the rigid PUMA 560 (dynid.simulate, the
default sinusoids) are identified by ordinary and weighted least squares (dynid.identify), and
each estimate's base parameters are compared with the true ones: the RMS over base parameters of
|beta_j - true_j| / s_j, with s_j = |true_j| (the mean true magnitude for a true value of 0), as
dynid's reports define the base-parameter error.

    PYTHONPATH=build/python python3 examples/python/noise_study.py --out noise_study
writes noise_study/noise_study.csv and, when matplotlib is installed, noise_study/noise_study.png.
--quick runs a smaller study (the test suite's).
"""
import argparse

import numpy as np

import dynid
from study_output import base_error, pyplot, save_figure, write_table


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="noise_study", help="output directory")
    parser.add_argument("--quick", action="store_true", help="fewer levels, seeds and seconds")
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    args = parser.parse_args()

    levels = [0.01, 0.1, 1.0] if args.quick else [0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0]
    seeds = range(1, 3) if args.quick else range(1, 9)
    duration = 2.0 if args.quick else 10.0
    robot = dynid.load_model("puma560")
    base = dynid.base_parameters(robot)
    truth = base.project(robot.parameters)

    rows = []
    for noise in levels:
        for seed in seeds:
            data = dynid.simulate(robot, duration=duration, noise_tau=noise, seed=seed)
            for method in ("ols", "wls"):
                estimate = dynid.identify(robot, data, method=method, threads=args.threads)
                rows.append({"noise_tau": noise, "seed": seed, "method": method,
                             "base_error": base_error(estimate.beta, truth),
                             "relative_error_percent": estimate.relative_error_percent,
                             "condition_number": estimate.condition_number})
        print(f"noise {noise:g} N m: done", flush=True)

    write_table(args.out, "noise_study.csv", rows)

    plt = pyplot()
    if plt is None:
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for method in ("ols", "wls"):
        means = [np.mean([r["base_error"] for r in rows
                          if r["noise_tau"] == level and r["method"] == method])
                 for level in levels]
        ax.loglog(levels, means, "o-", label=method)
    ax.set_xlabel("torque noise [N m]")
    ax.set_ylabel("RMS relative base-parameter error")
    ax.set_title("PUMA 560, least squares")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    save_figure(fig, args.out, "noise_study.png")


if __name__ == "__main__":
    main()
