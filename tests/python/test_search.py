"""The paper's machinery and the data pipelines: gc_error, search, refine, excite, prepare, each
against the CLI with the same settings and seed."""
import json
import os
import pathlib
import signal
import threading
import warnings

import numpy as np
import pytest

import dynid
from conftest import less_provenance, read_json, run_cli


def without(document, keys):
    """The document without the given keys at any depth (wall times, the start file's name)."""
    if isinstance(document, dict):
        return {k: without(v, keys) for k, v in document.items() if k not in keys}
    if isinstance(document, list):
        return [without(v, keys) for v in document]
    return document


@pytest.fixture(scope="module")
def puma():
    return dynid.load_model("puma560")


def test_gc_error_is_the_same_for_any_thread_count_and_data_form(puma, puma_csv):
    one = dynid.gc_error(puma, puma_csv, segments=40, threads=1)
    assert dynid.gc_error(puma, puma_csv, segments=40, threads=2) == one
    assert dynid.gc_error(puma, dynid.read_dataset(puma_csv), segments=40) == one
    assert one > 0  # the torques carry noise: no model predicts the states exactly
    other = puma.copy()
    other.set_parameter("m3", puma.parameter("m3") * 1.5)
    assert dynid.gc_error(other, puma_csv, segments=40) > one
    with pytest.raises(ValueError, match="horizon"):
        dynid.gc_error(puma, puma_csv, horizon=0.0123456)


@pytest.fixture(scope="module")
def cli_search(tmp_path_factory, puma_csv):
    out = tmp_path_factory.mktemp("search")
    run_cli("search", "--method", "nlo", "--robot", "puma560", "--data", puma_csv, "--perturb",
            0.3, "--budget-evals", 150, "--segments", 20, "--seed", 3, "--threads", 2, "--out", out)
    return out


def test_search_equals_the_cli_for_the_same_seed(puma, puma_csv, cli_search):
    result = dynid.search(puma, str(puma_csv), "nlo", perturb=0.3, budget_evals=150,
                          segments=20, seed=3, threads=1)
    cli = read_json(cli_search / "search.json")
    assert (without(json.loads(result.to_json()), {"seconds", "provenance"})
            == without(cli, {"seconds", "provenance"}))
    assert result.evaluations == 150 and result.termination == "evaluations"
    assert len(result.history) == len(cli["history"])
    assert [h["best_gc"] for h in result.history] == [h["best_gc_error"] for h in cli["history"]]
    assert result.initial_parameter_error is None  # no truth given
    assert result.best_gc <= result.initial_gc
    assert len(result.best_x) == len(result.free_names)
    assert dynid.gc_error(result.model, puma_csv, segments=20) == pytest.approx(result.best_gc,
                                                                               rel=1e-12)
    arrays = dynid.search(puma, dynid.read_dataset(puma_csv), "nlo", perturb=0.3,
                          budget_evals=150, segments=20, seed=3)
    assert np.array_equal(arrays.best_x, result.best_x)


def test_ga_and_bad_search_settings(puma, puma_csv):
    ga = dynid.search(puma, puma_csv, "ga", perturb=0.2, budget_evals=60, population=20,
                      segments=10, seed=4, truth=puma)
    assert ga.evaluations >= 60 and ga.final_parameter_error is not None
    assert ga.initial_parameter_error > 0
    with pytest.raises(ValueError, match="init or perturb"):
        dynid.search(puma, puma_csv, "nlo", init=puma, perturb=0.1)
    with pytest.raises(ValueError, match="unknown method 'ols'"):
        dynid.search(puma, puma_csv, "ols")
    with pytest.raises(ValueError, match="mass_constraint"):
        dynid.search(puma, puma_csv, "nlo", mass_constraint="maybe")
    with pytest.raises(ValueError, match="budget"):
        dynid.search(puma, puma_csv, "nlo", budget_evals=-1)


