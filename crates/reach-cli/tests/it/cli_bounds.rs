//! Bounded resources, Ctrl-C and limits on outputs (issue 12): every size a command sets is
//! checked against its cap before anything is allocated or run, so a huge request fails at
//! once with one line naming the flag, the size and the cap (exit status 2) — the cap is the
//! proof that it ends quickly, no test here measures time. Ctrl-C stops long work with
//! `error: interrupted` and exit status 130. Starts and goals outside the joint limits are
//! refused before anything is written.

use crate::common::{fails, ok, one_error_line, reach_command};

const CEILING: &str = "examples/seed004_ceiling.toml";

#[test]
fn cspace_with_a_tiny_step_is_refused_before_allocating() {
    // Once aborted allocating 960 GB: the node count is now computed from the axis lengths.
    fails(
        &["cspace", "varan4", CEILING, "--step", "1e-9", "--fix", "q1=0"],
        2,
        &["--step", "0.000000001°", "nodes", "more than the cap of 20000000", "200000000"],
    );
}

#[test]
fn cspace_cap_names_the_grid_size_and_max_nodes_checks_its_value() {
    // A 0.5° grid over three swept joints of varan4: 55 758 001 nodes.
    fails(&["cspace", "varan4", CEILING, "--step", "0.5", "--fix", "q1=0"], 2, &["--step", "55758001 nodes"]);
    fails(
        &["cspace", "varan4", CEILING, "--step", "0.5", "--fix", "q1=0", "--max-nodes", "1000"],
        2,
        &["more than the cap of 1000"],
    );
    fails(&["cspace", "varan4", CEILING, "--max-nodes", "0", "--fix", "q1=0"], 2, &["--max-nodes", "0"]);
    fails(
        &["cspace", "varan4", CEILING, "--max-nodes", "300000000", "--fix", "q1=0"],
        2,
        &["--max-nodes", "between 1 and 200000000"],
    );
    fails(&["cspace", "varan4", CEILING, "--max-nodes", "many", "--fix", "q1=0"], 2, &["--max-nodes", "many"]);
    // The cap at its exact size passes: 9 × 17 × 17 nodes.
    let out = ok(&["cspace", "varan4", CEILING, "--fix", "q1=0", "--max-nodes", "2601"]);
    assert!(out.contains("2601"), "{out}");
    fails(&["cspace", "varan4", CEILING, "--fix", "q1=0", "--max-nodes", "2600"], 2, &["2601 nodes"]);
}

#[test]
fn ik_with_a_billion_restarts_and_no_budget_is_refused() {
    // Once ran for hours.
    fails(
        &["ik", "panda", "--xyz", "0.4,0,0.4", "--rpy", "180,0,0", "--restarts", "1000000000"],
        2,
        &["--restarts", "1000000000 starts", "cap of 1000000", "time budget"],
    );
}

#[test]
fn ik_with_a_billion_restarts_ends_at_its_time_budget() {
    let out = ok(&[
        "ik",
        "panda",
        "--xyz",
        "0.4,0,0.4",
        "--rpy",
        "180,0,0",
        "--restarts",
        "1000000000",
        "--time-budget",
        "0.2",
    ]);
    assert!(out.contains("status"), "{out}");
}

#[test]
fn avoid_refuses_a_start_outside_the_joint_limits() {
    fails(
        &["avoid", "planar3", "--from", "600,-40,-30", "--to-xy", "2.4,0.2", "--obstacle", "2.0,0.7"],
        2,
        &["--from", "joint 1 `O` = 600 deg", "[0, 180] deg"],
    );
}

#[test]
fn path_refuses_a_start_or_goal_outside_the_joint_limits() {
    let scene = "examples/path_planar3_post.toml";
    fails(
        &["path", "planar3", scene, "--from", "60,-40,-30", "--to", "0,-30,-300"],
        2,
        &["--to", "joint 3 `A` = -300 deg", "[-180, 0] deg"],
    );
    fails(&["path", "planar3", scene, "--from", "60,-40,-300", "--to", "0,-30,-30"], 2, &["--from", "joint 3 `A`"]);
}

/// Runs `reach ARGS`, sends it SIGINT (Ctrl-C) after half a second, and checks that it ends
/// with one line and exit status 130.
#[cfg(unix)]
fn interrupted_after_half_a_second(args: &[&str]) {
    use std::process::Stdio;
    let child = reach_command(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run reach");
    std::thread::sleep(std::time::Duration::from_millis(500));
    let status = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(status.success());
    let run = crate::common::Run::from_output(child.wait_with_output().expect("wait for reach"));
    assert_eq!(run.code, 130, "stderr: {}", run.stderr);
    assert_eq!(one_error_line(&run), "error: interrupted");
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_long_grid_with_one_line_and_status_130() {
    // 55 758 001 nodes: far longer than the half second before Ctrl-C.
    interrupted_after_half_a_second(&[
        "cspace",
        "varan4",
        CEILING,
        "--step",
        "0.5",
        "--fix",
        "q1=0",
        "--max-nodes",
        "60000000",
        "--json",
    ]);
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_long_tool_space_tracking() {
    // Seed 003's weld at 1 mm/s sampled every 2 ms: about 435 000 samples to track.
    interrupted_after_half_a_second(&[
        "move",
        "welder6r",
        "--from-xyz",
        "0.05,0.74,0.07",
        "--from-rpy",
        "0,-41.86854343693031,-50.19442890773481",
        "--to-xyz",
        "0.5,0.2,0.7",
        "--to-rpy",
        "0,-41.86854343693031,-50.19442890773481",
        "--space",
        "tool",
        "--speed",
        "0.001",
        "--dt",
        "0.002",
        "--json",
    ]);
}
