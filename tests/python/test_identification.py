"""Identifiability and identification: base_parameters, identifiability, identify, predict."""
import hashlib
import json

import numpy as np
import pytest

import dynid
from conftest import less_provenance, read_json, run_cli


@pytest.fixture(scope="module")
def puma():
    return dynid.load_model("puma560")


def test_base_parameters_span_what_the_regressor_sees(puma):
    base = dynid.base_parameters(puma)
    assert base.num_base == 36 and base.num_standard == 60
    assert base.names[0] == "Iyy1R" and base.expressions[0].startswith("Iyy1")
    assert len(base.zero_columns) > 0
    rng = np.random.default_rng(3)
    q, dq, ddq = (rng.uniform(-2, 2, (50, 6)) for _ in range(3))
    Y = dynid.regressor(puma, q, dq, ddq).reshape(-1, 60)
    scale = np.abs(Y).max()
    # W N = 0 and W = W P^T P-consistent: relative round-off of 60-term sums (1e-10 leaves margin).
    assert np.abs(Y @ base.null_space).max() < 1e-10 * scale
    theta = puma.parameters
    beta = base.project(theta)
    assert np.allclose(base.projection @ theta, beta, rtol=1e-12, atol=1e-12)
    Y1 = Y[:, base.independent]
    assert np.allclose(Y1 @ beta, Y @ theta, rtol=1e-10, atol=1e-10 * scale)
    back = base.standard_from_base(beta, np.zeros(60))
    assert np.allclose(base.project(back), beta, rtol=1e-12, atol=1e-12)
    assert base.combination(0)[0] == ("Iyy1", 1.0)


def test_identifiability_document_equals_the_cli(tmp_path, puma, puma_csv):
    run_cli("identifiability", "--robot", "puma560", "--data", puma_csv, "--out", tmp_path)
    result = dynid.identifiability(puma, data=str(puma_csv))
    assert (less_provenance(json.loads(result.to_json()))
            == less_provenance(read_json(tmp_path / "identifiability.json")))
    assert result.data["rank"] == 36 and result.data["unexcited"] == []
    assert result.condition_number > 1
    document = read_json(tmp_path / "identifiability.json")
    base = result.base
    assert base.names == [b["name"] for b in document["base_parameters"]]
    assert base.expressions == [b["expression"] for b in document["base_parameters"]]
    assert [dict(base.combination(j)) for j in range(base.num_base)] == \
        [b["coefficients"] for b in document["base_parameters"]]
    assert np.array_equal(base.null_space, np.array(document["null_space"]["basis"]).T)
    assert base.rank_gap == document["rank_gap"] and base.tolerance == document["rank_tolerance"]
    assert [base.standard_names[i] for i in base.zero_columns] == document["unidentifiable"]
    assert len(base.dependent) == base.num_standard - base.num_base
    assert base.K.shape == (base.num_base, len(base.dependent))
    assert np.all(base.significance[base.independent] > 1)
    assert np.array_equal(result.model_beta, [b["model_value"] for b in document["base_parameters"]])
    in_memory = dynid.identifiability(puma, data=dynid.read_dataset(puma_csv))
    assert in_memory.data["condition_number"] == result.data["condition_number"]
    assert dynid.identifiability(puma).data is None


@pytest.mark.parametrize("method", ["ols", "wls", "pc"])
def test_identify_equals_the_cli_estimate(tmp_path, puma_csv, puma_validate_csv, method):
    robot = "puma560-consistent" if method == "pc" else "puma560"
    model = dynid.load_model(robot)
    run_cli("identify", "--robot", robot, "--data", puma_csv, "--validate", puma_validate_csv,
            "--method", method, "--out", tmp_path)
    estimate = dynid.identify(model, str(puma_csv), method=method,
                              validate=str(puma_validate_csv), robot_spec=robot)
    assert (less_provenance(json.loads(estimate.to_json()))
            == less_provenance(read_json(tmp_path / "estimate.json")))
    assert estimate.method == method and estimate.num_samples == 4001
    assert estimate.beta.shape == (36,) and estimate.std_dev.shape == (36,)
    assert estimate.validation["num_samples"] == 2001
    document = read_json(tmp_path / "estimate.json")
    if method != "pc":
        rows = document["base_parameters"]
        assert np.array_equal(estimate.beta, [r["estimate"] for r in rows])
        assert np.array_equal(estimate.std_dev, [r["std_dev"] for r in rows])
        assert np.array_equal(estimate.relative_std_dev_percent,
                              [r["relative_std_dev_percent"] for r in rows])
        assert estimate.base_names == [r["name"] for r in rows]
    values = document["standard_estimate"]["values"]
    assert np.array_equal(estimate.standard, [values[k] for k in estimate.standard_names])
    assert estimate.condition_number == document["condition_number"]
    assert np.array_equal(estimate.residual_rms, document["residual_rms"])
    # Noise 0.05 N m on torques of tens of N m: the fit explains all but about 1 %.
    assert estimate.relative_error_percent < 2
    if method == "pc":
        assert estimate.violations == []


