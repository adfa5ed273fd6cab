"""Least-squares summaries from Python: dynid.summarize, the Summary's + and pickling, and identify
on a Summary giving the estimate of the logs together, as the CLI's summarize does."""
import pickle

import numpy as np
import pytest

import dynid
from conftest import less_provenance, read_json, run_cli


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Two 3 s PUMA logs (with its drive terms) and the two as one file, the second's stamps 10 s
    later."""
    d = tmp_path_factory.mktemp("summaries")
    paths = []
    for seed in (1, 2):
        path = d / f"s{seed}.csv"
        run_cli("simulate", "--robot", "puma560", "--drives", "--duration", 3, "--noise-tau", 0.1,
                "--seed", seed, "--out", path)
        paths.append(path)
    first = paths[0].read_text().splitlines()
    second = paths[1].read_text().splitlines()[1:]
    shifted = [f"{float(row.split(',', 1)[0]) + 10.0!r},{row.split(',', 1)[1]}" for row in second]
    (d / "all.csv").write_text("\n".join(first + shifted) + "\n")
    return d, paths


def test_summaries_give_the_logs_estimate_in_any_order(logs):
    d, paths = logs
    model = dynid.load_model("puma560", drives=True)
    a, b = (dynid.summarize(model, p, rest_velocity=[1e-3]) for p in paths)
    assert a.samples == 3001 and len(a.sources) == 1 and a.sources[0]["sha256"]
    whole = dynid.identify(model, d / "all.csv", method="pc", rest_velocity=[1e-3])
    for merged in (a + b, b + a, sum([a, b])):
        e = dynid.identify(model, merged, method="pc")
        # 1e-10 relative: the same rows' QR in another order (issue 70's bound).
        assert np.linalg.norm(e.beta - whole.beta) < 1e-10 * np.linalg.norm(whole.beta)
        assert e.num_samples == whole.num_samples


def test_a_summary_pickles_and_matches_the_clis(logs):
    d, paths = logs
    model = dynid.load_model("puma560", drives=True)
    s = dynid.summarize(model, paths[0], robot_spec="puma560")
    back = pickle.loads(pickle.dumps(s))
    assert back.samples == s.samples and back.num_batches == s.num_batches
    e1 = dynid.identify(model, s, method="wls")
    e2 = dynid.identify(model, back, method="wls")
    assert np.array_equal(e1.beta, e2.beta)  # the factors travel bit for bit
    run_cli("summarize", "--robot", "puma560", "--drives", "--data", paths[0], "--out", d / "cli")
    cli = read_json(d / "cli" / "s1.summary.json")
    mine = __import__("json").loads(s.to_json())
    assert mine["provenance"]["interface"] == "python"
    assert less_provenance(mine) == less_provenance(cli)
    loaded = dynid.Summary.load(d / "cli" / "s1.summary.json")
    assert np.array_equal(dynid.identify(model, loaded, method="wls").beta, e1.beta)


def test_summaries_of_other_robots_do_not_merge(logs):
    _, paths = logs
    with_drives = dynid.summarize(dynid.load_model("puma560", drives=True), paths[0])
    without = dynid.summarize(dynid.load_model("puma560"), paths[0])
    with pytest.raises(dynid.InputError, match="drive terms"):
        with_drives + without
    with pytest.raises(dynid.InputError, match="another robot"):
        dynid.identify(dynid.load_model("puma560"), with_drives)
    with pytest.raises(dynid.InputError, match="combined"):
        dynid.identify(dynid.load_model("puma560", drives=True), with_drives, method="combined")
    with pytest.raises(ValueError, match="rest_velocity"):
        dynid.identify(dynid.load_model("puma560", drives=True), with_drives, rest_velocity=[0.1])
    with pytest.raises(TypeError):
        with_drives + 1
