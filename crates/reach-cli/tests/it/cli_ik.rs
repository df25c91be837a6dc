//! End-to-end tests of `reach ik`: FK → IK round trips through the JSON and the matrix
//! argument, the seeds' worked examples (notes 001 §5.2, notes 003 §5.3, notes 000 §6.3),
//! hand-derived planar solutions, negative comma lists, exit status 3 with a report on stdout
//! and one line on stderr, and bad input (exit 2, empty stdout).

use serde_json::Value;

use crate::common::{Run, angle_gap, fails, json, nums, ok, reach, stdout_json};

/// No solution: exit 3, the report on stdout, one `error: ` line on stderr.
fn infeasible(args: &[&str]) -> Run {
    let run = reach(args);
    assert_eq!(run.code, 3, "reach {args:?}: expected exit 3, got {}; stderr: {}", run.code, run.stderr);
    assert!(!run.stdout.is_empty(), "reach {args:?}: no report on stdout");
    assert_eq!(run.stderr.lines().count(), 1, "reach {args:?}: stderr is not one line:\n{}", run.stderr);
    assert!(run.stderr.starts_with("error: "), "{}", run.stderr);
    run
}

fn same_angles(a: &[f64], b: &[f64], tol_deg: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| angle_gap(*x, *y).abs() < tol_deg)
}

fn solutions(report: &Value) -> Vec<Vec<f64>> {
    report["solutions"].as_array().unwrap().iter().map(|s| nums(&s["q_deg"])).collect()
}

fn chosen_q(report: &Value) -> Vec<f64> {
    let i = report["chosen"].as_u64().unwrap_or_else(|| panic!("no chosen solution: {report}")) as usize;
    nums(&report["solutions"][i]["q_deg"])
}

/// `--matrix` text of a row-major 4×4 matrix (shortest round-trip formatting of each entry).
fn matrix_arg(rows: &[Vec<f64>]) -> String {
    rows.iter().flatten().map(|v| v.to_string()).collect::<Vec<_>>().join(",")
}

/// The tool position of `q_deg` by `reach fk` (an independent path through the binary).
fn fk_xyz(robot: &str, q_deg: &[f64]) -> Vec<f64> {
    let q: Vec<String> = q_deg.iter().map(|v| v.to_string()).collect();
    let mut args = vec!["fk", robot, "--json"];
    args.extend(q.iter().map(String::as_str));
    nums(&json(&args)["pose"]["xyz_m"])
}

// ---------------------------------------------------------------------------------------
// Round trips

#[test]
fn fk_then_ik_finds_the_original_configuration_puma560_and_ur5() {
    // Configurations inside the limits, away from singularities, with negative angles.
    let cases: &[(&str, [f64; 6])] = &[
        ("puma560", [10.0, -20.0, 30.0, -40.0, 50.0, -60.0]),
        ("puma560", [-75.0, 35.0, -150.0, 100.0, -70.0, 170.0]),
        ("puma560", [130.0, 160.0, 20.0, -10.0, 25.0, 5.0]),
        ("ur5", [-90.0, -45.5, 30.0, -60.0, 80.0, 10.0]),
        ("ur5", [150.0, -120.0, -100.0, 45.0, -30.0, -170.0]),
        ("ur5", [5.0, -80.0, 110.0, -200.0, 95.0, 300.0]),
    ];
    for (robot, q) in cases {
        let q_text: Vec<String> = q.iter().map(|v| v.to_string()).collect();
        let mut args = vec!["fk", *robot, "--json"];
        args.extend(q_text.iter().map(String::as_str));
        let fk = json(&args);
        let rows: Vec<Vec<f64>> = fk["pose"]["matrix"].as_array().unwrap().iter().map(nums).collect();
        let m = matrix_arg(&rows);
        let report = json(&["ik", robot, "--matrix", &m, "--all", "--json"]);
        assert_eq!(report["status"], "ok", "{robot} {q:?}: {report}");
        assert!(report["reason"].is_null());
        let all = solutions(&report);
        assert!(all.iter().any(|s| same_angles(s, q, 1e-6)), "{robot}: {q:?} not among {all:#?}");
        for s in report["solutions"].as_array().unwrap() {
            assert!(s["position_error_m"].as_f64().unwrap() < 1e-9, "{s}");
            assert!(s["orientation_error_rad"].as_f64().unwrap() < 1e-9, "{s}");
            assert!(s["branch"].as_str().unwrap().contains('='), "{s}");
        }
        // Starting from the configuration itself, the chosen solution is that configuration.
        let from = q_text.join(",");
        let report = json(&["ik", robot, "--matrix", &m, "--from", &from, "--json"]);
        assert_eq!(report["solutions"].as_array().unwrap().len(), 1);
        assert!(same_angles(&chosen_q(&report), q, 1e-6), "{robot}: {report}");
    }
}

