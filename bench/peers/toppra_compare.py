#!/usr/bin/env python3
"""reach next to toppra: time-optimal parameterisation of the same cubic-spline paths.

50 random 7-joint paths (numpy seed 2026) through 10 waypoints each, uniform in [-2, 2] rad
per joint, joined by the not-a-knot cubic spline at uniform parameter over [0, 1]
(toppra's `SplineInterpolator(linspace(0, 1, 10), waypoints)`, reach's
`PiecewiseCubic::spline`), under the Franka Panda's published velocity and acceleration
limits. Both start and end at rest.

What is timed per path:
  toppra  `TOPPRA([JointVelocityConstraint, JointAccelerationConstraint], path,
          parametrizer="ParametrizeConstAccel")` + `compute_trajectory()` (its default grid,
          collocation at the grid points only), median of --rounds calls
  reach   `PiecewiseCubic::spline` + `time_optimal(path, limits, --points-per-piece)` in
          `bench/src/bin/retime_timing.rs` (release), the same median; its result is slowed
          where needed so that the limits hold between the grid points (exact maxima), which
          toppra does not check

Prints per-path and summary duration ratios (reach / toppra) and the time ratio.

    python3 -m venv /tmp/toppra-venv && /tmp/toppra-venv/bin/pip install toppra==0.6.10
    /tmp/toppra-venv/bin/python bench/peers/toppra_compare.py [--paths 50] [--rounds 21]
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import numpy as np
import toppra as ta
import toppra.algorithm as algo
import toppra.constraint as constraint

ROOT = pathlib.Path(__file__).resolve().parents[2]
VELOCITY = [2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61]
ACCELERATION = [15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0]


def toppra_time(waypoints):
    n = len(waypoints)
    path = ta.SplineInterpolator(np.linspace(0, 1, n), waypoints)
    vel = constraint.JointVelocityConstraint(np.array(VELOCITY))
    acc = constraint.JointAccelerationConstraint(np.array(ACCELERATION))
    instance = algo.TOPPRA([vel, acc], path, parametrizer="ParametrizeConstAccel")
    trajectory = instance.compute_trajectory(0, 0)
    return trajectory, instance


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--paths", type=int, default=50)
    parser.add_argument("--waypoints", type=int, default=10)
    parser.add_argument("--rounds", type=int, default=21)
    parser.add_argument("--points-per-piece", type=int, default=0, help="reach's grid (0: its default)")
    args = parser.parse_args()
    ta.setup_logging("WARNING")

    rng = np.random.default_rng(2026)
    paths = [rng.uniform(-2, 2, size=(args.waypoints, 7)) for _ in range(args.paths)]

    toppra_rows = []
    for waypoints in paths:
        trajectory, instance = toppra_time(waypoints)
        times = []
        for _ in range(args.rounds):
            start = time.perf_counter()
            toppra_time(waypoints)
            times.append(time.perf_counter() - start)
        grid = len(instance.problem_data.gridpoints)
        # toppra enforces the limits at its grid points only: its worst ratio between them.
        ts = np.linspace(0, trajectory.duration, 20001)
        over_v = np.max(np.abs(trajectory(ts, 1)) / np.array(VELOCITY))
        over_a = np.max(np.abs(trajectory(ts, 2)) / np.array(ACCELERATION))
        toppra_rows.append(
            {"duration_s": trajectory.duration, "grid_points": grid, "s": statistics.median(times), "v": over_v, "a": over_a}
        )

    subprocess.run(
        ["cargo", "build", "--release", "-q", "--manifest-path", str(ROOT / "bench/Cargo.toml"), "--bin", "retime_timing"],
        check=True,
    )
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        f.write(" ".join(map(repr, VELOCITY)) + "\n" + " ".join(map(repr, ACCELERATION)) + "\n")
        for waypoints in paths:
            f.write(f"{len(waypoints)}\n")
            for row in waypoints:
                f.write(" ".join(repr(float(v)) for v in row) + "\n")
        name = f.name
    out = subprocess.run(
        [str(ROOT / "bench/target/release/retime_timing"), name, str(args.points_per_piece), str(args.rounds)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    reach_rows = [json.loads(line) for line in out.splitlines() if line.strip()]

    print(f"{'path':>4} {'toppra s':>10} {'reach s':>10} {'ratio':>8} {'toppra ms':>10} {'reach ms':>9} {'speed-up':>8}")
    duration_ratios, speedups = [], []
    for i, (t, r) in enumerate(zip(toppra_rows, reach_rows)):
        dr = r["duration_s"] / t["duration_s"]
        su = t["s"] / (r["ns"] * 1e-9)
        duration_ratios.append(dr)
        speedups.append(su)
        print(
            f"{i:>4} {t['duration_s']:>10.5f} {r['duration_s']:>10.5f} {dr:>8.5f} {t['s'] * 1e3:>10.3f} "
            f"{r['ns'] * 1e-6:>9.4f} {su:>8.1f}"
        )
    worst_v = max(r["worst_velocity_ratio"] for r in reach_rows)
    worst_a = max(r["worst_acceleration_ratio"] for r in reach_rows)
    print()
    print(f"grid points: toppra median {statistics.median(t['grid_points'] for t in toppra_rows)}, "
          f"reach median {statistics.median(r['grid_points'] for r in reach_rows)}")
    print(f"duration reach/toppra: median {statistics.median(duration_ratios):.5f}, "
          f"min {min(duration_ratios):.5f}, max {max(duration_ratios):.5f}")
    print(f"time per path: toppra median {statistics.median(t['s'] for t in toppra_rows) * 1e3:.3f} ms, "
          f"reach median {statistics.median(r['ns'] for r in reach_rows) * 1e-6:.4f} ms, "
          f"speed-up median {statistics.median(speedups):.1f}x")
    print(f"reach worst ratio to a limit between grid points (exact): velocity {worst_v:.12f}, acceleration {worst_a:.12f}")
    print(f"toppra worst ratio to a limit at 20001 samples of each trajectory: velocity "
          f"{max(t['v'] for t in toppra_rows):.6f}, acceleration {max(t['a'] for t in toppra_rows):.6f}")


if __name__ == "__main__":
    main()
