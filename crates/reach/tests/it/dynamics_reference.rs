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
