//! The README's tour runs as written: every `reach …` line of its first `sh` block under
//! "## Tour" succeeds (files it writes go to a scratch directory), and the key numbers the
//! README and the seeds quote are unchanged — IK branch counts, seed 004's allowed nodes, seed
//! 003's infeasible interval, seed 001's J1 = 7π/36.

use crate::common::{REPO_ROOT, json, num, reach, scratch};

/// The tour's command lines: continuation lines joined, comments and the leading `reach`
/// removed, a `> file` redirection dropped; with the exit status each must end with, 0 unless
/// its comment (on its line or the comment lines below it) says `exit status N`.
fn tour_commands() -> Vec<(Vec<String>, i32)> {
    let readme = std::fs::read_to_string(format!("{REPO_ROOT}/README.md")).expect("README.md");
    let tour = readme.split("\n## Tour").nth(1).expect("a `## Tour` section");
    let block = tour.split("```sh").nth(1).and_then(|b| b.split("```").next()).expect("an sh block in the tour");
    let mut commands = Vec::new();
    let mut pending = String::new();
    for line in block.lines() {
        let code = line.split(" #").next().unwrap_or("").trim_end();
        if let Some(head) = code.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        pending.push_str(code);
        let full = std::mem::take(&mut pending);
        let full = full.split(" > ").next().unwrap_or("").trim().to_string();
        if let Some(rest) = full.strip_prefix("reach ") {
            commands.push((rest.split_whitespace().map(str::to_string).collect(), 0));
        }
        let comment = line.split_once(" #").map_or("", |(_, c)| c);
        if let (Some(n), Some((_, status))) = (comment.split("exit status ").nth(1), commands.last_mut()) {
            let digits: String = n.chars().take_while(char::is_ascii_digit).collect();
            *status = digits.parse().expect("a number after `exit status` in a tour comment");
        }
    }
    commands
}

/// Options whose value is a file or directory the command writes.
const OUTPUT_OPTIONS: [&str; 6] = ["--svg", "--png", "-o", "--csv", "--ros", "--state"];

/// A `reach serve` line runs until Ctrl-C: it must start and say where it listens (on a free
/// loopback port, with its state in the scratch directory); then it is killed.
fn serve_starts(args: &[String]) {
    use std::io::BufRead;
    let mut args = args.to_vec();
    if !args.iter().any(|a| a == "--listen") {
        args.extend(["--listen".to_string(), "127.0.0.1:0".to_string()]);
    }
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut child = crate::common::reach_command(&refs)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start reach serve");
    let mut line = String::new();
    let read = std::io::BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut line);
    let _ = child.kill();
    let _ = child.wait();
    assert!(
        read.is_ok() && line.contains("listening on http://"),
        "`reach {}` did not start: `{line}`",
        args.join(" ")
    );
}

#[test]
fn every_tour_command_succeeds() {
    let commands = tour_commands();
    assert!(commands.len() >= 25, "the tour has {} commands", commands.len());
    let dir = scratch("tour");
    for (k, (args, status)) in commands.iter().enumerate() {
        let mut args = args.clone();
        for i in 1..args.len() {
            if OUTPUT_OPTIONS.contains(&args[i - 1].as_str()) {
                args[i] = dir.join(format!("{k}-{}", args[i].replace('/', "_"))).display().to_string();
            }
        }
        if args[0] == "serve" {
            serve_starts(&args);
            continue;
        }
        // `a | reach b`: each stage reads the previous one's output on its standard input.
        let mut input: Option<String> = None;
        for stage in args.split(|a| a == "|") {
            let stage = if input.is_some() { &stage[1..] } else { stage };
            let run = run_stage(stage, input.take());
            assert_eq!(run.code, *status, "`reach {}` exit status: {}", stage.join(" "), run.stderr);
            let writes_file = stage.iter().any(|a| a == "-o");
            assert!(!run.stdout.is_empty() || writes_file, "`reach {}` printed nothing", stage.join(" "));
            input = Some(run.stdout);
        }
    }
}

/// One stage of a tour line, fed `input` on its standard input when a pipe precedes it.
fn run_stage(args: &[String], input: Option<String>) -> crate::common::Run {
    use std::io::Write;
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let Some(input) = input else { return reach(&refs) };
    let mut child = crate::common::reach_command(&refs)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start a piped tour stage");
    child.stdin.take().expect("stdin").write_all(input.as_bytes()).expect("feed the pipe");
    crate::common::Run::from_output(child.wait_with_output().expect("a piped tour stage"))
}

