"""Bad input raises ValueError carrying the library's message, naming the argument."""

import numpy as np
import pytest

import reach


def test_nan_is_rejected_with_the_library_message():
    ur5 = reach.Robot.preset("ur5")
    q = np.zeros((3, 6))
    q[2, 4] = np.nan
    with pytest.raises(ValueError, match=r"q\[2\]: joint 5: value must be a finite number, got NaN"):
        ur5.fk(q)
    with pytest.raises(reach.ReachError):
        ur5.jacobian(q)
    T = ur5.fk(np.zeros((2, 6)))
    T[1, 0, 3] = np.inf
    with pytest.raises(ValueError, match=r"T\[1\]\.matrix\[4\]: expected a finite number, got inf"):
        ur5.ik_all(T)


def test_wrong_shapes_name_the_argument_and_the_shape():
    ur5 = reach.Robot.preset("ur5")
    with pytest.raises(ValueError, match=r"q: expected shape \(6,\) or \(N, 6\), got \(3, 5\)"):
        ur5.fk(np.zeros((3, 5)))
    with pytest.raises(ValueError, match=r"T: expected shape \(4, 4\) or \(N, 4, 4\), got \(2, 3, 3\)"):
        ur5.ik_all(np.zeros((2, 3, 3)))
    with pytest.raises(ValueError, match=r"seeds: expected shape \(6,\) or \(N, 6\)"):
        ur5.ik_all(np.eye(4), seeds=np.zeros(5))
    with pytest.raises(ValueError, match="seeds"):
        ur5.ik_all(np.stack([np.eye(4)] * 3), seeds=np.zeros((2, 6)))
    with pytest.raises(ValueError, match=r"rows: expected shape \(n, 4\) or \(n, 6\)"):
        reach.Robot.from_dh(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="q: expected an array of numbers"):
        ur5.fk(["a"] * 6)


def test_bad_poses_and_requests_carry_the_library_message():
    ur5 = reach.Robot.preset("ur5")
    T = np.eye(4)
    T[0, 0] = 2.0
    with pytest.raises(ValueError, match=r"T\[0\]\.matrix: the rotation part .* is not orthonormal"):
        ur5.ik_all(T)
    with pytest.raises(ValueError, match="unknown robot|unknown preset|not a preset"):
        reach.Robot.preset("nope")
    with pytest.raises(ValueError, match="duration_s"):
        ur5.move(**{"from": {"joints": {"deg": [0] * 6}}, "to": {"joints": {"deg": [10] * 6}}, "duration_s": -1})
    with pytest.raises(ValueError, match="finite"):
        ur5.move(**{"from": {"joints": {"deg": [0] * 6}}, "to": {"joints": {"deg": [float("nan")] * 6}}})
    with pytest.raises(ValueError, match="solver"):
        ur5.ik_all(np.eye(4), solver="magic")