def test_refine_from_a_search_equals_the_cli_refine_from_its_file(tmp_path, puma, puma_csv,
                                                                  cli_search):
    run_cli("refine", "--robot", "puma560", "--from", cli_search / "search.json", "--data",
            puma_csv, "--max-iterations", 2, "--no-base-stage", "--out", tmp_path)
    cli = read_json(tmp_path / "refine.json")
    search = dynid.search(puma, puma_csv, "nlo", perturb=0.3, budget_evals=150, segments=20,
                          seed=3)
    refined = dynid.refine(puma, search, puma_csv, max_iterations=2, base_stage=False)
    mine = json.loads(refined.to_json())
    assert (without(mine, {"seconds", "from", "provenance"})
            == without(cli, {"seconds", "from", "provenance"}))
    from_file = dynid.refine(puma, cli_search / "search.json", puma_csv, max_iterations=2,
                             base_stage=False)
    assert np.array_equal(from_file.x, refined.x)
    assert refined.final_gc <= refined.initial_gc
    assert refined.termination == cli["termination"]
    assert refined.free_names == search.free_names
    assert refined.final_parameter_error is None  # no truth given
    with pytest.raises(ValueError, match="max_iterations"):
        dynid.refine(puma, search, puma_csv, max_iterations=0)


def test_refine_from_an_estimate(puma, puma_csv):
    estimate = dynid.identify(dynid.load_model("puma560-consistent"), puma_csv, method="pc")
    refined = dynid.refine(dynid.load_model("puma560-consistent"), estimate, puma_csv,
                           max_iterations=2, segments=10, base_stage=False, truth=puma)
    assert np.isfinite(refined.final_gc) and refined.final_gc <= refined.initial_gc * (1 + 1e-12)
    assert refined.final_parameter_error > 0 and refined.final_base_error > 0


def test_a_refine_progress_callback_sees_every_iteration_and_can_stop_it(puma, puma_csv):
    """Refinement's progress= gets a dict per solver iteration; False stops it with the
    parameters so far (no warning: the caller asked), an exception in it is raised."""
    estimate = dynid.identify(dynid.load_model("puma560-consistent"), puma_csv, method="pc")
    seen = []

    def progress(info):
        seen.append(info)
        return len(seen) < 2

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        refined = dynid.refine(dynid.load_model("puma560-consistent"), estimate, puma_csv,
                               max_iterations=50, segments=10, base_stage=False,
                               progress=progress)
    assert len(seen) == 2
    assert [s["iteration"] for s in seen] == [0, 1]
    assert all(0.0 <= s["done"] <= 1.0 and s["stage"] == "parameters" for s in seen)
    assert "[refine] parameters iteration 1" in seen[1]["line"] and "%" in seen[1]["line"]
    assert refined.termination.startswith("USER_SUCCESS")
    with pytest.raises(RuntimeError, match="from the callback"):
        dynid.refine(dynid.load_model("puma560-consistent"), estimate, puma_csv,
                     max_iterations=5, segments=10, base_stage=False,
                     progress=lambda info: (_ for _ in ()).throw(RuntimeError("from the callback")))


def test_excite_equals_the_cli_design(tmp_path, puma):
    run_cli("excite", "--robot", "puma560", "--starts", 2, "--evaluations", 60, "--seed", 3,
            "--out", tmp_path)
    design = dynid.excite(puma, starts=2, evaluations=60, seed=3, robot_spec="puma560")
    assert without(json.loads(design.to_json()), {"seconds", "provenance"}) == \
        without(read_json(tmp_path / "excitation.json"), {"seconds", "provenance"})
    cli = read_json(tmp_path / "excitation.json")
    assert np.array_equal(design.a, cli["design"]["a"]) and np.array_equal(design.b, cli["design"]["b"])
    assert np.array_equal(design.offset, cli["design"]["offset"])
    assert design.condition_number == cli["designed"]["condition_unit"]
    assert design.baseline_condition_number > design.condition_number  # the design's purpose
    motion = design.sample(100.0)
    assert motion.time[-1] == pytest.approx(design.period, rel=1e-12)
    # At rest at both ends of the period (the design's constraints), to round-off.
    assert np.abs(motion.dq[0]).max() < 1e-9 and np.abs(motion.dq[-1]).max() < 1e-9
    design_file = tmp_path / "excitation.json"
    simulated = dynid.simulate(puma, duration=2, trajectory=design_file)
    assert simulated.num_samples == 2001
    # Without a duration: one period of the design (a 3 s one: not the default duration).
    short = read_json(design_file)
    short["design"]["period"] = 3.0
    short_file = tmp_path / "short.json"
    short_file.write_text(json.dumps(short))
    assert dynid.simulate(puma, trajectory=short_file).num_samples == 3001
    # A design of an earlier version is tracked as it is, with a warning that says so.
    older = tmp_path / "older.json"
    older_doc = dict(less_provenance(short), schema_version=3)
    del older_doc["stand"]  # version 5's key
    older.write_text(json.dumps(older_doc))
    with pytest.warns(UserWarning, match="version 3 .current 5.: read as it is"):
        assert dynid.simulate(puma, trajectory=older).num_samples == 3001
    with pytest.raises(ValueError):
        dynid.excite(puma, criterion="best")