#[test]
fn tour_key_numbers_are_unchanged() {
    // IK: the Puma 560 pose has eight branches; the UR5 pose of the ranking table too.
    let puma = json(&["ik", "puma560", "--xyz", "0.5,-0.2,0.3", "--rpy", "180,0,0", "--all", "--json"]);
    assert_eq!(puma["solutions"].as_array().map(Vec::len), Some(8), "{puma}");
    // Seed 004: 635 allowed nodes at 15° with q1 fixed (README tour).
    let cspace =
        json(&["cspace", "varan4", "examples/seed004_ceiling.toml", "--step", "15", "--fix", "q1=0", "--json"]);
    assert_eq!(cspace["allowed"].as_u64(), Some(635), "{cspace:.300}");
    // Seed 003: the −β configuration breaks θ4 on s ∈ (618.10, 882.21) mm.
    let plan = json(&["plan", "examples/seed003_welding.toml", "--json"]);
    let text = plan.to_string();
    assert!(text.contains("618.1") && text.contains("882.2"), "the seed-003 interval moved: {text:.2000}");
    // Seed 001: the joint-space motion costs J1 = 7π/36 (the task's tool-space motion breaks
    // spbu6's q4 limit, so the plan exits with status 3 after printing its report).
    let run = reach(&["plan", "examples/seed001_tool_vs_joint.toml", "--json"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let seed001: serde_json::Value = serde_json::from_str(&run.stdout).expect("the plan's report");
    let j1 = seed001["motions"]
        .as_array()
        .and_then(|m| m.iter().find(|m| m["space"] == "joint"))
        .map(|m| num(&m["effort"]["j1"]))
        .expect("a joint-space motion in the seed 001 task");
    assert!((j1 - 7.0 * std::f64::consts::PI / 36.0).abs() < 1e-9, "J1 = {j1}");
}

/// The ranking rows (`rank  #  branch…  value norm …  score  pareto`) of `reach ik … --choose
/// METHOD` as printed: (rank, solution, the four criterion values, score, pareto).
fn ranking_rows(args: &[&str]) -> Vec<Vec<String>> {
    let text = crate::common::ok(args);
    text.lines()
        .map(|l| l.split_whitespace().map(str::to_string).collect::<Vec<_>>())
        .filter(|t| t.len() == 15 && t[0].parse::<u32>().is_ok() && t[1].parse::<u32>().is_ok())
        .map(|t| {
            vec![
                t[0].clone(),
                t[1].clone(),
                t[5].clone(),
                t[7].clone(),
                t[9].clone(),
                t[11].clone(),
                t[13].clone(),
                t[14].clone(),
            ]
        })
        .collect()
}

/// Issue 35 point 7: the README's TOPSIS table is what its command prints — every row's
/// rank, solution, criterion values, closeness, Pareto status, and VIKOR's Q and rank.
#[test]
fn point7_readme_topsis_table_matches_the_binary() {
    let readme = std::fs::read_to_string(format!("{REPO_ROOT}/README.md")).expect("README.md");
    let section = readme.split("### Choosing among solutions").nth(1).expect("the choosing section");
    let command = section.split("```sh").nth(1).and_then(|b| b.split("```").next()).expect("its command");
    let command = command.replace("\\\n", " ");
    let args: Vec<&str> = command.split_whitespace().skip(1).collect();
    let table: Vec<Vec<String>> = section
        .lines()
        .filter(|l| l.starts_with("| ") && l.split('|').nth(1).is_some_and(|c| c.trim().parse::<u32>().is_ok()))
        .map(|l| l.split('|').map(|c| c.trim().trim_matches('`').to_string()).filter(|c| !c.is_empty()).collect())
        .collect();
    let topsis = ranking_rows(&args);
    assert_eq!(table.len(), topsis.len(), "README rows vs printed rows");
    let mut vikor_args = args.clone();
    let k = vikor_args.iter().position(|a| *a == "topsis").expect("--choose topsis in the README command");
    vikor_args[k] = "vikor";
    let vikor = ranking_rows(&vikor_args);
    for (row, printed) in table.iter().zip(&topsis) {
        // README: rank | # | branch | change | limits | manipulability | σmin | closeness | Q (rank) | Pareto
        let readme_row = [&row[0], &row[1], &row[3], &row[4], &row[5], &row[6], &row[7], &row[9]];
        assert_eq!(
            readme_row.map(String::as_str),
            printed.iter().map(String::as_str).collect::<Vec<_>>()[..],
            "{row:?}"
        );
        let v = vikor.iter().find(|v| v[1] == row[1]).expect("the solution in the VIKOR ranking");
        assert_eq!(row[8], format!("{} ({})", v[6], v[0]), "VIKOR of #{}", row[1]);
    }
}
