"""reach: plan and check the motions of robot manipulators, from Python.

numpy in and out: ``Robot.fk`` / ``Robot.jacobian`` take one joint vector ``(dof,)`` or a
batch ``(N, dof)``; ``Robot.ik`` solves one pose with every branch and the choice among them;
``Robot.ik_all`` solves a batch ``(N, 4, 4)`` on all cores into NaN-padded arrays with a
validity mask; ``Robot.rne`` / ``gravload`` / ``inertia`` are the rigid-body dynamics. The
workflows (``move``, ``track``, ``plan``, ``avoid``, ``cspace``, ``drive``, ``path``,
``check``, and any request through ``run``) take the same requests as the ``reach`` command
line and return the same reports (its ``--json`` output) as dicts, numeric lists as numpy
arrays, with two differences: a sampled motion (``move``, ``track``, each motion of ``plan``,
the timed path of ``path``) carries its trajectory as arrays ``t`` ``(M,)`` and ``q``, ``qd``,
``qdd`` ``(M, dof)`` instead of its list of samples, and ``check``'s ``verdict`` is a string
(its details beside it as ``verdict_*``, ``clear`` the whole check's outcome).

One unit: every result is SI (radians, metres, seconds), whatever unit a request is written
in (a request's ``{"deg": [...]}`` joint values are read as degrees, the result is still in
radians); ``degrees=True`` asks for degrees (prismatic joints stay in metres). Bad input
raises ``ReachError`` (a ``ValueError``) with the library's message naming the field.

Scenes: ``Scene.from_file(path)``, ``Scene.from_toml(text)`` or ``Scene().add_sphere(...)``;
``scene=`` takes a ``Scene``, a path or a scene file's text. In Jupyter a ``Robot``, a
motion's result (``Motion``, a dict) and a ``Scene`` with a robot show in the 3-D viewer of
``reach view``, offline (``Robot.view(q, scene)`` for any configuration).

Optional parts: ``reach.distributed`` (Ray), ``reach.interop`` (SciPy ``Rotation``,
spatialmath ``SE3``).
"""

from ._reach import MAX_BATCH, ReachError, Robot
from ._results import Motion, View
from .scene import Scene

__all__ = ["MAX_BATCH", "Motion", "ReachError", "Robot", "Scene", "View"]
