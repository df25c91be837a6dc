//! Inverse-kinematics benchmarks, one criterion group per kind of solver.
//!
//! Run with `cargo bench -p reach --bench ik` (add `-- numeric` to run one group).
//!
//! * `closed_form` — every solution of one generic pose (`ik::solve` work without the solver
//!   detection: the solver is built once) for puma560, ur5, welder6r, spbu6, and the one
//!   branch of the generic configuration (`IkSolver::solve_branch`);
//! * `planar_scan` — seed 000's α scan at 0.01° (`PlanarRedundant::paper_scan`);
//! * `numeric` — first-found from the home configuration, first-found from a nearby seed
//!   (tracking) and all distinct solutions (16 starts), for ur5 and panda;
//! * `from_geometry` — the KUKA KR 16-2 URDF (closed form through its standard-DH equivalent)
//!   against that equivalent as a DH robot.
//!
//! The success rate and time distribution over 10 000 random poses are measured by the
//! example `ik_protocol` (`cargo run --release -p reach --example ik_protocol`).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::Robot;
use reach::ik::numeric::{Numeric, NumericOptions, SearchMode};
use reach::ik::planar::PlanarRedundant;
use reach::ik::{IkOptions, IkSolver, IkTarget, SolverKind};
use reach::model::presets;

/// A generic (non-singular, within-limits) configuration per benchmarked robot.
fn generic_q(name: &str) -> Vec<f64> {
    match name {
        "ur5" => vec![0.4, -1.1, 1.3, -0.6, 1.2, 0.3],
        "panda" => vec![0.3, -0.2, 0.1, -2.0, 0.2, 1.8, 0.5],
        "puma560" => vec![0.2, 0.6, -0.8, 0.4, 0.7, -0.3],
        "welder6r" => vec![0.3, 0.5, -0.4, 0.3, 0.6, -0.2],
        "spbu6" => vec![0.5, 0.3, -0.4, 0.2, 0.6, -0.3],
        other => panic!("no benchmark configuration for `{other}`"),
    }
}

/// `(robot, pose target of generic_q, generic_q)`.
fn problem(name: &str) -> (Robot, IkTarget, Vec<f64>) {
    let robot = presets::get(name).expect("preset");
    let q = generic_q(name);
    let target = IkTarget::Pose(robot.fk(&q).expect("fk"));
    (robot, target, q)
}

/// Closed forms: all solutions of one pose (FK check of each, limits, labels included).
fn closed_form(c: &mut Criterion) {
    let mut group = c.benchmark_group("closed_form");
    for (name, kind) in [
        ("puma560", SolverKind::SphericalWrist),
        ("ur5", SolverKind::ParallelAxes),
        ("welder6r", SolverKind::ParallelAxes),
        ("spbu6", SolverKind::TwoLinkWrist),
    ] {
        let (robot, target, _) = problem(name);
        let solver = kind.build(&robot).expect("closed form fits");
        let options = IkOptions::default();
        let n = solver.solve(&robot, &target, &options).expect("solve").solutions.len();
        group.bench_function(format!("{name}/all_{n}_solutions"), |b| {
            b.iter(|| solver.solve(black_box(&robot), black_box(&target), black_box(&options)).expect("solve"));
        });
        // One branch (`IkSolver::solve_branch`, as path tracking calls it): that of generic_q.
        let all = solver.solve(&robot, &target, &options).expect("solve");
        let q = generic_q(name);
        let own = all
            .solutions
            .iter()
            .find(|s| s.q.iter().zip(&q).all(|(a, b)| reach::angle::wrap(a - b).abs() < 1e-9))
            .expect("generic_q is a solution");
        let branch = own.branch.clone();
        group.bench_function(format!("{name}/one_branch"), |b| {
            b.iter(|| {
                solver
                    .solve_branch(black_box(&robot), black_box(&target), black_box(&branch), black_box(&options))
                    .expect("solve")
            });
        });
    }
    group.finish();
}

