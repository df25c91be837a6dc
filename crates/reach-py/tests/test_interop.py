"""Optional interop: SciPy Rotation and spatialmath SE3 (skipped when not installed)."""

import numpy as np
import pytest

import reach
from reach import interop


def test_scipy_rotation_round_trip():
    Rotation = pytest.importorskip("scipy.spatial.transform").Rotation
    ur5 = reach.Robot.preset("ur5")
    T = ur5.fk(np.radians([10, -80, 70, 20, 60, 30]))
    R = interop.rotation(T)
    np.testing.assert_allclose(interop.pose(T[:3, 3], R), T, atol=1e-12)
    assert isinstance(R, Rotation)


def test_se3_is_accepted_as_a_pose():
    pytest.importorskip("spatialmath")
    ur5 = reach.Robot.preset("ur5")
    T = ur5.fk(np.radians([[10, -80, 70, 20, 60, 30], [0, -90, 90, 0, 90, 0]]))
    X = interop.se3(T)
    np.testing.assert_array_equal(ur5.ik_all(X)["q"], ur5.ik_all(T)["q"])


def test_pose_builds_matrices_from_rotation_matrices():
    T = interop.pose([[1, 2, 3], [4, 5, 6]], np.eye(3))
    assert T.shape == (2, 4, 4) and T[1, 2, 3] == 6 and T[0, 3, 3] == 1
