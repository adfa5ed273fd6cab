"""The truth and the prior of examples/combined/run.sh, from a `dynid model export` JSON.

models.py ROBOT EXPORT.json TRUTH.json PRIOR.json
The Panda's truth gets joint friction (the built-in model has none); the prior scales each link's
ten inertial parameters by its own factor in [0.8, 1.2] (a realisable body stays realisable) and
the friction by [0.7, 1.3], with no offset. Fixed seed.
"""
import json
import random
import sys

robot, exported, truth_path, prior_path = sys.argv[1:5]
random.seed(7)
model = json.load(open(exported))
if robot == "panda":
    for i, body in enumerate(model["bodies"]):
        body["drive"]["Fv"] = [0.6, 0.6, 0.5, 0.5, 0.3, 0.2, 0.1][i]
        body["drive"]["Fc"] = [0.4, 0.4, 0.3, 0.3, 0.2, 0.15, 0.1][i]
        body["drive"]["Fo"] = [0.05, -0.1, 0.05, 0.1, -0.05, 0.02, 0.01][i]
json.dump(model, open(truth_path, "w"), indent=1)
for body in model["bodies"]:
    factor = 1.0 + 0.2 * (2 * random.random() - 1)
    for key in body["inertial"]:
        body["inertial"][key] *= factor
    for key in ("Fv", "Fc"):
        body["drive"][key] *= 1.0 + 0.3 * (2 * random.random() - 1)
    body["drive"]["Fo"] = 0.0
json.dump(model, open(prior_path, "w"), indent=1)