#[test]
fn named_numeric_solver_reaches_the_fk_pose() {
    let fk = json(&["fk", "ur5", "--json", "20", "-60", "70", "-40", "60", "30"]);
    let rows: Vec<Vec<f64>> = fk["pose"]["matrix"].as_array().unwrap().iter().map(nums).collect();
    let report =
        json(&["ik", "ur5", "--matrix", &matrix_arg(&rows), "--solver", "numeric", "--restarts", "4", "--json"]);
    assert_eq!(report["solver"], "numeric");
    let q = chosen_q(&report);
    let xyz = fk_xyz("ur5", &q);
    let want = nums(&fk["pose"]["xyz_m"]);
    for (a, b) in xyz.iter().zip(&want) {
        assert!((a - b).abs() < 1e-6, "{xyz:?} vs {want:?}");
    }
    let human = ok(&["ik", "ur5", "--matrix", &matrix_arg(&rows), "--solver", "numeric", "--restarts", "4"]);
    assert!(human.contains("numeric (--solver)"), "{human}");
}

/// A URDF file gets the closed form its axes fit (issue 16): the KUKA KR 16-2 from
/// `examples/urdf/`, a pose from `reach fk`, all 8 solutions by the spherical-wrist solver,
/// each within 1e-9 of the pose, the original configuration among them.
#[test]
fn a_urdf_arm_gets_its_closed_form_and_all_eight_solutions() {
    let kr16 = "examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf";
    let q = [20.0, -100.0, 120.0, 45.0, -50.0, 70.0];
    let q_text: Vec<String> = q.iter().map(|v| v.to_string()).collect();
    let mut args = vec!["fk", kr16, "--tip", "tool0", "--json"];
    args.extend(q_text.iter().map(String::as_str));
    let fk = json(&args);
    let rows: Vec<Vec<f64>> = fk["pose"]["matrix"].as_array().unwrap().iter().map(nums).collect();
    let m = matrix_arg(&rows);
    let report = json(&["ik", kr16, "--tip", "tool0", "--matrix", &m, "--all", "--json"]);
    assert_eq!(report["status"], "ok", "{report}");
    assert_eq!(report["solver"], "spherical-wrist", "{report}");
    let all = solutions(&report);
    assert_eq!(all.len(), 8, "{all:#?}");
    assert!(all.iter().any(|s| same_angles(s, &q, 1e-6)), "{q:?} not among {all:#?}");
    for s in report["solutions"].as_array().unwrap() {
        assert!(s["position_error_m"].as_f64().unwrap() < 1e-9, "{s}");
        assert!(s["orientation_error_rad"].as_f64().unwrap() < 1e-9, "{s}");
    }
    let human = ok(&["ik", kr16, "--tip", "tool0", "--matrix", &m, "--all"]);
    assert!(human.contains("spherical-wrist"), "{human}");
}

// ---------------------------------------------------------------------------------------
// The seeds' examples

#[test]
fn spbu6_goal_pose_t1_gives_90_0_0_90_0_0_from_home() {
    // Notes 001 §5.1–5.2: T1 = [[1,0,0,0],[0,0,1,3],[0,−1,0,5]]; IK(T1) = (90°, 0, 0, 90°, 0, 0),
    // a wrist singularity (q5 = 0).
    let t1 = "1,0,0,0,0,0,1,3,0,-1,0,5,0,0,0,1";
    let report = json(&["ik", "spbu6", "--matrix", t1, "--json"]);
    assert_eq!(report["robot"], "spbu6");
    assert_eq!(report["solver"], "two-link-wrist");
    assert_eq!(report["status"], "ok");
    assert!(same_angles(&chosen_q(&report), &[90.0, 0.0, 0.0, 90.0, 0.0, 0.0], 1e-9), "{report}");
    let chosen = &report["solutions"][report["chosen"].as_u64().unwrap() as usize];
    assert_eq!(chosen["singular"], serde_json::json!(["wrist"]));
    assert_eq!(chosen["within_limits"], true);
    let human = ok(&["ik", "spbu6", "--matrix", t1]);
    assert!(human.contains("90 0 0 90 0 0 [deg]"), "{human}");
    assert!(human.contains("two-link-wrist (auto-detected)"), "{human}");
}

