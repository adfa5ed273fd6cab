"""dynid.study: the CLI's study from Python, with the combined estimator's front and the estimate
chosen from it; the same table as `dynid study`."""
import json
import math

import pytest

import dynid
from conftest import run_cli


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """A noisy PUMA (fv, fc) training log and another motion held out."""
    d = tmp_path_factory.mktemp("study")
    train, held = d / "train.csv", d / "held.csv"
    run_cli("simulate", "--robot", "puma560", "--drives", "--duration", 2, "--noise-tau", 0.3,
            "--seed", 4, "--out", train)
    run_cli("simulate", "--robot", "puma560", "--drives", "--duration", 1.5, "--noise-tau", 0.3,
            "--seed", 5, "--out", held)
    return d, train, held


def test_the_front_and_the_choice_are_the_clis(logs):
    d, train, held = logs
    model = dynid.load_model("puma560", drive_terms="fv,fc")
    doc = dynid.study(model, train, held, methods="pc,combined", front_weights=[0.3, 3.0],
                      refine_iterations=3, segments=8, threads=1)
    assert doc["kind"] == "dynid.study" and doc["schema_version"] == 5
    points = doc["front"]["points"]
    assert [p["weight"] for p in points] == [0.3, 3.0]
    assert all(p["physically_consistent"] for p in points)
    choice = doc["choice"]
    assert choice["key"] is not None
    chosen = (points[[p["weight"] for p in points].index(choice["front_weight"])]
              if choice["key"] == "front" else doc["methods"][choice["key"]])
    assert chosen["torque_relative_error_test"] <= choice["torque_bound"]
    # The CLI on the same data and settings: the same numbers (iterations bound every stage).
    run_cli("study", "--robot", "puma560", "--drive-terms", "fv,fc", "--data", train,
            "--validate", held, "--methods", "pc,combined", "--front-weights", "0.3,3",
            "--refine-iterations", 3, "--segments", 8, "--threads", 1, "--out", d / "cli")
    cli = json.loads((d / "cli" / "study.json").read_text())
    for mine, theirs in zip(points, cli["front"]["points"]):
        assert mine["gc_error_test"] == theirs["gc_error_test"]
        assert mine["torque_relative_error_test"] == theirs["torque_relative_error_test"]
    assert cli["choice"] == choice
    # front=True: the default sweep, 0.01 to 100, two points a decade.
    default = dynid.study(model, train, held, methods="pc", front=True, refine_iterations=1,
                          segments=4, threads=1)
    assert [p["weight"] for p in default["front"]["points"]] == [
        0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0]


def test_bad_weights_are_refused_by_their_name(logs):
    _, train, held = logs
    model = dynid.load_model("puma560", drive_terms="fv,fc")
    with pytest.raises(dynid.InputError, match="front_weights"):
        dynid.study(model, train, held, methods="pc", front_weights=[1.0, 0.5])
    with pytest.raises(dynid.InputError, match="front_tolerance"):
        dynid.study(model, train, held, methods="pc", front_tolerance=-1.0)
    assert math.isfinite(dynid.study(model, train, held, methods="pc", segments=4,
                                     threads=1)["choice"]["torque_bound"])