def test_prepare_equals_the_cli(tmp_path, puma_csv):
    data = dynid.read_dataset(puma_csv)
    # A raw log: milliseconds, degrees, no accelerations, named columns.
    log = tmp_path / "log.csv"
    rows = np.column_stack([data.time * 1e3, np.degrees(data.q), data.tau])
    header = "stamp_ms," + ",".join(f"pos{j}" for j in range(1, 7)) + "," + \
        ",".join(f"eff{j}" for j in range(1, 7))
    np.savetxt(log, rows, delimiter=",", header=header, comments="", fmt="%.17g")
    run_cli("prepare", "--log", log, "--time", "stamp_ms", "--q", "pos*", "--tau", "eff*",
            "--time-unit", "ms", "--angle-unit", "deg", "--validate-fraction", 0.25, "--out",
            tmp_path / "cli")
    prepared = dynid.prepare(str(log), time_column="stamp_ms", q_columns="pos*",
                             tau_columns="eff*", time_unit="ms", angle_unit="deg",
                             validate_fraction=0.25)
    cli_train = dynid.read_dataset(tmp_path / "cli" / "train.csv")
    for field in ("time", "q", "dq", "ddq", "tau"):
        assert np.array_equal(getattr(prepared.train, field), getattr(cli_train, field))
    assert prepared.validate.num_samples == \
        dynid.read_dataset(tmp_path / "cli" / "validate.csv").num_samples
    assert (less_provenance(json.loads(prepared.to_json()))
            == less_provenance(read_json(tmp_path / "cli" / "prepare.json")))
    assert prepared.cutoff == 10.0 and prepared.rate == pytest.approx(1000.0, rel=1e-9)
    assert np.array_equal(prepared.tau_noise,
                          read_json(tmp_path / "cli" / "prepare.json")["tau_noise_rms"])
    # The joints on one thread: the same numbers as on every core.
    one = dynid.prepare(str(log), time_column="stamp_ms", q_columns="pos*", tau_columns="eff*",
                        time_unit="ms", angle_unit="deg", validate_fraction=0.25, threads=1)
    for field in ("time", "q", "dq", "ddq", "tau"):
        assert np.array_equal(getattr(one.train, field), getattr(prepared.train, field))
    with pytest.raises(dynid.InputError, match="threads"):
        dynid.prepare(str(log), q_columns="pos*", tau_columns="eff*", threads=-1)
    with pytest.raises(ValueError, match="cutoff"):
        dynid.prepare(str(log), q_columns="pos*", tau_columns="eff*", cutoff="high")
    with pytest.raises(dynid.ParseError):
        dynid.prepare(str(log), q_columns="nothing*", tau_columns="eff*")
    # Windows, torque's own cutoff and the plausibility bounds: the CLI's options, the same data.
    run_cli("prepare", "--log", log, "--time", "stamp_ms", "--q", "pos*", "--tau", "eff*",
            "--time-unit", "ms", "--angle-unit", "deg", "--window", "0.5:2.5",
            "--tau-cutoff", "none", "--dq-max", 30, "--out", tmp_path / "cli_window")
    windowed = dynid.prepare(log, time_column="stamp_ms", q_columns="pos*", tau_columns="eff*",
                             time_unit="ms", angle_unit="deg", window=[(0.5, 2.5)],
                             tau_cutoff="none", dq_max=30)
    assert (less_provenance(json.loads(windowed.to_json()))
            == less_provenance(read_json(tmp_path / "cli_window" / "prepare.json")))
    assert windowed.train.time[0] >= 0.5 and windowed.train.time[-1] <= 2.5
    assert windowed.time_origin == 0.0 and windowed.warnings == []
    with pytest.raises(dynid.InputError, match="dq_max"):  # the keyword argument, not --dq-max
        dynid.prepare(log, time_column="stamp_ms", q_columns="pos*", tau_columns="eff*",
                      time_unit="ms", angle_unit="deg", dq_max=1e-3)
    with pytest.raises(dynid.InputError, match="time_unit"):  # milliseconds read as seconds
        dynid.prepare(log, time_column="stamp_ms", q_columns="pos*", tau_columns="eff*",
                      angle_unit="deg")


