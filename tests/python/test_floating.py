"""Floating-base robots (docs/FLOATING.md): what each sensor set determines, equal to the CLI's."""
import json
import os
import sqlite3
import struct
from pathlib import Path

import numpy as np
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
    with pytest.raises(ValueError, match="method.*not one motion"):
        dynid.floating_identify(ANYMAL, data, method="combined")  # random states: no rollout
    with pytest.raises(ValueError, match="combined_"):
        dynid.floating_identify(ANYMAL, data, method="pc", combined_weight=2.0)
    with pytest.raises(ValueError, match="contacts"):
        dynid.floating_identify(ANYMAL, data, contacts=["LF_FOOT"])


def test_floating_identify_a_payload(tmp_path):
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", contacts=FEET, samples=60)
    doc = dynid.floating_identify(ANYMAL, data, method="ols", payload_link="base")
    # The robot read is the one simulated: no payload, to round-off.
    for s in doc["payload"]["sets"]:
        assert abs(s["mass"]) < 1e-9
    # From a pair (here the same robot twice: no payload either), the robot's parameters unused.
    other = dynid.simulate_floating(ANYMAL, tmp_path / "u.csv", contacts=FEET, samples=60, seed=2)
    pair = dynid.floating_identify(ANYMAL, data, method="ols", payload_link="base", unloaded=other)
    assert pair["payload"]["from"] == "unloaded_data"
    for s in pair["payload"]["sets"]:
        assert abs(s["mass"]) < 1e-8
    with pytest.raises(ValueError, match="payload_link"):
        dynid.floating_identify(ANYMAL, data, unloaded=other)


