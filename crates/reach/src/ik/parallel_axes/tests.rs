//! Tests of the parallel-axes solver: Chace's formula, the family check, seed 003's welder
//! example and the configurations and measures.
use nalgebra::{Rotation3, Vector3};

use super::*;
use crate::model::presets;
use crate::model::{Joint, JointKind};

#[test]
fn chace_solves_non_orthogonal_tetrahedra() {
    // Notes 003 §6.2 item 6: the corrected normalisation on non-orthogonal e_i, e_j.
    let cases = [
        (Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.6, 0.8, 0.0), 0.5, 0.3),
        (Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.9, 0.19f64.sqrt()), -0.2, 0.7),
        (Vector3::new(0.3, -0.4, 0.866), Vector3::new(0.5, 0.1, 0.8), 0.5, 0.6),
    ];
    for (ei, ej, cik, cjk) in cases {
        let (ei, ej) = (ei.normalize(), ej.normalize());
        let [p, m] = chace(&ei, &ej, cik, cjk).expect("solvable");
        for ek in [p, m] {
            assert!((ek.norm() - 1.0).abs() < 1e-12, "{ek}");
            assert!((ek.dot(&ei) - cik).abs() < 1e-12);
            assert!((ek.dot(&ej) - cjk).abs() < 1e-12);
        }
        assert!(ei.cross(&ej).dot(&p) > 0.0 && ei.cross(&ej).dot(&m) < 0.0);
        // The literally printed form (no /s² on the first terms, /s on the last) is not unit.
        let c_ij = ei.dot(&ej);
        let s = ei.cross(&ej).norm();
        let d = 1.0 - c_ij * c_ij - cik * cik - cjk * cjk + 2.0 * c_ij * cik * cjk;
        let printed = ei * (cik - c_ij * cjk) + ej * (cjk - c_ij * cik) + ei.cross(&ej) * (d.sqrt() / s);
        assert!((printed.dot(&ei) - cik).abs() > 1e-2, "printed form should fail for s_ij ≠ 1");
    }
    // No solution: cosines incompatible with the angle between e_i and e_j.
    assert!(chace(&Vector3::x(), &Vector3::y(), 0.9, 0.9).is_none());
    // Parallel e_i, e_j.
    assert!(chace(&Vector3::x(), &Vector3::x(), 0.5, 0.5).is_none());
}

