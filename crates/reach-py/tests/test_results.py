"""Issue 35, point 9: one unit in every result, trajectories as arrays, scenes as objects or
files, a flat check verdict, a useful repr and the viewer inline in a notebook."""

import html
import json
import pathlib
import re
import subprocess

import numpy as np
import pytest

import reach
from conftest import ROOT, _reach_bin

START = [0, -90, 90, 0, 90, 0]
GOAL = [30, -60, 60, 30, 60, 30]
BALL = ROOT / "examples" / "ur5_ball.toml"


def _move(robot, **kw):
    return robot.move(**{"from": {"joints": {"deg": START}}, "to": {"joints": {"deg": GOAL}}, "duration_s": 2.0}, **kw)


def test_move_returns_si_arrays(cli):
    ur5 = reach.Robot.preset("ur5")
    ours = _move(ur5)
    theirs = cli("move", "ur5", "--from", ",".join(map(str, START)), "--to", ",".join(map(str, GOAL)), "--duration", "2")
    samples = theirs.pop("samples")
    m = len(samples)
    assert "samples" not in ours and isinstance(ours, dict) and isinstance(ours, reach.Motion)
    assert ours["t"].shape == (m,) and ours["q"].shape == ours["qd"].shape == ours["qdd"].shape == (m, 6)
    # Radians although the request is in degrees.
    np.testing.assert_allclose(ours["q"][0], np.radians(START), atol=1e-12)
    np.testing.assert_allclose(ours["q"][-1], np.radians(GOAL), atol=1e-12)
    np.testing.assert_allclose(ours["q"], np.radians([s["q_deg"] for s in samples]), atol=1e-12)
    np.testing.assert_allclose(ours["qd"], np.radians([s["qd_deg_s"] for s in samples]), atol=1e-12)
    np.testing.assert_allclose(ours["t"], [s["t_s"] for s in samples], atol=0)
    np.testing.assert_allclose(ours["tool_xyz"], [s["xyz_m"] for s in samples], atol=1e-12)
    np.testing.assert_allclose(ours["tool_rpy"], np.radians([s["rpy_deg"] for s in samples]), atol=1e-12)
    # qdd is the rate of qd (the library's three-point rule on q); a smooth profile starts
    # and ends at rest.
    np.testing.assert_allclose(ours["qdd"][1:-1], np.gradient(ours["qd"], ours["t"], axis=0)[1:-1], atol=2e-2)
    assert np.abs(ours["qdd"]).max() > 0.1
    # The rest of the report is the CLI's.
    for key in ("duration_s", "feasible", "reasons", "intervals", "events", "space"):
        assert json.dumps(ours[key], default=lambda x: x.tolist()) == json.dumps(theirs[key]), key
    assert abs(ours["effort"]["energy_j"] - theirs["effort"]["energy_j"]) < 1e-9
    # Degrees only when asked for.
    deg = _move(ur5, degrees=True)
    np.testing.assert_allclose(deg["q"], np.degrees(ours["q"]), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(deg["qdd"], np.degrees(ours["qdd"]), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(deg["t"], ours["t"], atol=0)


def _rrp():
    """A base yaw, a shoulder and a slide (limits: ±180°, -90°..90°, 0..0.5 m)."""
    rows = [[0, np.pi / 2, 0.3, 0, -np.pi, np.pi], [0.4, 0, 0, 0, -np.pi / 2, np.pi / 2], [0, 0, 0.1, 0, 0, 0.5]]
    return reach.Robot.from_dh(rows, prismatic=[2], name="rrp")


def test_move_returns_si_arrays_prismatic_in_metres():
    rrp = _rrp()
    start, goal = [0.0, 0.1, 0.1], [0.5, -0.2, 0.3]
    req = {"from": {"joints": {"rad": start}}, "to": {"joints": {"rad": goal}}, "duration_s": 1.0}
    r = rrp.move(**req)
    np.testing.assert_allclose(r["q"][0], start, atol=1e-12)
    np.testing.assert_allclose(r["q"][-1], goal, atol=1e-12)
    d = rrp.move(**req, degrees=True)
    np.testing.assert_allclose(d["q"][:, 2], r["q"][:, 2], atol=0)  # metres either way
    np.testing.assert_allclose(d["qd"][:, 2], r["qd"][:, 2], atol=0)
    np.testing.assert_allclose(d["q"][:, :2], np.degrees(r["q"][:, :2]), atol=1e-12)


def test_track_returns_si_arrays():
    ur5 = reach.Robot.preset("ur5")
    r = ur5.track(**{"from": {"joints": {"deg": START}}, "to": {"joints": {"deg": [10, -80, 80, 0, 90, 0]}}, "duration_s": 1.0})
    assert r["space"] == "tool"
    np.testing.assert_allclose(r["tool_xyz"][0], ur5.fk(np.radians(START))[:3, 3], atol=1e-9)
    # Issue 35 point 1: the motion starts at the joint values given, on their branch.
    np.testing.assert_allclose(r["q"][0], np.radians(START), atol=1e-12)
    assert r["intervals"][0]["decision"] == "start"
    # The tool moves on a straight line: every sample's FK is its tool_xyz.
    np.testing.assert_allclose(ur5.fk(r["q"])[:, :3, 3], r["tool_xyz"], atol=1e-9)


def test_plan_motions_carry_si_arrays(cli):
    task = ROOT / "examples" / "seed001_tool_vs_joint.toml"
    spbu6 = reach.Robot.preset("spbu6")
    ours = spbu6.plan(task=task.read_text())
    theirs = cli("plan", task)
    assert len(ours["motions"]) == len(theirs["motions"]) > 0
    for mine, cli_motion in zip(ours["motions"], theirs["motions"]):
        s = cli_motion["samples"]
        assert "samples" not in mine and mine["q"].shape == (len(s), spbu6.dof)
        want = np.array([x["q_deg"] for x in s])
        rev = np.array([k == "revolute" for k in spbu6.joint_kinds])
        want[:, rev] = np.radians(want[:, rev])
        np.testing.assert_allclose(mine["q"], want, atol=1e-12)
        assert mine["qdd"].shape == mine["q"].shape


def test_path_carries_si_arrays():
    planar3 = reach.Robot.preset("planar3")
    scene = ROOT / "examples" / "path_planar3_post.toml"
    r = planar3.path(scene=scene, duration_s=10.0, **{"from": {"deg": [60, -40, -30]}, "to": {"deg": [0, -30, -30]}})
    assert r["found"]
    np.testing.assert_allclose(r["q"][0], np.radians([60, -40, -30]), atol=1e-9)
    np.testing.assert_allclose(r["q"][-1], np.radians([0, -30, -30]), atol=1e-9)
    np.testing.assert_allclose(r["q"][[0, -1]], np.radians(np.array(r["waypoints_deg"])[[0, -1]]), atol=1e-9)
    np.testing.assert_allclose(planar3.fk(r["q"])[:, :3, 3], r["tool_xyz"], atol=1e-9)
    assert r["t"][-1] == pytest.approx(r["duration_s"], abs=1e-9)
    assert r["qd"].shape == r["qdd"].shape == r["q"].shape


def test_scene_as_object_file_path_or_text():
    ur5 = reach.Robot.preset("ur5")
    q = {"deg": [0, -90, 0, -90, 0, 0]}
    text = BALL.read_text()
    built = reach.Scene().add_sphere("ball", [0, -0.136, 0.3], 0.02)
    reports = [
        ur5.check(scene=s, q=q)
        for s in (text, BALL, str(BALL), reach.Scene.from_file(BALL), reach.Scene.from_toml(text), built)
    ]
    for r in reports[1:]:
        assert r["links"] == reports[0]["links"]
    assert reports[0]["verdict"] == "obstacle"
    assert repr(built) == "Scene(1 obstacle: 'ball')"
    assert built.obstacles == ["ball"] and built.tool_zone == []
    # Added to a file in millimetres and degrees: converted into its units.
    mm = reach.Scene.from_toml('length_unit = "mm"\nangle_unit = "deg"\n')
    mm.add_sphere("ball", [0, -0.136, 0.3], 0.02).add_box("crate", [0.5, 0.5, 0.1], [0.1, 0.1, 0.1], rpy=[0, 0, np.pi / 4])
    m = reach.Scene().add_sphere("ball", [0, -0.136, 0.3], 0.02).add_box("crate", [0.5, 0.5, 0.1], [0.1, 0.1, 0.1], rpy=[0, 0, np.pi / 4])
    a, b = ur5.check(scene=mm, q=q), ur5.check(scene=m, q=q)
    for x, y in zip(a["links"], b["links"]):
        assert x["obstacle"] == y["obstacle"] and x["clearance_m"] == pytest.approx(y["clearance_m"], abs=1e-12)
    assert repr(m) == "Scene(2 obstacles: 'ball', 'crate')"
    zone = reach.Scene().add_tool_zone("front", "halfspace", point=[0.2, 0, 0], outward_normal=[-1, 0, 0])
    assert zone.tool_zone == ["front"] and "tool zone: 'front'" in repr(zone)


def test_scene_errors_name_the_field(tmp_path):
    s = reach.Scene()
    with pytest.raises(reach.ReachError, match="radius"):
        s.add_sphere("ball", [0, 0, 0], -1)
    with pytest.raises(reach.ReachError, match="center: expected 3 numbers, got 2"):
        s.add_sphere("ball", [0, 0], 0.1)
    with pytest.raises(reach.ReachError, match="radius: expected finite"):
        s.add_sphere("ball", [0, 0, 0], float("nan"))
    with pytest.raises(reach.ReachError, match="unknown shape `cone`"):
        s.add("c", "cone", center=[0, 0, 0])
    assert s.obstacles == []  # a refused entry is not kept
    with pytest.raises(OSError, match="nope.toml"):
        reach.Scene.from_file(tmp_path / "nope.toml")
    with pytest.raises(ValueError, match="scene: no such scene file `nope.toml`"):
        reach.Robot.preset("ur5").check(scene="nope.toml", q={"deg": [0] * 6})
    bad = tmp_path / "bad.toml"
    bad.write_text('length_unit = "m"\n[[obstacles]]\nname = "b"\nshape = "sphere"\ncenter = [0, 0]\nradius = 1\n')
    with pytest.raises(reach.ReachError, match="bad.toml: scene file, line 5"):
        reach.Scene.from_file(bad)


def test_check_verdict_is_flat(cli):
    ur5 = reach.Robot.preset("ur5")
    q = [0, -90, 0, -90, 0, 0]
    ours = ur5.check(scene=BALL, q={"deg": q})
    theirs = cli("check", "ur5", BALL, *q)
    assert ours["verdict"] == theirs["verdict"]["verdict"] == "obstacle"
    assert ours["verdict_link"] == theirs["verdict"]["link"] == 3
    assert ours["verdict_obstacle"] == 0 and ours["clear"] is False
    assert ours["verdict_text"] == theirs["verdict_text"]
    free = ur5.check(scene=BALL, q={"deg": [180, -90, 0, -90, 0, 0]})
    assert free["verdict"] == "free" and free["clear"] is True
    assert not any(k.startswith("verdict_") and k != "verdict_text" for k in free)
    swept = ur5.check(scene=BALL, q={"deg": [180, -90, 0, -90, 0, 0]}, to={"deg": q})
    assert swept["verdict"] == "free" and swept["clear"] is False  # the start is free, the motion is not


def test_robot_repr():
    assert repr(reach.Robot.preset("ur5")) == (
        "Robot(name='ur5', dof=6, joints='RRRRRR', limits_deg=[±360, ±360, ±360, ±360, ±360, ±360], solver='parallel-axes')"
    )
    assert repr(_rrp()) == "Robot(name='rrp', dof=3, joints='RRP', limits_deg=[±180, ±90, 0..0.5], solver='numeric')"


def _cli_page(tmp_path, *args):
    binary = _reach_bin()
    if binary is None:
        pytest.skip("no reach binary")
    out = tmp_path / "view.html"
    subprocess.run([binary, "view", *map(str, args), "-o", out], check=True, capture_output=True)
    return out.read_text()


def _frame_page(frame):
    m = re.fullmatch(r'<iframe srcdoc="([^"]*)".*</iframe>', frame, flags=re.S)
    assert m, frame[:200]
    return html.unescape(m.group(1))


def test_repr_html_is_the_offline_viewer(tmp_path):
    ur5 = reach.Robot.preset("ur5")
    page = _frame_page(ur5._repr_html_())
    cli_page = _cli_page(tmp_path, "ur5")
    assert page == cli_page  # the page `reach view` exports, byte for byte
    assert ur5.view().html == cli_page
    bundle = re.search(r"<script>(.*)</script>", cli_page, flags=re.S).group(1)
    assert len(bundle) > 10_000
    assert '"robot":"ur5"' in page and not re.search(r"<script[^>]*\ssrc=", page)
    motion = _move(ur5)
    mpage = _frame_page(motion._repr_html_())
    assert bundle in mpage and '"robot":"ur5"' in mpage and not re.search(r"<script[^>]*\ssrc=", mpage)
    data = json.loads(re.search(r'<script id="reach-view-data" type="application/json">(.*?)</script>', mpage, flags=re.S).group(1))
    assert data["samples_total"] == len(motion["t"]) and data["duration_s"] == pytest.approx(2.0)
    scene = reach.Scene.from_file(BALL)
    assert "ball" in scene._repr_html_() and "<iframe" not in scene._repr_html_()
    scene.robot = ur5
    spage = _frame_page(scene._repr_html_())
    sdata = json.loads(re.search(r'<script id="reach-view-data" type="application/json">(.*?)</script>', spage, flags=re.S).group(1))
    assert len(sdata["shapes"]) == 1 and bundle in spage
    assert _frame_page(ur5.view(scene=BALL)._repr_html_()) == _cli_page(tmp_path, "ur5", "--scene", BALL)


def test_check_and_path_give_joint_values_in_si():
    ur5 = reach.Robot.preset("ur5")
    q = [180, -90, 0, -90, 0, 0]
    r = ur5.check(scene=BALL, q={"deg": q}, to={"deg": START})
    np.testing.assert_allclose(r["q"], np.radians(q), atol=1e-12)
    np.testing.assert_allclose(r["motion"]["to"], np.radians(START), atol=1e-12)
    np.testing.assert_allclose(ur5.check(scene=BALL, q={"deg": q}, degrees=True)["q"], q, atol=1e-12)
    planar3 = reach.Robot.preset("planar3")
    p = planar3.path(scene=ROOT / "examples" / "path_planar3_post.toml", duration_s=10.0, **{"from": {"deg": [60, -40, -30]}, "to": {"deg": [0, -30, -30]}})
    np.testing.assert_allclose(p["waypoints"], np.radians(p["waypoints_deg"]), atol=1e-12)


def test_plan_shows_its_motions_in_the_viewer(tmp_path):
    task = ROOT / "examples" / "seed001_tool_vs_joint.toml"
    spbu6 = reach.Robot.preset("spbu6")
    page = _frame_page(spbu6.plan(task=task.read_text())._repr_html_())
    assert page == _cli_page(tmp_path, "spbu6", "--plan", task)


def test_urdf_robot_is_shown_with_its_meshes(tmp_path):
    urdf = ROOT / "examples" / "urdf" / "kuka_kr16_support" / "urdf" / "kr16_2.urdf"
    kr16 = reach.Robot.from_file(urdf, tip="tool0")
    page = kr16.view().html
    assert page == _cli_page(tmp_path, urdf, "--tip", "tool0")
    data = json.loads(re.search(r'<script id="reach-view-data" type="application/json">(.*?)</script>', page, flags=re.S).group(1))
    assert len(data["urdf"]["meshes"]) == 7
    assert "urdf" not in json.loads(
        re.search(r'<script id="reach-view-data" type="application/json">(.*?)</script>', kr16.view(meshes=False).html, flags=re.S).group(1)
    )
    import pickle

    assert pickle.loads(pickle.dumps(kr16)).view().html == page
