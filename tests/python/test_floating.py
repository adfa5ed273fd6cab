"""Floating-base robots (docs/FLOATING.md): what each sensor set determines, equal to the CLI's."""
import os
from pathlib import Path

import pytest

import dynid
from conftest import less_provenance, read_json, run_cli

ANYMAL = Path(os.environ["DYNID_SOURCE_DIR"]) / "examples/floating/anymal_c/anymal.urdf"
FEET = ["LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT"]


def test_floating_identifiability_equals_the_clis(tmp_path):
    doc = dynid.floating_identifiability(ANYMAL, contacts=FEET, drive_terms="fv,fc")
    assert doc["kind"] == "dynid.floating_identifiability"
    counts = {s["sensors"]: s["num_base"] for s in doc["sets"]}
    # The base rows see every inertial base parameter; the torques add the 24 friction terms.
    assert counts["torques_wrenches"] - counts["wrenches"] == 24
    assert counts["torques_contacts"] == counts["torques_wrenches"]
    run_cli("identifiability", "--robot", ANYMAL, "--floating-base", "--contacts", ",".join(FEET),
            "--drive-terms", "fv,fc", "--out", tmp_path)
    cli = read_json(tmp_path / "floating_identifiability.json")
    assert less_provenance(doc) == less_provenance(cli)


def test_floating_identifiability_names_what_is_wrong():
    with pytest.raises(ValueError, match="contacts"):
        dynid.floating_identifiability(ANYMAL, contacts=["LF_PAW"])
    with pytest.raises(ValueError, match="sensors"):
        dynid.floating_identifiability(ANYMAL, contacts=FEET, sensors=["imu"])
    with pytest.raises(ValueError, match="motion"):
        dynid.floating_identifiability(ANYMAL, motion="free", sensors=["wrenches"])


def test_simulate_and_identify_a_floating_base_equal_the_clis(tmp_path):
    train = dynid.simulate_floating(ANYMAL, tmp_path / "train.csv", contacts=FEET, samples=200,
                                    noise_tau=0.5, noise_force=2.0, seed=3)
    dynid.simulate_floating(ANYMAL, tmp_path / "test.csv", contacts=FEET, samples=100, seed=4)
    doc = dynid.floating_identify(ANYMAL, train, validate=tmp_path / "test.csv")
    assert doc["kind"] == "dynid.floating_identification"
    assert doc["method"] == "wls"
    assert [s["sensors"] for s in doc["sets"]] == ["wrenches", "torques_wrenches",
                                                  "torques_contacts"]
    noise = doc["sets"][1]["noise_sd"]
    # 2400 torque and force residuals: each sd within a few percent; 10 % is the bound.
    assert noise["torque"] == pytest.approx(0.5, rel=0.1)
    assert noise["force"] == pytest.approx(2.0, rel=0.1)
    run_cli("identify", "--robot", ANYMAL, "--floating-base", "--data", train, "--validate",
            tmp_path / "test.csv", "--out", tmp_path / "cli")
    cli = read_json(tmp_path / "cli" / "floating_identification.json")
    assert less_provenance(doc) == less_provenance(cli)


def test_floating_identify_names_what_is_wrong(tmp_path):
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", contacts=FEET, samples=20)
    with pytest.raises(ValueError, match="method"):
        dynid.floating_identify(ANYMAL, data, method="pc")
    with pytest.raises(ValueError, match="contacts"):
        dynid.floating_identify(ANYMAL, data, contacts=["LF_FOOT"])


def test_floating_identify_a_payload(tmp_path):
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", contacts=FEET, samples=60)
    doc = dynid.floating_identify(ANYMAL, data, method="ols", payload_link="base")
    # The robot read is the one simulated: no payload, to round-off.
    for s in doc["payload"]["sets"]:
        assert abs(s["mass"]) < 1e-9
