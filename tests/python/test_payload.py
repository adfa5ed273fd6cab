"""payload: a payload at the PUMA's flange from arrays and files, equal to the CLI's."""
import json
import pathlib

import numpy as np
import pytest

import dynid
from conftest import read_json, run_cli


def _motion(n, seconds=6.0, rate=200.0):
    t = np.arange(int(seconds * rate) + 1) / rate
    q, dq, ddq = (np.zeros((t.size, n)) for _ in range(3))
    for j in range(n):
        w = 2 * np.pi * (0.11 + 0.037 * j)
        for h in (1, 2, 3):
            a, x = 0.5 / h, h * w * t + 0.7 * j + h
            q[:, j] += a * np.sin(x)
            dq[:, j] += a * h * w * np.cos(x)
            ddq[:, j] -= a * (h * w) ** 2 * np.sin(x)
    return t, q, dq, ddq


@pytest.fixture(scope="module")
def loaded():
    """The PUMA with 1.5 kg at (0.02, -0.01, 0.06) m of link 6 (a sphere of radius 5 cm)."""
    arm = dynid.load_model("puma560")
    m, c = 1.5, np.array([0.02, -0.01, 0.06])
    inertia = 0.4 * m * 0.05**2 * np.eye(3) + m * (c @ c * np.eye(3) - np.outer(c, c))
    body = [m, *(m * c), inertia[0, 0], inertia[0, 1], inertia[0, 2], inertia[1, 1],
            inertia[1, 2], inertia[2, 2]]
    heavy = arm.copy()
    for name, value in zip(["m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"], body):
        heavy.set_parameter(name + "6", heavy.parameter(name + "6") + value)
    t, q, dq, ddq = _motion(6)
    return arm, dynid.Dataset(t, q, dq, ddq, dynid.rnea(heavy, q, dq, ddq)), \
        dynid.Dataset(t, q, dq, ddq, dynid.rnea(arm, q, dq, ddq)), np.array(body)


def test_payload_from_arrays_is_the_body(loaded):
    arm, with_load, without, body = loaded
    result = dynid.payload(arm, with_load)
    assert result.mode == "single" and result.link == "link6"
    # Exact torques: the body to round-off of the solve (1e-9 relative).
    assert np.allclose(result.standard, body, rtol=0, atol=1e-9 * np.abs(body).max())
    assert result.mass == pytest.approx(1.5, rel=1e-10)
    assert np.allclose(result.com, [0.02, -0.01, 0.06], atol=1e-10)
    assert all(q["determined"] for q in result.quantities if q["group"] != "principal axes")
    # A sphere: equal principal moments leave its axes free, and the result says so: an axis that
    # is not determined has no value, only its estimate and resolution.
    axes = [q for q in result.quantities if q["group"] == "principal axes"]
    assert not any(q["determined"] for q in axes)
    assert all(q["value"] is None and q["estimate"] is not None for q in axes)
    assert all(q["value"] == q["estimate"] for q in result.quantities if q["determined"])
    assert any("principal axes" in w for w in result.warnings)
    pair = dynid.payload(arm, with_load, unloaded=without)
    assert pair.mode == "difference"
    assert pair.mass == pytest.approx(1.5, rel=1e-10)
    assert "set_target_payload(1.5, " in result.vendor("ur")
    with pytest.raises(dynid.InputError):
        result.vendor("fanuc")


def test_payload_equals_the_cli_and_takes_paths(tmp_path, loaded):
    arm, with_load, _, _ = loaded
    csv = tmp_path / "loaded.csv"
    # The Dataset written as the CLI reads it.
    rows = np.column_stack([with_load.time, with_load.q, with_load.dq, with_load.ddq,
                            with_load.tau])
    header = ",".join(["t"] + [f"{k}{j}" for k in ("q", "dq", "ddq", "tau") for j in range(1, 7)])
    np.savetxt(csv, rows, delimiter=",", header=header, comments="", fmt="%.17g")
    run_cli("payload", "--arm", "puma560", "--data", csv, "--out", tmp_path / "out")
    result = dynid.payload(arm, pathlib.Path(csv))
    cli = read_json(tmp_path / "out" / "payload.json")
    mine = json.loads(result.to_json())
    for key in ("mass", "com", "standard", "quantities", "mode", "link"):
        assert mine[key] == cli[key], key
    # The body written by the CLI as a prior, by path.
    run_cli("payload", "--arm", "puma560", "--data", csv, "--format", "json", "--out",
            tmp_path / "out2")
    again = dynid.payload(arm, str(csv), prior=tmp_path / "out2" / "payload.body.json")
    assert again.mass == pytest.approx(result.mass, rel=1e-9)


def test_payload_refusals(loaded):
    arm, with_load, _, _ = loaded
    with pytest.raises(dynid.InputError, match="no_such"):
        dynid.payload(arm, with_load, link="no_such")
    with pytest.raises(dynid.InputError, match="payload_mass|known_mass|unloaded"):
        dynid.payload(arm, with_load, payload_mass=1.0)
    with pytest.raises(dynid.InputError):
        dynid.payload(arm, with_load, unloaded=with_load, payload_mass=-1.0)
    with pytest.raises(ValueError):
        dynid.payload(arm, with_load, tool_xyz=[0, 0])


def test_attach_is_the_hand_made_loaded_arm(loaded):
    arm, _, _, body = loaded
    # The fixture's body (a 5 cm sphere of 1.5 kg) from its mass, centre and inertia about it.
    m, c = 1.5, np.array([0.02, -0.01, 0.06])
    inertia_c = 0.4 * m * 0.05**2
    heavy = dynid.attach(arm, mass=m, com=c, inertia=[inertia_c, 0, 0, inertia_c, 0, inertia_c])
    names = ["m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"]
    for name, value in zip(names, body):
        assert heavy.parameter(name + "6") == pytest.approx(arm.parameter(name + "6") + value,
                                                            rel=1e-12, abs=1e-15)
    same = dynid.attach(arm, body=body)
    assert np.allclose(same.parameters, heavy.parameters, rtol=1e-12, atol=1e-15)
    with pytest.raises(ValueError, match="inertia"):
        dynid.attach(arm, mass=1.0, inertia=[0.01, 0, 0, 0.001, 0, 0.001])
    with pytest.raises(ValueError, match="one of them"):
        dynid.attach(arm, mass=1.0, body=body)
