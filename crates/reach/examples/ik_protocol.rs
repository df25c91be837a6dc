//! The random-pose protocol of the numeric IK solver: success rate and time per solve.
//!
//! For each robot: `N` random joint vectors inside the limits (revolute ranges cut to
//! [−π, π], a fixed pseudo-random sequence) → forward kinematics → the numeric solver from a
//! FIXED seed (the robot's home configuration), first-found mode with restarts, full 6-D pose
//! at 1e-6 m / 1e-6 rad (position only at 1e-6 m for the 4-DOF `varan4`). A solve succeeds
//! when it returns a solution within the limits whose pose, recomputed here by forward
//! kinematics, is within the tolerances. The time of each solve is measured around the call.
//!
//! ```text
//! cargo run --release -p reach --example ik_protocol               # table, 10 000 poses
//! cargo run --release -p reach --example ik_protocol -- --poses 1000 --json
//! cargo run --release -p reach --example ik_protocol -- --robots ur5,panda
//! cargo run --release -p reach --example ik_protocol -- --restarts 1 --random-start  # one random start
//! cargo run --release -p reach --example ik_protocol -- --restarts 1 --random-start --no-reseed  # one descent
//! ```
//!
//! `bench/peers/ik_compare.py` runs this binary with `--json` and the same protocol on the
//! Robotics Toolbox for Python.

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::Point3;
use reach::Robot;
use reach::ik::numeric::{Numeric, NumericOptions, SearchMode, TaskAxes};
use reach::ik::{IkOptions, IkSolver, IkTarget};
use reach::model::{JointKind, presets};

/// Settings of one protocol run.
struct Protocol {
    poses: usize,
    rng_seed: u64,
    restarts: usize,
    max_iterations: usize,
    /// Start each solve from a random joint vector (its own sequence) instead of home.
    random_start: bool,
    /// Re-seed a start that ends in a local minimum (the solver's default; `--no-reseed`).
    reseed: bool,
}

/// Result for one robot.
struct Row {
    robot: String,
    dof: usize,
    task: &'static str,
    poses: usize,
    successes: usize,
    median_us: f64,
    p95_us: f64,
    mean_us: f64,
    max_us: f64,
}

/// SplitMix64: the protocol's pose generator (independent of the solver's start generator).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random joint vector inside the limits (revolute ranges cut to [−π, π]).
fn random_q(robot: &Robot, rng: &mut Rng) -> Vec<f64> {
    robot
        .joints()
        .iter()
        .map(|j| {
            let (mut lo, mut hi) = (j.limits.lower, j.limits.upper);
            if j.kind == JointKind::Revolute {
                lo = lo.max(-PI);
                hi = hi.min(PI);
            }
            lo + (hi - lo) * rng.uniform()
        })
        .collect()
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let k = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[k]
}

