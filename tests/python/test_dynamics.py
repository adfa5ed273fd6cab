"""rnea, aba, crba and regressor: one state and batches, against the CLI and each other."""
import json

import numpy as np
import pytest

import dynid
from conftest import run_cli


@pytest.fixture(scope="module")
def model():
    return dynid.load_model("puma560", drives=True)


@pytest.fixture(scope="module")
def states():
    rng = np.random.default_rng(5)
    n = 6
    return rng.uniform(-2, 2, (1000, n)), rng.uniform(-2, 2, (1000, n)), rng.uniform(-5, 5, (1000, n))


def joined(v):
    return ",".join(repr(float(x)) for x in v)


def test_one_state_equals_the_cli(model, states):
    q, dq, ddq = (s[17] for s in states)
    done = run_cli("dynamics", "--robot", "puma560", "--drives", "--q", joined(q), "--dq",
                   joined(dq), "--ddq", joined(ddq), "--json")
    cli = json.loads(done.stdout)
    # The CLI prints shortest round-trip numbers and parses ours exactly: the same doubles.
    assert np.array_equal(dynid.rnea(model, q, dq, ddq), cli["tau"])
    assert np.array_equal(dynid.crba(model, q), np.array(cli["M"]))
    tau = dynid.rnea(model, q, dq, ddq)
    done = run_cli("dynamics", "--robot", "puma560", "--drives", "--q", joined(q), "--dq",
                   joined(dq), "--tau", joined(tau), "--json")
    assert np.array_equal(dynid.aba(model, q, dq, tau), json.loads(done.stdout)["ddq"])


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_a_batch_equals_the_states_one_by_one_for_any_thread_count(model, states, threads):
    q, dq, ddq = states
    tau = dynid.rnea(model, q, dq, ddq, threads=threads)
    assert tau.shape == (1000, 6)
    one_by_one = np.array([dynid.rnea(model, q[k], dq[k], ddq[k]) for k in range(1000)])
    assert np.array_equal(tau, one_by_one)  # bit for bit: each row is one thread's RNEA
    ddq_back = dynid.aba(model, q, dq, tau, threads=threads)
    assert np.array_equal(ddq_back[999], dynid.aba(model, q[999], dq[999], tau[999]))
    M = dynid.crba(model, q[:300], threads=threads)
    assert M.shape == (300, 6, 6) and np.array_equal(M[299], dynid.crba(model, q[299]))
    Y = dynid.regressor(model, q[:300], dq[:300], ddq[:300], threads=threads)
    assert Y.shape == (300, 6, model.num_parameters)
    assert np.array_equal(Y[123], dynid.regressor(model, q[123], dq[123], ddq[123]))


def test_the_algorithms_agree_with_each_other(model, states):
    q, dq, ddq = states
    tau = dynid.rnea(model, q, dq, ddq)
    # ABA inverts RNEA: relative round-off of a 6x6 solve with condition ~1e3 (1e-9 leaves margin).
    assert np.allclose(dynid.aba(model, q, dq, tau), ddq, rtol=1e-9, atol=1e-9)
    # RNEA = M ddq + RNEA(q, dq, 0): the mass matrix, sums of ~10 products (1e-10 relative).
    M = dynid.crba(model, q)
    bias = dynid.rnea(model, q, dq, np.zeros_like(ddq))
    assert np.allclose(np.einsum("kij,kj->ki", M, ddq) + bias, tau, rtol=1e-10, atol=1e-10)
    assert np.array_equal(M, np.transpose(M, (0, 2, 1)))
    # Y theta = tau: 60-term sums of terms up to ~1e2 N m (1e-10 relative).
    Y = dynid.regressor(model, q, dq, ddq)
    assert np.allclose(Y @ model.parameters, tau, rtol=1e-10, atol=1e-10)


def test_inputs_of_other_layouts_and_integer_dtypes_are_converted(model, states):
    q, dq, ddq = states
    expected = dynid.rnea(model, q[:10], dq[:10], ddq[:10])
    assert np.array_equal(dynid.rnea(model, np.asfortranarray(q[:10]), dq[:10], ddq[:10]),
                          expected)
    wide = np.zeros((10, 12))
    wide[:, ::2] = q[:10]
    assert np.array_equal(dynid.rnea(model, wide[:, ::2], dq[:10], ddq[:10]), expected)
    assert np.array_equal(dynid.rnea(model, q[:10].tolist(), dq[:10], ddq[:10]), expected)
    zeros = np.zeros(6, dtype=np.int32)
    assert np.array_equal(dynid.rnea(model, zeros, zeros, zeros),
                          dynid.rnea(model, np.zeros(6), np.zeros(6), np.zeros(6)))
    assert dynid.rnea(model, np.zeros((0, 6)), np.zeros((0, 6)), np.zeros((0, 6))).shape == (0, 6)


@pytest.mark.parametrize("q, dq, error, match", [
    (np.zeros(5), np.zeros(6), ValueError, "q: expected shape \\(6,\\)"),
    (np.zeros((4, 6)), np.zeros((3, 6)), ValueError, "dq: expected shape \\(4, 6\\)"),
    (np.zeros((4, 6)), np.zeros(6), ValueError, "dq"),
    (np.zeros((2, 2, 6)), np.zeros((2, 2, 6)), ValueError, "dimensions"),
    (np.zeros(6, dtype=complex), np.zeros(6), TypeError, "complex"),
    (np.array(["a"] * 6), np.zeros(6), TypeError, "q"),
    (np.zeros(6, dtype=bool), np.zeros(6), TypeError, "bool"),
    (None, np.zeros(6), TypeError, "None"),
    ([[1, 2], [3]], np.zeros(6), TypeError, "q"),
    (np.zeros(6, dtype=object), np.zeros(6), TypeError, "object"),
])
def test_wrong_shapes_and_dtypes_raise_instead_of_crashing(model, q, dq, error, match):
    with pytest.raises(error, match=match):
        dynid.rnea(model, q, dq, np.zeros_like(dq, dtype=float))


def test_a_negative_or_absurd_thread_count_raises(model, states):
    q = states[0][:10]
    with pytest.raises(ValueError, match="threads"):
        dynid.rnea(model, q, q, q, threads=-1)
    with pytest.raises(ValueError):
        dynid.rnea(model, q, q, q, threads=100000)


def test_non_finite_states_give_non_finite_torques_not_errors(model):
    q = np.zeros(6)
    q[2] = np.nan
    assert np.isnan(dynid.rnea(model, q, np.zeros(6), np.zeros(6))).any()
