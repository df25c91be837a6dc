//! Seed 004: R-conjunction and region primitives (notes 004 §3, §5.3 test vectors).

use reach::world::rfunction::{Parabola, Primitive, Region, plane_through, r_and};

#[test]
fn r_conjunction_vectors() {
    // Notes 004 §5.3.
    for (a, b, e) in [
        (3.0, 4.0, 2.0),
        (30.0, 90.0, 25.131670),
        (0.0, 5.0, 0.0),
        (5.0, 0.0, 0.0),
        (1.0, 1.0, 0.585786),
        (-1.0, 100.0, -1.005000),
        (-3.0, -4.0, -12.0),
        (0.0, -5.0, -10.0),
        (0.0, 0.0, 0.0),
    ] {
        assert!((r_and(a, b) - e).abs() < 5e-7, "{a} ∧ {b} = {}", r_and(a, b));
    }
    // Sign property on a grid of pairs: ∧ ≥ 0 ⇔ both ≥ 0.
    for i in -20..=20 {
        for j in -20..=20 {
            let (a, b) = (i as f64 * 0.37, j as f64 * 1.9);
            assert_eq!(r_and(a, b) >= 0.0, a >= 0.0 && b >= 0.0, "{a} {b}");
        }
    }
}

fn paper_box() -> Region {
    Region { limits: [[0.0, 120.0], [-120.0, 120.0], [-120.0, 120.0]], primitives: Vec::new() }
}

#[test]
fn box_chain_vectors() {
    // Notes 004 §5.3: F_Ω for the paper's limits.
    let r = paper_box();
    for (q, e) in [
        ([30.0, 0.0, 0.0], 17.255829),
        ([0.0, 0.0, 0.0], 0.0),
        ([-15.0, 0.0, 0.0], -20.958733),
        ([60.0, -120.0, 120.0], 0.0),
        ([60.0, 45.0, -30.0], 20.121437),
        ([130.0, 0.0, 0.0], -12.437208),
    ] {
        assert!((r.box_value(q) - e).abs() < 5e-6, "{q:?}: {}", r.box_value(q));
    }
}

#[test]
fn primitives_by_hand() {
    // Ellipse tilted 90°: u = q4 − c4, v = −(q3 − c3); a = 20 along u, b = 10 along v.
    let e = Primitive::EllipticCylinder { phi_deg: 90.0, a: 20.0, b: 10.0, centre: [1.0, 0.0, 0.0, 5.0] };
    // q2 = 10 → centre (10, 5); q = (10, 10, 25): u = 20, v = 0 → on the boundary.
    assert!(e.value([10.0, 10.0, 25.0]).unwrap().abs() < 1e-12);
    // (10, 20, 5): v = −10 → boundary; (10, 10, 5): centre → −1.
    assert!(e.value([10.0, 20.0, 5.0]).unwrap().abs() < 1e-12);
    assert!((e.value([10.0, 10.0, 5.0]).unwrap() + 1.0).abs() < 1e-12);
    // Parabola s² − 2p·t with φ = 0, vertex (10, 0), p = 2: at q2 = 14, boundary t = 4.
    let p = Primitive::ParabolicCylinder { phi_deg: 0.0, vertex: [10.0, 0.0], p: 2.0, variant: Parabola::SquareFirst };
    assert!(p.value([14.0, 4.0, 99.0]).unwrap().abs() < 1e-12);
    assert!(p.value([10.0, 1.0, 0.0]).unwrap() < 0.0); // the focus side
    let p2 = Primitive::ParabolicCylinder { phi_deg: 0.0, vertex: [0.0, 0.0], p: 2.0, variant: Parabola::SquareSecond };
    assert!((p2.value([1.0, 3.0, 0.0]).unwrap() - 5.0).abs() < 1e-12);
    // Kinematic ellipse: semi-axis a(q2) = 10 − q2 ≤ 0 beyond q2 = 10 → inactive.
    let k = Primitive::KinematicEllipse {
        phi_deg: 110.0,
        m3: [0.0; 4],
        m4: [0.0; 4],
        a: [10.0, -1.0, 0.0, 0.0],
        b: [5.0, 0.0, 0.0, 0.0],
    };
    assert!(k.value([5.0, 0.0, 0.0]).unwrap() < 0.0);
    assert!(k.value([12.0, 0.0, 0.0]).is_none());
}

#[test]
fn plane_from_support_points_and_membership() {
    // Plane q3 + q4 = 100 through three points; interior (60, 0, 0) must be on the ≥ 0 side.
    let h = plane_through([0.0, 100.0, 0.0], [0.0, 0.0, 100.0], [50.0, 50.0, 50.0], [60.0, 0.0, 0.0]).unwrap();
    let v = h.value([60.0, 0.0, 0.0]).unwrap();
    assert!(v > 0.0);
    assert!(h.value([10.0, 70.0, 30.0]).unwrap().abs() < 1e-9);
    assert!(plane_through([0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [5.0, 0.0, 0.0]).is_none());
    let mut region = paper_box();
    region.primitives.push(h);
    assert!(region.contains([60.0, 0.0, 0.0]));
    assert!(!region.contains([60.0, 90.0, 90.0])); // beyond the plane
    assert!(!region.contains([130.0, 0.0, 0.0])); // outside the box
    assert!(region.contains([0.0, 0.0, 0.0])); // box boundary included
}