def _cdr(header_stamp_ns, frame, doubles, prefix=b""):
    """A ROS 2 CDR message (little endian, XCDR1): header, then `prefix`, then float64s aligned."""
    body = struct.pack("<iI", header_stamp_ns // 10**9, header_stamp_ns % 10**9)
    body += struct.pack("<I", len(frame) + 1) + frame.encode() + b"\0" + prefix
    body += b"\0" * (-len(body) % 8)
    return b"\x00\x01\x00\x00" + body + struct.pack(f"<{len(doubles)}d", *doubles)


def _joint_state(stamp_ns, names, q, tau):
    """sensor_msgs/JointState: names, then positions, no velocities, efforts."""
    def aligned(b, n):
        return b + b"\0" * (-len(b) % n)
    body = struct.pack("<iI", stamp_ns // 10**9, stamp_ns % 10**9) + struct.pack("<I", 1) + b"\0"
    body = aligned(body, 4) + struct.pack("<I", len(names))
    for name in names:
        body = aligned(body, 4) + struct.pack("<I", len(name) + 1) + name.encode() + b"\0"
    for values in (q, [], tau):
        body = aligned(body, 4) + struct.pack("<I", len(values))
        if values:
            body = aligned(body, 8) + struct.pack(f"<{len(values)}d", *values)
    return b"\x00\x01\x00\x00" + body


def _standing_recording(path, joints):
    """A robot held still for 2 s: joints at 500 Hz, an IMU at 400 Hz reading gravity, a
    force-torque sensor at 1 kHz; rosbag2 SQLite, written here from the message definitions."""
    db = sqlite3.connect(path)
    db.executescript(
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
        " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
        " timestamp INTEGER NOT NULL, data BLOB NOT NULL);")
    db.executemany("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')",
                   [(1, "/joint_states", "sensor_msgs/msg/JointState"),
                    (2, "/imu", "sensor_msgs/msg/Imu"),
                    (3, "/ft", "geometry_msgs/msg/WrenchStamped")])
    rows = []
    for k in range(1001):
        t = 10**9 + k * 2 * 10**6
        rows.append((1, t, _joint_state(t, joints, [0.1] * len(joints), [1.0] * len(joints))))
    imu = [0, 0, 0, 1] + [0] * 9 + [0, 0, 0] + [0] * 9 + [0, 0, 9.81] + [0] * 9
    for k in range(801):
        t = 10**9 + k * 2500000
        rows.append((2, t, _cdr(t, "imu_link", imu)))
    for k in range(2001):
        t = 10**9 + k * 10**6
        rows.append((3, t, _cdr(t, "face_rear", [0, 0, 500.0, 0, 0, 0])))
    db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", rows)
    db.commit()
    db.close()


def test_prepare_floating_equals_the_clis(tmp_path):
    joints = [f"{leg}_{part}" for leg in ("LF", "RF", "LH", "RH") for part in ("HAA", "HFE", "KFE")]
    bag = tmp_path / "standing.db3"
    _standing_recording(bag, joints)
    doc = dynid.prepare_floating(ANYMAL, bag, tmp_path / "floating.csv")
    assert doc["kind"] == "dynid.floating_prepare"
    assert [t["topic"] for t in doc["topics"]] == ["/joint_states", "/imu", "/ft"]
    assert doc["rate"] == pytest.approx(500.0)
    # 2 s of overlap less the 0.2 s trim at each end, at 500 Hz.
    assert doc["samples"] == 801
    run_cli("prepare", "--floating-base", "--robot", ANYMAL, "--log", bag, "--out",
            tmp_path / "cli")
    cli = read_json(tmp_path / "cli" / "floating_prepare.json")
    assert less_provenance(doc) == less_provenance(cli)
    assert (tmp_path / "floating.csv").read_bytes() == \
        (tmp_path / "cli" / "floating_dataset.csv").read_bytes()
    with pytest.raises(ValueError, match="imu_topic"):
        dynid.prepare_floating(ANYMAL, bag, tmp_path / "x.csv", imu_topic="/imu/data")
    # The sensor reads 500 N throughout: a flag at its frame, holding in every sample.
    flagged = dynid.prepare_floating(ANYMAL, bag, tmp_path / "flags.csv", contact_threshold=100)
    assert flagged["thresholded_contacts"] == [{"frame": "face_rear", "holding_fraction": 1.0}]
    assert "contact:face_rear" in (tmp_path / "flags.csv").read_text().splitlines()[0]
    with pytest.raises(ValueError, match="contact_threshold"):
        dynid.prepare_floating(ANYMAL, bag, tmp_path / "x.csv", contact_threshold=-1)
    # A contact topic must be a std_msgs/Bool one.
    with pytest.raises(ValueError, match="not std_msgs/msg/Bool"):
        dynid.prepare_floating(ANYMAL, bag, tmp_path / "x.csv", contact_topics={"/ft": "LF_FOOT"})


def test_simulate_floating_follows_a_design_on_the_suspended_robot(tmp_path):
    design = Path(os.environ["DYNID_SOURCE_DIR"]) / "tests/data/floating/fixtures/anymal_excitation.json"
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", trajectory=design, samples=50)
    doc = dynid.floating_identify(ANYMAL, data, method="ols", sensors=["torques_contacts"])
    assert doc["motion"] == "suspended"  # the support's wrench is at the base link
    # 50 states over the design's 10 s are 5 Hz: a motion, but 0.05 s is under half a period.
    assert "horizon" in doc["gc"]["refused"]
    doc = dynid.floating_identify(ANYMAL, data, method="ols", sensors=["torques_contacts"],
                                  horizon=0.4, num_segments=5)
    assert doc["gc"]["refused"] is None and doc["gc"]["segments_train"] == 5
    with pytest.raises(ValueError, match="horizon"):
        dynid.floating_identify(ANYMAL, data, horizon=-1.0)
    with pytest.raises(ValueError, match="trajectory"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", trajectory=design, motion="free")
    tilted = dynid.simulate_floating(ANYMAL, tmp_path / "t.csv", trajectory=design, samples=50,
                                     stand_tilts=[(0.0, 0.0), (0.4, 0.0), (0.0, 0.4)])
    doc = dynid.floating_identify(ANYMAL, tilted, method="ols")
    assert all(s["refused"] is None for s in doc["sets"])  # one orientation refuses the wrench sets
    with pytest.raises(ValueError, match="stand_tilts"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", motion="suspended",
                                stand_tilts=[(0.4, 0.0)])


def test_floating_identify_by_the_combined_estimator(tmp_path):
    design = Path(os.environ["DYNID_SOURCE_DIR"]) / "tests/data/floating/fixtures/anymal_excitation.json"
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", trajectory=design, samples=700,
                                   stand_tilts=[(0.0, 0.0), (0.4, 0.0), (0.0, 0.4)],
                                   noise_tau=0.05, noise_force=0.2, noise_moment=0.05)
    doc = dynid.floating_identify(ANYMAL, data, method="combined", sensors=["torques_wrenches"],
                                  horizon=0.02, num_segments=5, combined_iterations=2, threads=2)
    combined = doc["sets"][0]["combined"]
    assert doc["method"] == "combined" and combined["iterations"] <= 2
    assert combined["final_gc"] <= combined["initial_gc"]
    assert combined["gc_floor"] > 0.0  # torques_wrenches estimates every channel's noise
    assert doc["sets"][0]["gc_error"]["train"] == combined["final_gc"]


def test_excite_chooses_a_stands_tilts_as_the_cli(tmp_path):
    robot = dynid.load_model(ANYMAL)
    quick = dict(check_rate=100.0, segments=10)  # the design's check and GC Jacobian: not tested here
    design = dynid.excite(robot, starts=1, evaluations=30, period=5.0, stands=2, max_tilt=0.3,
                          tilt_grid=3, robot_spec=ANYMAL, threads=1, **quick)
    tilts = design.stand_tilts
    assert len(tilts) == 2 and tilts[0] == (0.0, 0.0)  # upright first
    assert all(abs(angle) <= 0.3 for tilt in tilts for angle in tilt)
    doc = json.loads(design.to_json())
    assert doc["stand"]["tilts"] == [list(t) for t in tilts] and doc["stand"]["candidates"] == 9
    path = tmp_path / "excitation.json"
    path.write_text(design.to_json())
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", trajectory=path, samples=20)
    assert dynid.floating_identify(ANYMAL, data, method="ols")["data"]["samples"] == 40
    assert dynid.excite(robot, starts=1, evaluations=5, period=2.0, **quick).stand_tilts is None
    with pytest.raises(ValueError, match="robot_spec"):
        dynid.excite(robot, starts=1, evaluations=5, stands=2)
    with pytest.raises(ValueError, match="apply with stands"):
        dynid.excite(robot, starts=1, evaluations=5, max_tilt=0.2)
    with pytest.raises(ValueError, match="stands"):
        dynid.excite(robot, starts=1, evaluations=5, stands=0, robot_spec=ANYMAL)


def test_simulate_floating_runs_a_design_at_the_stand_orientations_it_chose(tmp_path):
    fixture = Path(os.environ["DYNID_SOURCE_DIR"]) / "tests/data/floating/fixtures/anymal_excitation.json"
    design = json.loads(fixture.read_text())
    design["schema_version"] = 5  # as `dynid excite --stands 3` writes it
    design["stand"] = {"tilts": [[0.0, 0.0], [-0.4, 0.4], [0.4, -0.4]]}
    path = tmp_path / "stands.json"
    path.write_text(json.dumps(design))
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", trajectory=path, samples=50)
    doc = dynid.floating_identify(ANYMAL, data, method="ols")
    assert doc["data"]["samples"] == 150  # 50 states at each of the three
    assert all(s["refused"] is None for s in doc["sets"])
    upright = dynid.simulate_floating(ANYMAL, tmp_path / "u.csv", trajectory=path, samples=50,
                                      stand_tilts=[(0.0, 0.0)])  # overrides the design's
    doc = dynid.floating_identify(ANYMAL, upright, method="ols", sensors=["wrenches"])
    assert doc["data"]["samples"] == 50 and "79 of the 80" in doc["sets"][0]["refused"]


def test_simulate_floating_keeps_the_feet_within_friction_cones(tmp_path):
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", contacts=FEET, samples=40,
                                   friction_cone=0.6)
    doc = dynid.floating_identify(ANYMAL, data, method="ols", sensors=["wrenches"])
    assert doc["motion"] == "holding"
    with pytest.raises(ValueError, match="friction_cone"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", motion="suspended", friction_cone=0.5)


def test_a_base_its_support_moves_is_carried(tmp_path):
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", motion="carried", samples=60,
                                   noise_tau=0.5, noise_force=2.0, noise_moment=0.5)
    # The support's wrench is at the base link and the base moves: identify says it takes it as
    # carried, with the field's Python name.
    with pytest.warns(UserWarning, match=r"moves the base \(carried\).*set motion to say otherwise"):
        doc = dynid.floating_identify(ANYMAL, data, method="ols")
    assert doc["motion"] == "carried"
    counts = {s["sensors"]: s["num_base"] for s in doc["sets"]}
    assert counts == {"wrenches": 94, "torques_wrenches": 94, "torques_contacts": 84}
    with pytest.raises(ValueError, match="holding, free, suspended or carried"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", motion="platform")


def test_simulate_floating_keeps_a_soles_centre_of_pressure_in_it(tmp_path):
    romeo = Path(os.environ["DYNID_SOURCE_DIR"]) / "examples/floating/romeo/romeo_small.urdf"
    data = dynid.simulate_floating(romeo, tmp_path / "d.csv", contacts=["l_sole:frame", "r_sole:frame"],
                                   samples=20, friction_cone=0.8, sole=(0.2, 0.1))
    header, *rows = [line.split(",") for line in Path(data).read_text().splitlines()]
    col = {name: k for k, name in enumerate(header)}
    for row in rows:
        for sole in ("l_sole", "r_sole"):
            n_x, n_y, f_z = (float(row[col[f"wrench:{sole}:{c}"]]) for c in ("nx", "ny", "fz"))
            if row[col[f"contact:{sole}"]] == "1":  # the centre of pressure within 0.2 x 0.1 m
                assert abs(n_y) <= 0.1 * f_z + 1e-6 and abs(n_x) <= 0.05 * f_z + 1e-6
    with pytest.raises(ValueError, match="sole"):
        dynid.simulate_floating(romeo, tmp_path / "x.csv", contacts=["l_sole:frame"], sole=(0.2, 0.1))


def test_simulate_floating_takes_a_soles_corners(tmp_path):
    romeo = Path(os.environ["DYNID_SOURCE_DIR"]) / "examples/floating/romeo/romeo_small.urdf"
    # A sole reaching 0.15 m ahead of the ankle frame and 0.05 m behind it, 0.1 m wide.
    corners = np.array([[-0.05, -0.05], [0.15, -0.05], [0.15, 0.05], [-0.05, 0.05]])
    data = dynid.simulate_floating(romeo, tmp_path / "d.csv", contacts=["l_sole:frame", "r_sole:frame"],
                                   samples=8, friction_cone=0.8, sole=corners)
    header, *rows = [line.split(",") for line in Path(data).read_text().splitlines()]
    col = {name: k for k, name in enumerate(header)}
    for row in rows:
        for sole in ("l_sole", "r_sole"):
            n_x, n_y, f_z = (float(row[col[f"wrench:{sole}:{c}"]]) for c in ("nx", "ny", "fz"))
            if row[col[f"contact:{sole}"]] == "1":  # the centre of pressure (-n_y, n_x) / f_z inside
                assert -0.05 * f_z - 1e-6 <= -n_y <= 0.15 * f_z + 1e-6 and abs(n_x) <= 0.05 * f_z + 1e-6
    for bad in ([(0.0, 0.0), (0.1, 0.0)], [(0.0, 0.0), (0.1, 0.0, 0.2)], "0.2,0.1", [(0.0, 0.0), (0.1, "x")]):
        with pytest.raises(ValueError, match="sole"):
            dynid.simulate_floating(romeo, tmp_path / "x.csv", contacts=["l_sole:frame"], friction_cone=0.8,
                                    sole=bad)


def test_simulate_floating_generates_a_standing_sway(tmp_path):
    stance = [0, 0.5, -1, 0, 0.5, -1, 0, -0.5, 1, 0, -0.5, 1]
    path = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", contacts=FEET, stance=stance,
                                   samples=300, friction_cone=0.6)
    cli = tmp_path / "cli.csv"
    run_cli("simulate", "--robot", ANYMAL, "--floating-base", "--contacts", ",".join(FEET),
            "--stance", ",".join(str(x) for x in stance), "--samples", "300",
            "--friction-cone", "0.6", "--out", cli)
    assert Path(path).read_text() == cli.read_text()
    with pytest.raises(ValueError, match="apply with stance"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", contacts=FEET, sway=0.1)
    with pytest.raises(ValueError, match="lower sway or turn"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", contacts=FEET, stance=stance, sway=0.5)


def test_simulate_floating_along_a_given_motion(tmp_path):
    first = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", contacts=FEET, samples=20, seed=4)
    again = dynid.simulate_floating(ANYMAL, tmp_path / "again.csv", motion_from=first)
    # Noise-free, the same torques and wrenches: the same file but for the last digits.
    a, b = (Path(p).read_text().splitlines() for p in (first, again))
    assert a[0] == b[0] and len(a) == len(b)
    for x, y in zip(a[1:], b[1:]):
        for u, v in zip(x.split(","), y.split(",")):
            assert abs(float(u) - float(v)) <= 1e-9 * (1 + abs(float(u)))
    with pytest.warns(UserWarning, match=r"of the motion's samples \(from t = .* s\) need a contact to pull or slide"):
        dynid.simulate_floating(ANYMAL, tmp_path / "cones.csv", motion_from=first, friction_cone=0.2)
    with pytest.raises(ValueError, match="motion_from"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", motion_from=first, motion="free")
    with pytest.raises(ValueError, match="samples does not apply to motion_from"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", motion_from=first, samples=5)


def test_floating_gc_error_rolls_a_suspended_motion_out(tmp_path):
    """The GC error on a floating base: a smooth joint motion of ANYmal hung from its base, its
    torques and support wrench simulated along it (motion_from), rolled out again."""
    header = Path(dynid.simulate_floating(ANYMAL, tmp_path / "h.csv", motion="suspended", samples=2)
                  ).read_text().splitlines()[0].split(",")
    rows = []
    for k in range(251):  # 0.5 s at 500 Hz
        t, row = k / 500.0, {}
        for i, joint in enumerate(name[2:] for name in header if name.startswith("q:")):
            w, phase = 2 * np.pi * (0.5 + 0.1 * i), 0.7 * i
            row[f"q:{joint}"] = 0.1 * i - 0.5 + 0.3 * np.sin(w * t + phase)
            row[f"dq:{joint}"] = 0.3 * w * np.cos(w * t + phase)
            row[f"ddq:{joint}"] = -0.3 * w * w * np.sin(w * t + phase)
        row.update({"t": t, "base:qw": 1.0})
        rows.append(",".join(repr(float(row.get(name, 0.0))) for name in header))
    (tmp_path / "motion.csv").write_text("\n".join([",".join(header), *rows]) + "\n")
    data = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", motion="suspended",
                                   motion_from=tmp_path / "motion.csv")
    gc = dynid.floating_gc_error(ANYMAL, data, horizon=0.02, num_segments=10)
    assert gc["samples_per_segment"] == 10 and len(gc["segment_errors"]) == 10
    assert gc["horizon"] == pytest.approx(0.02)
    # The torques held over each 2 ms: about four times the 1 ms hold's 1.2e-4 of the C++ test
    # (tests/search/floating/floating_gc_test.cpp); measured 5.6e-4, a margin of nine.
    assert 0 < gc["error"] < 5e-3
    with pytest.raises(ValueError, match="'LF_FOOT'"):  # no wrench is measured at a foot here
        dynid.floating_gc_error(ANYMAL, data, contacts=["LF_FOOT"])


def test_excite_standing_equals_the_clis_design_and_simulate_follows_it(tmp_path):
    stance = [0, 0.5, -1, 0, 0.5, -1, 0, -0.5, 1, 0, -0.5, 1]
    doc = dynid.excite_standing(ANYMAL, FEET, stance, out=tmp_path / "s.json", friction_cone=0.6,
                                starts=1, evaluations=40)
    run_cli("excite", "--robot", ANYMAL, "--floating-base", "--contacts", ",".join(FEET),
            "--stance", ",".join(str(x) for x in stance), "--friction-cone", "0.6", "--starts",
            "1", "--evaluations", "40", "--out", tmp_path / "cli")
    cli = read_json(tmp_path / "cli" / "standing_excitation.json")
    assert doc["kind"] == "dynid.standing_excitation"
    for key in ("design", "sets", "stance", "contacts", "limits", "designed"):
        assert doc[key] == cli[key], key  # the same seed: the same sway, whatever the front end
    assert read_json(tmp_path / "s.json")["design"] == doc["design"]
    assert [s["design"]["determined"] for s in doc["sets"]] == [93, 94, 90]
    path = dynid.simulate_floating(ANYMAL, tmp_path / "d.csv", trajectory=tmp_path / "s.json",
                                   friction_cone=0.6, rate=100)
    assert dynid.floating_identify(ANYMAL, path, method="ols")["data"]["samples"] == 400
    with pytest.raises(ValueError, match="standing design for other feet"):
        dynid.simulate_floating(ANYMAL, tmp_path / "x.csv", trajectory=tmp_path / "s.json",
                                contacts=FEET[:2])
    with pytest.raises(ValueError, match="max_sway"):
        dynid.excite_standing(ANYMAL, FEET, stance, max_sway=0.0)
    with pytest.raises(ValueError, match="sensors"):
        dynid.excite_standing(ANYMAL, FEET, stance, sensors="imu")
