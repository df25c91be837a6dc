#!/usr/bin/env python3
"""Batch FK throughput of reach's Python package: `Robot.fk` of an `(N, dof)` array.

Protocol: for `ur5`, `puma560` and `panda`, N random joint vectors inside the limits (`qlim`,
cut to [-pi, pi]; numpy's default generator, seed 2024; no peer library is needed, so the
Robotics Toolbox is not imported) -> `Robot.fk(q)` -> `(N, 4, 4)`. Throughput is poses per second of the best of `--repeats`
calls (conversion of the input and allocation of the output array included), of wall time and
of CPU time (this process, all threads: the cost on a loaded machine). Measured on one core
(RAYON_NUM_THREADS=1, a separate process) and on all cores. Each run also checks a few rows
against `Robot.fk` of the single joint vector (1e-12).

Run: `python bench/peers/fk_batch.py [--poses 100000]` in a venv holding numpy and reach
(`pip install ./crates/reach-py`).
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np


def reach_fk_throughput(name, poses, seed, repeats):
    """Poses per second of reach's batch fk in this process (threads as RAYON_NUM_THREADS says)."""
    import reach

    robot = reach.Robot.preset(name)
    lo, hi = np.clip(robot.qlim, -np.pi, np.pi)
    q = np.random.default_rng(seed).uniform(lo, hi, size=(poses, len(lo)))
    best, best_cpu = float("inf"), float("inf")
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        T = robot.fk(q)
        best = min(best, time.perf_counter() - t0)
        best_cpu = min(best_cpu, time.process_time() - c0)
    worst = max(np.abs(T[i] - robot.fk(q[i])).max() for i in [0, 1, poses // 2, poses - 1])
    if not worst <= 1e-12:
        raise SystemExit(f"{name}: batch row differs from the single fk by {worst}")
    return {"poses_per_s": poses / best, "poses_per_cpu_s": poses / best_cpu}


def in_subprocess(name, args, threads):
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    else:
        env.pop("RAYON_NUM_THREADS", None)
    cmd = [sys.executable, __file__, "--reach-only", name, "--poses", str(args.poses), "--seed", str(args.seed),
           "--repeats", str(args.repeats)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--poses", type=int, default=100000)
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--reach-only", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.reach_only:
        print(json.dumps(reach_fk_throughput(args.reach_only, args.poses, args.seed, args.repeats)))
        return
    print(f"# {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"{'robot':<10} {'threads':<8} {'poses/s':>12} {'poses/CPU-s':>12}")
    for name in ["ur5", "puma560", "panda"]:
        for threads in [1, 0]:
            v = in_subprocess(name, args, threads)
            label = "1" if threads else f"all ({os.cpu_count()})"
            print(f"{name:<10} {label:<8} {v['poses_per_s']:>12,.0f} {v['poses_per_cpu_s']:>12,.0f}")


if __name__ == "__main__":
    main()