/// Seed 003's weld start P = (50, 740, 70) mm with the tool frame x = n, y = e6, z = l
/// (notes 003 §5.1–5.2, corrected sign of l_x), as a row-major matrix in metres.
fn weld_start_matrix() -> String {
    let (p, m) = ([50.0f64, 740.0, 70.0], [500.0f64, 200.0, 700.0]);
    let d = [m[0] - p[0], m[1] - p[1], m[2] - p[2]];
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let n = [d[0] / len, d[1] / len, d[2] / len];
    let h = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let e6 = [(p[1] - m[1]) / h, (m[0] - p[0]) / h, 0.0];
    let l = [n[1] * e6[2] - n[2] * e6[1], n[2] * e6[0] - n[0] * e6[2], n[0] * e6[1] - n[1] * e6[0]];
    // The notes' rounded values (§5.2).
    for (a, b) in n.iter().chain(&l).zip([0.476731, -0.572078, 0.667424, -0.427274, 0.512729, 0.744678]) {
        assert!((a - b).abs() < 5e-7, "{a} vs {b}");
    }
    let rows = vec![
        vec![n[0], e6[0], l[0], p[0] / 1000.0],
        vec![n[1], e6[1], l[1], p[1] / 1000.0],
        vec![n[2], e6[2], l[2], p[2] / 1000.0],
        vec![0.0, 0.0, 0.0, 1.0],
    ];
    matrix_arg(&rows)
}

#[test]
fn welder6r_at_the_weld_start_gives_the_notes_plus_and_minus_beta() {
    // Notes 003 §5.3 (paper convention), printed to 4 decimals.
    let plus = [105.2482, -32.9417, 43.3392, -169.6025, -155.4427, 138.1315];
    let minus = [105.2482, 3.9000, -43.3392, 140.5608, -155.4427, 138.1315];
    let m = weld_start_matrix();
    let report = json(&["ik", "welder6r", "--matrix", &m, "--all", "--json"]);
    assert_eq!(report["solver"], "parallel-axes");
    let branch = |label: &str| -> Vec<f64> {
        let s = report["solutions"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["branch"] == label)
            .unwrap_or_else(|| panic!("no branch {label}: {report}"));
        assert_eq!(s["within_limits"], true, "{s}");
        nums(&s["q_deg"])
    };
    let p = branch("shoulder=w config=+β wrist=e5");
    assert!(same_angles(&p, &plus, 1e-4), "+β: {p:?}");
    let n = branch("shoulder=w config=−β wrist=e5");
    assert!(same_angles(&n, &minus, 1e-4), "−β: {n:?}");
    // Starting from (near) either configuration chooses it.
    for (expected, from) in [(plus, "105,-33,43,-170,-155,138"), (minus, "105,4,-43,140,-155,138")] {
        let report = json(&["ik", "welder6r", "--matrix", &m, "--from", from, "--json"]);
        assert!(same_angles(&chosen_q(&report), &expected, 1e-4), "{from}: {report}");
    }
    let human = ok(&["ik", "welder6r", "--matrix", &m, "--all"]);
    assert!(human.contains("config=+β") && human.contains("config=−β"), "{human}");
}

#[test]
fn weights_change_the_chosen_solution() {
    let m = weld_start_matrix();
    let all = json(&["ik", "welder6r", "--matrix", &m, "--all", "--json"]);
    // Arm joints only, from home: |θ1| + |θ2| + |θ3| over the feasible branches of notes 003
    // §5.3 (θ1 = 105.2482° on the `w` shoulder): +β e5 181.53, −β e5 152.49, +β −e5
    // 105.2482 + 6.9711 + 31.8536 = 144.07 (least), −β −e5 171.26; the `−w` shoulder is worse.
    let arm_only = json(&["ik", "welder6r", "--matrix", &m, "--joint-weights", "1,1,1,0,0,0", "--json"]);
    let i = arm_only["chosen"].as_u64().unwrap() as usize;
    assert_eq!(arm_only["solutions"][i]["branch"], "shoulder=w config=+β wrist=−e5", "{arm_only}");
    // Any weights: the chosen one has the least Σ wᵢ·|θᵢ| (wrapped) among the feasible
    // solutions, computed here from the --all list. Seed 001's weights (notes 001).
    for weights in
        [[1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 18.0, 1.0 / 18.0, 1.0 / 18.0], [0.0, 0.0, 0.0, 1.0, 1.0, 1.0]]
    {
        let text: Vec<String> = weights.iter().map(|w| w.to_string()).collect();
        let report = json(&["ik", "welder6r", "--matrix", &m, "--joint-weights", &text.join(","), "--json"]);
        let cost = |q: &[f64]| -> f64 { q.iter().zip(&weights).map(|(v, w)| w * angle_gap(*v, 0.0).abs()).sum() };
        let best = all["solutions"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s["within_limits"] == true)
            .map(|s| nums(&s["q_deg"]))
            .min_by(|a, b| cost(a).total_cmp(&cost(b)))
            .unwrap();
        assert!(same_angles(&chosen_q(&report), &best, 1e-9), "{weights:?}: {report}");
    }
}