#[test]
fn accepts_the_family_and_rejects_others() {
    for name in ["welder6r", "ur5"] {
        let robot = presets::get(name).unwrap();
        ParallelAxes::from_robot(&robot).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    for (name, needle) in [("puma560", "α3"), ("spbu6", "α3"), ("planar3", "6 joints"), ("panda", "7")] {
        let robot = presets::get(name).unwrap();
        let err = ParallelAxes::from_robot(&robot).unwrap_err().to_string();
        assert!(err.contains(needle), "{name}: {err}");
    }
}

fn welder_with(change: impl FnOnce(&mut Vec<Joint>)) -> Result<ParallelAxes, IkError> {
    let mut spec = presets::get("welder6r").unwrap().spec().clone();
    change(&mut spec.joints);
    ParallelAxes::from_robot(&Robot::new(spec).unwrap())
}

#[test]
fn names_the_failed_condition() {
    let set = |i: usize, f: fn(&mut crate::model::DhParams)| {
        move |j: &mut Vec<Joint>| {
            if let crate::model::JointGeometry::Dh(p) = &mut j[i].geometry {
                f(p);
            }
        }
    };
    let err = welder_with(set(4, |p| p.a = 0.01)).unwrap_err().to_string();
    assert!(err.contains("a5"), "{err}");
    let err = welder_with(set(1, |p| p.a = 0.0)).unwrap_err().to_string();
    assert!(err.contains("a2 = 0"), "{err}");
    let err = welder_with(set(0, |p| p.alpha = 0.0)).unwrap_err().to_string();
    assert!(err.contains("α1"), "{err}");
    let err = welder_with(set(1, |p| p.alpha = 0.3)).unwrap_err().to_string();
    assert!(err.contains("α2"), "{err}");
    let err = welder_with(set(3, |p| p.alpha = 1.0)).unwrap_err().to_string();
    assert!(err.contains("α4"), "{err}");
    let err = welder_with(set(4, |p| p.alpha = 0.0)).unwrap_err().to_string();
    assert!(err.contains("α5"), "{err}");
    let err = welder_with(|j| j[2].kind = JointKind::Prismatic).unwrap_err().to_string();
    assert!(err.contains("joint 3"), "{err}");
    // Offsets the method supports.
    welder_with(|j| {
        for (i, joint) in j.iter_mut().enumerate() {
            if let crate::model::JointGeometry::Dh(p) = &mut joint.geometry {
                p.d += 0.01 * (i as f64 + 1.0);
                p.theta_offset = 0.1 * i as f64;
                if i != 4 {
                    p.a += 0.02;
                }
            }
        }
    })
    .unwrap();
}

#[test]
fn welder_start_point_plus_beta() {
    // Notes 003 §5.3, start P, configuration "+β".
    let robot = presets::get("welder6r").unwrap();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    let n = Vector3::new(450.0, -540.0, 630.0).normalize();
    let e6 = Vector3::new(540.0, 450.0, 0.0).normalize();
    let l = n.cross(&e6);
    let r = Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_columns(&[n, e6, l]));
    let pose = Isometry3::from_parts(nalgebra::Translation3::new(0.050, 0.740, 0.070), r.into());
    let all = solver.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
    assert_eq!(all.solutions.len(), 8);
    let s = all
        .solutions
        .iter()
        .find(|s| {
            s.branch.get("config") == Some("+β")
                && s.branch.get("shoulder") == Some("w")
                && s.branch.get("wrist") == Some("e5")
        })
        .unwrap();
    let expected = [105.2482, -32.9417, 43.3392, -169.6025, -155.4427, 138.1315];
    for (q, e) in s.q.iter().zip(expected) {
        assert!((q.to_degrees() - e).abs() < 1e-4, "{} vs {e}", q.to_degrees());
    }
}

#[test]
fn configurations_are_the_papers_two_and_the_measures_their_arm() {
    use crate::ik::configuration_order::{check, labels};
    for name in ["welder6r", "ur5"] {
        let robot = presets::get(name).unwrap();
        let s = ParallelAxes::from_robot(&robot).unwrap();
        assert!(s.enumerates_all_branches());
        assert_eq!(labels(&s, &robot), ["shoulder=w config=+β wrist=e5", "shoulder=w config=−β wrist=e5"]);
        assert!(check(&s, &robot, 200) > 50, "{name}");
        // The paper's configurations use one arm (w, e5): its elbow and wrist, and the shoulder.
        let m = s.singularity_measures(&robot, &s.configurations(&robot)).unwrap();
        assert_eq!(m.kinds(), [SingularityKind::Elbow, SingularityKind::Wrist, SingularityKind::Shoulder]);
        // Any solution: all four arms.
        let m = s.singularity_measures(&robot, &[Branch::default()]).unwrap();
        assert_eq!(m.kinds().len(), 9);
        // At a pose: the elbow measure is √(1 − |cos θ_elbow|) of the paper's arm.
        let pose = robot.fk(&[0.3, 0.2, 0.9, -1.0, -0.8, 0.4]).unwrap();
        let paper = *s.measures(&robot, &pose, &IkOptions::default()).unwrap().paper().unwrap();
        let values = s.singularity_measures(&robot, &s.configurations(&robot)).unwrap().at(&robot, &pose).unwrap();
        assert!((values[0].unwrap() - paper.elbow_margin().sqrt()).abs() < 1e-15, "{name}");
        assert_eq!(values[1], Some(paper.wrist_sine));
    }
}