def test_combined_with_its_options_equals_the_cli(tmp_path, puma_csv):
    # Two iterations and no time budget: the same bits whatever the machine's speed.
    model = dynid.load_model("puma560-consistent")
    run_cli("identify", "--robot", "puma560-consistent", "--data", puma_csv, "--method",
            "combined", "--combined-iterations", "2", "--combined-seconds", "0", "--segments",
            "40", "--out", tmp_path)
    estimate = dynid.identify(model, puma_csv, method="combined", combined_iterations=2,
                              combined_seconds=0.0, segments=40,
                              robot_spec="puma560-consistent")
    # Equal but for the wall times (combined's cost history and its total).
    def timeless(node):
        if isinstance(node, dict):
            return {k: timeless(v) for k, v in node.items() if k != "seconds"}
        if isinstance(node, list):
            return [timeless(v) for v in node]
        return node
    assert (timeless(less_provenance(json.loads(estimate.to_json())))
            == timeless(less_provenance(read_json(tmp_path / "estimate.json"))))
    assert estimate.method == "combined" and estimate.violations == []
    with pytest.raises(ValueError, match="apply to method 'combined'"):
        dynid.identify(model, puma_csv, method="pc", combined_iterations=2)
    with pytest.raises(dynid.InputError):
        dynid.identify(model, puma_csv, method="combined", combined_iterations=-1)


def test_the_front_equals_the_cli_and_returns_its_points(tmp_path, puma_csv):
    model = dynid.load_model("puma560-consistent")
    held = tmp_path / "held.csv"
    run_cli("simulate", "--robot", "puma560", "--duration", "1.5", "--noise-tau", "0.1",
            "--seed", "5", "--out", held)
    options = ["--combined-iterations", "2", "--combined-seconds", "0", "--segments", "8"]
    run_cli("identify", "--robot", "puma560-consistent", "--data", puma_csv, "--validate", held,
            "--method", "combined", "--front-weights", "0.3,3", *options, "--out",
            tmp_path / "cli")
    estimate = dynid.identify(model, puma_csv, method="combined", validate=str(held),
                              front_weights=[0.3, 3.0], combined_iterations=2,
                              combined_seconds=0.0, segments=8,
                              robot_spec="puma560-consistent")
    document = json.loads(estimate.to_json())
    cli = read_json(tmp_path / "cli" / "estimate.json")
    assert document["front"]["chosen_weight"] == cli["front"]["chosen_weight"]
    assert [p["weight"] for p in estimate.front] == [0.3, 3.0]
    assert sum(p["chosen"] for p in estimate.front) == 1
    chosen = next(p for p in estimate.front if p["chosen"])
    assert chosen["weight"] == document["front"]["chosen_weight"]
    assert chosen["gc_test"] == document["combined"]["gc_error_test"]["combined"]
    assert dynid.identify(model, puma_csv, method="pc").front is None
    with pytest.raises(ValueError, match="front_tolerance applies"):
        dynid.identify(model, puma_csv, method="combined", front_tolerance=0.1)
    with pytest.raises(dynid.InputError, match="needs validate"):
        dynid.identify(model, puma_csv, method="combined", front=True)


def test_documents_record_the_call_that_made_them(tmp_path, puma, puma_csv):
    estimate = dynid.identify(puma, str(puma_csv), seed=5, threads=1)
    p = json.loads(estimate.to_json())["provenance"]
    assert p["interface"] == "python" and p["version"] == dynid.__version__
    # The function, where it was called from and that line of source.
    assert p["command"][0] == "dynid.identify"
    assert p["command"][1].startswith(__file__ + ":")
    assert p["command"][2] == "estimate = dynid.identify(puma, str(puma_csv), seed=5, threads=1)"
    digest = hashlib.sha256(puma_csv.read_bytes()).hexdigest()
    assert p["inputs"] == [{"file": str(puma_csv), "sha256": digest}]
    assert p["seed"] == 5 and p["threads"] == 1 and p["seconds"] > 0
    # A call is not a command: `dynid rerun` says so.
    (tmp_path / "estimate.json").write_text(estimate.to_json())
    done = run_cli("rerun", tmp_path / "estimate.json", "--out", tmp_path / "again", check=False)
    assert done.returncode == 1 and "made by a python call" in done.stderr


def test_arrays_give_the_same_estimate_as_the_file(puma, puma_csv):
    from_file = dynid.identify(puma, puma_csv)
    data = dynid.read_dataset(puma_csv)
    from_arrays = dynid.identify(puma, data, threads=1)
    assert np.array_equal(from_file.beta, from_arrays.beta)  # the same samples, the same sums
    assert np.array_equal(from_file.covariance, from_arrays.covariance)
    assert from_arrays.to_json().count("<arrays>") == 1
    two = dynid.identify(puma, data, threads=2)
    assert np.array_equal(two.beta, from_arrays.beta)


