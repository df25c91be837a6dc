#!/usr/bin/env python3
"""Batch IK throughput: reach's `Robot.ik_all` (every branch, numpy batch) against the Robotics
Toolbox for Python (`ik_LM`, `ikine_a`) and, where installed, py-opw-kinematics, on the same poses.

Protocol: for `ur5` and `puma560`, N random joint vectors inside the limits (revolute ranges cut
to [-pi, pi]; SplitMix64 seed 2024, as `ik_compare.py`) -> forward kinematics -> IK of every
pose. Throughput is poses per second over the whole batch (conversion of the inputs included),
of wall time and of CPU time (this process, all threads: the cost on a loaded machine). reach is measured on one core (RAYON_NUM_THREADS=1, a separate process) and
on all cores; it returns every branch of every pose, each verified by FK. Correct = the
generating configuration is among the returned solutions (reach, py-opw `inverse`), or the
returned solution's pose is within 1e-6 m / 1e-6 rad of the target (rtb, py-opw `batch_inverse`).

Peers:
* rtb `ik_LM` (C++ Levenberg-Marquardt, one solution, from home, joint limits on), fewer poses
  (it is ~100x slower), per call in a Python loop;
* rtb `ikine_a` (analytic Puma 560, one configuration `"lun"`, on the toolbox's own Puma560);
* py-opw-kinematics (Rust rs-opw-kinematics): `batch_inverse` (one solution per pose, closest to
  the current joints) and `inverse` (all solutions) in a Python loop, on an OPW model with the
  Puma 560's lengths and its own FK of the same joint vectors (UR arms are not OPW arms).

Run: `python bench/peers/ik_batch_compare.py [--poses 10000]` in a venv holding
`bench/peers/requirements.txt` and reach (`pip install ./crates/reach-py`).
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))


def reach_throughput(name, poses, seed, repeats=3):
    """Poses per second of reach's ik_all in this process (threads as RAYON_NUM_THREADS says)."""
    import reach
    from ik_compare import SplitMix64, load_preset, random_q

    _, qlim, _ = load_preset(name)
    rng = SplitMix64(seed)
    q = np.array([random_q(qlim, rng) for _ in range(poses)])
    robot = reach.Robot.preset(name)
    T = robot.fk(q)
    best, best_cpu = float("inf"), float("inf")
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        out = robot.ik_all(T)
        best = min(best, time.perf_counter() - t0)
        best_cpu = min(best_cpu, time.process_time() - c0)
    d = np.abs(np.angle(np.exp(1j * (out["q"] - q[:, None, :])))).max(axis=2)
    hit = (np.where(out["valid"], d, np.inf).min(axis=1) < 1e-7).mean()
    return {"poses_per_s": poses / best, "poses_per_cpu_s": poses / best_cpu, "correct": float(hit),
            "solutions_per_pose": float(out["count"].mean())}


def reach_in_subprocess(name, poses, seed, threads):
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    else:
        env.pop("RAYON_NUM_THREADS", None)
    out = subprocess.run(
        [sys.executable, __file__, "--reach-only", name, "--poses", str(poses), "--seed", str(seed)],
        env=env, capture_output=True, text=True, check=True,
    )
    return json.loads(out.stdout)


class Clock:
    """Wall and CPU (this process, all threads) time of a block."""

    def __enter__(self):
        self.t0, self.c0 = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.wall, self.cpu = time.perf_counter() - self.t0, time.process_time() - self.c0

    def rates(self, n):
        return {"poses_per_s": n / self.wall, "poses_per_cpu_s": n / self.cpu}


