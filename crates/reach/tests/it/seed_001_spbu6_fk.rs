//! Seed 001 (notes 001 §2.4, §5.1–5.2): the `spbu6` preset reproduces the paper's poses.

use approx::assert_relative_eq;
use nalgebra::Matrix4;
use reach::model::presets;

fn matrix(robot: &reach::Robot, q_deg: [f64; 6]) -> Matrix4<f64> {
    let q: Vec<f64> = q_deg.iter().map(|v| v.to_radians()).collect();
    robot.fk_matrix(&q).unwrap().to_homogeneous()
}

#[test]
fn home_pose_is_the_papers_t0() {
    let robot = presets::get("spbu6").unwrap();
    #[rustfmt::skip]
    let t0 = Matrix4::new(0.0, 0.0, 1.0, 3.0,
                          0.0, -1.0, 0.0, 0.0,
                          1.0, 0.0, 0.0, 5.0,
                          0.0, 0.0, 0.0, 1.0);
    assert_relative_eq!(matrix(&robot, [0.0; 6]), t0, epsilon = 1e-12);
}

#[test]
fn fk_of_90_0_0_90_0_0_is_the_papers_t1() {
    let robot = presets::get("spbu6").unwrap();
    #[rustfmt::skip]
    let t1 = Matrix4::new(1.0, 0.0, 0.0, 0.0,
                          0.0, 0.0, 1.0, 3.0,
                          0.0, -1.0, 0.0, 5.0,
                          0.0, 0.0, 0.0, 1.0);
    assert_relative_eq!(matrix(&robot, [90.0, 0.0, 0.0, 90.0, 0.0, 0.0]), t1, epsilon = 1e-12);
}

/// Notes 001 §5.2 "extra FK vectors" (radians), computed from the printed link matrices.
#[test]
fn fk_matches_the_notes_extra_vectors() {
    let robot = presets::get("spbu6").unwrap();
    let cases: [([f64; 6], [[f64; 4]; 3]); 2] = [
        (
            [0.3, -0.4, 0.5, 0.7, -0.2, 1.1],
            [
                [0.349402, -0.323648, 0.879301, 0.991564],
                [-0.905197, 0.125729, 0.405970, 0.306727],
                [-0.241945, -0.937787, -0.249035, 4.305805],
            ],
        ),
        (
            [1.0, 0.5, -0.3, 0.4, 0.8, -0.6],
            [
                [-0.482261, 0.558488, 0.674919, 2.883770],
                [-0.202962, -0.820700, 0.534095, 4.491206],
                [0.852192, 0.120591, 0.509144, 3.791905],
            ],
        ),
    ];
    for (q, expected) in cases {
        let t = robot.fk_matrix(&q).unwrap().to_homogeneous();
        for r in 0..3 {
            for c in 0..4 {
                assert!(
                    (t[(r, c)] - expected[r][c]).abs() < 2e-6,
                    "q={q:?} ({r},{c}): {} vs {}",
                    t[(r, c)],
                    expected[r][c]
                );
            }
        }
    }
}

/// Notes 001 §2.5: |p|² = l1² + l2² − 2·l1·l2·sin(q3), for any q.
#[test]
fn wrist_centre_distance_follows_the_closed_form() {
    let robot = presets::get("spbu6").unwrap();
    for &(q2, q3) in &[(0.0, 0.0), (0.3, -0.7), (-1.0, 1.2), (0.5, -1.5)] {
        let q = [0.4, q2, q3, 0.1, 0.2, 0.3];
        let p = robot.fk_matrix(&q).unwrap().translation.vector;
        assert_relative_eq!(p.norm_squared(), 25.0 + 9.0 - 30.0 * f64::sin(q3), epsilon = 1e-12);
    }
}
