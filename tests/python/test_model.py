"""Models and datasets: load_model, Model, Dataset, read_dataset, write_dataset."""
import copy
import json
import math

import numpy as np
import pytest

import dynid
from conftest import read_json, run_cli


def test_builtin_robots_and_their_parameter_names():
    puma = dynid.load_model("puma560")
    assert puma.num_joints == 6 and puma.num_parameters == 60
    assert puma.parameter_names[:11] == ["m1", "mx1", "my1", "mz1", "Ixx1", "Ixy1", "Ixz1",
                                         "Iyy1", "Iyz1", "Izz1", "m2"]
    assert puma.paper_parameter_names[:7] == ["m1", "cx1", "cy1", "cz1", "Ixx1", "Iyy1", "Izz1"]
    assert puma.drive_terms == []
    drives = dynid.load_model("puma560", drives=True)
    assert drives.drive_terms == ["ia", "fv", "fc", "fa"]
    assert drives.parameter_names[10:14] == ["Ia1", "Fv1", "Fc1", "Fa1"]
    panda = dynid.load_model("panda", drive_terms="fv,fc,fo")
    assert panda.num_joints == 7 and panda.num_parameters == 7 * 13
    assert len(panda.link_names) == 7 and len(panda.joint_names) == 7


def test_parameters_match_the_cli_and_round_trip_through_json(tmp_path):
    model = dynid.load_model("puma560", drives=True)
    run_cli("model", "export", "--robot", "puma560", "--drives", "--format", "json", "--out",
            tmp_path / "cli.json")
    assert (tmp_path / "cli.json").read_text() == model.to_json()
    model.export(tmp_path / "py.json", "json")
    again = dynid.load_model(str(tmp_path / "py.json"))
    # The JSON holds shortest round-trip numbers: the same doubles come back.
    assert np.array_equal(again.parameters, model.parameters)
    assert again.parameter_names == model.parameter_names
    assert model.show() == run_cli("model", "show", "--robot", "puma560", "--drives").stdout
    # What the format cannot carry is a UserWarning, as the CLI's note (Ia has no URDF element).
    with pytest.warns(UserWarning, match=r"URDF has no element for rotor inertia \(Ia\)"):
        model.to_urdf()
    for fmt, text in (("urdf", model.to_urdf()), ("mjcf", model.to_mjcf())):
        run_cli("model", "export", "--robot", "puma560", "--drives", "--format", fmt, "--out",
                tmp_path / f"cli.{fmt}")
        assert (tmp_path / f"cli.{fmt}").read_text() == text


def test_parameter_access_by_name_and_vector():
    model = dynid.load_model("puma560")
    theta = model.parameters
    assert model.parameter("m3") == theta[20]
    assert model.parameters_dict()["Izz2"] == theta[19]
    model.set_parameter("m3", 5.5)
    assert model.parameter("m3") == 5.5
    theta[0] = 1.25
    model.parameters = theta
    assert model.parameter("m1") == 1.25
    other = model.copy()
    other.set_parameter("m1", 2.0)
    assert model.parameter("m1") == 1.25  # copies are independent
    deep = copy.deepcopy(model)
    assert np.array_equal(deep.parameters, model.parameters)


@pytest.mark.parametrize("bad", [np.zeros(59), np.zeros((60, 1)), "x", None])
def test_parameters_of_the_wrong_shape_or_type_raise(bad):
    model = dynid.load_model("puma560")
    with pytest.raises((ValueError, TypeError)):
        model.parameters = bad


def test_non_finite_or_unknown_parameters_raise_value_errors():
    model = dynid.load_model("puma560")
    theta = model.parameters
    theta[3] = math.nan
    with pytest.raises(ValueError, match="mz1"):
        model.parameters = theta
    with pytest.raises(ValueError, match="no parameter 'Ia1'"):
        model.parameter("Ia1")
    with pytest.raises(ValueError, match="m2"):
        model.set_parameter("m2", math.inf)
    with pytest.raises(ValueError):
        model.gravity = [0, 0, math.nan]


def test_check_reports_what_the_cli_reports(tmp_path):
    assert len(dynid.load_model("puma560").check()) == 2  # Corke's links 1 and 3 (docs/MODEL.md)
    model = dynid.load_model("puma560-consistent")
    assert model.check() == []
    model.set_parameter("Izz2", 100.0)  # far above Ixx2 + Iyy2
    violations = model.check()
    assert violations and violations[0]["link"] == 1 and "triangle" in violations[0]["condition"]
    model.export(tmp_path / "bad.json", "json")
    done = run_cli("model", "check", "--robot", tmp_path / "bad.json", "--json", check=False)
    assert done.returncode == 1
    report = json.loads(done.stdout)
    assert len(report["violations"]) == len(violations)


def test_gravity_and_limits():
    model = dynid.load_model("panda")
    assert np.array_equal(model.gravity, [0, 0, -9.81])
    model.gravity = [0.0, 0.0, -1.62]
    assert model.gravity[2] == -1.62
    assert model.lower_limits.shape == (7,) and np.all(model.lower_limits < model.upper_limits)
    assert np.all(model.effort_limits > 0)


def test_unknown_robot_and_bad_drive_terms_raise_value_errors():
    with pytest.raises(ValueError):
        dynid.load_model("not-a-robot")
    with pytest.raises(ValueError, match="xx"):
        dynid.load_model("puma560", drive_terms="fv,xx")