def test_prepare_reads_a_ros1_bag_as_the_cli(tmp_path):
    # Written by ROS's own writer (tools/make_ros1_bag_fixtures.py): joints in the messages' order.
    bag = os.path.join(os.path.dirname(__file__), "..", "data", "bags", "fixtures",
                       "joint_states_bz2.bag")
    run_cli("prepare", "--log", bag, "--cutoff", 0, "--trim", 0, "--out", tmp_path / "cli")
    prepared = dynid.prepare(bag, cutoff=0, trim=0)
    cli_train = dynid.read_dataset(tmp_path / "cli" / "train.csv")
    for field in ("time", "q", "dq", "ddq", "tau"):
        assert np.array_equal(getattr(prepared.train, field), getattr(cli_train, field))
    assert prepared.time_origin == 1700000000.0 and prepared.train.num_samples == 200
    # The robot's joints matched by name, in its order; the gripper ignored.
    matched = dynid.prepare(bag, cutoff=0, trim=0, joint_names=["joint1", "joint2"],
                            topic="/joint_states", stamp="receive")
    assert np.array_equal(matched.train.q[:, 0], prepared.train.q[:, 1])
    assert np.array_equal(matched.train.tau[:, 1], prepared.train.tau[:, 0])
    with pytest.raises(dynid.InputError, match="lack the robot's joints elbow"):
        dynid.prepare(bag, cutoff=0, trim=0, joint_names=["joint1", "elbow"])
    with pytest.raises(ValueError, match="stamp"):
        dynid.prepare(bag, stamp="sideways")


def test_prepare_takes_arrays_as_the_same_log_in_a_file(tmp_path, puma_csv):
    data = dynid.read_dataset(puma_csv)
    # Epoch stamps in ms, degrees: the arrays go through the same units, checks and filters.
    t = 1.7e12 + data.time * 1e3
    log = tmp_path / "log.csv"
    np.savetxt(log, np.column_stack([t, np.degrees(data.q), data.tau]), delimiter=",",
               header="t," + ",".join(f"q{j}" for j in range(1, 7)) + "," +
               ",".join(f"tau{j}" for j in range(1, 7)), comments="", fmt="%.17g")
    from_file = dynid.prepare(log, time_column="t", q_columns="q*", tau_columns="tau*",
                              time_unit="ms", angle_unit="deg")
    from_arrays = dynid.prepare(t=t, q=np.degrees(data.q), tau=data.tau, time_unit="ms",
                                angle_unit="deg")
    for field in ("time", "q", "dq", "ddq", "tau"):
        assert np.array_equal(getattr(from_arrays.train, field),
                              getattr(from_file.train, field)), field
    assert from_arrays.time_origin == from_file.time_origin == 1.7e12 / 1e3
    assert json.loads(from_arrays.to_json())["source"]["arrays"].startswith("in memory")
    # Logged velocities are used, not derived; shapes that disagree are named.
    with_dq = dynid.prepare(t=data.time, q=data.q, tau=data.tau, dq=data.dq)
    assert with_dq.train.num_samples > 0
    with pytest.raises(ValueError, match="tau"):
        dynid.prepare(t=data.time, q=data.q, tau=data.tau[:, :5])
    with pytest.raises(ValueError, match="t, q and tau"):
        dynid.prepare(t=data.time, q=data.q)
    with pytest.raises(ValueError, match="not both"):
        dynid.prepare(log, t=data.time, q=data.q, tau=data.tau)


