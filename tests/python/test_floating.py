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
