"""Base-parameter errors, torque errors and GC errors of pc, combined and the front's chosen
estimate (examples/combined/run.sh).

compare.py OUT_DIR
Base-parameter error: RMS over the base parameters of (estimate - truth) / max(|truth|, 1e-3),
the truth's base parameters being OLS on the same motion without noise (exact to round-off).
"""
import json
import math
import sys

out = sys.argv[1]
truth = [p["estimate"] for p in json.load(open(out + "/truth_ols/estimate.json"))["base_parameters"]]
for method in ("pc", "combined", "front"):
    d = json.load(open(f"{out}/{method}/estimate.json"))
    est = [p["estimate"] for p in d["base_parameters"]]
    rel = math.sqrt(sum(((e - t) / max(abs(t), 1e-3)) ** 2 for e, t in zip(est, truth)) / len(truth))
    line = (f"{method:9s} base-parameter error {rel:.4g}; torque error train "
            f"{100 * d['relative_error']:.4f} %, held out {100 * d['validation']['relative_error']:.4f} %")
    if "combined" in d:
        c = d["combined"]
        line += (f"; GC train {c['gc_error_train']['pc']:.4g} -> {c['gc_error_train']['combined']:.4g}, "
                 f"held out {c['gc_error_test']['pc']:.4g} -> {c['gc_error_test']['combined']:.4g}, "
                 f"noise floor {c['gc_noise_floor']:.4g}")
    if "front" in d:
        f = d["front"]
        consistent = sum(p["physically_consistent"] for p in f["points"])
        line += (f"; front: {consistent} of {len(f['points'])} points physically consistent, "
                 f"chosen w = {f['chosen_weight']:g}")
    print(line)
