//! Fuzz targets on the stable toolchain: proptest harnesses that mutate real input files
//! (robot TOML, URDF, scene files, task files, `reach tasks` files) with a grammar of
//! plausible tokens — numbers replaced by NaN, infinities, 1e308, −0, huge counts; lines
//! deleted, duplicated, swapped; tokens inserted; text cut off — and feed them to the
//! parsers and a first computation on what parses. A panic fails the case (proptest shrinks
//! it); a hang would show as a test that does not end.
//!
//! Cases per target: 48 by default (a few seconds in all); `REACH_FUZZ_CASES=200000` for a
//! long run. See `docs/fuzzing.md` for how long each ran and what they found; every crasher
//! found is kept below as a named regression test.

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use reach::Robot;
use reach::jobs::motion::Task;
use reach::jobs::tasks::{TaskKind, TasksRequest, tasks};
use reach::model::{UrdfChain, presets};
use reach::world::{CollisionChecker, Scene};

macro_rules! repo_file {
    ($path:literal) => {
        include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../", $path))
    };
}

const ROBOTS: [&str; 4] = [
    repo_file!("crates/reach/robots/planar3.toml"),
    repo_file!("crates/reach/robots/puma560.toml"),
    repo_file!("crates/reach/robots/panda.toml"),
    repo_file!("crates/reach/robots/varan4.toml"),
];
const URDF: &str = repo_file!("crates/reach/tests/data/three_link.urdf");
const SCENES: [&str; 3] = [
    repo_file!("examples/seed004_ceiling.toml"),
    repo_file!("examples/seed004_two_planes.toml"),
    repo_file!("examples/path_planar3_post.toml"),
];
const TASKS: [&str; 3] = [
    repo_file!("examples/seed001_tool_vs_joint.toml"),
    repo_file!("examples/seed003_welding.toml"),
    repo_file!("examples/choose_tracking.toml"),
];
const TASK_LISTS: [&str; 2] =
    [repo_file!("examples/tasks_collection.toml"), repo_file!("examples/tasks_visiting.toml")];

/// Numbers and tokens that reach the edges of the parsers and the arithmetic behind them.
const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-308",
    "-0",
    "0",
    "-0.0",
    "1",
    "-1",
    "2",
    "360",
    "-720",
    "1e9",
    "18446744073709551615",
    "9999999999999999999999",
    "1e-9",
    "0.5",
    "\"\"",
    "\"x\"",
    "[]",
    "[1, 2]",
    "[[1]]",
    "{}",
    "=",
    "[",
    "]",
    "\"deg\"",
    "\"rad\"",
    "\"mm\"",
    "\"revolute\"",
    "\"prismatic\"",
    "true",
    "false",
    "\n",
    "#",
    "<",
    ">",
    "/>",
    "<joint",
    "<link",
    "name=\"a\"",
    "\"",
];

/// One edit of a text's lines or tokens.
#[derive(Debug, Clone)]
enum Mutation {
    /// Replace the n-th number-like token with a grammar token.
    Number(usize, usize),
    /// Insert a grammar token at byte position (rounded to a char boundary).
    Insert(usize, usize),
    /// Delete a line.
    DeleteLine(usize),
    /// Duplicate a line.
    DuplicateLine(usize),
    /// Swap two lines.
    SwapLines(usize, usize),
    /// Cut the text off at a byte position.
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0..TOKENS.len()).prop_map(|(i, t)| Mutation::Number(i, t)),
        2 => (any::<usize>(), 0..TOKENS.len()).prop_map(|(i, t)| Mutation::Insert(i, t)),
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn floor_boundary(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Byte ranges of number-like tokens (digits with signs, dots, exponents).
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_digit() {
            let start = if i > 0 && bytes[i - 1] == b'-' { i - 1 } else { i };
            let mut end = i;
            while end < bytes.len() && (bytes[end].is_ascii_digit() || matches!(bytes[end], b'.' | b'e' | b'E' | b'_'))
            {
                end += 1;
            }
            spans.push((start, end));
            i = end;
        } else {
            i += 1;
        }
    }
    spans
}