#[test]
fn planar3_free_angle_gives_the_hand_derived_elbows() {
    // Tool at (2, 1) with the last link at φ = 0: the wrist is at (1, 1). Elbow at B = (0, 1):
    // q = (90°, −90°, 0) (within the paper's limits); B = (1, 0): q = (0, 90°, −90°), q2 > 0
    // is outside them. From home (0, 0, 0) the feasible one is chosen.
    let report = json(&["ik", "planar3", "--xyz", "2,1,0", "--free-angle", "0", "--all", "--json"]);
    let all = solutions(&report);
    assert_eq!(all.len(), 2, "{report}");
    assert!(same_angles(&chosen_q(&report), &[90.0, -90.0, 0.0], 1e-9), "{report}");
    let other = report["solutions"].as_array().unwrap().iter().find(|s| s["within_limits"] == false).unwrap();
    assert!(same_angles(&nums(&other["q_deg"]), &[0.0, 90.0, -90.0], 1e-9), "{other}");
    assert_eq!(other["violations"][0]["joint"], 2);
    assert_eq!(other["violations"][0]["value_deg"].as_f64().unwrap().round(), 90.0);
    // φ = −90°: the wrist is at (2, 2), |W| = 2√2 > 2 links: that orientation is not possible.
    let run = infeasible(&["ik", "planar3", "--xyz", "2,1,0", "--free-angle", "-90", "--json"]);
    let report = stdout_json(&run);
    assert_eq!(report["status"], "orientation_unreachable");
}

#[test]
fn planar3_scan_reproduces_the_min_s_rows_of_notes_000() {
    // Notes 000 §6.3: start (α0, β0, γ0) = (150°, 140°, 60°), i.e. q = (γ, β − 180, α − 180)
    // = (60, −40, −30); target (2.4, 0.2), Δα = 0.01°: 7847 rows, the least S = 23.756601° at
    // row index 4846, α = 149.996959°, β = 121.048252°, γ = 55.198188°.
    let path = crate::common::temp_file("scan.csv", "");
    let text = ok(&[
        "ik",
        "planar3",
        "--xyz",
        "2.4,0.2,0",
        "--scan",
        "0.01",
        "--from",
        "60,-40,-30",
        "--csv",
        path.to_str().unwrap(),
    ]);
    assert!(text.contains("23.756601"), "the text report is printed too: {text}");
    let csv = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "alpha_deg,beta_deg,gamma_deg,q1_deg,q2_deg,q3_deg,S_deg,within_limits,chosen");
    assert_eq!(lines.len(), 1 + 7847);
    let chosen: Vec<usize> = (1..lines.len()).filter(|&i| lines[i].ends_with(",true")).collect();
    assert_eq!(chosen, vec![1 + 4846]);
    let cells: Vec<f64> = lines[1 + 4846].split(',').take(7).map(|c| c.parse().unwrap()).collect();
    for (got, want) in cells.iter().zip([149.996959, 121.048252, 55.198188]) {
        assert!((got - want).abs() < 1.5e-6, "{cells:?}");
    }
    // q = (γ, β − 180°, α − 180°) for planar3; S as printed.
    assert!((cells[3] - cells[2]).abs() < 1e-9 && (cells[4] - (cells[1] - 180.0)).abs() < 1e-9);
    assert!((cells[5] - (cells[0] - 180.0)).abs() < 1e-9);
    assert!((cells[6] - 23.756601).abs() < 1.5e-6, "{cells:?}");
    // First row at α_min = 101.536959° with β = 180°, γ = 28.770005° (notes 000 §6.2).
    let first: Vec<f64> = lines[1].split(',').take(3).map(|c| c.parse().unwrap()).collect();
    for (got, want) in first.iter().zip([101.536959, 180.0, 28.770005]) {
        assert!((got - want).abs() < 1.5e-6, "{first:?}");
    }

    // Notes 000 §6.3: start (150°, 100°, 60°) → q = (60, −80, −30); target (2, 1): 9001 rows,
    // least S = 35.068953° at index 6000 (α = 150°, β = 108.976675°, γ = 86.092278°).
    let human = ok(&["ik", "planar3", "--xyz", "2,1,0", "--scan", "0.01", "--from", "60,-80,-30"]);
    assert!(human.contains("rows       9001"), "{human}");
    assert!(human.contains("alpha_min  90.000000 deg"), "{human}");
    let line = human.lines().find(|l| l.trim_start().starts_with("chosen")).expect("chosen row");
    let cells: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(&cells[..6], &["chosen", "6001", "150.000000", "108.976675", "86.092278", "86.092278"], "{line}");
    assert_eq!(cells[8], "35.068953", "{line}");
}

