"""Batch FK and Jacobian equal the CLI's `--json` for the same inputs; shapes and units."""

import numpy as np
import pytest

import reach
from conftest import random_q


@pytest.mark.parametrize("name", ["ur5", "puma560", "panda", "planar3", "welder6r"])
def test_batch_fk_and_jacobian_equal_the_cli(cli, name):
    robot = reach.Robot.preset(name)
    q = random_q(robot, 4, seed=1)
    T = robot.fk(q)
    J = robot.jacobian(q)
    assert T.shape == (4, 4, 4) and J.shape == (4, 6, robot.dof)
    for i in range(4):
        fk = cli("fk", name, *q[i], "--rad")
        np.testing.assert_allclose(T[i], np.array(fk["pose"]["matrix"]), rtol=0, atol=1e-12)
        jac = cli("jacobian", name, *q[i], "--rad")
        np.testing.assert_allclose(J[i], np.array(jac["jacobian"]), rtol=0, atol=1e-12)
        # one vector gives the same as its row of the batch
        np.testing.assert_array_equal(robot.fk(q[i]), T[i])


def test_degrees_flag_converts_revolute_joints_only():
    ur5 = reach.Robot.preset("ur5")
    q = np.array([10.0, -20.0, 30.0, 40.0, -50.0, 60.0])
    np.testing.assert_array_equal(ur5.fk(q, degrees=True), ur5.fk(np.radians(q)))
    np.testing.assert_array_equal(ur5.limits(degrees=True), np.degrees(ur5.limits()))


def test_model_properties():
    puma = reach.Robot.preset("puma560")
    assert puma.dof == 6 and puma.name == "puma560"
    assert puma.joint_names[0] == "waist" and puma.joint_kinds == ["revolute"] * 6
    np.testing.assert_allclose(puma.limits(degrees=True)[1], [-45.0, 225.0])
    np.testing.assert_array_equal(puma.qlim, puma.limits().T)
    assert "ur5" in reach.Robot.presets()


def test_from_dh_matches_the_preset_with_the_same_table():
    # Puma 560, standard DH (crates/reach/robots/puma560.toml): [a, alpha, d, offset].
    rows = [
        [0, 90, 0.6718, 0],
        [0.4318, 0, 0, 0],
        [0.0203, -90, 0.15005, 0],
        [0, 90, 0.4318, 0],
        [0, -90, 0, 0],
        [0, 0, 0, 0],
    ]
    dh = reach.Robot.from_dh(rows, degrees=True)
    puma = reach.Robot.preset("puma560")
    q = random_q(puma, 50, seed=3)
    np.testing.assert_allclose(dh.fk(q), puma.fk(q), atol=1e-12)


def test_robots_pickle(tmp_path):
    import pickle

    for robot in [reach.Robot.preset("ur5"), reach.Robot.from_dh([[0.5, 0, 0, 0], [0.3, 0, 0, 0]])]:
        again = pickle.loads(pickle.dumps(robot))
        q = random_q(robot, 5, seed=4)
        np.testing.assert_array_equal(again.fk(q), robot.fk(q))


def test_from_file_reads_toml_and_urdf(tmp_path):
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[3]
    toml = root / "crates" / "reach" / "robots" / "ur5.toml"
    robot = reach.Robot.from_file(toml)
    q = random_q(robot, 3, seed=5)
    np.testing.assert_array_equal(robot.fk(q), reach.Robot.preset("ur5").fk(q))
    urdf = tmp_path / "two.urdf"
    urdf.write_text(
        """<robot name="two">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="t" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
</robot>"""
    )
    two = reach.Robot.from_file(urdf, tip="tool")
    assert two.joint_names == ["j1", "j2"]
    np.testing.assert_allclose(two.fk([0, np.pi / 2])[:3, 3], [0.5, 0.3, 0.1], atol=1e-12)
