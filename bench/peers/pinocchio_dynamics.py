#!/usr/bin/env python3
"""URDF arms' inverse dynamics, gravity load and mass matrix from Pinocchio.

Writes (with --out) a JSON fixture of Pinocchio's `rnea(q, qd, qdd)`,
`computeGeneralizedGravity(q)` and `crba(q)` (its upper triangle mirrored: Pinocchio fills
only that) for 20 random states (numpy seed 35) of each URDF arm with inertias that the
repository ships: the KUKA KR 16-2 and KR 120 R2500 pro (examples/urdf/). reach's test
`crates/reach/tests/it/dynamics_urdf.rs` loads the same files and compares
`batch::inverse_dynamics_many` and `batch::mass_matrix_many` to 1e-9
(`crates/reach/tests/data/reference/urdf_dynamics.json`).

Both use the standard gravity [0, 0, -9.80665] m/s^2 (reach's default; Pinocchio's is
-9.81, set here). Joint values are uniform inside the URDF's limits, rates in [-2, 2] rad/s,
accelerations in [-5, 5] rad/s^2.

Usage (a venv of its own: Pinocchio comes as cmeel wheels, bench/peers/requirements-urdf.txt):
  python3 -m venv /tmp/pin-venv && /tmp/pin-venv/bin/pip install -r bench/peers/requirements-urdf.txt
  /tmp/pin-venv/bin/python bench/peers/pinocchio_dynamics.py --out crates/reach/tests/data/reference/urdf_dynamics.json
"""

import argparse
import json
import pathlib
import sys

import numpy as np
import pinocchio as pin

ROOT = pathlib.Path(__file__).resolve().parents[2]
ARMS = {
    "kr16_2": "examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf",
    "kr120r2500pro": "examples/urdf/kuka_kr120_support/urdf/kr120r2500pro.urdf",
}
GRAVITY = [0.0, 0.0, -9.80665]
STATES = 20


def arm(name: str, path: str, rng: np.random.Generator) -> dict:
    model = pin.buildModelFromUrdf(str(ROOT / path))
    model.gravity.linear = np.array(GRAVITY)
    data = model.createData()
    if model.nq != model.nv:
        raise SystemExit(f"{name}: a joint with nq != nv (continuous?), not compared")
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    states = []
    for _ in range(STATES):
        q = rng.uniform(lo, hi)
        qd = rng.uniform(-2.0, 2.0, model.nv)
        qdd = rng.uniform(-5.0, 5.0, model.nv)
        tau = pin.rnea(model, data, q, qd, qdd).copy()
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        m = pin.crba(model, data, q).copy()
        m = np.triu(m) + np.triu(m, 1).T
        states.append(
            {"q": q.tolist(), "qd": qd.tolist(), "qdd": qdd.tolist(), "tau": tau.tolist(), "gravity": g.tolist(), "mass_matrix": m.tolist()}
        )
    joints = [model.names[i] for i in range(1, model.njoints)]
    return {"urdf": path, "joints": joints, "states": states}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the fixture here (default: print it)")
    args = parser.parse_args()
    rng = np.random.default_rng(35)
    fixture = {
        "source": f"Pinocchio {pin.__version__}: rnea, computeGeneralizedGravity, crba (bench/peers/pinocchio_dynamics.py)",
        "gravity_m_s2": GRAVITY,
        "arms": {name: arm(name, path, rng) for name, path in ARMS.items()},
    }
    text = json.dumps(fixture, indent=1) + "\n"
    if args.out:
        pathlib.Path(args.out).write_text(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