def test_paths_and_drive_term_lists_are_taken_as_the_cli_takes_strings(tmp_path):
    """load_model takes a pathlib.Path and drive_terms as a list or tuple, as well as strings."""
    path = tmp_path / "puma.json"
    run_cli("model", "export", "--robot", "puma560", "--format", "json", "--out", str(path))
    from_path = dynid.load_model(path, drive_terms=["fv", "fc"])
    from_text = dynid.load_model(str(path), drive_terms="fv,fc")
    assert from_path.parameter_names == from_text.parameter_names
    assert "Fv3" in from_path.parameter_names and "Ia3" not in from_path.parameter_names
    assert dynid.load_model("puma560", drive_terms=("ia",)).parameter_names[-1] == "Ia6"
    assert dynid.load_model("puma560", drive_terms=[]).drive_terms == []
    with pytest.raises(TypeError):
        dynid.load_model("puma560", drive_terms=["fv", 3])
    with pytest.raises(TypeError):
        dynid.load_model(3)


def test_a_malformed_model_file_raises_a_parse_error_with_its_position(tmp_path):
    path = tmp_path / "broken.urdf"
    path.write_text("<robot name='r'><link name='a'>\n<inertial><mass value='-x'/></inertial>"
                    "</link></robot>")
    with pytest.raises(dynid.ParseError) as caught:
        dynid.load_model(str(path))
    assert caught.value.file == str(path)
    assert isinstance(caught.value, ValueError)


def test_dataset_round_trips_exactly_and_matches_the_cli_file(tmp_path, puma_csv):
    data = dynid.read_dataset(puma_csv)
    assert data.num_joints == 6 and len(data) == data.num_samples == 4001
    assert data.q.shape == (4001, 6) and data.time.shape == (4001,)
    again = dynid.Dataset(data.time, data.q, data.dq, data.ddq, data.tau)
    dynid.write_dataset(tmp_path / "copy.csv", again)
    assert (tmp_path / "copy.csv").read_bytes() == puma_csv.read_bytes()
    back = dynid.read_dataset(str(tmp_path / "copy.csv"), joints=6)
    for field in ("time", "q", "dq", "ddq", "tau"):
        assert np.array_equal(getattr(back, field), getattr(data, field))


def test_simulate_equals_the_cli_simulation(puma_csv):
    data = dynid.simulate(dynid.load_model("puma560"), duration=4, noise_tau=0.05, seed=7)
    cli = dynid.read_dataset(puma_csv)
    for field in ("time", "q", "dq", "ddq", "tau"):
        assert np.array_equal(getattr(data, field), getattr(cli, field))


def test_simulate_with_stiction_holds_the_arm_in_its_pauses():
    model = dynid.load_model("puma560", drives=True)
    common = dict(duration=6, amplitude=0.4, pauses=(2.0, 1.5))
    held = dynid.simulate(model, stiction=True, **common)
    law = dynid.simulate(model, **common)
    # The holds (2000 samples at 1 kHz) and the reversals that stick: 2278 to 2510 stopped per
    # joint; the law's sign(dq) chatters about zero instead.
    assert np.all(np.sum(held.dq == 0.0, axis=0) > 2000)
    assert np.all(np.sum(law.dq == 0.0, axis=0) < 10)


def test_dataset_from_arrays_is_checked_at_the_boundary():
    t = np.arange(5) * 0.01
    q = np.zeros((5, 2))
    assert np.array_equal(dynid.Dataset(t, q, q).tau, q)  # missing ddq, tau: zeros
    with pytest.raises(ValueError, match="row 3"):
        dynid.Dataset(np.array([0, 1, 2, 2, 3.0]), q, q)
    bad = q.copy()
    bad[2, 1] = math.inf
    with pytest.raises(ValueError, match="row 2: dq2"):
        dynid.Dataset(t, q, bad)
    with pytest.raises(ValueError, match="tau"):
        dynid.Dataset(t, q, q, q, np.zeros((4, 2)))
    with pytest.raises(TypeError, match="q"):
        dynid.Dataset(t, np.zeros((5, 2), dtype=complex), q)
    with pytest.raises(ValueError, match="no samples"):
        dynid.Dataset(np.zeros(0), np.zeros((0, 2)), np.zeros((0, 2)))


def test_a_malformed_csv_raises_a_parse_error_naming_line_and_column(tmp_path, puma_csv):
    lines = puma_csv.read_text().splitlines()
    cells = lines[10].split(",")
    cells[3] = "abc"
    lines[10] = ",".join(cells)
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(dynid.ParseError) as caught:
        dynid.read_dataset(path)
    assert caught.value.line == 11 and caught.value.field == "q3"
    assert "bad.csv:11" in str(caught.value)
    with pytest.raises(ValueError, match="7"):
        dynid.read_dataset(puma_csv, joints=7)
    with pytest.raises(TypeError):
        dynid.read_dataset(42)
    with pytest.raises(RuntimeError, match="cannot read"):
        dynid.read_dataset(tmp_path / "missing.csv")


def test_fix_joints_merges_a_urdfs_moving_joints_as_the_cli_does(tmp_path):
    urdf = tmp_path / "panda.urdf"
    dynid.load_model("panda").export(urdf, "urdf")
    fixed = dynid.load_model(urdf, fix_joints=["joint7"])
    assert fixed.num_joints == 6
    run_cli("model", "export", "--robot", urdf, "--fix-joints", "joint7", "--format", "urdf",
            "--out", tmp_path / "cli.urdf")
    assert (tmp_path / "cli.urdf").read_text() == fixed.to_urdf()
    with pytest.raises(dynid.ParseError, match="joint 'joint9'"):
        dynid.load_model(urdf, fix_joints=["joint9"])
    with pytest.raises(dynid.InputError, match="applies to a URDF robot"):
        dynid.load_model("panda", fix_joints=["joint7"])