#[test]
fn planar3_scan_of_an_unreachable_target_exits_3() {
    // Notes 000 §6.2: (0, 3.2) is beyond 3L.
    let path = crate::common::temp_file("unreachable.csv", "");
    let run = infeasible(&["ik", "planar3", "--xyz", "0,3.2,0", "--scan", "0.01", "--csv", path.to_str().unwrap()]);
    let csv = std::fs::read_to_string(&path).unwrap();
    assert_eq!(csv.lines().count(), 1, "header only: {csv}");
    assert!(run.stderr.contains("out of reach"), "{}", run.stderr);
    let run = infeasible(&["ik", "planar3", "--xyz", "0,3.2,0", "--scan", "0.01"]);
    assert!(run.stdout.contains("unreachable"), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------
// Infeasible targets: exit 3, report on stdout, reason on stderr

#[test]
fn unreachable_target_exits_3_with_a_report_and_one_line() {
    // 3 m from the base is beyond puma560's reach (0.43 + 0.43 m links and offsets).
    let run = infeasible(&["ik", "puma560", "--xyz", "3,0,0", "--rpy", "0,0,0", "--json"]);
    let report = stdout_json(&run);
    assert_eq!(report["status"], "unreachable");
    assert!(report["chosen"].is_null());
    assert!(report["solutions"].as_array().unwrap().is_empty());
    let reason = report["reason"].as_str().unwrap();
    assert!(run.stderr.contains(reason), "{} vs {reason}", run.stderr);
    let run = infeasible(&["ik", "puma560", "--xyz", "3,0,0", "--rpy", "0,0,0"]);
    assert!(run.stdout.contains("status") && run.stdout.contains("unreachable"), "{}", run.stdout);
}

#[test]
fn all_solutions_outside_limits_exit_3_and_are_listed() {
    // puma560, tool position (0.5, 0, 0): every branch violates a limit.
    let run = infeasible(&["ik", "puma560", "--xyz", "0.5,0,0", "--json"]);
    let report = stdout_json(&run);
    assert_eq!(report["status"], "outside_limits");
    assert!(report["chosen"].is_null());
    let all = report["solutions"].as_array().unwrap();
    assert!(!all.is_empty());
    assert!(all.iter().all(|s| s["within_limits"] == false && !s["violations"].as_array().unwrap().is_empty()));
    // Every listed solution still reaches the position.
    for s in all {
        let xyz = fk_xyz("puma560", &nums(&s["q_deg"]));
        assert!((xyz[0] - 0.5).abs() < 1e-9 && xyz[1].abs() < 1e-9 && xyz[2].abs() < 1e-9, "{xyz:?}");
    }
}

// ---------------------------------------------------------------------------------------
// Negative comma lists

#[test]
fn comma_lists_may_start_with_a_minus() {
    // Position only, negative first value: the chosen configuration reaches it.
    let report = json(&["ik", "ur5", "--xyz", "-0.3,0.2,0.5", "--json"]);
    let xyz = fk_xyz("ur5", &chosen_q(&report));
    for (a, b) in xyz.iter().zip([-0.3, 0.2, 0.5]) {
        assert!((a - b).abs() < 1e-9, "{xyz:?}");
    }
    // --matrix starting with −0.5: Rz(120°) (cos = −0.5, sin = √3/2) at (−0.3, 0.2, 0.5), the
    // same pose as --rpy 0,0,120.
    let s = 0.75f64.sqrt();
    let m = format!("-0.5,{},0,-0.3,{s},-0.5,0,0.2,0,0,1,0.5,0,0,0,1", -s);
    let by_matrix = json(&["ik", "ur5", "--matrix", &m, "--all", "--json"]);
    let by_rpy = json(&["ik", "ur5", "--xyz", "-0.3,0.2,0.5", "--rpy", "0,0,120", "--all", "--json"]);
    assert_eq!(by_matrix["status"], "ok");
    let (a, b) = (solutions(&by_matrix), solutions(&by_rpy));
    assert!(!a.is_empty() && a.len() == b.len(), "{a:?} vs {b:?}");
    for q in &a {
        assert!(b.iter().any(|r| same_angles(q, r, 1e-6)), "{q:?} not in {b:?}");
    }
    // Negative --from, --joint-weights and --free-angle values.
    let q = chosen_q(&json(&["ik", "ur5", "--matrix", &m, "--from", "-100,-50,-60,-10,-90,-20", "--json"]));
    assert!(a.iter().any(|r| same_angles(&q, r, 1e-9)));
    let w = json(&["ik", "ur5", "--matrix", &m, "--joint-weights", "1,1,1,0.5,0.5,0.5", "--json"]);
    assert_eq!(w["status"], "ok");
    let report = json(&["ik", "planar3", "--xyz", "2,1,0", "--free-angle", "-30", "--json"]);
    assert_eq!(report["status"], "ok");
    // Options given as --name=value work as well.
    let report = json(&["ik", "ur5", "--xyz=-0.3,0.2,0.5", "--json"]);
    assert_eq!(report["status"], "ok");
}

// ---------------------------------------------------------------------------------------
// Bad input

#[test]
fn bad_input_exits_2_with_empty_stdout() {
    let identity = "1,0,0,0.4,0,1,0,0,0,0,1,0.3,0,0,0,1";
    fails(&["ik", "puma560", "--matrix", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0"], 2, &["--matrix", "16", "got 15"]);
    fails(&["ik", "puma560", "--matrix", &format!("{identity},1")], 2, &["--matrix", "got 17"]);
    fails(&["ik", "puma560", "--matrix", "1,0,0,0,0,1,0,0,0,0,1.1,0,0,0,0,1"], 2, &["--matrix", "orthonormal"]);
    fails(&["ik", "puma560", "--matrix", "0.7,0.7,0,0,-0.7,0.7,0,0,0,0,1,0,0,0,0,1"], 2, &["orthonormal"]);
    fails(&["ik", "puma560", "--matrix", "1,0,0,0,0,1,0,0,0,0,-1,0,0,0,0,1"], 2, &["reflection"]);
    fails(&["ik", "puma560", "--matrix", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,1,1"], 2, &["last row", "0 0 0 1"]);
    fails(&["ik", "puma560", "--matrix", "1,0,0,NaN,0,1,0,0,0,0,1,0,0,0,0,1"], 2, &["--matrix value 4", "finite"]);
    fails(&["ik", "puma560", "--xyz", "nan,0,0"], 2, &["--xyz value 1", "finite"]);
    fails(&["ik", "puma560", "--xyz", "0.4,0,inf", "--rpy", "0,0,0"], 2, &["--xyz value 3"]);
    fails(&["ik", "puma560", "--xyz", "0.4,0,0.3", "--rpy", "0,NaN,0"], 2, &["--rpy value 2"]);
    fails(&["ik", "puma560", "--xyz", "0.4,0"], 2, &["--xyz", "3", "got 2"]);
    fails(&["ik", "puma560", "--xyz", "0.4,x,0"], 2, &["--xyz value 2", "\"x\""]);
    fails(&["ik", "puma560", "--matrix", identity, "--solver", "foo"], 2, &["unknown solver `foo`", "spherical-wrist"]);
    fails(&["ik", "puma560", "--matrix", identity, "--solver", "planar"], 2, &["planar", "puma560", "3 joints"]);
    fails(&["ik", "puma560", "--matrix", identity, "--from", "1,2,3"], 2, &["--from", "6 joints"]);
    fails(&["ik", "puma560", "--matrix", identity, "--from", "0,0,nan,0,0,0"], 2, &["--from", "joint 3"]);
    fails(
        &["ik", "puma560", "--matrix", identity, "--joint-weights", "1,1,1,1,1,-1"],
        2,
        &["--joint-weights value 6", "negative"],
    );
    fails(&["ik", "puma560", "--matrix", identity, "--restarts", "0"], 2, &["--restarts"]);
    fails(&["ik", "planar3", "--xyz", "2,1,0", "--step", "-1"], 2, &["--step", "positive"]);
    fails(&["ik", "planar3", "--xyz", "2,1,0", "--free-angle", "inf"], 2, &["--free-angle", "finite"]);
    fails(&["ik", "planar3", "--xyz", "2,1,0", "--scan", "0"], 2, &["--scan", "positive"]);
    fails(&["ik", "puma560", "--xyz", "2,1,0", "--scan", "0.1"], 2, &["planar", "puma560"]);
    fails(&["ik", "nosuchrobot", "--xyz", "0,0,0"], 2, &["unknown robot"]);
    // Usage errors (clap): no target, both targets, --rpy without --xyz, --csv without --scan.
    for args in [
        &["ik", "puma560"][..],
        &["ik", "puma560", "--xyz", "0,0,0", "--matrix", identity],
        &["ik", "puma560", "--matrix", identity, "--rpy", "0,0,0"],
        &["ik", "planar3", "--xyz", "2,1,0", "--csv", "t.csv"],
        // --weights are criterion weights: they need --choose (joint weights are --joint-weights).
        &["ik", "puma560", "--matrix", identity, "--weights", "1,1,1,1,1,1"],
        &["ik", "puma560", "--matrix", identity, "--criteria", "change"],
    ] {
        let run = reach(args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert!(run.stdout.is_empty() && !run.stderr.contains("panicked"), "{args:?}");
    }
}

// ---------------------------------------------------------------------------------------
// Help and demo

#[test]
fn help_and_demo_show_ik() {
    let help = ok(&["--help"]);
    assert!(help.contains("reach ik puma560 --xyz") && help.contains("--scan 0.01"), "{help}");
    let help = ok(&["ik", "--help"]);
    for needle in [
        "--matrix",
        "--all",
        "--from",
        "--joint-weights",
        "--choose",
        "--criteria",
        "--weights",
        "--solver",
        "--free-angle",
        "--scan",
        "--json",
        "Examples:",
    ] {
        assert!(help.contains(needle), "ik --help lacks {needle}");
    }
    let demo = ok(&["demo"]);
    assert!(demo.contains("Inverse kinematics"), "{demo}");
    // The notes' +β angles at the weld start, and spbu6's T1 answer marked as chosen.
    assert!(demo.contains("105.2482  -32.9417   43.3392 -169.6025 -155.4427  138.1315"), "{demo}");
    assert!(demo.contains("*1  shoulder=front elbow=up wrist=noflip"), "{demo}");
    let puma = demo.lines().skip_while(|l| !l.starts_with("puma560 — fk(")).nth(4).unwrap();
    assert!(puma.contains("20.0000  -40.0000   30.0000   10.0000   40.0000  -30.0000"), "{puma}");
}

#[test]
fn a_half_turn_matrix_is_read_exactly() {
    // R = diag(−1, 1, −1) (a half turn about y): nalgebra's iterative `from_matrix` stalls on
    // half turns; the pose reached must be the one given.
    let m = "-1,0,0,0.4,0,1,0,-0.2,0,0,-1,0.3,0,0,0,1";
    let report = json(&["ik", "ur5", "--matrix", m, "--json"]);
    let q: Vec<String> = chosen_q(&report).iter().map(|v| v.to_string()).collect();
    let mut args = vec!["fk", "ur5"];
    args.extend(q.iter().map(String::as_str));
    args.push("--json");
    let fk = json(&args);
    let rows: Vec<f64> = fk["pose"]["matrix"].as_array().unwrap().iter().flat_map(nums).collect();
    let want: Vec<f64> = m.split(',').map(|v| v.parse().unwrap()).collect();
    assert!(rows.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-9), "{rows:?}");
}

// ---------------------------------------------------------------------------------------
// The --json output is the library's report (reach::jobs::ik)

fn ik_job(robot: &str, request: reach::jobs::IkRequest) -> reach::jobs::Job {
    reach::jobs::Job {
        robot: reach::jobs::RobotInput::Preset(robot.into()),
        request: reach::jobs::Request::Ik(request),
    }
}

#[test]
fn ik_json_is_the_library_report() {
    use reach::jobs::ik::{IkChoice, IkChoiceMethod, IkCriterionName};
    use reach::jobs::{IkRequest, Pose};
    let pose = Pose::xyz_rpy_deg([0.5, -0.2, 0.3], [180.0, 0.0, 0.0]);
    let all = IkRequest { all: true, ..IkRequest::new(pose.clone()) };
    let args = ["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", "180,0,0", "--all", "--json"];
    let by_rpy = crate::common::assert_report(&args, &ik_job("puma560", all), "ik.report");
    assert!(by_rpy["solutions"].as_array().unwrap().len() > 1, "{by_rpy}");
    // The same orientation as a quaternion (180° about x: w = 0, x = 1) and as radians.
    let quat = Pose { xyz_m: Some([0.5, -0.2, 0.3]), quat_wxyz: Some([0.0, 1.0, 0.0, 0.0]), ..Pose::default() };
    let args = ["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--quat", "0,1,0,0", "--all", "--json"];
    let by_quat = crate::common::assert_report(
        &args,
        &ik_job("puma560", IkRequest { all: true, ..IkRequest::new(quat) }),
        "ik.report",
    );
    let q = |r: &Value| -> Vec<Vec<f64>> { solutions(r) };
    assert_eq!(q(&by_quat).len(), q(&by_rpy).len());
    for (a, b) in q(&by_quat).iter().zip(q(&by_rpy)) {
        assert!(same_angles(a, &b, 1e-9), "{a:?} vs {b:?}");
    }
    let pi = std::f64::consts::PI.to_string();
    let rad =
        json(&["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", &format!("{pi},0,0"), "--rad", "--all", "--json"]);
    for (a, b) in q(&rad).iter().zip(q(&by_rpy)) {
        assert!(same_angles(a, &b, 1e-9), "{a:?} vs {b:?}");
    }
    // --choose topsis: the ranking is the library's.
    let choice = IkChoice {
        method: IkChoiceMethod::Topsis,
        criteria: vec![IkCriterionName::Change, IkCriterionName::Limits],
        weights: Some(vec![0.7, 0.3]),
    };
    let request = IkRequest { choose: Some(choice), ..IkRequest::new(pose) };
    let args = [
        "ik",
        "puma560",
        "--xyz",
        "0.5,-0.2,0.3",
        "--rpy",
        "180,0,0",
        "--choose",
        "topsis",
        "--criteria",
        "change,limits",
        "--weights",
        "0.7,0.3",
        "--json",
    ];
    let ranked = crate::common::assert_report(&args, &ik_job("puma560", request), "ik.report");
    assert_eq!(ranked["ranking"]["ranked"][0]["solution"], ranked["chosen"]);
    // --matrix: seed 001's T1 on spbu6.
    let t1 = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 3.0], [0.0, -1.0, 0.0, 5.0], [0.0, 0.0, 0.0, 1.0]];
    let request = IkRequest::new(Pose { matrix: Some(t1), ..Pose::default() });
    let args = ["ik", "spbu6", "--matrix", "1,0,0,0,0,0,1,3,0,-1,0,5,0,0,0,1", "--json"];
    let report = crate::common::assert_report(&args, &ik_job("spbu6", request), "ik.report");
    assert!(same_angles(&chosen_q(&report), &[90.0, 0.0, 0.0, 90.0, 0.0, 0.0], 1e-6), "{report}");
}

#[test]
fn scan_json_is_the_library_report() {
    use reach::jobs::{IkScanRequest, Joints};
    let request =
        IkScanRequest { xyz_m: [2.4, 0.2, 0.0], step_deg: 1.0, from: Some(Joints::Deg(vec![60.0, -40.0, -30.0])) };
    let job = reach::jobs::Job {
        robot: reach::jobs::RobotInput::Preset("planar3".into()),
        request: reach::jobs::Request::IkScan(request),
    };
    let args = ["ik", "planar3", "--xyz", "2.4,0.2,0", "--scan", "1", "--from", "60,-40,-30", "--json"];
    let report = crate::common::assert_report(&args, &job, "ik_scan.report");
    let rows = report["rows"].as_array().unwrap();
    let chosen = report["chosen"].as_u64().unwrap() as usize;
    assert!(rows.len() > 10 && rows.iter().all(|r| r["s_deg"].as_f64() >= rows[chosen]["s_deg"].as_f64()));
    // The CSV lists the same rows.
    let path = crate::common::temp_file("rows.csv", "");
    ok(&[
        "ik",
        "planar3",
        "--xyz",
        "2.4,0.2,0",
        "--scan",
        "1",
        "--from",
        "60,-40,-30",
        "--csv",
        path.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read_to_string(&path).unwrap().lines().count(), rows.len() + 1);
}
