#!/usr/bin/env python3
"""Numeric IK: reach against the Robotics Toolbox for Python on the same random-pose protocol.

Protocol (identical to reach's `examples/ik_protocol.rs`, same poses): for each robot,
N random joint vectors inside the limits (revolute ranges cut to [-pi, pi]) drawn with
SplitMix64 from the same seed -> forward kinematics -> IK from a FIXED start, the robot's
home configuration, full 6-D pose. A solve succeeds when the returned configuration is inside
the joint limits and its pose, recomputed by forward kinematics, is within 1e-6 m and 1e-6 rad
of the target. Times are wall-clock per call (median, 95th percentile), in microseconds.

Robots are built from reach's own preset files (crates/reach/robots/*.toml: standard or modified DH,
lengths, twists, offsets, limits, home, tool), so both libraries solve the same chains.

Peers:
  * rtb ik_LM   -- Levenberg-Marquardt (C++ core), q0 = home, tol on E = 1/2 e'e set to
                   5e-13 (= 1/2 (1e-6)^2), joint limits on, default restarts (slimit=100,
                   ilimit=30) as the library ships them;
  * rtb ikine_a -- the analytic Puma 560 solution (Python), config "lun", puma560 only.

Usage:
  python ik_compare.py                    # runs `cargo run --release -p reach --example ik_protocol -- --json`
  python ik_compare.py --poses 1000
  python ik_compare.py --reach-json out.json   # reuse a saved reach result
"""

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time
import tomllib

import numpy as np
import roboticstoolbox as rtb
from spatialmath import SE3

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MASK64 = (1 << 64) - 1