def rtb_throughput(name, poses, seed):
    import roboticstoolbox as rtb
    from ik_compare import SplitMix64, load_preset, pose_errors, random_q, within
    from spatialmath import SE3

    robot, qlim, home = load_preset(name)
    rng = SplitMix64(seed)
    qs = [random_q(qlim, rng) for _ in range(poses)]
    targets = [robot.fkine(q).A for q in qs]
    tool = robot.tool.A
    res = {}
    ok = 0
    with Clock() as clock:
        sols = [robot.ik_LM(T @ tool, q0=home, tol=5e-13, joint_limits=True) for T in targets]
    for T, sol in zip(targets, sols):
        if sol.success:
            dp, da = pose_errors(T, robot.fkine(sol.q).A)
            ok += dp <= 1e-6 and da <= 1e-6 and within(qlim, sol.q)
    res["rtb ik_LM (one solution)"] = {**clock.rates(poses), "correct": ok / poses, "poses": poses}
    if name == "puma560":
        puma = rtb.models.DH.Puma560()
        Ts = [SE3(puma.fkine(q).A, check=False) for q in qs]
        with Clock() as clock:
            sols = [puma.ikine_a(T, config="lun") for T in Ts]
        ok = sum(bool(s.success) and pose_errors(T.A, puma.fkine(s.q).A)[0] <= 1e-6 for T, s in zip(Ts, sols))
        res["rtb ikine_a (one configuration)"] = {**clock.rates(poses), "correct": ok / poses, "poses": poses}
    return res


def opw_throughput(poses, seed):
    try:
        import py_opw_kinematics as opw
    except ImportError:
        return {}
    from ik_compare import SplitMix64, load_preset, random_q

    # Puma 560 lengths in OPW's parameters (its own frames; its own FK makes the targets).
    model = opw.KinematicModel(a1=0.0, a2=-0.0203, b=0.15005, c1=0.6718, c2=0.4318, c3=0.4318, c4=0.0)
    robot = opw.Robot(model, degrees=False)
    _, qlim, _ = load_preset("puma560")
    rng = SplitMix64(seed)
    q = np.array([random_q(qlim, rng) for _ in range(poses)])
    T = robot.batch_forward(q)
    res = {}
    with Clock() as clock:
        one = np.asarray(robot.batch_inverse(T))
    back = robot.batch_forward(np.nan_to_num(one))
    err = np.linalg.norm(back.translation - T.translation, axis=1)
    res["py-opw batch_inverse (one solution)"] = {**clock.rates(poses), "correct": float((err < 1e-6).mean()), "poses": poses}
    n = min(poses, 2000)
    with Clock() as clock:
        alls = [robot.inverse(T[i]) for i in range(n)]
    hit = np.mean([
        any(np.abs(np.angle(np.exp(1j * (np.array(s) - q[i])))).max() < 1e-7 for s in alls[i]) for i in range(n)
    ])
    res["py-opw inverse (all solutions, Python loop)"] = {**clock.rates(n), "correct": float(hit), "poses": n}
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--poses", type=int, default=10000)
    ap.add_argument("--rtb-poses", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--reach-only", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.reach_only:
        print(json.dumps(reach_throughput(args.reach_only, args.poses, args.seed)))
        return
    print(f"# {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    rows = []
    for name in ["ur5", "puma560"]:
        rows.append((name, "reach ik_all, 1 core (all branches)", reach_in_subprocess(name, args.poses, args.seed, 1)))
        rows.append((name, f"reach ik_all, {os.cpu_count()} cores (all branches)", reach_in_subprocess(name, args.poses, args.seed, 0)))
        try:
            for k, v in rtb_throughput(name, args.rtb_poses, args.seed).items():
                rows.append((name, k, v))
        except ImportError:
            pass
    for k, v in opw_throughput(args.poses, args.seed).items():
        rows.append(("puma560 (OPW)", k, v))
    print(f"{'robot':<15} {'solver':<48} {'poses/s':>10} {'poses/CPU-s':>12} {'correct':>8}")
    for name, k, v in rows:
        print(f"{name:<15} {k:<48} {v['poses_per_s']:>10,.0f} {v['poses_per_cpu_s']:>12,.0f} {100 * v['correct']:>7.2f}%")


if __name__ == "__main__":
    main()
