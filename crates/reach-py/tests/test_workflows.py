"""Workflows through the jobs layer: the same requests as the CLI, the same reports."""

import json

import numpy as np
import pytest

import reach
from conftest import ROOT


def _same(ours, theirs, where="report"):
    """Equal reports: ours against the CLI's JSON with its numeric lists as numpy
    (``reach._convert.arrays``, what every report goes through)."""
    from reach._convert import arrays

    _equal(ours, arrays(theirs), where)


def _equal(a, b, where):
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), where
        for k in a:
            _equal(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            _equal(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12, err_msg=where)
    else:
        assert a == b, where


TRAJECTORY = ("t", "q", "qd", "qdd", "tool_xyz", "tool_rpy")


def _same_motion(ours, theirs, where="report"):
    """A motion's report against the CLI's: its arrays against the CLI's samples (in SI),
    everything else equal."""
    samples = theirs["samples"]
    np.testing.assert_allclose(ours["t"], [s["t_s"] for s in samples], rtol=0, atol=0, err_msg=where)
    np.testing.assert_allclose(ours["tool_xyz"], [s["xyz_m"] for s in samples], rtol=0, atol=1e-12, err_msg=where)
    assert ours["q"].shape == (len(samples), len(samples[0]["q_deg"])), where
    _same({k: v for k, v in ours.items() if k not in TRAJECTORY}, {k: v for k, v in theirs.items() if k != "samples"}, where)


def test_move_equals_the_cli(cli):
    ur5 = reach.Robot.preset("ur5")
    report = ur5.move(**{"from": {"joints": {"deg": [0, -90, 90, 0, 90, 0]}}, "to": {"joints": {"deg": [30, -60, 60, 30, 60, 30]}}, "duration_s": 2.0})
    theirs = cli("move", "ur5", "--from", "0,-90,90,0,90,0", "--to", "30,-60,60,30,60,30", "--duration", "2")
    _same_motion(report, theirs)


def test_track_is_a_tool_space_move():
    ur5 = reach.Robot.preset("ur5")
    a = ur5.track(**{"from": {"joints": {"deg": [0, -90, 90, 0, 90, 0]}}, "to": {"joints": {"deg": [10, -80, 80, 0, 90, 0]}}, "duration_s": 1.0})
    b = ur5.run({"kind": "move", "space": "tool", "from": {"joints": {"deg": [0, -90, 90, 0, 90, 0]}}, "to": {"joints": {"deg": [10, -80, 80, 0, 90, 0]}}, "duration_s": 1.0})
    assert json.dumps(a, default=lambda x: x.tolist()) == json.dumps(b, default=lambda x: x.tolist())


def test_plan_of_an_example_task_file_equals_the_cli(cli):
    task = ROOT / "examples" / "seed001_tool_vs_joint.toml"
    spbu6 = reach.Robot.preset("spbu6")
    ours, theirs = spbu6.plan(task=task.read_text()), cli("plan", task)
    assert len(ours["motions"]) == len(theirs["motions"])
    for i, (a, b) in enumerate(zip(ours["motions"], theirs["motions"])):
        _same_motion(a, b, f"motions[{i}]")
    _same({k: v for k, v in ours.items() if k != "motions"}, {k: v for k, v in theirs.items() if k != "motions"})


def test_drive_equals_the_cli(cli):
    planar3 = reach.Robot.preset("planar3")
    ours = planar3.drive(motion={"point_to_point": {"from": {"deg": [0, 0, 0]}, "to": {"deg": [30, -20, -10]}, "duration_s": 2.0}})
    theirs = cli("drive", "planar3", "--from", "0,0,0", "--to", "30,-20,-10", "--duration", "2", "--format", "json")
    _same(ours, theirs)


def test_run_takes_any_request(cli):
    puma = reach.Robot.preset("puma560")
    ours = puma.run({"kind": "fk", "q": {"deg": [10, 20, 30, 40, 50, 60]}})
    _same(ours, cli("fk", "puma560", 10, 20, 30, 40, 50, 60))
    again = puma.run('{"kind": "jacobian", "q": {"rad": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]}}')
    np.testing.assert_allclose(again["jacobian"], puma.jacobian([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]), atol=0)


def test_time_parameterize_equals_retime_and_speaks_si(cli, tmp_path):
    panda = reach.Robot.preset("panda")
    deg = np.array([[0, -17, 0, -126, 0, 115, 45], [30, 0, 20, -100, 10, 90, 0], [10, -30, 0, -140, 0, 100, 45]])
    ours = panda.time_parameterize(np.radians(deg), max_acceleration_scale=0.5)
    csv = tmp_path / "w.csv"
    csv.write_text("\n".join(",".join(str(v) for v in row) for row in deg))
    theirs = cli("retime", "panda", csv, "--max-acceleration-scale", "0.5")
    assert abs(ours["duration_s"] - theirs["duration_s"]) < 1e-9
    assert ours["q"].shape == (len(theirs["samples"]), 7) and ours["t"].shape == (len(theirs["samples"]),)
    np.testing.assert_allclose(ours["qd"], [s["qd"] for s in theirs["samples"]], atol=1e-9)
    np.testing.assert_allclose(ours["q"][-1], np.radians(deg[-1]), atol=1e-12)
    assert max(ours["worst_acceleration_ratio"]) <= 1 + 1e-9
    with pytest.raises(ValueError, match="waypoints"):
        panda.time_parameterize(np.radians(deg[0]))
