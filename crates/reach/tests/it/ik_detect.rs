//! Solver selection (`ik::SolverKind`): names round-trip, robots that no closed form fits fall
//! back to the numeric solver, and `ik::solve` then answers with it.
//!
//! Which closed form claims which preset is tested with each closed-form solver.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use reach::Robot;
use reach::ik::{self, IkOptions, IkTarget, SolverKind};
use reach::model::{Convention, Joint, JointGeometry, JointKind, Limits, RobotSpec, presets};

/// xorshift64*, for reproducible random robots.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
}

/// A random URDF-style chain: random origins (up to 0.3 m, any orientation), random axes,
/// limits ±170°; `prismatic` marks prismatic joints.
fn random_urdf_robot(rng: &mut Rng, dof: usize, prismatic: &[usize]) -> Robot {
    let joints = (0..dof)
        .map(|i| {
            let origin = Isometry3::from_parts(
                Translation3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(0.0, 0.3)),
                UnitQuaternion::from_euler_angles(rng.range(-3.0, 3.0), rng.range(-1.5, 1.5), rng.range(-3.0, 3.0)),
            );
            let axis =
                Unit::new_normalize(Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.2, 1.0)));
            let kind = if prismatic.contains(&i) { JointKind::Prismatic } else { JointKind::Revolute };
            let limits = match kind {
                JointKind::Revolute => Limits::new(-170f64.to_radians(), 170f64.to_radians()),
                JointKind::Prismatic => Limits::new(0.0, 0.4),
            };
            Joint {
                name: format!("j{}", i + 1),
                kind,
                geometry: JointGeometry::Axis { origin, axis },
                limits,
                max_velocity: None,
                max_acceleration: None,
                max_jerk: None,
                home: 0.0,
                drive: None,
                flip: false,
            }
        })
        .collect();
    let mut spec = RobotSpec::new("random-urdf", Convention::Urdf, joints);
    spec.tool = Isometry3::translation(0.0, 0.0, 0.1);
    Robot::new(spec).unwrap()
}

#[test]
fn names_round_trip() {
    for kind in SolverKind::ALL {
        assert_eq!(SolverKind::parse(kind.as_str()), Some(kind));
    }
    assert_eq!(SolverKind::parse("numeric"), Some(SolverKind::Numeric));
    assert_eq!(SolverKind::parse("Numeric"), None);
    assert_eq!(SolverKind::parse(""), None);
    assert_eq!(SolverKind::parse("levenberg"), None);
    // Names are distinct.
    for (i, a) in SolverKind::ALL.iter().enumerate() {
        for b in &SolverKind::ALL[i + 1..] {
            assert_ne!(a.as_str(), b.as_str());
        }
    }
    // The numeric solver is tried last.
    assert_eq!(SolverKind::ALL.last(), Some(&SolverKind::Numeric));
}

#[test]
fn panda_falls_back_to_numeric() {
    let panda = presets::get("panda").unwrap();
    assert_eq!(SolverKind::detect(&panda), SolverKind::Numeric);
    // ik::solve uses it.
    let q = [0.3, -0.2, 0.1, -2.0, 0.2, 1.8, 0.5];
    let target = IkTarget::Pose(panda.fk(&q).unwrap());
    let all = ik::solve(&panda, &target, &IkOptions::default()).unwrap();
    assert_eq!(all.solver, "numeric");
    assert!(all.failure.is_none());
    for s in &all.solutions {
        let pose = panda.fk(&s.q).unwrap();
        assert!((pose.translation.vector - target.position().coords).norm() < 1e-6);
    }
}

#[test]
fn random_five_joint_urdf_robots_fall_back_to_numeric() {
    let mut rng = Rng(0xD1CE_5EED_0000_0005);
    for (trial, prismatic) in [vec![], vec![2], vec![], vec![0, 4], vec![]].into_iter().enumerate() {
        let robot = random_urdf_robot(&mut rng, 5, &prismatic);
        assert_eq!(SolverKind::detect(&robot), SolverKind::Numeric, "random robot {trial}");
        // And the numeric solver answers: a position produced by FK is reached.
        let q: Vec<f64> = robot
            .joints()
            .iter()
            .map(|j| match j.kind {
                JointKind::Revolute => rng.range(-1.5, 1.5),
                JointKind::Prismatic => rng.range(0.05, 0.35),
            })
            .collect();
        let target = IkTarget::Position(Point3::from(robot.fk(&q).unwrap().translation.vector));
        let all = ik::solve(&robot, &target, &IkOptions::default()).unwrap();
        assert_eq!(all.solver, "numeric");
        assert!(all.failure.is_none(), "random robot {trial}: {:?}", all.failure);
    }
}

#[test]
fn five_joint_toml_robot_falls_back_to_numeric() {
    // A 5-axis arm (yaw, shoulder, elbow, wrist pitch, wrist roll), as in small teaching robots.
    let robot = Robot::from_toml_str(
        r#"
name = "five-axis"
convention = "dh"
length_unit = "mm"
angle_unit = "deg"
[[joints]]
d = 120
alpha = 90
limits = [-170, 170]
[[joints]]
a = 250
limits = [-10, 190]
[[joints]]
a = 200
limits = [-150, 150]
[[joints]]
alpha = 90
theta = 90
limits = [-120, 120]
[[joints]]
d = 80
limits = [-180, 180]
"#,
    )
    .unwrap();
    assert_eq!(SolverKind::detect(&robot), SolverKind::Numeric);
    let q = [0.3, 0.9, -0.7, 0.4, 1.1];
    let target = IkTarget::Pose(robot.fk(&q).unwrap());
    let all = ik::solve(&robot, &target, &IkOptions::default()).unwrap();
    assert_eq!(all.solver, "numeric");
    assert!(all.failure.is_none(), "{:?}", all.failure);
}

#[test]
fn numeric_builds_for_every_preset() {
    for name in presets::names() {
        let robot = presets::get(name).unwrap();
        let solver = SolverKind::Numeric.build(&robot).unwrap();
        assert_eq!(solver.name(), SolverKind::Numeric.as_str(), "{name}");
    }
}
