"""Shared fixtures: the `reach` command line (for `--json` comparisons) and random poses."""

import json
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def _reach_bin():
    path = os.environ.get("REACH_BIN") or shutil.which("reach") or str(ROOT / "target" / "debug" / "reach")
    return path if pathlib.Path(path).exists() else None


@pytest.fixture(scope="session")
def cli():
    """Runs `reach ARGS --json` and returns the parsed report (skips when no binary is built)."""
    binary = _reach_bin()
    if binary is None:
        pytest.skip("no reach binary: build it with `cargo build -p reach-cli` or set REACH_BIN")

    def run(*args):
        args = [str(a) for a in args]
        if "--format" not in args:
            args.append("--json")
        out = subprocess.run([binary, *args], capture_output=True, text=True)
        # 3: no solution within limits / infeasible — the report is still printed
        assert out.returncode in (0, 3), out.stderr
        return json.loads(out.stdout)

    return run


def wrapped(a):
    """Angles wrapped into (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(a)))


def random_q(robot, n, seed):
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, (n, robot.dof))
