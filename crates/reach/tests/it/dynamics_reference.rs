//! External check of the Newton–Euler inverse dynamics against the Robotics Toolbox for Python.
//!
//! `tests/data/reference/puma560_rne.json` is written by `bench/peers/rne_reference.py`: the
//! Toolbox's `models.DH.Puma560` (`rne(q, qd, qdd)` with friction removed, motor inertia Jm = 0,
//! gravity `(0, 0, −9.80665)`) for 20 random states, the first one static. Our side is the
//! shipped `puma560` preset, whose DH table and link parameters equal the Toolbox's.

use reach::effort::dynamics::{Dynamics, gravity_torques, inverse_dynamics};
use reach::model::presets;
use serde_json::Value;

/// Largest accepted absolute torque difference, N·m (torques reach ~100 N·m; measured 2e-14).
const TOLERANCE: f64 = 1e-11;

fn vector(v: &Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect()
}

fn fixture() -> Value {
    let text = include_str!("../data/reference/puma560_rne.json");
    serde_json::from_str(text).expect("valid JSON fixture")
}

#[test]
fn puma560_rne_matches_the_robotics_toolbox() {
    let doc = fixture();
    let puma = presets::get("puma560").unwrap();
    assert_eq!(vector(&doc["gravity"]), puma.gravity().as_slice().to_vec());
    let states = doc["states"].as_array().unwrap();
    assert_eq!(states.len(), 20);
    let mut dynamics = Dynamics::new(&puma).unwrap();
    let mut tau = [0.0; 6];
    let mut largest = 0.0_f64;
    let mut worst = 0.0_f64;
    for (k, s) in states.iter().enumerate() {
        let (q, qd, qdd, expected) = (vector(&s["q"]), vector(&s["qd"]), vector(&s["qdd"]), vector(&s["tau"]));
        dynamics.inverse_dynamics_into(&q, &qd, &qdd, &mut tau).unwrap();
        for i in 0..6 {
            let diff = (tau[i] - expected[i]).abs();
            worst = worst.max(diff);
            assert!(diff < TOLERANCE, "state {k}, joint {}: reach {} vs toolbox {}", i + 1, tau[i], expected[i]);
            largest = largest.max(expected[i].abs());
        }
        // The allocating form agrees exactly with the workspace form.
        assert_eq!(inverse_dynamics(&puma, &q, &qd, &qdd).unwrap(), tau.to_vec());
    }
    eprintln!("largest difference to the toolbox: {worst:e} N·m");
    // The fixture exercises sizeable torques, not just rounding.
    assert!(largest > 20.0, "{largest}");
}

#[test]
fn static_state_is_gravity_only() {
    let doc = fixture();
    let puma = presets::get("puma560").unwrap();
    let s = &doc["states"][0];
    assert!(vector(&s["qd"]).iter().chain(&vector(&s["qdd"])).all(|v| *v == 0.0));
    let g = gravity_torques(&puma, &vector(&s["q"])).unwrap();
    for (mine, theirs) in g.iter().zip(vector(&s["tau"])) {
        assert!((mine - theirs).abs() < TOLERANCE, "{mine} vs {theirs}");
    }
}

/// Issue 35: the URDF arms with inertias against Pinocchio (`bench/peers/pinocchio_dynamics.py`,
/// `tests/data/reference/urdf_dynamics.json`): `rnea`, `computeGeneralizedGravity` and `crba`
/// of the same files, 20 random states each, to 1e-9 relative to the largest entry, through
/// the batch kernels the Python package calls (`Robot.rne`, `gravload`, `inertia`).
#[test]
fn urdf_arms_dynamics_match_pinocchio() {
    use reach::model::{Robot, UrdfChain};
    let doc: Value = serde_json::from_str(include_str!("../data/reference/urdf_dynamics.json")).unwrap();
    let arms = doc["arms"].as_object().unwrap();
    assert_eq!(arms.len(), 2);
    for (name, arm) in arms {
        let path = format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), arm["urdf"].as_str().unwrap());
        let chain = UrdfChain { base: None, tip: Some("tool0".into()) };
        let robot = Robot::from_urdf_str(&std::fs::read_to_string(&path).unwrap(), &chain).unwrap();
        assert_eq!(robot.gravity().as_slice(), vector(&doc["gravity_m_s2"]).as_slice());
        let names: Vec<&str> = robot.joints().iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, arm["joints"].as_array().unwrap().iter().map(|j| j.as_str().unwrap()).collect::<Vec<_>>());
        let dof = robot.dof();
        let states = arm["states"].as_array().unwrap();
        let rows = |key: &str| -> Vec<f64> { states.iter().flat_map(|s| vector(&s[key])).collect() };
        let (q, qd, qdd) = (rows("q"), rows("qd"), rows("qdd"));
        let tau = reach::batch::inverse_dynamics_many(&robot, &q, Some(&qd), Some(&qdd)).unwrap();
        let gravity = reach::batch::inverse_dynamics_many(&robot, &q, None, None).unwrap();
        let mass = reach::batch::mass_matrix_many(&robot, &q).unwrap();
        let want_mass: Vec<f64> =
            states.iter().flat_map(|s| s["mass_matrix"].as_array().unwrap().iter().flat_map(vector)).collect();
        for (what, got, want) in
            [("rnea", &tau, rows("tau")), ("gravity", &gravity, rows("gravity")), ("crba", &mass, want_mass)]
        {
            assert_eq!(got.len(), want.len(), "{name} {what}");
            let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!(scale > 1.0, "{name} {what}: the fixture exercises sizeable values ({scale})");
            let worst = got.iter().zip(&want).map(|(g, w)| (g - w).abs()).fold(0.0, f64::max);
            eprintln!("{name} {what}: largest difference {worst:e} of {scale:e}");
            assert!(worst <= 1e-9 * scale, "{name} {what}: {worst:e} against entries up to {scale:e}");
        }
        // One row of the batch is the single-state workspace call.
        let single = inverse_dynamics(&robot, &q[..dof], &qd[..dof], &qdd[..dof]).unwrap();
        assert_eq!(single.as_slice(), &tau[..dof]);
        assert_eq!(gravity_torques(&robot, &q[..dof]).unwrap().as_slice(), &gravity[..dof]);
    }
}