fn apply(text: &str, mutations: &[Mutation]) -> String {
    let mut s = text.to_string();
    for m in mutations {
        match *m {
            Mutation::Number(i, t) => {
                let spans = number_spans(&s);
                if !spans.is_empty() {
                    let (a, b) = spans[i % spans.len()];
                    s.replace_range(a..b, TOKENS[t]);
                }
            }
            Mutation::Insert(i, t) => {
                let at = floor_boundary(&s, i % (s.len() + 1));
                s.insert_str(at, TOKENS[t]);
            }
            Mutation::DeleteLine(i) | Mutation::DuplicateLine(i) | Mutation::SwapLines(i, _) => {
                let mut lines: Vec<&str> = s.lines().collect();
                if lines.is_empty() {
                    continue;
                }
                let k = i % lines.len();
                match *m {
                    Mutation::DeleteLine(_) => {
                        lines.remove(k);
                    }
                    Mutation::DuplicateLine(_) => lines.insert(k, lines[k]),
                    Mutation::SwapLines(_, j) => {
                        let j = j % lines.len();
                        lines.swap(k, j);
                    }
                    _ => {}
                }
                s = lines.join("\n");
            }
            Mutation::Truncate(i) => {
                let at = floor_boundary(&s, i % (s.len() + 1));
                s.truncate(at);
            }
        }
    }
    s
}

/// Cases per target: `REACH_FUZZ_CASES`, else 48.
fn cases() -> u32 {
    std::env::var("REACH_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(48)
}

/// Runs `check` on mutations of `seeds` for [`cases`] cases.
fn fuzz(seeds: &'static [&'static str], check: impl Fn(&str)) {
    let mut runner = TestRunner::new(Config { cases: cases(), failure_persistence: None, ..Config::default() });
    let strategy = (0..seeds.len(), prop::collection::vec(mutation(), 1..6));
    runner
        .run(&strategy, |(k, mutations)| {
            check(&apply(seeds[k], &mutations));
            Ok(())
        })
        .unwrap();
}

/// What a parsed robot must survive: forward kinematics and Jacobian at home and at its
/// limits' midpoints.
fn exercise_robot(robot: &Robot) {
    let home = robot.home();
    let _ = robot.fk(&home);
    let _ = robot.jacobian(&home);
    let mid: Vec<f64> = robot.joints().iter().map(|j| 0.5 * (j.limits.lower + j.limits.upper)).collect();
    let _ = robot.fk(&mid);
}

fn robot_toml(text: &str) {
    if let Ok(robot) = Robot::from_toml_str(text) {
        exercise_robot(&robot);
    }
}

fn urdf(text: &str) {
    if let Ok(robot) = Robot::from_urdf_str(text, &UrdfChain::default()) {
        exercise_robot(&robot);
    }
}

fn scene(text: &str) {
    if let Ok(scene) = Scene::from_toml_str(text) {
        for name in ["varan4", "planar3"] {
            let robot = presets::get(name).unwrap();
            let _ = CollisionChecker::new(&robot, &scene).check(&robot.home());
        }
    }
}

fn task(text: &str) {
    let _ = Task::parse(text);
}

fn task_list(text: &str) {
    let robot = presets::get("ur5").unwrap();
    for task_kind in [TaskKind::Collection, TaskKind::Visiting] {
        let _ = tasks(&robot, &TasksRequest { task_kind, task: text.to_string(), budget_s: None });
    }
}

#[test]
fn fuzz_robot_toml() {
    fuzz(&ROBOTS, robot_toml);
}

#[test]
fn fuzz_urdf() {
    static SEEDS: [&str; 1] = [URDF];
    fuzz(&SEEDS, urdf);
}

#[test]
fn fuzz_scene() {
    fuzz(&SCENES, scene);
}

#[test]
fn fuzz_task_file() {
    fuzz(&TASKS, task);
}

#[test]
fn fuzz_tasks_file() {
    fuzz(&TASK_LISTS, task_list);
}

#[test]
fn mutations_change_the_text_and_keep_it_valid_utf8() {
    let text = ROBOTS[0];
    let spans = number_spans(text);
    assert!(!spans.is_empty());
    let changed = apply(text, &[Mutation::Number(0, 0)]);
    assert_ne!(changed, text);
    assert!(changed.contains("nan"));
    assert_eq!(apply("ab", &[Mutation::Truncate(1)]), "a");
    assert_eq!(apply("a\nb", &[Mutation::SwapLines(0, 1)]), "b\na");
    assert_eq!(apply("é", &[Mutation::Insert(1, 1)]), "infé");
}
