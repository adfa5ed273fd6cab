"""Errors: dynid's exceptions as Python exceptions with its messages; wrong types and shapes are
exceptions, never a crash."""
import math

import numpy as np
import pytest

import dynid


def test_the_exception_classes_are_value_and_runtime_errors():
    assert issubclass(dynid.InputError, ValueError)
    assert issubclass(dynid.ParseError, ValueError)
    assert issubclass(dynid.NumericalError, RuntimeError)
    assert issubclass(dynid.Error, RuntimeError)


def test_a_parse_error_carries_the_file_line_and_field(tmp_path):
    path = tmp_path / "data.csv"
    path.write_text("t,q1,dq1,ddq1,tau1\n0,0,0,0,0\n0.001,0,nan?,0,0\n")
    with pytest.raises(dynid.ParseError) as caught:
        dynid.read_dataset(path)
    error = caught.value
    assert (error.file, error.line, error.field) == (str(path), 3, "dq1")
    assert str(error).startswith(f"{path}:3")


def test_an_unwritable_output_raises_a_runtime_error(tmp_path):
    data = dynid.Dataset(np.arange(3.0), np.zeros((3, 1)), np.zeros((3, 1)))
    with pytest.raises(dynid.Error, match="cannot write"):
        dynid.write_dataset(tmp_path / "missing-dir" / "out.csv", data)
    assert not (tmp_path / "missing-dir").exists()


@pytest.mark.parametrize("call", [
    lambda m: dynid.rnea("puma560", np.zeros(6), np.zeros(6), np.zeros(6)),
    lambda m: dynid.rnea(None, np.zeros(6), np.zeros(6), np.zeros(6)),
    lambda m: dynid.crba(m, {"q": 1}),
    lambda m: dynid.identify(m, None),
    lambda m: dynid.identify(m, np.zeros((10, 6))),
    lambda m: dynid.gc_error(m, 12),
    lambda m: dynid.search(m, "x.csv", 3),
    lambda m: dynid.Dataset("t", np.zeros((2, 6)), np.zeros((2, 6))),
    lambda m: dynid.load_model(None),
    lambda m: dynid.base_parameters(m).project("theta"),
])
def test_wrong_argument_types_raise_type_errors(call):
    with pytest.raises(TypeError):
        call(dynid.load_model("puma560"))


@pytest.mark.parametrize("call, match", [
    (lambda m: m.set_parameter("m1", math.nan), "m1"),
    (lambda m: dynid.base_parameters(m).project(np.zeros(59)), "theta"),
    (lambda m: dynid.base_parameters(m, tolerance=-1), "tolerance"),
    (lambda m: dynid.simulate(m, duration=-1), "duration"),
    (lambda m: dynid.simulate(m, controller="pid"), "controller"),
    (lambda m: dynid.simulate(m, amplitude=np.ones(5)), "amplitude"),
    (lambda m: dynid.simulate(m, integrator="verlet"), "verlet"),
    (lambda m: dynid.identifiability(m, samples=-3), "samples"),
    (lambda m: dynid.predict(m, "nonexistent.csv", threads=-2), "threads"),
    (lambda m: dynid.excite(m, harmonics=1), "harmonics"),
])
def test_invalid_values_raise_value_errors_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call(dynid.load_model("puma560"))


def test_a_missing_dataset_raises_a_runtime_error_naming_it(tmp_path):
    model = dynid.load_model("puma560")
    for call in (lambda p: dynid.identify(model, p), lambda p: dynid.predict(model, p),
                 lambda p: dynid.gc_error(model, p), lambda p: dynid.identifiability(model, p)):
        with pytest.raises(dynid.Error, match="missing.csv"):
            call(str(tmp_path / "missing.csv"))


def test_a_library_message_names_the_python_argument_not_the_cli_flag(tmp_path):
    # The library names request fields (`time_column`, `calibration`); the CLI says --time and
    # --calibration, Python its keyword arguments.
    log = tmp_path / "log.csv"
    log.write_text("stamp,pos1,eff1\n0,0,0\n0.001,0,0\n")
    with pytest.raises(dynid.ParseError) as caught:
        dynid.prepare(str(log), time_column="nothing", q_columns="pos*", tau_columns="eff*")
    assert caught.value.field == "time_column"
    assert "--" not in str(caught.value) and "`" not in str(caught.value)
    with pytest.raises(dynid.InputError) as caught:
        dynid.monitor("puma560", str(log))
    message = str(caught.value)
    assert "calibration" in message and "thresholds" in message, message
    assert "--" not in message and "`" not in message, message
