"""Optional interop with SciPy's ``Rotation`` and spatialmath's ``SE3`` (each only if installed).

Every ``reach`` function that takes poses already accepts an ``SE3`` (one or many) through its
``.A`` matrices; these helpers build and read 4×4 arrays::

    T = reach.interop.pose(xyz, Rotation.from_euler("xyz", [0, 90, 0], degrees=True))
    R = reach.interop.rotation(robot.fk(q))        # a (possibly stacked) scipy Rotation
    X = reach.interop.se3(robot.fk(qs))            # a spatialmath SE3 of N poses
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt


def pose(xyz: npt.ArrayLike, rotation: Any) -> npt.NDArray[np.float64]:
    """4×4 (or ``(N, 4, 4)``) homogeneous matrices from positions ``(3,)`` / ``(N, 3)`` and a
    SciPy ``Rotation`` (one or N), or rotation matrices ``(3, 3)`` / ``(N, 3, 3)``."""
    r = rotation.as_matrix() if hasattr(rotation, "as_matrix") else np.asarray(rotation, dtype=float)
    p = np.asarray(xyz, dtype=float)
    n = max(r.shape[0] if r.ndim == 3 else 0, p.shape[0] if p.ndim == 2 else 0)
    if n == 0:
        out = np.eye(4)
        out[:3, :3] = r
        out[:3, 3] = p
        return out
    out = np.tile(np.eye(4), (n, 1, 1))
    out[:, :3, :3] = r
    out[:, :3, 3] = p
    return out


def rotation(T: npt.ArrayLike) -> Any:
    """The SciPy ``Rotation`` of 4×4 matrices ``(4, 4)`` or ``(N, 4, 4)``."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(np.asarray(T, dtype=float)[..., :3, :3])


def se3(T: npt.ArrayLike) -> Any:
    """A spatialmath ``SE3`` of 4×4 matrices ``(4, 4)`` or ``(N, 4, 4)``."""
    from spatialmath import SE3

    a = np.asarray(T, dtype=float)
    return SE3(a, check=False) if a.ndim == 2 else SE3([SE3(m, check=False) for m in a])
