#!/usr/bin/env python3
"""reach next to Pinocchio (C++): forward kinematics and the frame Jacobian of real URDF arms.

Both libraries load the same URDF file and are timed on the same joint vectors (numpy seed
2024, uniform inside the URDF's limits cut to [-pi, pi]), each in its own compiled program:
reach's `bench/src/bin/urdf_timing.rs` (release) and `bench/peers/pinocchio/fk_jacobian.cpp`
(g++ -O3 -DNDEBUG against the headers and libraries of the `pin` wheels; the wheels ship no
urdfdom headers, so Pinocchio's Python loader builds the model from the URDF and the C++ program
reads it back with `Model::loadFromBinary`). Rounds alternate between the two programs; each
program reports the median over its passes; the ratio is reach / Pinocchio of the medians over
rounds. Before timing, the tool pose of the first joint vector must agree to 1e-9.

What is timed per call:
  FK        reach `Robot::fk_matrix(q)`;  Pinocchio `forwardKinematics` + `updateFramePlacement`
  Jacobian  reach `Robot::jacobian_into(q, J)` (geometric, tool point, world axes);
            Pinocchio `computeFrameJacobian(..., LOCAL_WORLD_ALIGNED, J)` (the same matrix; it
            runs its forward kinematics itself)

Run from the repository root (see bench/peers/README.md):
    python3 -m venv /tmp/pin-venv
    /tmp/pin-venv/bin/pip install -r bench/peers/requirements-urdf.txt
    /tmp/pin-venv/bin/python bench/peers/pinocchio_compare.py [--poses 1000] [--rounds 11]

The compiled Pinocchio program is kept in bench/target/peers/ (one per Pinocchio version) and
rebuilt only when its source is newer or with --rebuild: its g++ build takes minutes.
`--reach-bin PATH` times another build of `urdf_timing` (e.g. a copy of the previous one, to
alternate old and new code against the same Pinocchio program) instead of building it.

`--native` compiles the Pinocchio program with `-march=native` as well (cached separately):
Eigen then uses the vector instructions this processor has (AVX2, FMA, AVX-512), which reach's
kernels pick at run time (`reach::simd`). Without it both are compiled for the x86-64
baseline. With `--native` the table gets one more column: the ratio against each build.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

import numpy as np
import pinocchio as pin

ARMS = [
    ("ur5", "examples/urdf/ur_description/urdf/ur5.urdf", "ee_link"),
    ("puma560", "examples/urdf/unimation_puma560_description/urdf/puma560_robot.urdf", "link7"),
    ("kr16_2", "examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf", "tool0"),
    ("panda", "examples/panda.urdf", "panda_hand"),
]


CPP_SOURCE = pathlib.Path("bench/peers/pinocchio/fk_jacobian.cpp")


def build(reach_bin, rebuild, native=False):
    """Builds (or reuses) both programs; returns their paths (Pinocchio's compiled with
    -march=native when `native`)."""
    if reach_bin is None:
        subprocess.run(
            ["cargo", "build", "--release", "--quiet", "--manifest-path", "bench/Cargo.toml", "--bin", "urdf_timing"],
            check=True,
        )
        reach_bin = "bench/target/release/urdf_timing"
    elif not os.access(reach_bin, os.X_OK):
        sys.exit(f"--reach-bin {reach_bin}: not an executable file")
    cache = pathlib.Path("bench/target/peers")
    cache.mkdir(parents=True, exist_ok=True)
    cpp = cache / f"fk_jacobian-pinocchio-{pin.__version__}{'-native' if native else ''}"
    if not rebuild and cpp.exists() and cpp.stat().st_mtime >= CPP_SOURCE.stat().st_mtime:
        return reach_bin, str(cpp)
    prefix = pathlib.Path(pin.__file__).resolve()  # cmeel.prefix/lib/python3.X/site-packages/pinocchio
    while prefix.name != "cmeel.prefix":
        prefix = prefix.parent
    subprocess.run(
        ["g++", "-O3", "-DNDEBUG", "-std=c++17", *(["-march=native"] if native else []),
         # Pinocchio's exported compile definitions (lib/cmake/pinocchio/pinocchioTargets.cmake)
         "-DBOOST_MPL_LIMIT_LIST_SIZE=30", "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
         "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
         f"-I{prefix}/include", f"-I{prefix}/include/eigen3", str(CPP_SOURCE),
         "-o", str(cpp), f"-L{prefix}/lib", "-lpinocchio_default", "-lboost_serialization", f"-Wl,-rpath,{prefix}/lib"],
        check=True,
    )
    return reach_bin, str(cpp)


def run(cmd):
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=11, help="alternating rounds (each program: 3 passes per round)")
    ap.add_argument("--reach-bin", help="an already built urdf_timing to time (default: build it)")
    ap.add_argument("--rebuild", action="store_true", help="recompile the Pinocchio program(s)")
    ap.add_argument("--native", action="store_true",
                    help="also time Pinocchio compiled with -march=native (one more column)")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="reach-pin-")
    reach, cpp = build(args.reach_bin, args.rebuild)
    peers = {"pin": cpp}
    if args.native:
        peers["native"] = build(reach, args.rebuild, native=True)[1]
    print(f"reach vs Pinocchio {pin.__version__} (C++), {args.poses} joint vectors per arm, median of "
          f"{args.rounds} alternating rounds; ratio = reach / Pinocchio (< 1: reach faster)")
    if args.native:
        print("| arm (URDF) | operation | reach ns/call | Pinocchio ns/call | ratio "
              "| Pinocchio -march=native ns/call | ratio |")
        print("|---|---|---|---|---|---|---|")
    else:
        print("| arm (URDF) | operation | reach ns/call | Pinocchio ns/call | ratio |")
        print("|---|---|---|---|---|")
    for name, urdf, tip in ARMS:
        model = pin.buildModelFromUrdf(urdf)
        if name == "panda":
            # reach's chain ends at the hand; Pinocchio's model also has the two finger joints:
            # lock them (at 0) so both move the same 7 joints.
            fingers = [model.getJointId(j) for j in ("panda_finger_joint1", "panda_finger_joint2")]
            model = pin.buildReducedModel(model, fingers, pin.neutral(model))
        model_file = os.path.join(work, f"{name}.bin")
        model.saveToBinary(model_file)
        rng = np.random.default_rng(2024)
        lo = np.maximum(model.lowerPositionLimit, -np.pi)
        hi = np.minimum(model.upperPositionLimit, np.pi)
        qs = lo + (hi - lo) * rng.random((args.poses, model.nq))
        qs_file = os.path.join(work, f"{name}.txt")
        np.savetxt(qs_file, qs, fmt="%.17g")
        a = run([reach, urdf, tip, qs_file, "1"])
        for peer in peers.values():
            b = run([peer, model_file, tip, qs_file, "1"])
            gap = max(abs(x - y) for x, y in zip(a["tip0"], b["tip0"]))
            if a["nq"] != b["nq"] or gap > 1e-9:
                sys.exit(f"{name}: the two models differ (nq {a['nq']} / {b['nq']}, tool pose by {gap:g})")
        cmds = {"reach": [reach, urdf, tip, qs_file, "3"]}
        cmds.update({who: [peer, model_file, tip, qs_file, "3"] for who, peer in peers.items()})
        times = {who: {"fk_ns": [], "jacobian_ns": []} for who in cmds}
        for _ in range(args.rounds):
            for who, cmd in cmds.items():
                out = run(cmd)
                for key in ("fk_ns", "jacobian_ns"):
                    times[who][key].append(out[key])
        for key, op in (("fk_ns", "FK"), ("jacobian_ns", "Jacobian")):
            r = statistics.median(times["reach"][key])
            cells = "".join(f" {p:.0f} | {r / p:.2f} |"
                            for p in (statistics.median(times[who][key]) for who in peers))
            print(f"| {name} | {op} | {r:.0f} |{cells}")


if __name__ == "__main__":
    main()