/// Runs the protocol on one robot.
fn run(robot: &Robot, position_only: bool, protocol: &Protocol) -> Row {
    let solver = Numeric::from_robot(robot).expect("the numeric solver fits every chain");
    let mut options = IkOptions {
        seed: Some(robot.home()),
        restarts: protocol.restarts,
        max_iterations: protocol.max_iterations,
        numeric: NumericOptions {
            axes: if position_only { TaskAxes::Position } else { TaskAxes::Pose },
            position_tolerance: 1e-6,
            orientation_tolerance: 1e-6,
            time_budget: None,
            mode: SearchMode::FirstFound,
            reseed: protocol.reseed,
        },
        ..IkOptions::default()
    };
    let mut rng = Rng(protocol.rng_seed);
    let mut starts = Rng(protocol.rng_seed ^ 0x5747_4152_5453);
    let mut times = Vec::with_capacity(protocol.poses);
    let mut successes = 0;
    for _ in 0..protocol.poses {
        let q = random_q(robot, &mut rng);
        let pose = robot.fk(&q).expect("fk");
        let target = if position_only {
            IkTarget::Position(Point3::from(pose.translation.vector))
        } else {
            IkTarget::Pose(pose)
        };
        if protocol.random_start {
            options.seed = Some(random_q(robot, &mut starts));
        }
        let t0 = Instant::now();
        let result = solver.solve(robot, &target, &options);
        times.push(t0.elapsed().as_secs_f64() * 1e6);
        let Ok(all) = result else { continue };
        let ok = all.feasible().any(|s| {
            let p = robot.fk(&s.q).expect("fk");
            let dp = (p.translation.vector - pose.translation.vector).norm();
            let da = if position_only { 0.0 } else { p.rotation.angle_to(&pose.rotation) };
            dp <= 1e-6 && da <= 1e-6
        });
        if ok {
            successes += 1;
        }
    }
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    Row {
        robot: robot.name().to_string(),
        dof: robot.dof(),
        task: if position_only { "position" } else { "pose" },
        poses: protocol.poses,
        successes,
        median_us: percentile(&sorted, 0.5),
        p95_us: percentile(&sorted, 0.95),
        mean_us: times.iter().sum::<f64>() / times.len().max(1) as f64,
        max_us: sorted.last().copied().unwrap_or(f64::NAN),
    }
}

fn main() {
    let mut protocol = Protocol {
        poses: 10_000,
        rng_seed: 2024,
        restarts: 32,
        max_iterations: 100,
        random_start: false,
        reseed: true,
    };
    let mut json = false;
    let mut robots = vec!["ur5".to_string(), "puma560".to_string(), "panda".to_string(), "varan4".to_string()];
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().unwrap_or_else(|| panic!("{name} needs a value"));
        match a.as_str() {
            "--json" => json = true,
            "--random-start" => protocol.random_start = true,
            "--no-reseed" => protocol.reseed = false,
            "--poses" => protocol.poses = value("--poses").parse().expect("--poses: a count"),
            "--seed" => protocol.rng_seed = value("--seed").parse().expect("--seed: an integer"),
            "--restarts" => protocol.restarts = value("--restarts").parse().expect("--restarts: a count"),
            "--iterations" => protocol.max_iterations = value("--iterations").parse().expect("--iterations: a count"),
            "--robots" => robots = value("--robots").split(',').map(str::to_string).collect(),
            other => panic!(
                "unknown argument `{other}` (--json, --poses N, --seed N, --restarts N, --iterations N, --robots a,b, --random-start, --no-reseed)"
            ),
        }
    }
    let mut rows = Vec::new();
    for name in &robots {
        let robot = presets::get(name).unwrap_or_else(|e| panic!("no preset `{name}`: {e}"));
        // An arm with fewer than 6 joints cannot set an arbitrary orientation: position only.
        rows.push(run(&robot, robot.dof() < 6, &protocol));
    }
    if json {
        let out: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "robot": r.robot, "dof": r.dof, "task": r.task, "poses": r.poses,
                    "successes": r.successes, "success_rate": r.successes as f64 / r.poses as f64,
                    "median_us": r.median_us, "p95_us": r.p95_us, "mean_us": r.mean_us, "max_us": r.max_us,
                    "restarts": protocol.restarts, "max_iterations": protocol.max_iterations,
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&out).expect("json"));
        return;
    }
    println!(
        "numeric IK, random reachable poses, seed = home, first-found, {} starts × {} iterations, tolerance 1e-6 m / 1e-6 rad",
        protocol.restarts, protocol.max_iterations
    );
    println!("| robot | dof | task | poses | success | median µs | p95 µs | mean µs | max µs |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {} | {} | {} | {:.2} % | {:.1} | {:.1} | {:.1} | {:.0} |",
            r.robot,
            r.dof,
            r.task,
            r.poses,
            100.0 * r.successes as f64 / r.poses as f64,
            r.median_us,
            r.p95_us,
            r.mean_us,
            r.max_us
        );
    }
}