def test_prepare_reads_rosbag2_directories_and_efforts_from_a_second_topic(tmp_path):
    fixtures = pathlib.Path(__file__).parent.parent / "data" / "bags" / "fixtures" / "ros2"
    split = dynid.prepare(fixtures / "joint_states_split", cutoff=0, trim=0)  # a pathlib.Path
    one = dynid.prepare(str(fixtures / "joint_states_zstd.mcap"), cutoff=0, trim=0)
    assert np.array_equal(split.train.q, one.train.q) and split.train.num_samples == 200
    efforts = dynid.prepare(fixtures / "joint_states_effort_topic.mcap", cutoff=0, trim=0,
                            topic="/joint_states", effort_topic="/joint_efforts")
    assert np.array_equal(efforts.train.tau, one.train.tau)
    with pytest.raises(dynid.InputError, match="effort_topic"):
        dynid.prepare(fixtures / "joint_states_effort_topic.mcap", topic="/joint_states")


def test_raw_held_out_torques_as_the_cli(tmp_path, puma, puma_csv):
    run_cli("prepare", "--log", puma_csv, "--q", "q*", "--tau", "tau*", "--validate-fraction",
            0.25, "--keep-raw-torque", "--out", tmp_path / "data")
    run_cli("identify", "--robot", "puma560", "--data", tmp_path / "data" / "train.csv",
            "--validate", tmp_path / "data" / "validate.csv", "--validate-raw",
            tmp_path / "data" / "validate_raw.csv", "--out", tmp_path / "ols")
    cli = read_json(tmp_path / "ols" / "estimate.json")["validation"]["raw_measurement"]
    prepared = dynid.prepare(puma_csv, q_columns="q*", tau_columns="tau*", validate_fraction=0.25,
                             keep_raw_torque=True)
    raw = np.loadtxt(tmp_path / "data" / "validate_raw.csv", delimiter=",", skiprows=1)
    assert np.array_equal(prepared.raw_validate_time, raw[:, 0])
    assert np.array_equal(prepared.raw_validate_tau, raw[:, 1:])
    estimate = dynid.identify(puma, tmp_path / "data" / "train.csv",
                              validate=prepared.validate,
                              validate_raw=tmp_path / "data" / "validate_raw.csv")
    assert estimate.raw_validation["relative_error"] == cli["relative_error"]
    assert estimate.raw_validation["not_bracketed"] == cli["not_bracketed"]
    with pytest.raises(dynid.InputError, match="held-out dataset"):
        dynid.identify(puma, tmp_path / "data" / "train.csv",
                       validate_raw=tmp_path / "data" / "validate_raw.csv")


def interrupted_after(seconds, call):
    """call() with a SIGINT (Ctrl-C) sent to this process `seconds` after it starts; its result
    and the warnings it gave."""
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        timer.start()
        try:
            result = call()
        finally:
            timer.join()
    return result, [str(w.message) for w in caught]


# Each run below would take minutes uninterrupted (refine: about 17 s), so only Ctrl-C ends it
# "interrupted"; and had it not been caught, KeyboardInterrupt would fail the test.
def test_ctrl_c_stops_a_search_with_its_best_result(puma, puma_csv):
    s, caught = interrupted_after(1.0, lambda: dynid.search(
        puma, puma_csv, "nlo", perturb=0.3, budget_evals=10**7, segments=20, seed=3))
    assert s.termination == "interrupted"
    assert 0 < s.evaluations < 10**7 and np.isfinite(s.best_gc) and s.best_gc <= s.initial_gc
    assert any("interrupted" in m for m in caught)


def test_ctrl_c_stops_a_refinement_with_its_best_result(puma, puma_csv):
    start = dynid.search(puma, puma_csv, "nlo", perturb=0.3, budget_evals=150, segments=20, seed=3)
    r, caught = interrupted_after(1.0, lambda: dynid.refine(puma, start, puma_csv,
                                                            budget_seconds=120))
    assert "interrupted" in r.termination
    assert np.isfinite(r.final_gc) and r.final_gc <= r.initial_gc
    assert any("interrupted" in m for m in caught)


def test_ctrl_c_stops_an_excitation_design(puma):
    design, caught = interrupted_after(1.0, lambda: dynid.excite(puma, starts=4,
                                                                 evaluations=100000, seed=3))
    assert design.termination == "interrupted"
    assert np.isfinite(design.condition_number)
    assert any("interrupted" in m for m in caught)


