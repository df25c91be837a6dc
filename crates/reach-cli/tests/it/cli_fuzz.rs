//! Fuzzing the command line: random argument vectors from a grammar of commands, robots,
//! flags and edge-case values (NaN, infinities, 1e308, −0, huge counts, malformed lists) run
//! through the real binary. Whatever the arguments, `reach` exits with 0, 2 or 3 — never a
//! panic (status 1, "internal error") or a signal — and a failure is one `error:` line
//! (bad input: with nothing on stdout; no solution: the report may precede it, as `ik`'s).
//! Long computations are kept short by the caps (`--max-nodes`, the motion sample cap, the
//! untimed IK iteration cap) and a time budget, so every case ends quickly.
//!
//! Cases: 24 by default; `REACH_FUZZ_CASES=N` for a long run (docs/fuzzing.md).

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

use crate::common::{one_error_line, reach};

const ROBOTS: &[&str] = &["planar3", "puma560", "panda", "varan4", "ur5", "nope", "crates/reach/robots/ur5.toml", ""];
const VALUES: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "-0",
    "0",
    "1",
    "-1",
    "1e-9",
    "0.5",
    "90",
    "18446744073709551616",
    "1000000000",
    "abc",
    "",
    "1,2,3",
    "0,0,0,0,0,0",
    "0,0,0,0,0,0,0",
    "nan,0,0",
    "1e308,1e308,1e308",
    "180,0,0",
    "0.4,0,0.4",
    "2.4,0.2",
    "q1=0",
    "q9=1",
    "q1=nan",
    "60 -40 -30",
    ",,",
    "-",
    "0.5,-0.5,43.66,1.920937",
    "3,-0.5,129.81,1.56205,30",
    "0,0,0,1,180",
    "1,0,180,nan",
];
const COMMANDS: &[(&str, &[&str], &[&str])] = &[
    ("fk", &[], &["--rad", "--json"]),
    ("jacobian", &[], &["--rad", "--json"]),
    (
        "ik",
        &["--xyz", "--rpy", "--quat", "--from", "--restarts", "--step", "--free-angle", "--weights"],
        &["--all", "--json", "--rad"],
    ),
    ("check", &[], &["--json", "--rad"]),
    ("avoid", &["--from", "--to-xy", "--obstacle", "--step"], &["--json", "--rad"]),
    ("cspace", &["--step", "--fix"], &["--json", "--fit"]),
    ("move", &["--from", "--to", "--duration", "--dt", "--speed", "--from-xyz", "--to-xyz"], &["--json", "--rad"]),
    ("drive", &["--from", "--to", "--duration"], &["--json", "--rad"]),
    ("path", &["--from", "--to", "--duration"], &["--json", "--rad"]),
    ("sense", &["--sensor", "--sensor", "--sigma"], &["--json"]),
    ("avoid", &["--from", "--to-xy", "--sensor", "--sigma"], &["--json"]),
];

/// One argument vector: command, robot, positional values and flags.
fn argv() -> impl Strategy<Value = Vec<String>> {
    let value = || prop::sample::select(VALUES).prop_map(str::to_string);
    (
        0..COMMANDS.len(),
        prop::sample::select(ROBOTS),
        prop::collection::vec(value(), 0..3),
        prop::collection::vec((any::<prop::sample::Index>(), value()), 0..4),
        prop::collection::vec(any::<prop::sample::Index>(), 0..2),
    )
        .prop_map(|(c, robot, positional, flags, switches)| {
            let (name, valued, bare) = COMMANDS[c];
            let mut args = vec![name.to_string(), robot.to_string()];
            match name {
                "check" | "cspace" => args.push("examples/seed004_ceiling.toml".into()),
                "path" => args.push("examples/path_planar3_post.toml".into()),
                _ => {}
            }
            args.extend(positional);
            if !valued.is_empty() {
                for (i, v) in flags {
                    args.push(i.get(valued).to_string());
                    args.push(v);
                }
            }
            for i in switches {
                args.push(i.get(bare).to_string());
            }
            // Keep every case short: a small grid cap, a time budget for the numeric solver.
            match name {
                "cspace" => args.extend(["--max-nodes".into(), "20000".into()]),
                "ik" | "path" => args.extend(["--time-budget".into(), "0.2".into()]),
                _ => {}
            }
            args
        })
}

#[test]
fn fuzz_command_lines() {
    let cases = std::env::var("REACH_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(24);
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    runner
        .run(&argv(), |args| {
            let refs: Vec<&str> = args.iter().map(String::as_str).collect();
            let run = reach(&refs);
            prop_assert!([0, 2, 3].contains(&run.code), "reach {refs:?}: exit {}: {}", run.code, run.stderr);
            prop_assert!(
                !run.stderr.contains("internal error") && !run.stderr.contains("panicked"),
                "reach {refs:?}: {}",
                run.stderr
            );
            // clap's usage errors: an `error:` line, then its usage or `--help` hint.
            let usage = run.stderr.contains("Usage:") || run.stderr.contains("For more information, try '--help'.");
            if run.code == 2 && usage {
                prop_assert!(run.stderr.starts_with("error: "), "reach {refs:?}: {}", run.stderr);
            } else if run.code == 2 {
                // Bad input: nothing on stdout, one line on stderr.
                one_error_line(&run);
            } else if run.code == 3 {
                // No solution: the report may be on stdout (`ik`), the verdict is one line.
                prop_assert_eq!(run.stderr.lines().count(), 1, "reach {:?}: {}", refs, run.stderr);
                prop_assert!(run.stderr.starts_with("error: "), "reach {refs:?}: {}", run.stderr);
            }
            Ok(())
        })
        .unwrap();
}
