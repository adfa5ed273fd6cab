"""The module's signatures, docstrings and type stubs (dynid.pyi, python/make_stubs.py): every
public name documented, no argument shown as pybind11's bare `handle`, and the stubs accepted by
mypy --strict, with typed code that uses them right passing and code that uses them wrong
failing."""
import importlib.util
import inspect
import os
import subprocess
import sys
import textwrap

import pytest

import dynid

mypy_missing = importlib.util.find_spec("mypy") is None


def public_names():
    for name, obj in vars(dynid).items():
        if name.startswith("_") or inspect.ismodule(obj):
            continue
        yield name, obj
        if inspect.isclass(obj):
            for attr, value in vars(obj).items():
                if not attr.startswith("_"):
                    yield f"{name}.{attr}", value


def test_every_public_name_has_a_docstring():
    undocumented = [n for n, obj in public_names()
                    if not (getattr(obj, "__doc__", None) or "").strip()]
    assert undocumented == []


def test_no_signature_shows_a_bare_handle_or_object_argument():
    """pybind11 shows py::handle and py::object arguments as `handle` and `object`; ours name the
    types they accept (a path: str or os.PathLike; an array: numpy.typing.ArrayLike)."""
    bare = []
    for name, obj in public_names():
        doc = getattr(obj, "__doc__", None) or ""
        first = doc.strip().splitlines()[0] if doc.strip() else ""
        if callable(obj) and ("handle" in first.split("->")[0] or ": object" in first):
            bare.append(f"{name}: {first}")
    assert bare == []
    assert "os.PathLike[str]" in dynid.load_model.__doc__
    assert "numpy.typing.ArrayLike" in dynid.rnea.__doc__


def stub_dir():
    for d in os.environ.get("PYTHONPATH", "").split(os.pathsep):
        if d and os.path.exists(os.path.join(d, "dynid.pyi")):
            return d
    pytest.fail("no dynid.pyi beside the module on PYTHONPATH (python/make_stubs.py)")


def mypy(*args, cwd):
    env = dict(os.environ, MYPYPATH=stub_dir())
    return subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                           "--cache-dir", os.devnull, *args],
                          capture_output=True, text=True, cwd=cwd, env=env)


@pytest.mark.skipif(mypy_missing, reason="Debian's python3-mypy is not installed")
def test_the_stubs_type_check_right_use_and_catch_wrong_use(tmp_path):
    stubs = os.path.join(stub_dir(), "dynid.pyi")
    done = mypy(stubs, cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr

    right = tmp_path / "right.py"
    right.write_text(textwrap.dedent("""\
        import pathlib
        import numpy as np
        import numpy.typing as npt
        import dynid

        def fit(path: pathlib.Path) -> float:
            robot = dynid.load_model("puma560", drive_terms=["fv", "fc"])
            data = dynid.read_dataset(path)
            estimate = dynid.identify(robot, data, method="ols")
            tau: npt.NDArray[np.float64] = dynid.rnea(robot, np.zeros(6), [0.0] * 6, np.zeros(6))
            print(tau.shape, estimate.base_names[0])
            prediction = dynid.predict(estimate.model, path)
            return prediction.relative_error_percent + float(estimate.beta[0])

        def stop_early(info: dict[str, object]) -> bool:
            return info["iteration"] != 3
        """))
    done = mypy(str(right), cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr

    wrong = tmp_path / "wrong.py"
    wrong.write_text(textwrap.dedent("""\
        import dynid
        robot = dynid.load_model(3)
        estimate = dynid.identify(robot, 4.5)
        estimate.relative_error_percent.upper()
        """))
    done = mypy(str(wrong), cwd=tmp_path)
    assert done.returncode == 1
    out = done.stdout
    assert 'Argument 1 to "load_model" has incompatible type "int"' in out, out
    assert 'Argument 2 to "identify" has incompatible type "float"' in out, out
    assert '"float" has no attribute "upper"' in out, out