def test_an_excite_progress_callback_sees_every_start_and_can_stop_the_design(puma):
    lines = []
    design = dynid.excite(puma, starts=3, evaluations=60, seed=3, threads=1, segments=10,
                          progress=lambda info: lines.append(info["line"]))
    assert [line.split(":")[0] for line in lines] == ["start 1/3", "start 2/3", "start 3/3"]
    assert all("%" in line for line in lines)
    assert design.termination == "evaluations"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a requested stop is no warning
        stopped = dynid.excite(puma, starts=3, evaluations=1000, seed=3, threads=1, segments=10,
                               progress=lambda info: False)
    assert stopped.termination == "interrupted"
    assert np.isfinite(stopped.condition_number)


def test_a_progress_callback_sees_every_round_and_can_stop_the_search(puma_csv):
    """progress= gets the share of the budget done and the CLI's line; False stops the search
    with its best result so far, with no warning (the caller asked for it)."""
    robot = dynid.load_model("puma560")
    seen = []

    def progress(info):
        seen.append(info)
        return len(seen) < 3  # stop after the third round

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "interrupted" warning for a requested stop
        result = dynid.search(robot, puma_csv, "nlo", perturb=0.3, seed=1, segments=20,
                              budget_evals=100000, threads=1, progress=progress)
    assert len(seen) == 3
    assert [s["iteration"] for s in seen] == sorted(s["iteration"] for s in seen)
    assert all(0.0 <= s["done"] <= 1.0 for s in seen)
    assert seen[-1]["evaluations"] < 100000
    assert "[nlo] round" in seen[0]["line"] and "%" in seen[0]["line"]
    assert result.termination == "interrupted"
    assert result.best_gc <= seen[-1]["best_gc"]

    def broken(info):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        dynid.search(robot, puma_csv, "nlo", perturb=0.3, seed=1, segments=20, budget_evals=1000,
                     threads=1, progress=broken)
    with pytest.raises(TypeError):
        dynid.search(robot, puma_csv, "nlo", perturb=0.3, budget_evals=10, progress=3)


def test_prepare_skips_dropouts_when_asked(tmp_path, puma_csv):
    data = dynid.read_dataset(puma_csv)
    rows = np.column_stack([data.time, data.q, data.tau])
    rows[40, 3] = np.nan  # a dropout in q3
    log = tmp_path / "dropout.csv"
    header = "t," + ",".join(f"q{j}" for j in range(1, 7)) + "," + \
        ",".join(f"tau{j}" for j in range(1, 7))
    np.savetxt(log, rows, delimiter=",", header=header, comments="", fmt="%.17g")
    with pytest.raises(dynid.ParseError, match="skip_missing"):
        dynid.prepare(log, time_column="t", q_columns="q*", tau_columns="tau*")
    prepared = dynid.prepare(log, time_column="t", q_columns="q*", tau_columns="tau*",
                             skip_missing=True)
    assert json.loads(prepared.to_json())["raw"]["missing_rows_skipped"] == 1
    assert any("left out (skip_missing)" in w for w in prepared.warnings)


def test_prepare_reads_decimal_commas_when_asked(tmp_path, puma_csv):
    data = dynid.read_dataset(puma_csv)
    rows = np.column_stack([data.time, data.q, data.tau])
    header = "t;" + ";".join(f"q{j}" for j in range(1, 7)) + ";" + \
        ";".join(f"tau{j}" for j in range(1, 7))
    point, comma = tmp_path / "point.csv", tmp_path / "comma.csv"
    np.savetxt(point, rows, delimiter=";", header=header, comments="", fmt="%.17g")
    comma.write_text(point.read_text().replace(".", ","))
    columns = dict(time_column="t", q_columns="q*", tau_columns="tau*")
    with pytest.raises(dynid.ParseError, match="decimal_comma"):
        dynid.prepare(comma, **columns)
    expected = dynid.prepare(point, **columns)
    prepared = dynid.prepare(comma, decimal_comma=True, **columns)
    assert np.array_equal(prepared.train.tau, expected.train.tau)
    assert np.array_equal(prepared.train.q, expected.train.q)


def test_prepare_refuses_recording_options_for_tables(puma_csv):
    columns = dict(time_column="t", q_columns="q*", tau_columns="tau*")
    for option in (dict(topic="/joint_states"), dict(stamp="receive"), dict(joint_prefix="left_"),
                   dict(effort_topic="/efforts"), dict(joint_names=["joint1"])):
        with pytest.raises(ValueError, match="apply to recordings"):
            dynid.prepare(puma_csv, **columns, **option)
