//! reach's half of `bench/peers/pinocchio_compare.py`: forward kinematics and the Jacobian of
//! a URDF arm, timed on joint vectors read from a file (the same file Pinocchio's half,
//! `bench/peers/pinocchio/fk_jacobian.cpp`, reads).
//!
//! ```text
//! urdf_timing URDF TIP_LINK QS_FILE ROUNDS
//! ```
//!
//! QS_FILE: one joint vector per line (radians, chain order). Prints, as JSON on one line, the
//! tool pose of the first joint vector (row-major 3×4: rotation and translation) and the median
//! over ROUNDS of the time per call, nanoseconds, of `Robot::fk_matrix` (`fk`) and
//! `Robot::jacobian_into` (`jacobian`: the geometric Jacobian of the tool point in world axes),
//! each round one pass over all joint vectors after a warm-up pass.

use std::hint::black_box;
use std::time::Instant;

use reach::Robot;
use reach::kinematics::Jacobian;
use reach::model::UrdfChain;
use reach_peers_bench::median;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [urdf, tip, qs_file, rounds] = args.as_slice() else {
        eprintln!("usage: urdf_timing URDF TIP_LINK QS_FILE ROUNDS");
        std::process::exit(2);
    };
    let text = std::fs::read_to_string(urdf).expect("read the URDF");
    let chain = UrdfChain { base: None, tip: Some(tip.clone()) };
    let robot = Robot::from_urdf_str(&text, &chain).expect("a URDF chain");
    let qs: Vec<Vec<f64>> = std::fs::read_to_string(qs_file)
        .expect("read the joint vectors")
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|x| x.parse().expect("a number")).collect())
        .collect();
    assert!(qs.iter().all(|q| q.len() == robot.dof()), "joint vectors of {} values expected", robot.dof());
    let rounds: usize = rounds.parse().expect("ROUNDS");
    let n = qs.len();
    let mut jacobian = Jacobian::zeros(robot.dof());
    let mut fk = |i: usize| {
        black_box(robot.fk_matrix(black_box(&qs[i])).expect("fk"));
    };
    let mut jac = |i: usize| {
        robot.jacobian_into(black_box(&qs[i]), &mut jacobian).expect("jacobian");
        black_box(&jacobian);
    };
    let pass = |f: &mut dyn FnMut(usize)| {
        let t0 = Instant::now();
        (0..n).for_each(&mut *f);
        t0.elapsed().as_secs_f64() * 1e9 / n as f64
    };
    pass(&mut fk);
    pass(&mut jac);
    let (mut t_fk, mut t_jac) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        t_fk.push(pass(&mut fk));
        t_jac.push(pass(&mut jac));
    }
    let t = robot.fk_matrix(&qs[0]).expect("fk");
    let (r, p) = (t.rotation.matrix(), t.translation.vector);
    let tip0: Vec<String> = (0..3)
        .flat_map(|i| (0..4).map(move |j| if j < 3 { r[(i, j)] } else { p[i] }))
        .map(|x| format!("{x:.17e}"))
        .collect();
    println!(
        "{{\"nq\": {}, \"poses\": {n}, \"fk_ns\": {:.2}, \"jacobian_ns\": {:.2}, \"tip0\": [{}]}}",
        robot.dof(),
        median(&mut t_fk),
        median(&mut t_jac),
        tip0.join(", ")
    );
}
