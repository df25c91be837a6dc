"""Issue 35: the library's dynamics from Python — `rne`, `gravload`, `inertia` — batch in
numpy, equal to Pinocchio's `rnea`, `computeGeneralizedGravity` and `crba` on the URDF arms
with inertias (the fixture of bench/peers/pinocchio_dynamics.py), and consistent with each
other and with the Robotics Toolbox's Puma 560 fixture."""

import json

import numpy as np
import pytest

import reach
from conftest import ROOT

FIXTURE = ROOT / "crates" / "reach" / "tests" / "data" / "reference"


@pytest.mark.parametrize("name", ["kr16_2", "kr120r2500pro"])
def test_urdf_arms_equal_pinocchio(name):
    arm = json.loads((FIXTURE / "urdf_dynamics.json").read_text())["arms"][name]
    robot = reach.Robot.from_file(str(ROOT / arm["urdf"]), tip="tool0")
    states = arm["states"]
    q, qd, qdd = (np.array([s[k] for s in states]) for k in ("q", "qd", "qdd"))
    tau, g, m = (np.array([s[k] for s in states]) for k in ("tau", "gravity", "mass_matrix"))
    assert robot.rne(q, qd, qdd).shape == (20, 6) and robot.inertia(q).shape == (20, 6, 6)
    np.testing.assert_allclose(robot.rne(q, qd, qdd), tau, rtol=0, atol=1e-9 * np.abs(tau).max())
    np.testing.assert_allclose(robot.gravload(q), g, rtol=0, atol=1e-9 * np.abs(g).max())
    np.testing.assert_allclose(robot.inertia(q), m, rtol=0, atol=1e-9 * np.abs(m).max())
    # One state gives its row of the batch.
    np.testing.assert_array_equal(robot.rne(q[3], qd[3], qdd[3]), robot.rne(q, qd, qdd)[3])


def test_puma560_equals_the_toolbox_and_the_parts_add_up():
    doc = json.loads((FIXTURE / "puma560_rne.json").read_text())
    puma = reach.Robot.preset("puma560")
    q, qd, qdd, tau = (np.array([s[k] for s in doc["states"]]) for k in ("q", "qd", "qdd", "tau"))
    np.testing.assert_allclose(puma.rne(q, qd, qdd), tau, rtol=0, atol=1e-11)
    # τ(q, 0, q̈) = M(q)·q̈ + g(q), and M is symmetric.
    m = puma.inertia(q)
    np.testing.assert_allclose(puma.rne(q, qdd=qdd), np.einsum("nij,nj->ni", m, qdd) + puma.gravload(q), atol=1e-10)
    np.testing.assert_array_equal(m, np.transpose(m, (0, 2, 1)))
    np.testing.assert_array_equal(puma.rne(q), puma.gravload(q))


def test_bad_dynamics_input_names_the_argument():
    puma = reach.Robot.preset("puma560")
    with pytest.raises(ValueError, match="qd: expected the shape of q"):
        puma.rne(np.zeros((3, 6)), np.zeros(6))
    with pytest.raises(ValueError, match=r"q: expected shape \(6,\)"):
        puma.inertia(np.zeros(5))
    with pytest.raises(reach.ReachError, match="q"):
        puma.gravload([0, 0, float("nan"), 0, 0, 0])
    with pytest.raises(reach.ReachError, match="inertial"):
        reach.Robot.preset("planar3").rne(np.zeros(3))
