//! Regression tests for issue 35 ("a newcomer's first day"), one test per point, named after it.

use crate::common::{fails, json, nums, ok, reach, stdout_json};

/// Point 3: joint values take commas or blanks everywhere, also as one positional argument.
#[test]
fn point3_joint_values_take_commas_or_blanks_in_one_argument() {
    let separate = json(&["fk", "ur5", "10", "-80", "100", "-110", "10", "0", "--json"]);
    for q in ["10,-80,100,-110,10,0", "10 -80 100 -110 10 0", "10, -80, 100, -110, 10, 0"] {
        let joined = json(&["fk", "ur5", q, "--json"]);
        assert_eq!(joined, separate, "reach fk ur5 {q:?}");
    }
    // A list starting with a minus sign, and lists mixed with separate values.
    let negative = json(&["fk", "ur5", "-10,-80,100", "-110", "10 0", "--json"]);
    assert_eq!(nums(&negative["q_deg"]), [-10.0, -80.0, 100.0, -110.0, 10.0, 0.0]);
    // Every command with positional joint values shares the rule.
    json(&["jacobian", "ur5", "10,-80,100,-110,10,0", "--json"]);
    crate::common::reported(&["check", "ur5", "examples/ur5_ball.toml", "10 -80 100 -110 10 0", "--json"], 3);
    // Errors still name the joint, counted across arguments.
    fails(&["fk", "ur5", "10,-80", "100,abc,10,0"], 2, &["joint 4", "\"abc\""]);
    fails(&["fk", "ur5", "10,-80,100,-110,10"], 2, &["6 joints", "got 5"]);
}