def test_the_estimated_model_predicts_what_the_cli_predicts(tmp_path, puma, puma_csv,
                                                           puma_validate_csv):
    run_cli("identify", "--robot", "puma560", "--data", puma_csv, "--out", tmp_path / "est")
    run_cli("predict", "--estimate", tmp_path / "est" / "estimate.json", "--data",
            puma_validate_csv, "--out", tmp_path / "pred")
    estimate = dynid.identify(puma, puma_csv)
    prediction = dynid.predict(estimate.model, puma_validate_csv, band=estimate)
    header = (tmp_path / "pred" / "predicted.csv").read_text().split("\n", 1)[0].split(",")
    assert header[7:13] == [f"tau_hat{j}" for j in range(1, 7)]
    assert header[13:] == [f"band{j}" for j in range(1, 7)]
    cli = np.loadtxt(tmp_path / "pred" / "predicted.csv", delimiter=",", skiprows=1)
    assert np.array_equal(prediction.time, cli[:, 0])
    assert np.array_equal(prediction.measured, cli[:, 1:7])
    assert np.array_equal(prediction.predicted, cli[:, 7:13])
    # The band from the estimate in memory and from estimate.json: the same numbers.
    assert np.allclose(prediction.band, cli[:, 13:], rtol=1e-12, atol=0)
    record = read_json(tmp_path / "pred" / "prediction.json")
    # One unit, named: percent as the CLI prints it; the fraction (the JSON's) warns.
    assert prediction.relative_error_percent == 100 * record["relative_error"]
    with pytest.warns(DeprecationWarning, match="relative_error_percent"):
        assert prediction.relative_error == record["relative_error"]
    in_memory = dynid.predict(estimate.model, dynid.read_dataset(puma_validate_csv), threads=1)
    assert np.array_equal(in_memory.predicted, prediction.predicted)
    # RNEA of the estimate, sample by sample.
    data = dynid.read_dataset(puma_validate_csv)
    assert np.array_equal(prediction.predicted,
                          dynid.rnea(estimate.model, data.q, data.dq, data.ddq))


def test_unexcited_data_raise_a_numerical_error(puma):
    t = np.arange(200) * 0.001
    q = np.zeros((200, 6))
    still = dynid.Dataset(t, q, q, q, dynid.rnea(puma, q, q, q))
    with pytest.raises(dynid.NumericalError, match="excite") as caught:
        dynid.identify(puma, still)
    assert isinstance(caught.value, RuntimeError)


def test_bad_identify_arguments_raise_value_errors(puma, puma_csv):
    with pytest.raises(ValueError, match="unknown method 'nlo'"):
        dynid.identify(puma, puma_csv, method="nlo")
    with pytest.raises(ValueError, match="prior_weight"):
        dynid.identify(puma, puma_csv, method="pc", prior_weight=0)
    with pytest.raises(ValueError, match="6 joints, robot .panda. has 7"):
        dynid.identify(dynid.load_model("panda"), dynid.read_dataset(puma_csv))
    with pytest.raises(TypeError, match="data"):
        dynid.identify(puma, 3.5)
    with pytest.raises(ValueError, match="samples"):
        dynid.identify(puma, puma_csv, samples=-1)
    with pytest.raises(ValueError, match="another parameter layout"):
        dynid.identify(puma, puma_csv, method="pc",
                       prior=dynid.load_model("puma560", drives=True))


def test_torque_filter_is_reproduced_when_given_and_refused_when_malformed(puma_csv):
    """torque_filter as identify's --torque-filter: auto (the prepare.json beside a file, none
    without one), none, a cutoff or (cutoff, order); the estimate records it in fit_rows."""
    arm = dynid.load_model("puma560", drives=True)
    data = dynid.simulate(arm, duration=6.0, noise_tau=0.05, seed=3)
    filtered = json.loads(dynid.identify(arm, data, torque_filter=(10.0, 4)).to_json())
    rows = filtered["fit_rows"]
    assert rows["torque_filter"]["cutoff_hz"] == 10.0 and rows["torque_filter"]["order"] == 4
    assert rows["torque_filter"]["reach_samples"] > 100  # 175 at 1 kHz
    plain = json.loads(dynid.identify(arm, data, torque_filter="none").to_json())
    assert plain["fit_rows"]["torque_filter"] is None
    auto = json.loads(dynid.identify(dynid.load_model("puma560"), puma_csv).to_json())
    assert "no prepare.json" in auto["fit_rows"]["torque_filter_source"]
    for bad in ("butterworth", -3.0, (10.0, 4.5), (10.0, 13), True):
        with pytest.raises(ValueError, match="torque_filter"):
            dynid.identify(arm, data, torque_filter=bad)
    # predict reproduces it as identify's held-out error does; predicted stays the model's torque.
    model = dynid.identify(arm, data, torque_filter=(10.0, 4)).model
    matched = dynid.predict(model, data, torque_filter=(10.0, 4))
    assert matched.torque_filter == (10.0, 4) and matched.torque_filter_source == "given"
    plain = dynid.predict(model, data, torque_filter="none")
    assert plain.torque_filter is None
    assert np.array_equal(matched.predicted, plain.predicted)
    assert matched.relative_error_percent != plain.relative_error_percent
    assert "data in memory" in dynid.predict(model, data).torque_filter_source
    with pytest.raises(ValueError, match="torque_filter"):
        dynid.predict(model, data, torque_filter="butterworth")
