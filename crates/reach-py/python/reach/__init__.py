"""reach: plan and check the motions of robot manipulators, from Python.

numpy in and out: ``Robot.fk`` / ``Robot.jacobian`` take one joint vector ``(dof,)`` or a
batch ``(N, dof)``; ``Robot.ik`` solves one pose with every branch and the choice among them;
``Robot.ik_all`` solves a batch ``(N, 4, 4)`` on all cores into NaN-padded arrays with a
validity mask. The workflows (``move``, ``track``, ``plan``, ``avoid``, ``cspace``, ``drive``,
``path``, ``check``, and any request through ``run``) take the same requests as the ``reach``
command line and return the same reports (its ``--json`` output) as dicts, numeric lists as
numpy arrays. Units: SI and radians unless ``degrees=True``. Bad input raises
``ReachError`` (a ``ValueError``) with the library's message.

Optional parts: ``reach.distributed`` (Ray), ``reach.interop`` (SciPy ``Rotation``,
spatialmath ``SE3``).
"""

from ._reach import MAX_BATCH, ReachError, Robot

__all__ = ["MAX_BATCH", "ReachError", "Robot"]