/// Seed 000's scan of the free angle α at 0.01°: the paper's target (2, 1) (α from 90° to
/// 180°, 9001 rows) and a target just outside the inner circle (≈ 17 900 rows).
fn planar_scan(c: &mut Criterion) {
    let mut group = c.benchmark_group("planar_scan");
    let arm = PlanarRedundant::from_robot(&presets::get("planar3").expect("preset")).expect("planar");
    let step = 0.01f64.to_radians();
    for (label, xy) in [("paper_2_1", [2.0, 1.0]), ("near_inner_1_0.1", [1.0, 0.1])] {
        let rows = arm.paper_scan(xy, step).expect("scan").rows.len();
        group.bench_function(format!("{label}/{rows}_rows"), |b| {
            b.iter(|| arm.paper_scan(black_box(xy), black_box(step)).expect("scan"));
        });
    }
    group.finish();
}

/// Numeric solver: first found from home (the protocol's fixed seed), first found from a seed
/// 0.1 rad away in every joint (tracking), and every distinct solution of 16 starts.
fn numeric(c: &mut Criterion) {
    let mut group = c.benchmark_group("numeric");
    for name in ["ur5", "panda"] {
        let (robot, target, q) = problem(name);
        let solver = Numeric::from_robot(&robot).expect("numeric fits every robot");
        let first = NumericOptions { mode: SearchMode::FirstFound, ..NumericOptions::default() };
        let from_home = IkOptions { seed: Some(robot.home()), numeric: first, ..IkOptions::default() };
        group.bench_function(format!("{name}/first_found_from_home"), |b| {
            b.iter(|| solver.solve(black_box(&robot), black_box(&target), black_box(&from_home)).expect("solve"));
        });
        let seed: Vec<f64> = q.iter().map(|v| v + 0.1).collect();
        let nearby = IkOptions { seed: Some(seed), numeric: first, ..IkOptions::default() };
        group.bench_function(format!("{name}/first_found_nearby_seed"), |b| {
            b.iter(|| solver.solve(black_box(&robot), black_box(&target), black_box(&nearby)).expect("solve"));
        });
        let full = IkOptions::default();
        group.bench_function(format!("{name}/all_distinct_{}_starts", full.restarts), |b| {
            b.iter(|| solver.solve(black_box(&robot), black_box(&target), black_box(&full)).expect("solve"));
        });
    }
    group.finish();
}

/// Issue 16: the KUKA KR 16-2 as its URDF file (`examples/urdf/`, solved through its
/// standard-DH equivalent) against that equivalent as a DH robot: the same closed form, all
/// solutions of one pose; the URDF path adds only its longer forward kinematics in the check.
fn from_geometry(c: &mut Criterion) {
    let mut group = c.benchmark_group("from_geometry");
    let text = include_str!("../../../examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf");
    let chain = reach::model::UrdfChain { base: None, tip: Some("tool0".into()) };
    let urdf = Robot::from_urdf_str(text, &chain).expect("urdf");
    let dh = urdf.dh_equivalent().expect("equivalent");
    let q = [0.35, -1.75, 2.1, 0.8, -0.9, 1.2];
    let target = IkTarget::Pose(urdf.fk(&q).expect("fk"));
    let options = IkOptions::default();
    for (name, robot) in [("kr16_urdf", &urdf), ("kr16_dh_equivalent", &dh)] {
        let solver = SolverKind::detect(robot).build(robot).expect("closed form fits");
        let n = solver.solve(robot, &target, &options).expect("solve").solutions.len();
        group.bench_function(format!("{name}/all_{n}_solutions"), |b| {
            b.iter(|| solver.solve(black_box(robot), black_box(&target), black_box(&options)).expect("solve"));
        });
    }
    group.finish();
}

criterion_group!(benches, closed_form, planar_scan, numeric, from_geometry);
criterion_main!(benches);
