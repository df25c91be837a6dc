#!/usr/bin/env python3
"""A UR5 workspace map (every IK branch at every grid point, one tool orientation) on Ray,
checked against the same map computed in one process.

    python crates/reach-py/examples/ray_workspace_map.py --workers 2            # local Ray
    python crates/reach-py/examples/ray_workspace_map.py --address auto         # on a cluster node
    python crates/reach-py/examples/ray_workspace_map.py --address ray://HEAD:10001   # Ray Client

Prints the grid size, the reachable fraction and the times of the Ray run and the
single-process run (Ray tasks use one core each; the single process uses all cores), and exits
non-zero if the maps differ.
"""

import argparse
import sys
import time

import numpy as np
import ray

import reach
from reach import distributed


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=41, help="grid points per axis (default 41: 68 921 poses)")
    ap.add_argument("--workers", type=int, default=2, help="local Ray: CPUs to start it with, and tasks at once")
    ap.add_argument("--address", help="join a running cluster instead of starting a local Ray")
    ap.add_argument("--chunk", type=int, default=distributed.DEFAULT_CHUNK)
    args = ap.parse_args(argv)
    if args.address:
        ray.init(address=args.address)
    else:
        ray.init(num_cpus=args.workers, include_dashboard=False, log_to_driver=False)
    ur5 = reach.Robot.preset("ur5")
    axis = np.linspace(-0.9, 0.9, args.points)
    try:
        # start every worker before timing (several small tasks)
        distributed.workspace_map(ur5, axis[:4], axis[:4], axis[:4], chunk=4, workers=args.workers)
        t0 = time.perf_counter()
        on_ray = distributed.workspace_map(ur5, axis, axis, axis, chunk=args.chunk, workers=args.workers)
        t_ray = time.perf_counter() - t0
    finally:
        ray.shutdown()
    t0 = time.perf_counter()
    local = distributed.workspace_map(ur5, axis, axis, axis, workers=0)
    t_local = time.perf_counter() - t0
    same = all(np.array_equal(on_ray[k], local[k]) for k in local)
    print(
        f"{axis.size ** 3} poses, reachable {on_ray['reachable'].mean():.3f}; "
        f"Ray ({args.workers} workers) {t_ray:.2f} s, one process {t_local:.2f} s; maps equal: {same}"
    )
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
