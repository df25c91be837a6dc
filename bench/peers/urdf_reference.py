#!/usr/bin/env python3
"""URDF forward kinematics and Jacobians from Pinocchio: the reference for reach's URDF loader.

Writes (to stdout) the fixture `crates/reach/tests/data/panda_urdf_reference.json` that
`crates/reach/tests/it/urdf_panda.rs` compares reach against. For every case (a URDF file and
a chain base link -> tip link), 100 joint vectors are drawn inside the limits (numpy seed
2024), and the script records the tip frame relative to the base frame (position, rotation
matrix) and the 6xn geometric Jacobian of the tip origin in base axes (rows vx vy vz wx wy wz).

Pinocchio loads every movable URDF joint as an independent joint. The script applies the
`<mimic>` rule itself, q_mimic = multiplier * q_master + offset, and folds the Jacobian with the
chain rule (column of the master += multiplier * column of the mimic joint). A mimic joint
whose master is not on the chain is held at its offset (reach's rule for that case). The
columns kept are those of the chain's independent joints, in chain order: reach's joint vector.

Run from the repository root:
    python3 -m venv /tmp/urdf-venv
    /tmp/urdf-venv/bin/pip install -r bench/peers/requirements-urdf.txt
    /tmp/urdf-venv/bin/python bench/peers/urdf_reference.py > crates/reach/tests/data/panda_urdf_reference.json
"""

import json
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

SEED = 2024
SAMPLES = 100
CASES = [
    ("examples/panda.urdf", "panda_link0", "panda_hand"),
    ("examples/panda.urdf", "panda_link0", "panda_leftfinger"),
    ("examples/panda.urdf", "panda_link0", "panda_rightfinger"),
    ("crates/reach/tests/data/mimic_arm.urdf", "base", "tool"),
    ("crates/reach/tests/data/mimic_arm.urdf", "base", "side_tip"),
]
MOVABLE = {"revolute", "continuous", "prismatic"}


def chain_joints(path, base, tip):
    """The URDF joints from base to tip (names, types, mimic data), read from the XML."""
    root = ET.parse(path).getroot()
    by_child = {}
    for j in root.findall("joint"):
        mimic = j.find("mimic")
        by_child[j.find("child").get("link")] = {
            "name": j.get("name"),
            "type": j.get("type"),
            "parent": j.find("parent").get("link"),
            "mimic": None
            if mimic is None
            else (mimic.get("joint"), float(mimic.get("multiplier", 1.0)), float(mimic.get("offset", 0.0))),
        }
    out, link = [], tip
    while link != base:
        j = by_child[link]
        out.append(j)
        link = j["parent"]
    return out[::-1]


def case(path, base, tip, rng):
    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    joints = [j for j in chain_joints(path, base, tip) if j["type"] in MOVABLE]
    independent = [j["name"] for j in joints if j["mimic"] is None]
    lower = np.array([model.lowerPositionLimit[model.joints[model.getJointId(n)].idx_q] for n in independent])
    upper = np.array([model.upperPositionLimit[model.joints[model.getJointId(n)].idx_q] for n in independent])
    base_id, tip_id = model.getFrameId(base), model.getFrameId(tip)
    samples = []
    for _ in range(SAMPLES):
        q_user = lower + (upper - lower) * rng.random(len(independent))
        value = dict(zip(independent, q_user))
        q = pin.neutral(model)  # joints off the chain stay at zero
        for j in joints:
            if j["mimic"] is not None:
                master, mult, off = j["mimic"]
                value[j["name"]] = mult * value[master] + off if master in independent else off
        for name, v in value.items():
            q[model.joints[model.getJointId(name)].idx_q] = v
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        o_base, o_tip = data.oMf[base_id], data.oMf[tip_id]
        rel = o_base.inverse() * o_tip
        jac = pin.computeFrameJacobian(model, data, q, tip_id, pin.LOCAL_WORLD_ALIGNED)
        r = o_base.rotation.T
        jac = np.vstack([r @ jac[:3], r @ jac[3:]])
        reduced = np.zeros((6, len(independent)))
        for j in joints:
            col = jac[:, model.joints[model.getJointId(j["name"])].idx_v]
            if j["mimic"] is None:
                reduced[:, independent.index(j["name"])] += col
            elif j["mimic"][0] in independent:
                reduced[:, independent.index(j["mimic"][0])] += j["mimic"][1] * col
        samples.append(
            {
                "q": q_user.tolist(),
                "position": rel.translation.tolist(),
                "rotation": rel.rotation.tolist(),
                "jacobian": reduced.tolist(),
            }
        )
    return {"urdf": path, "base": base, "tip": tip, "joints": independent, "samples": samples}


def main():
    rng = np.random.default_rng(SEED)
    out = {
        "generator": "bench/peers/urdf_reference.py",
        "pinocchio": pin.__version__,
        "seed": SEED,
        "note": "rotation: row-major 3x3; jacobian: 6 rows (vx vy vz wx wy wz) of one entry per joint, base axes, tip origin",
        "cases": [case(p, b, t, rng) for p, b, t in CASES],
    }
    json.dump(out, sys.stdout, separators=(",", ":"))
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
