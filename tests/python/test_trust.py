"""Trusting the model in use: predict's band, monitor and audit, equal to the CLI's."""
from pathlib import Path

import numpy as np
import pytest

import dynid
from conftest import read_json, run_cli


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Two noisy PUMA logs, a clean one and a pushed one with its ground truth."""
    d = tmp_path_factory.mktemp("trust")
    for name, args in [("train", ["--seed", 3, "--duration", 5]),
                       ("test", ["--seed", 4, "--phase", 0.5, "--duration", 5]),
                       ("clean", ["--seed", 5, "--duration", 8]),
                       ("pushed", ["--seed", 6, "--duration", 5, "--disturbance",
                                   "joint=2,torque=10,at=2,for=0.2"])]:
        run_cli("simulate", "--robot", "puma560", "--noise-tau", 0.1, "--noise-dq", 0.001, *args,
                "--out", d / f"{name}.csv")
    return d


def test_predict_band_covers_fresh_data(logs):
    model = dynid.load_model("puma560")
    est = dynid.identify(model, str(logs / "train.csv"))
    plain = dynid.predict(est.model, str(logs / "test.csv"))
    assert plain.band is None and plain.band_coverage is None
    banded = dynid.predict(est.model, str(logs / "test.csv"), band=est)
    assert banded.band.shape == banded.predicted.shape
    # 5001 samples with the training noise: 95 % within the binomial spread and the estimate's.
    assert np.all(banded.band_coverage > 0.92) and np.all(banded.band_coverage < 0.98)
    inside = np.abs(banded.measured - banded.predicted) <= banded.band
    assert np.allclose(inside.mean(axis=0), banded.band_coverage, atol=1e-12)


def test_monitor_and_audit_equal_the_cli(logs, tmp_path):
    result = dynid.monitor("puma560", str(logs / "pushed.csv"),
                           calibration=str(logs / "clean.csv"),
                           truth=str(logs / "pushed.truth.csv"))
    assert result["kind"] == "dynid.monitor"
    assert result["truth"]["detected"] == 1 and result["truth"]["false_alarms"] == 0
    run_cli("monitor", "--arm", "puma560", "--data", logs / "pushed.csv", "--calibration",
            logs / "clean.csv", "--out", tmp_path / "m")
    cli = read_json(tmp_path / "m" / "monitor.json")
    assert cli["events"] == result["events"]
    with pytest.raises(dynid.InputError):
        dynid.monitor("puma560", str(logs / "pushed.csv"))  # no threshold source
    audit = dynid.audit(data=[str(logs / "train.csv"), str(logs / "test.csv")], robot="puma560")
    assert audit["kind"] == "dynid.audit" and len(audit["sessions"]) == 2
    run_cli("audit", "--robot", "puma560", "--data", logs / "train.csv", logs / "test.csv",
            "--out", tmp_path / "a")
    assert read_json(tmp_path / "a" / "audit.json")["chi2"] == audit["chi2"]


def test_monitor_reads_recordings_by_joint_name(logs):
    # The MCAP project's writer's fixture holds joints joint2, joint1 and a gripper: the PUMA's
    # joint3..joint6 are missing, and the error names them (the recording was read).
    bag = Path(__file__).resolve().parents[1] / "data/bags/fixtures/ros2/joint_states_zstd.mcap"
    with pytest.raises(dynid.InputError, match="lack the robot's joints joint3"):
        dynid.monitor("puma560", bag, calibration=str(logs / "clean.csv"), topic="/joint_states")
    with pytest.raises(ValueError, match="stamp"):
        dynid.monitor("puma560", bag, calibration=str(logs / "clean.csv"), stamp="sent")
    # How a recording is read, given for dataset CSVs: refused, not ignored.
    for option in (dict(topic="/joint_states"), dict(joint_prefix="left_"),
                   dict(joint_names=[f"A{j}" for j in range(1, 7)]), dict(stamp="receive")):
        with pytest.raises(dynid.InputError, match="apply to recordings"):
            dynid.monitor("puma560", str(logs / "pushed.csv"),
                          calibration=str(logs / "clean.csv"), **option)


def test_monitor_torque_constants_apply_to_recordings_not_datasets(logs):
    # Currents are a recording's (or stdin's) raw efforts; a dataset CSV's tau is torque already.
    with pytest.raises(dynid.InputError, match="hold torques already"):
        dynid.monitor("puma560", str(logs / "pushed.csv"), calibration=str(logs / "clean.csv"),
                      torque_constants=[1.0] * 6)


def test_friction_at_rest_is_static_and_predict_measures_its_rest_velocity(logs):
    model = dynid.load_model("puma560")
    est = dynid.identify(model, str(logs / "train.csv"))
    # The training log's velocity noise (0.001 rad/s, white) sets each joint's rest velocity.
    assert est.rest_velocity.shape == (6,)
    assert np.all(est.rest_velocity > 0.002) and np.all(est.rest_velocity < 0.005)
    got = dynid.predict(est.model, str(logs / "test.csv"))
    rest = got.at_rest
    assert set(rest) >= {"rest_velocity", "samples", "band_low", "band_high", "within_band"}
    assert np.all(rest["band_low"] <= 0) and np.all(rest["band_high"] >= 0)
    given = dynid.predict(est.model, str(logs / "test.csv"), rest_velocity=[0.0])
    assert np.all(given.at_rest["rest_velocity"] == 0.0)
    with pytest.raises(dynid.InputError, match="rest_velocity"):
        dynid.predict(est.model, str(logs / "test.csv"), rest_velocity=[1.0, 2.0])


def test_covariance_policy_is_hac_and_white_on_request(logs):
    model = dynid.load_model("puma560")
    data = dynid.read_dataset(str(logs / "train.csv"))
    est = dynid.identify(model, str(logs / "train.csv"))
    policy = est.covariance_policy
    assert policy["name"] == "hac" and policy["batch"] >= 1
    assert len(policy["autocorrelation"]) >= 1
    # The file and the arrays give the same covariance (one pass over each).
    arrays = dynid.identify(model, data)
    assert np.allclose(arrays.covariance, est.covariance, rtol=1e-9, atol=0)
    white = dynid.identify(model, str(logs / "train.csv"), covariance="white")
    assert white.covariance_policy["name"] == "white"
    assert np.array_equal(white.beta, est.beta)
    with pytest.raises(ValueError, match="covariance"):
        dynid.identify(model, str(logs / "train.csv"), covariance="newey-west")


def test_pauses_make_stops_and_the_monitor_learns_thresholds_at_rest(tmp_path):
    model = dynid.load_model("puma560")
    stops = dynid.simulate(model, duration=12, noise_tau=0.1, noise_dq=1e-3, seed=3,
                           pauses=(2.0, 2.5, 0.4))
    run_cli("simulate", "--robot", "puma560", "--duration", 12, "--noise-tau", 0.1, "--noise-dq",
            0.001, "--seed", 3, "--pauses", "move=2,hold=2.5,ramp=0.4", "--out",
            tmp_path / "stops.csv")
    assert np.array_equal(dynid.read_dataset(str(tmp_path / "stops.csv")).dq, stops.dq)
    # The holds (from 2 s to 4.5 s) are still but for the velocity noise.
    hold = (stops.time > 2.6) & (stops.time < 4.4)
    assert np.abs(stops.dq[hold]).max() < 0.01
    with pytest.raises(ValueError):
        dynid.simulate(model, pauses=(1.0, 1.0, 0.6))  # move must exceed two ramps
    result = dynid.monitor("puma560", str(tmp_path / "stops.csv"),
                           calibration=str(tmp_path / "stops.csv"))
    thresholds = result["thresholds"]
    assert thresholds["schema_version"] == 5
    assert len(thresholds["moving_regimes"]["speed_scale"]) == 6
    assert len(thresholds["thresholds_at_rest"]) == 6 and thresholds["rest_seconds"] > 2
    assert result["events"] == []  # a clean run raises no alarm
