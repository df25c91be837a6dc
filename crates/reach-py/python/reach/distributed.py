"""Scaling out over a Ray cluster (optional extra: ``pip install './crates/reach-py[ray]'``).

A reachability map, a workspace map or an IK data set is computed by chunks of poses: each
chunk is one Ray task that solves its poses with ``Robot.ik_all`` (every branch, on the
worker's cores), and the driver stitches the chunks back in order. The chunks are computed
exactly as one process would compute them, so the result equals the single-process run
(``workers=0``) bit for bit.

The same code runs on a laptop and on a cluster: ``ray.init()`` starts a local Ray;
``ray.init(address="auto")`` (on a cluster node) or ``ray.init("ray://head:10001")`` (Ray
Client) joins a cluster. If Ray is not initialised when a function here needs it, it is started
locally (``ray.init()``).
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence

import numpy as np
import numpy.typing as npt

from ._reach import Robot

#: Poses per Ray task by default: large enough that a task's overhead (a few ms) is small
#: next to its work, small enough to spread 100 000 poses over tens of workers.
DEFAULT_CHUNK = 5000


def grid_poses(
    x: Sequence[float], y: Sequence[float], z: Sequence[float], rotation: Optional[npt.ArrayLike] = None
) -> npt.NDArray[np.float64]:
    """The poses ``(len(x)·len(y)·len(z), 4, 4)`` of a position grid (x slowest, z fastest),
    all with one tool rotation (``(3, 3)``; default the identity)."""
    xs, ys, zs = np.meshgrid(np.asarray(x, float), np.asarray(y, float), np.asarray(z, float), indexing="ij")
    t = np.tile(np.eye(4), (xs.size, 1, 1))
    if rotation is not None:
        t[:, :3, :3] = np.asarray(rotation, float)
    t[:, 0, 3], t[:, 1, 3], t[:, 2, 3] = xs.ravel(), ys.ravel(), zs.ravel()
    return t


def _chunk_summary(robot: Robot, poses: np.ndarray, ik_options: Dict[str, Any]) -> Dict[str, np.ndarray]:
    """Per pose of one chunk: IK solutions found (every branch) and those within the joint limits."""
    r = robot.ik_all(poses, **ik_options)
    return {
        "count": r["count"],
        "within_limits": (r["valid"] & r["within_limits"]).sum(axis=1).astype(np.int64),
    }


def _chunk_solutions(robot: Robot, poses: np.ndarray, ik_options: Dict[str, Any]) -> Dict[str, Any]:
    r = robot.ik_all(poses, **ik_options)
    return {k: r[k] for k in ("q", "valid", "within_limits", "position_error", "orientation_error", "count", "status", "branch")}


def _split(poses: np.ndarray, chunk: int) -> List[np.ndarray]:
    if chunk < 1:
        raise ValueError(f"chunk: expected a whole number >= 1, got {chunk}")
    return [poses[i : i + chunk] for i in range(0, len(poses), chunk)]


def _map(fn: Any, robot: Robot, poses: npt.ArrayLike, chunk: int, workers: Optional[int], ik_options: Dict[str, Any]) -> List[Any]:
    """``fn(robot, chunk, ik_options)`` for every chunk, in order: in this process when
    ``workers == 0``, else as Ray tasks (at most ``workers`` at once; ``None``: as many as
    the cluster runs)."""
    p = np.ascontiguousarray(poses, dtype=np.float64)
    if p.ndim != 3 or p.shape[1:] != (4, 4):
        raise ValueError(f"poses: expected shape (N, 4, 4), got {p.shape}")
    chunks = _split(p, chunk)
    if workers == 0:
        return [fn(robot, c, ik_options) for c in chunks]
    import ray

    if not ray.is_initialized():
        ray.init()
    # One core per task: the library's thread pool in the worker is sized to match, so
    # `workers` tasks use `workers` cores.
    task = ray.remote(num_cpus=1, runtime_env={"env_vars": {"RAYON_NUM_THREADS": "1"}})(fn)
    robot_ref = ray.put(robot)
    limit = workers if workers is not None else len(chunks)
    pending: Dict[Any, int] = {}
    results: List[Any] = [None] * len(chunks)
    next_chunk = 0
    while next_chunk < len(chunks) or pending:
        while next_chunk < len(chunks) and len(pending) < limit:
            pending[task.remote(robot_ref, chunks[next_chunk], ik_options)] = next_chunk
            next_chunk += 1
        done, _ = ray.wait(list(pending), num_returns=1)
        for ref in done:
            results[pending.pop(ref)] = ray.get(ref)
    return results


def reachability_map(
    robot: Robot,
    poses: npt.ArrayLike,
    chunk: int = DEFAULT_CHUNK,
    workers: Optional[int] = None,
    **ik_options: Any,
) -> Dict[str, np.ndarray]:
    """For every pose ``(N, 4, 4)``: ``count`` (IK solutions, every branch), ``within_limits``
    (of those, how many respect the joint limits) and ``reachable`` (at least one within
    limits). ``workers=0`` computes in this process; otherwise chunks of ``chunk`` poses run as
    Ray tasks. ``ik_options`` go to ``Robot.ik_all`` (``solver``, ``mask``, ``restarts``, …)."""
    parts = _map(_chunk_summary, robot, poses, chunk, workers, ik_options)
    count = np.concatenate([c["count"] for c in parts]) if parts else np.zeros(0, np.int64)
    within = np.concatenate([c["within_limits"] for c in parts]) if parts else np.zeros(0, np.int64)
    return {"count": count, "within_limits": within, "reachable": within > 0}


def workspace_map(
    robot: Robot,
    x: Sequence[float],
    y: Sequence[float],
    z: Sequence[float],
    rotation: Optional[npt.ArrayLike] = None,
    chunk: int = DEFAULT_CHUNK,
    workers: Optional[int] = None,
    **ik_options: Any,
) -> Dict[str, np.ndarray]:
    """The reachability map of a position grid with one tool rotation ([`grid_poses`]):
    ``count`` and ``within_limits`` shaped ``(len(x), len(y), len(z))``, and ``reachable``."""
    shape = (len(x), len(y), len(z))
    m = reachability_map(robot, grid_poses(x, y, z, rotation), chunk, workers, **ik_options)
    return {k: v.reshape(shape) for k, v in m.items()}


def ik_dataset(
    robot: Robot,
    q: npt.ArrayLike,
    chunk: int = DEFAULT_CHUNK,
    workers: Optional[int] = None,
    **ik_options: Any,
) -> Dict[str, Any]:
    """An IK data set: the poses ``T = fk(q)`` of joint vectors ``q`` ``(N, dof)`` and every IK
    solution of each, as ``Robot.ik_all`` returns them (``q`` ``(N, kmax, dof)`` NaN-padded,
    ``valid``, …), solved by chunks (on Ray unless ``workers=0``)."""
    T = robot.fk(np.asarray(q, dtype=np.float64).reshape(-1, robot.dof))
    parts = _map(_chunk_solutions, robot, T, chunk, workers, ik_options)
    kmax = max((p["q"].shape[1] for p in parts), default=0)

    def pad(a: np.ndarray, fill: Any) -> np.ndarray:
        width = [(0, 0), (0, kmax - a.shape[1])] + [(0, 0)] * (a.ndim - 2)
        return np.pad(a, width, constant_values=fill)

    out: Dict[str, Any] = {"T": T, "q_generating": np.asarray(q, dtype=np.float64).reshape(-1, robot.dof)}
    out["q"] = np.concatenate([pad(p["q"], np.nan) for p in parts]) if parts else np.zeros((0, 0, robot.dof))
    for key, fill in (("valid", False), ("within_limits", False), ("position_error", np.nan), ("orientation_error", np.nan)):
        out[key] = np.concatenate([pad(p[key], fill) for p in parts]) if parts else np.zeros((0, 0))
    out["count"] = np.concatenate([p["count"] for p in parts]) if parts else np.zeros(0, np.int64)
    out["status"] = [s for p in parts for s in p["status"]]
    out["branch"] = [b for p in parts for b in p["branch"]]
    return out
