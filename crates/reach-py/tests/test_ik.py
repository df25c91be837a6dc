"""IK: batch all-branch IK against the CLI, the generating configuration among the branches of
10 000 random poses, choice, numeric IK with seeds and masks."""

import numpy as np
import pytest

import reach
from conftest import random_q, wrapped


@pytest.mark.parametrize("name", ["ur5", "puma560", "welder6r", "spbu6"])
def test_batch_ik_equals_the_cli(cli, name):
    robot = reach.Robot.preset(name)
    q = random_q(robot, 3, seed=7)
    out = robot.ik_all(robot.fk(q))
    for i in range(3):
        T = robot.fk(q[i])
        report = cli("ik", name, "--matrix", ",".join(repr(float(v)) for v in T.ravel()), "--all")
        assert report["solver"] == out["solver"]
        assert report["found"] == out["count"][i]
        cli_q = {s["branch"]: np.radians(s["q_deg"]) for s in report["solutions"]}
        ours = {out["branch"][i][k]: out["q"][i, k] for k in range(out["count"][i])}
        assert set(cli_q) == set(ours)
        for label, value in cli_q.items():
            # the CLI expresses each solution near `--from` (whole turns): compare angles
            np.testing.assert_allclose(wrapped(ours[label] - value), 0, atol=1e-9)


@pytest.mark.parametrize("name", ["ur5", "puma560"])
def test_every_generating_configuration_is_among_the_branches_of_10000_poses(name):
    robot = reach.Robot.preset(name)
    q = random_q(robot, 10_000, seed=11)
    out = robot.ik_all(robot.fk(q))
    assert out["q"].shape == (10_000, out["q"].shape[1], 6) and out["valid"].shape == out["q"].shape[:2]
    diff = np.abs(wrapped(out["q"] - q[:, None, :])).max(axis=2)  # NaN in padding
    hit = np.nanmin(np.where(out["valid"], diff, np.inf), axis=1)
    assert (hit < 1e-7).all(), f"missing at rows {np.flatnonzero(hit >= 1e-7)[:10]}"
    assert np.isnan(out["q"][~out["valid"]]).all()
    assert (out["position_error"][out["valid"]] < 1e-9).all()
    assert (out["valid"].sum(axis=1) == out["count"]).all()


def test_single_ik_report_arrays_and_choice():
    puma = reach.Robot.preset("puma560")
    q = np.radians([20, 30, -40, 10, 50, 60])
    r = puma.ik(puma.fk(q))
    assert r["status"] == "ok" and r["q"].shape == (r["found"], 6)
    assert np.min(np.abs(wrapped(r["q"] - q)).max(axis=1)) < 1e-9
    assert len(r["branch"]) == r["found"] and r["within_limits"].dtype == bool
    chosen = puma.ik(puma.fk(q), choose="topsis", criteria=["change", "manipulability"], weights=[0.5, 0.5])
    assert chosen["ranking"]["method"] == "topsis" and chosen["chosen"] is not None
    deg = puma.ik(puma.fk(q), degrees=True)
    np.testing.assert_allclose(deg["q"], np.degrees(r["q"]), atol=1e-9)


def test_numeric_ik_with_seeds_and_masks():
    panda = reach.Robot.preset("panda")
    lo, hi = panda.limits().T
    q = lo + (hi - lo) * np.random.default_rng(13).uniform(0.1, 0.9, (20, 7))
    T = panda.fk(q)
    out = panda.ik_all(T, seeds=q + 0.05, restarts=2)
    assert out["solver"] == "numeric"
    assert out["valid"][:, 0].all() and (out["position_error"][:, 0] < 1e-6).all()
    pos = panda.ik_all(T[:5], solver="numeric", mask="position", restarts=2)
    assert (pos["orientation_error"][pos["valid"]] == 0).all()
    with pytest.raises(ValueError, match="mask"):
        panda.ik_all(T, mask="xyz")
    with pytest.raises(ValueError, match="numeric.restarts"):
        panda.ik_all(T[:1], restarts=1_000_000)