/// Point 2: `check` exits as it reports: status 3 (after the report) for a collision or a
/// swept check not proven clear, 0 only when the whole check holds; with `--to` the first
/// line gives the verdict of the whole check (start and sweep), not of the start only.
#[test]
fn point2_check_exits_non_zero_unless_the_whole_check_is_clear() {
    // The command: the start collides, the sweep is not proven clear.
    let run = reach(&["check", "ur5", "examples/ur5_ball.toml", "0,-90,90,-90,-90,0", "--to", "20,-80,90,-90,-90,0"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let first = run.stdout.lines().next().unwrap_or_default();
    assert!(first.starts_with("verdict") && first.contains("NOT clear") && first.contains("collision"), "{first}");
    let line = one_error_line_after_report(&run);
    assert!(line.contains("collision") && line.contains("NOT proven clear"), "{line}");
    // A free start whose motion is not proven clear: the first line says so, exit 3.
    let run = reach(&["check", "planar3", "examples/path_planar3_post.toml", "60 -40 -30", "--to", "0,-30,-30"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let first = run.stdout.lines().next().unwrap_or_default();
    assert!(first.contains("NOT clear: start free, motion NOT proven clear"), "{first}");
    assert!(one_error_line_after_report(&run).contains("`post`"), "{}", run.stderr);
    // The JSON report is printed whatever the verdict, with the same exit status.
    let run =
        reach(&["check", "planar3", "examples/path_planar3_post.toml", "60 -40 -30", "--to", "0,-30,-30", "--json"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert_eq!(stdout_json(&run)["motion"]["clear"], false);
    // A collision without a motion.
    let run = reach(&["check", "ur5", "examples/ur5_ball.toml", "0 -90 0 -90 0 0", "--json"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert_eq!(stdout_json(&run)["verdict"]["verdict"], "obstacle");
    // A clear check, with and without a motion, exits 0.
    let text = ok(&["check", "planar3", "examples/path_planar3_post.toml", "60 -40 -30", "--to", "61,-40,-30"]);
    assert!(text.lines().next().unwrap_or_default().contains("clear: start free, motion proven clear"), "{text}");
    let text = ok(&["check", "varan4", "examples/seed004_two_planes.toml", "0 60 -30 -30"]);
    assert!(text.starts_with("verdict") && text.lines().next().unwrap_or_default().ends_with("free"), "{text}");
}

/// The one line on stderr of a command that printed its report on stdout first.
fn one_error_line_after_report(run: &crate::common::Run) -> String {
    assert!(!run.stdout.is_empty(), "no report on stdout");
    assert_eq!(run.stderr.lines().count(), 1, "stderr is not one line:\n{}", run.stderr);
    let line = run.stderr.trim_end().to_string();
    assert!(line.starts_with("error: ") && !line.contains("panicked"), "stderr: {line}");
    line
}

/// Point 5: `reach drive` on an arm without drive data uses the default simulated motors of
/// `reach serve` (`reach::drive::with_simulated_drives`), says so, and drives the motion.
#[test]
fn point5_drive_uses_the_default_simulated_motors_like_serve() {
    let args = ["drive", "ur5", "--from", "0,-90,90,-90,-90,0", "--to", "20,-80,90,-90,-90,0", "--duration", "2"];
    let text = ok(&args);
    assert!(text.contains("simulated drives     joints 1, 2, 3, 4, 5, 6"), "{text}");
    let v = json(&[&args[..], &["--format", "json"]].concat());
    // The schedule integrates back onto the plan (the default motors' resolution).
    assert_eq!(v["check"]["within_one_step"], true, "{:.400}", v["check"]);
    // The same motors as the service's: the library's defaults, joint by joint.
    let (robot, simulated) = reach::drive::with_simulated_drives(&reach::model::presets::get("ur5").unwrap()).unwrap();
    assert_eq!(simulated, [0, 1, 2, 3, 4, 5]);
    assert!(reach::drive::axes(&robot).is_ok());
    // An arm with its own drive data keeps it (no simulated line).
    assert!(!ok(&["drive", "planar3", "--from", "0,0,0", "--to", "3.6,-14.4,-7.2"]).contains("simulated drives"));
}

/// `reach args` fed `input` on its standard input.
fn piped(args: &[&str], input: &str) -> crate::common::Run {
    use std::io::Write;
    let mut child = crate::common::reach_command(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start reach");
    child.stdin.take().expect("stdin").write_all(input.as_bytes()).expect("feed stdin");
    crate::common::Run::from_output(child.wait_with_output().expect("reach"))
}

/// Point 4 (the `-` part): `-` is standard input for every file argument read through the
/// shared reader (`--motion` of `view`, `check` and `drive`'s motion file, `retime`'s path),
/// also when the command reads it twice (`view` takes samples and events from one report).
#[test]
fn point4_dash_is_standard_input_for_motion_files() {
    let motion = ok(&["move", "planar3", "--from", "0,-10,-10", "--to", "10,-20,-20", "--duration", "1", "--json"]);
    let dir = crate::common::scratch("point4");
    let html = dir.join("view.html");
    let run = piped(&["view", "planar3", "--motion", "-", "-o", html.to_str().unwrap()], &motion);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("101 states of 101 samples"), "{}", run.stdout);
    let run = piped(
        &["check", "planar3", "examples/path_planar3_post.toml", "0 -10 -10", "--motion", "-", "--json"],
        &motion,
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(stdout_json(&run)["samples"]["clear"], true);
    // The same file from disk gives the same report.
    let file = dir.join("motion.json");
    std::fs::write(&file, &motion).unwrap();
    let from_file = json(&[
        "check",
        "planar3",
        "examples/path_planar3_post.toml",
        "0 -10 -10",
        "--motion",
        file.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(stdout_json(&run), from_file);
    // Nothing on standard input is a readable error, not a hang or a panic.
    fails_piped(&["check", "planar3", "examples/path_planar3_post.toml", "0 -10 -10", "--motion", "-"]);
}

/// Point 4 (the chain part): `reach path --json` is a motion `reach view --motion` and `reach
/// check --motion` read: its waypoints at the cumulative segment times.
#[test]
fn point4_path_json_is_accepted_by_view_motion() {
    let path = ok(&[
        "path",
        "planar3",
        "examples/path_planar3_post.toml",
        "--from",
        "60,-40,-30",
        "--to",
        "0,-30,-30",
        "--duration",
        "10",
        "--json",
    ]);
    let report: serde_json::Value = serde_json::from_str(&path).unwrap();
    let n = report["waypoints_deg"].as_array().map(Vec::len).unwrap();
    let dir = crate::common::scratch("point4-path");
    let html = dir.join("view.html");
    let run = piped(&["view", "planar3", "--motion", "-", "-o", html.to_str().unwrap()], &path);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains(&format!("{n} states of {n} samples")), "{}", run.stdout);
    // The path's edges, checked again from its report: proven clear, as the planner proved them.
    let run =
        piped(&["check", "planar3", "examples/path_planar3_post.toml", "60 -40 -30", "--motion", "-", "--json"], &path);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(stdout_json(&run)["samples"]["clear"], true);
}

fn fails_piped(args: &[&str]) {
    let run = piped(args, "");
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(crate::common::one_error_line(&run).contains("standard input: "), "{}", run.stderr);
}

/// Dynamics as a workflow: `reach dynamics` prints the library's report (torques, gravity
/// load, mass matrix), equal to Pinocchio's `rnea`, `computeGeneralizedGravity` and `crba` of
/// the same URDF (the fixture of bench/peers/pinocchio_dynamics.py) to 1e-9; rates are typed in
/// the unit of the joint values; a robot without mass properties is one readable error.
#[test]
fn dynamics_reach_dynamics_equals_pinocchio_on_the_kr16_urdf() {
    let text = std::fs::read_to_string(format!(
        "{}/crates/reach/tests/data/reference/urdf_dynamics.json",
        crate::common::REPO_ROOT
    ))
    .unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let arm = &doc["arms"]["kr16_2"];
    let state = &arm["states"][0];
    let list = |key: &str| nums(&state[key]).iter().map(|x| format!("{x:.17e}")).collect::<Vec<_>>().join(",");
    let (q, qd, qdd) = (list("q"), list("qd"), list("qdd"));
    let urdf = arm["urdf"].as_str().unwrap();
    let report = json(&["dynamics", urdf, "--tip", "tool0", &q, "--qd", &qd, "--qdd", &qdd, "--rad", "--json"]);
    for (got, want) in [
        (nums(&report["tau_si"]), nums(&state["tau"])),
        (nums(&report["gravity_tau_si"]), nums(&state["gravity"])),
        (
            report["mass_matrix_si"].as_array().unwrap().iter().flat_map(nums).collect(),
            state["mass_matrix"].as_array().unwrap().iter().flat_map(nums).collect(),
        ),
    ] {
        let scale = want.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-9 * scale, "reach {g} vs Pinocchio {w}");
        }
    }
    // Degrees: the rates follow the joint values' unit.
    let deg = json(&["dynamics", "puma560", "0,45,-90,0,30,0", "--qd", "10,0,0,0,0,0", "--json"]);
    assert!((nums(&deg["qd_si"])[0] - 10f64.to_radians()).abs() < 1e-15, "{deg}");
    let text = ok(&["dynamics", "puma560", "0", "45", "-90", "0", "30", "0"]);
    assert!(text.contains("mass matrix M(q)") && text.contains("2 shoulder"), "{text}");
    fails(&["dynamics", "planar3", "0", "0", "0"], 2, &["no inertial data"]);
    fails(&["dynamics", "puma560", "0", "0", "0", "0", "0", "0", "--qd", "1,2"], 2, &["qd", "6 joints"]);
}

/// Point 1: a tool-space move from joint values starts at exactly those joint values, on
/// their branch (the start is on none of the UR5's two default configurations), and
/// keeps that branch: every step is small (no jump to the same pose on another branch).
#[test]
fn point1_tool_space_move_starts_at_the_from_joint_values_on_their_branch() {
    let from = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0];
    let report = json(&[
        "move",
        "ur5",
        "--from",
        "0,-90,90,-90,-90,0",
        "--to",
        "20,-80,90,-90,-90,0",
        "--space",
        "tool",
        "--duration",
        "2",
        "--json",
    ]);
    let samples = report["samples"].as_array().unwrap();
    let q: Vec<Vec<f64>> = samples.iter().map(|s| nums(&s["q_deg"])).collect();
    for (a, b) in q[0].iter().zip(&from) {
        assert!((a - b).abs() < 1e-9, "first sample {:?}, from {from:?}", q[0]);
    }
    // The straight tool line between two poses of one branch ends on that branch: at `to`.
    let last = q.last().unwrap();
    for (a, b) in last.iter().zip([20.0, -80.0, 90.0, -90.0, -90.0, 0.0]) {
        assert!((a - b).abs() < 1e-6, "last sample {last:?}");
    }
    let worst_step = q.windows(2).flat_map(|w| w[0].iter().zip(&w[1]).map(|(a, b)| (a - b).abs())).fold(0.0, f64::max);
    assert!(worst_step < 1.0, "a step of {worst_step}°");
    let interval = &report["intervals"][0];
    assert_eq!(interval["decision"], "start", "{interval}");
    assert_eq!(interval["configuration"], "shoulder=−w config=+β wrist=−e5");
    // A start from a pose (no joint state) is chosen as before: the default configuration.
    let from_pose = json(&[
        "move",
        "ur5",
        "--from-xyz",
        "-0.4869,-0.10915,0.431859",
        "--from-rpy",
        "-180,0,90",
        "--to",
        "20,-80,90,-90,-90,0",
        "--space",
        "tool",
        "--duration",
        "2",
        "--json",
    ]);
    assert_ne!(from_pose["intervals"][0]["decision"], "start", "{}", from_pose["intervals"][0]);
}

/// Point 8: a redundant arm's self-motion listing can be thinned (`ik --all --max N`, the
/// chosen one always kept); "out of reach" says what is measured from where and whether the
/// target is too far or too close; a blocked start names the link by its name too.
#[test]
fn point8_ik_max_thins_the_list_and_out_of_reach_says_from_where() {
    let every = json(&["ik", "planar3", "--xyz", "1.5,1,0", "--all", "--json"]);
    let few = json(&["ik", "planar3", "--xyz", "1.5,1,0", "--all", "--max", "7", "--json"]);
    let found = every["found"].as_u64().unwrap();
    assert!(found > 300, "{found}");
    assert_eq!((few["found"].as_u64(), few["solutions"].as_array().unwrap().len()), (Some(found), 7));
    let chosen = |r: &serde_json::Value| r["solutions"][r["chosen"].as_u64().unwrap() as usize].clone();
    assert_eq!(chosen(&few), chosen(&every));
    let text = ok(&["ik", "planar3", "--xyz", "1.5,1,0", "--all", "--max", "7"]);
    assert!(text.contains(&format!("7 of the {found} solutions, evenly spaced (--max)")), "{text}");
    fails(&["ik", "planar3", "--xyz", "1.5,1,0", "--all", "--max", "0"], 2, &["--max", "at least 1"]);
    fails(&["ik", "planar3", "--xyz", "1.5,1,0", "--all", "--max", "many"], 2, &["--max", "whole number"]);
    // The message: a target on the UR5's base axis is too close, not too far.
    let run = reach(&["ik", "ur5", "--xyz", "0,0,0.3", "--rpy", "0,0,0"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let line = one_error_line_after_report(&run);
    assert!(
        line.contains("(too close): the wrist point is 0.000000 m from joint 1's axis, inside the inner workspace bound 0.109150 m"),
        "{line}"
    );
    let run = reach(&["ik", "puma560", "--xyz", "3,0,0.1", "--rpy", "0,0,0"]);
    let line = one_error_line_after_report(&run);
    assert!(
        line.contains("(too far): the wrist centre is") && line.contains("m from joint 2, beyond the outer"),
        "{line}"
    );
    // Links by name: a start in collision.
    let run =
        reach(&["path", "ur5", "examples/ur5_ball.toml", "--from", "0,-90,0,-90,0,0", "--to", "20,-80,90,-90,-90,0"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let line = one_error_line_after_report(&run);
    assert!(line.contains("link 3 (`upper_arm_link`) collides with obstacle `ball`"), "{line}");
}

/// Point 4: `move --csv` names its units in the header and is read back by the commands that
/// read a trajectory (`view --motion`, `drive`, `retime`), the same samples as its JSON.
#[test]
fn point4_move_csv_has_units_and_is_read_by_view_drive_and_retime() {
    let dir = crate::common::scratch("issue35-csv");
    let csv = dir.join("m.csv");
    let csv_arg = csv.to_str().unwrap();
    let args = ["move", "ur5", "--from", "0,-90,90,0,90,0", "--to", "45,-60,60,0,90,0", "--duration", "2"];
    let report = json(&[&args[..], &["--json", "--csv", csv_arg]].concat());
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("t_s,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,qd1_deg_s,"), "{text}");
    let samples = reach::jobs::input::parse_motion_file(&text).unwrap();
    assert_eq!(samples.len(), report["samples"].as_array().unwrap().len());
    for (s, j) in samples.iter().zip(report["samples"].as_array().unwrap()) {
        assert_eq!(s.q_deg, nums(&j["q_deg"]));
    }
    let html = dir.join("v.html");
    let line = ok(&["view", "ur5", "--motion", csv_arg, "-o", html.to_str().unwrap()]);
    assert!(line.contains(&format!("{} states of {} samples", samples.len(), samples.len())), "{line}");
    ok(&["drive", "ur5", csv_arg]);
    let retimed = json(&["retime", "ur5", csv_arg, "--json"]);
    assert_eq!(retimed["waypoints"].as_u64(), Some(samples.len() as u64));
}