class SplitMix64:
    """Same generator and same mapping to [0, 1) as reach's protocol."""

    def __init__(self, seed):
        self.state = seed & MASK64

    def uniform(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK64
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
        z ^= z >> 31
        return (z >> 11) / float(1 << 53)


def load_preset(name):
    """An rtb DHRobot from crates/reach/robots/<name>.toml, plus the limits and home in SI units / radians."""
    with open(os.path.join(REPO, "crates", "reach", "robots", f"{name}.toml"), "rb") as f:
        spec = tomllib.load(f)
    ls = {"m": 1.0, "mm": 1e-3}[spec.get("length_unit", "m")]
    an = {"rad": 1.0, "deg": math.pi / 180.0}[spec.get("angle_unit", "rad")]
    mdh = spec.get("convention", "dh") == "mdh"
    links, qlim, home = [], [], []
    for j in spec["joints"]:
        if j.get("kind", "revolute") != "revolute" or j.get("flip", False):
            raise SystemExit(f"{name}: only plain revolute joints are supported here")
        lo, hi = (v * an for v in j.get("limits", [-180 / an * an, 180]))
        args = dict(d=j.get("d", 0.0) * ls, a=j.get("a", 0.0) * ls, alpha=j.get("alpha", 0.0) * an,
                    offset=j.get("theta", 0.0) * an, qlim=[lo, hi])
        links.append(rtb.RevoluteMDH(**args) if mdh else rtb.RevoluteDH(**args))
        qlim.append((lo, hi))
        # reach's default home: 0 if inside the limits, else the middle of the range.
        h = j.get("home")
        home.append(h * an if h is not None else (0.0 if lo <= 0.0 <= hi else 0.5 * (lo + hi)))
    tool = SE3()
    if "tool" in spec:
        xyz = [v * ls for v in spec["tool"].get("xyz", [0, 0, 0])]
        rpy = [v * an for v in spec["tool"].get("rpy", [0, 0, 0])]
        # reach: fixed axes X then Y then Z, R = Rz(yaw) Ry(pitch) Rx(roll).
        tool = SE3(*xyz) * SE3.RPY(rpy, order="zyx")
    base = SE3()
    if "base" in spec:
        xyz = [v * ls for v in spec["base"].get("xyz", [0, 0, 0])]
        rpy = [v * an for v in spec["base"].get("rpy", [0, 0, 0])]
        base = SE3(*xyz) * SE3.RPY(rpy, order="zyx")
    robot = rtb.DHRobot(links, name=name, tool=tool, base=base)
    return robot, qlim, np.array(home)


def random_q(qlim, rng):
    q = []
    for lo, hi in qlim:
        lo, hi = max(lo, -math.pi), min(hi, math.pi)
        q.append(lo + (hi - lo) * rng.uniform())
    return np.array(q)


def pose_errors(T, Tq):
    dp = np.linalg.norm(T[:3, 3] - Tq[:3, 3])
    R = T[:3, :3].T @ Tq[:3, :3]
    vee = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return dp, math.atan2(0.5 * np.linalg.norm(vee), 0.5 * (np.trace(R) - 1.0))


def within(qlim, q, slack=1e-9):
    return all(lo - slack <= v <= hi + slack for v, (lo, hi) in zip(q, qlim))


def stats(times, successes, n):
    t = np.array(times)
    return {"successes": successes, "success_rate": successes / n, "median_us": float(np.median(t)),
            "p95_us": float(np.percentile(t, 95)), "mean_us": float(t.mean())}


def run_peer(name, poses, seed, random_start=False):
    robot, qlim, home = load_preset(name)
    rng = SplitMix64(seed)
    qs = [random_q(qlim, rng) for _ in range(poses)]
    # --random-start: the same start sequence as ik_protocol.rs (its own SplitMix64 stream),
    # one search per pose (slimit=1).
    start_rng = SplitMix64(seed ^ 0x574741525453)
    q0s = [random_q(qlim, start_rng) for _ in range(poses)] if random_start else [home] * poses
    slimit = 1 if random_start else 100
    targets = [robot.fkine(q).A for q in qs]
    # rtb 1.5's ik_LM on a DHRobot with a tool ends at fkine(q) = Tep * tool^-1 (checked on
    # panda: the result misses T by exactly the tool), so it is given Tep = T * tool; success
    # is judged on the tool pose by fkine.
    tool = robot.tool.A
    results = {}
    times, ok = [], 0
    for T, q0 in zip(targets, q0s):
        t0 = time.perf_counter()
        sol = robot.ik_LM(T @ tool, q0=q0, tol=5e-13, joint_limits=True, slimit=slimit)
        times.append((time.perf_counter() - t0) * 1e6)
        if sol.success:
            dp, da = pose_errors(T, robot.fkine(sol.q).A)
            if dp <= 1e-6 and da <= 1e-6 and within(qlim, sol.q):
                ok += 1
    results["rtb ik_LM"] = stats(times, ok, poses)
    if name == "puma560" and not random_start:
        # ikine_a solves rtb's own Puma560 model, whose d1 is 0.67183 m (reach's preset:
        # 0.6718 m); its targets are that model's FK of the same joint vectors.
        puma = rtb.models.DH.Puma560()
        times, ok = [], 0
        for q in qs:
            T = puma.fkine(q).A
            t0 = time.perf_counter()
            sol = puma.ikine_a(SE3(T, check=False), config="lun")
            times.append((time.perf_counter() - t0) * 1e6)
            if sol.success:
                dp, da = pose_errors(T, puma.fkine(sol.q).A)
                if dp <= 1e-6 and da <= 1e-6:
                    ok += 1
        results["rtb ikine_a (one config, no limits)"] = stats(times, ok, poses)
    return results


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--poses", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--robots", default="ur5,puma560,panda")
    ap.add_argument("--random-start", action="store_true",
                    help="one search per pose from a random start (reach: --restarts 1 --random-start; rtb: slimit=1)")
    ap.add_argument("--reach-json", help="reach protocol output (JSON) to use instead of running cargo")
    args = ap.parse_args()
    robots = args.robots.split(",")

    if args.reach_json:
        with open(args.reach_json) as f:
            reach_rows = json.load(f)
    else:
        cmd = ["cargo", "run", "--release", "--quiet", "-p", "reach", "--example", "ik_protocol", "--",
               "--json", "--poses", str(args.poses),
               *(["--restarts", "1", "--random-start"] if args.random_start else []), "--seed", str(args.seed), "--robots", ",".join(robots)]
        out = subprocess.run(cmd, cwd=REPO, check=True, capture_output=True, text=True)
        reach_rows = json.loads(out.stdout)
    reach = {r["robot"]: r for r in reach_rows}

    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load {os.getloadavg()[0]:.1f}; python {platform.python_version()}, "
          f"roboticstoolbox {rtb.__version__}, numpy {np.__version__}")
    print(f"protocol: {args.poses} random reachable poses per robot (seed {args.seed}), "
          f"start = {'random, one search' if args.random_start else 'home, restarts'}, "
          f"success = within limits and 1e-6 m / 1e-6 rad by FK")
    print()
    print("| robot | solver | success % | median µs | p95 µs | mean µs |")
    print("|---|---|---|---|---|---|")
    for name in robots:
        r = reach.get(name)
        if r:
            print(f"| {name} | reach numeric (first found) | {100 * r['success_rate']:.2f} | "
                  f"{r['median_us']:.1f} | {r['p95_us']:.1f} | {r['mean_us']:.1f} |")
        for solver, s in run_peer(name, args.poses, args.seed, args.random_start).items():
            print(f"| {name} | {solver} | {100 * s['success_rate']:.2f} | {s['median_us']:.1f} | "
                  f"{s['p95_us']:.1f} | {s['mean_us']:.1f} |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
