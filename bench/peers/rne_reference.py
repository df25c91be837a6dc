#!/usr/bin/env python3
"""Puma 560 inverse dynamics reference from the Robotics Toolbox for Python.

Prints (or writes with --out) a JSON fixture of `rne(q, qd, qdd)` of the toolbox's
`models.DH.Puma560` for 20 random states (numpy seed 560), which reach's test
`crates/reach/tests/dynamics_reference.rs` compares against
(`crates/reach/tests/data/reference/puma560_rne.json`).

Only the rigid-body model is compared: friction (viscous B and Coulomb Tc) is removed with
`nofriction(coulomb=True, viscous=True)` and the motor inertia Jm is set to 0, so the gear
ratios G no longer enter. Gravity is passed explicitly as [0, 0, -9.80665] m/s^2 (the toolbox's
default is -9.81). The toolbox's table equals reach's crates/reach/robots/puma560.toml (d1 = 0.6718 m, no
offsets); its link dynamic parameters (m, r, I) are the ones copied into that file.

Usage:
  /tmp/peers-venv/bin/python bench/peers/rne_reference.py --out crates/reach/tests/data/reference/puma560_rne.json
"""

import argparse
import json
import sys

import numpy as np
import roboticstoolbox as rtb

GRAVITY = [0.0, 0.0, -9.80665]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the fixture here instead of stdout")
    parser.add_argument("--states", type=int, default=20)
    args = parser.parse_args()

    robot = rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)
    for link in robot.links:
        link.Jm = 0.0
    rng = np.random.default_rng(560)
    states = []
    for k in range(args.states):
        q = rng.uniform(-np.pi, np.pi, 6)
        qd = rng.uniform(-2.0, 2.0, 6)
        qdd = rng.uniform(-5.0, 5.0, 6)
        if k == 0:  # one static state: gravity torques only
            qd[:] = 0.0
            qdd[:] = 0.0
        tau = robot.rne(q, qd, qdd, gravity=GRAVITY)
        states.append({"q": q.tolist(), "qd": qd.tolist(), "qdd": qdd.tolist(), "tau": np.asarray(tau).tolist()})
    fixture = {
        "source": f"roboticstoolbox-python {rtb.__version__}, models.DH.Puma560, nofriction(coulomb, viscous), Jm = 0",
        "robot": "puma560",
        "units": "q rad, qd rad/s, qdd rad/s^2, tau N·m",
        "gravity": GRAVITY,
        "states": states,
    }
    text = json.dumps(fixture, indent=1)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text + "\n")
    else:
        sys.stdout.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
