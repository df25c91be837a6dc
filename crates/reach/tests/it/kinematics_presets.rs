//! Forward kinematics and Jacobian of the presets and of small hand-written arms, checked
//! against values derived by hand, against an independent plain product of 4×4 DH matrices
//! (`common::dh_frames`), and against finite differences of FK.

use crate::common;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use crate::common::{Rng, all_presets, dh_frames, dh_product, fd_jacobian, max_abs_diff, rx, tr};
use approx::assert_relative_eq;
use nalgebra::{Matrix3, Matrix4, Vector3};
use reach::Robot;
use reach::model::presets;

/// Finite-difference step for the Jacobian checks: central differences have truncation error
/// ~h²·|f'''|/6 ≈ 1e-11 (lengths up to ~8 m in `spbu6`) and rounding error ~ε·|f|/h ≈ 1e-9.
const FD_STEP: f64 = 1e-6;
/// Accepted disagreement between the analytic and the finite-difference Jacobian.
const FD_TOLERANCE: f64 = 1e-6;

fn pose(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    robot.fk_matrix(q).unwrap().to_homogeneous()
}

/// A homogeneous matrix from rotation columns (x, y, z axes of the frame) and a position.
fn frame(x: [f64; 3], y: [f64; 3], z: [f64; 3], p: [f64; 3]) -> Matrix4<f64> {
    let mut m = Matrix4::identity();
    for r in 0..3 {
        m[(r, 0)] = x[r];
        m[(r, 1)] = y[r];
        m[(r, 2)] = z[r];
        m[(r, 3)] = p[r];
    }
    m
}

const X: [f64; 3] = [1.0, 0.0, 0.0];
const Y: [f64; 3] = [0.0, 1.0, 0.0];
const Z: [f64; 3] = [0.0, 0.0, 1.0];
fn neg(v: [f64; 3]) -> [f64; 3] {
    [-v[0], -v[1], -v[2]]
}

// ---------------------------------------------------------------------------------------
// Home poses, derived by hand from robots/*.toml.
//
// Notation: X, Y, Z are the world axes; a standard DH row is Rz(θ)·Tz(d)·Tx(a)·Rx(α), so
// Tz(d) moves along the current z axis, Tx(a) along the current x axis, and Rx(α) maps the
// current frame (x, y, z) to (x, y·cosα + z·sinα, −y·sinα + z·cosα); in particular
// Rx(90°): (x, y, z) → (x, z, −y), Rx(−90°): (x, y, z) → (x, −z, y), Rx(180°): (x, −y, −z).
// Every preset below has θ offsets 0 except spbu6 joint 2, and home q = 0 except panda.
// ---------------------------------------------------------------------------------------

#[test]
fn home_configurations_are_as_written_in_the_files() {
    let expected: [(&str, Vec<f64>); 8] = [
        // Unspecified homes default to 0, which lies inside every limit of these presets.
        ("planar3", vec![0.0; 3]),
        ("log-loader", vec![0.0; 3]),
        ("spbu6", vec![0.0; 6]),
        ("puma560", vec![0.0; 6]),
        ("welder6r", vec![0.0; 6]),
        ("varan4", vec![0.0; 4]),
        ("ur5", vec![0.0; 6]),
        // The Toolbox's ready pose qr (joint 4 must be in [−3.0718, −0.0698]).
        ("panda", vec![0.0, -0.3, 0.0, -2.2, 0.0, 2.0, FRAC_PI_4]),
    ];
    for (name, home) in expected {
        let robot = presets::get(name).unwrap();
        assert_eq!(robot.home().len(), home.len(), "{name}");
        for (a, b) in robot.home().iter().zip(&home) {
            assert_relative_eq!(*a, *b, epsilon = 1e-15);
        }
    }
}

fn assert_home_pose(name: &str, expected: Matrix4<f64>) {
    let robot = presets::get(name).unwrap();
    let t = pose(&robot, &robot.home());
    assert!(max_abs_diff(&t, &expected) < 1e-12, "{name} home pose\n got {t}\n expected {expected}");
}

/// planar3: three 1 m links along x, no twists: the tool is at (3, 0, 0) with R = I.
#[test]
fn planar3_home() {
    assert_home_pose("planar3", frame(X, Y, Z, [3.0, 0.0, 0.0]));
}

/// log-loader: A1 = Rx(90°) turns the frame to (X, Z, −Y) at the origin; A2 = A3 = Tx(1 m)
/// move along X twice: p = (2, 0, 0), axes (X, Z, −Y).
#[test]
fn log_loader_home() {
    assert_home_pose("log-loader", frame(X, Z, neg(Y), [2.0, 0.0, 0.0]));
}

/// spbu6: A1 = Rx(−90°): (X, −Z, Y). A2 = Rz(−90°)·Tx(5): rotating by −90° about z₁ = Y gives
/// x₂ = −y₁ = Z, y₂ = x₁ = X, then 5 along Z: p = (0, 0, 5). A3 = Rx(−90°): (Z, −Y, X).
/// A4 = Tz(3)·Rx(−90°): 3 along X: p = (3, 0, 5), axes (Z, −X, −Y). A5 = Rx(90°): (Z, −Y, X).
/// A6 = I. This is the thesis's T0 = [[0,0,1,3],[0,−1,0,0],[1,0,0,5]] (notes 001 §2.4).
#[test]
fn spbu6_home() {
    assert_home_pose("spbu6", frame(Z, neg(Y), X, [3.0, 0.0, 5.0]));
}

/// puma560: A1 = Tz(0.6718)·Rx(90°): p = (0, 0, 0.6718), axes (X, Z, −Y). A2 = Tx(0.4318):
/// p = (0.4318, 0, 0.6718). A3 = Tz(0.15005)·Tx(0.0203)·Rx(−90°): 0.15005 along −Y and 0.0203
/// along X: p = (0.4521, −0.15005, 0.6718), axes back to (X, Y, Z). A4 = Tz(0.4318)·Rx(90°):
/// p = (0.4521, −0.15005, 1.1036), axes (X, Z, −Y). A5 = Rx(−90°): (X, Y, Z). A6 = I.
#[test]
fn puma560_home() {
    assert_home_pose("puma560", frame(X, Y, Z, [0.4521, -0.15005, 1.1036]));
}

/// welder6r (mm → m): A1 = Rx(90°): (X, Z, −Y). A2 = Tx(0.4): p = (0.4, 0, 0).
/// A3 = Tx(0.3)·Rx(180°): p = (0.7, 0, 0), axes (X, −Z, Y). A4 = Rx(−90°): (X, −Y, −Z).
/// A5 = Tz(0.2)·Rx(90°): 0.2 along −Z: p = (0.7, 0, −0.2), axes (X, −Z, Y).
/// A6 = Tz(0.25)·Tx(0.05)·Rx(90°): 0.25 along Y, 0.05 along X: p = (0.75, 0.25, −0.2),
/// axes (X, Y, Z).
#[test]
fn welder6r_home() {
    assert_home_pose("welder6r", frame(X, Y, Z, [0.75, 0.25, -0.2]));
}

/// varan4 (mm → m): A1 = Rx(90°): (X, Z, −Y); then 0.9 + 0.7 + 0.5 m along X.
#[test]
fn varan4_home() {
    assert_home_pose("varan4", frame(X, Z, neg(Y), [2.1, 0.0, 0.0]));
}

/// ur5: A1 = Tz(0.089159)·Rx(90°): p = (0, 0, 0.089159), axes (X, Z, −Y).
/// A2 = Tx(−0.425), A3 = Tx(−0.39225): p = (−0.81725, 0, 0.089159).
/// A4 = Tz(0.10915)·Rx(90°): 0.10915 along −Y, axes (X, −Y, −Z).
/// A5 = Tz(0.09465)·Rx(−90°): 0.09465 along −Z: p_z = −0.005491, axes (X, Z, −Y).
/// A6 = Tz(0.0823): along −Y: p = (−0.81725, −0.19145, −0.005491), axes (X, Z, −Y).
#[test]
fn ur5_home() {
    assert_home_pose("ur5", frame(X, Z, neg(Y), [-0.81725, -0.19145, -0.005491]));
}

/// panda (modified DH, rows Rx(α)·Tx(a)·Rz(θ)·Tz(d)) at qr = (0, −0.3, 0, −2.2, 0, 2.0, π/4):
/// joints 1, 3, 5 are 0, so every link stays in the world XZ plane. Write u(φ) = (cos φ, 0,
/// sin φ) for the unit vector at angle φ from X towards Z.
/// Row 1: 0.333 up Z. Row 2: Rx(−90°) gives (X, −Z, Y), then Rz(−0.3) about Y:
/// x₂ = u(0.3), y₂ = u(0.3 − π/2), z₂ = Y. Row 3: Rx(90°): x₃ = u(0.3), y₃ = Y,
/// z₃ = −y₂ = u(0.3 + π/2); 0.316 along z₃. Row 4: Rx(90°) gives (u(0.3), u(0.3 + π/2), −Y),
/// 0.0825 along u(0.3), then Rz(−2.2): x₄ = u(−1.9), y₄ = u(−1.9 + π/2), z₄ = −Y.
/// Row 5: Rx(−90°): (u(−1.9), Y, y₄); −0.0825 along u(−1.9), 0.384 along u(−1.9 + π/2).
/// Row 6: Rx(90°): (u(−1.9), u(−1.9 + π/2), −Y), Rz(2.0): x₆ = u(0.1), y₆ = u(0.1 + π/2).
/// Row 7: Rx(90°): (u(0.1), −Y, u(0.1 − π/2)); 0.088 along u(0.1); Rz(π/4); 0.107 along z₇.
/// Tool: Tz(0.103)·Rz(−π/4): 0.103 more along z₇ = u(0.1 − π/2), and Rz(π/4)·Rz(−π/4) = I
/// leaves the axes (u(0.1), −Y, u(0.1 − π/2)).
#[test]
fn panda_home() {
    let u = |phi: f64| Vector3::new(phi.cos(), 0.0, phi.sin());
    let p = Vector3::new(0.0, 0.0, 0.333) + 0.316 * u(0.3 + FRAC_PI_2) + 0.0825 * u(0.3) - 0.0825 * u(-1.9)
        + 0.384 * u(-1.9 + FRAC_PI_2)
        + 0.088 * u(0.1)
        + (0.107 + 0.103) * u(0.1 - FRAC_PI_2);
    let expected = frame(u(0.1).into(), neg(Y), u(0.1 - FRAC_PI_2).into(), p.into());
    assert_home_pose("panda", expected);
    // The expression above, evaluated once separately (a short script), to catch a slip in it.
    assert_relative_eq!(p, Vector3::new(0.484006882, 0.0, 0.413027777), epsilon = 1e-9);
}

// ---------------------------------------------------------------------------------------
// Independent FK (plain product of DH matrices) and finite-difference Jacobian, all presets.
// ---------------------------------------------------------------------------------------

#[test]
fn fk_and_frames_agree_with_a_plain_product_of_dh_matrices_for_every_preset() {
    let mut rng = Rng::new(0x5eed_0001);
    for robot in all_presets() {
        for _ in 0..50 {
            let q = rng.joints(&robot);
            let expected = dh_product(&robot, &q);
            let scale = 1.0 + expected.fixed_view::<3, 1>(0, 3).norm();
            assert!(max_abs_diff(&pose(&robot, &q), &expected) < 1e-12 * scale, "{} q={q:?}", robot.name());
            assert!(
                max_abs_diff(&robot.fk(&q).unwrap().to_homogeneous(), &expected) < 1e-12 * scale,
                "{} fk() q={q:?}",
                robot.name()
            );
            let frames = robot.frames(&q).unwrap();
            for (i, (f, e)) in frames.iter().zip(dh_frames(&robot, &q)).enumerate() {
                assert!(max_abs_diff(&f.to_homogeneous(), &e) < 1e-12 * scale, "{} frame {}", robot.name(), i + 1);
            }
        }
    }
}

#[test]
fn jacobian_agrees_with_finite_differences_for_every_preset() {
    let mut rng = Rng::new(0x5eed_0002);
    for robot in all_presets() {
        for _ in 0..20 {
            let q = rng.joints(&robot);
            let j = robot.jacobian(&q).unwrap();
            let fd = fd_jacobian(&robot, &q, FD_STEP);
            let err = max_abs_diff(&j, &fd);
            assert!(err < FD_TOLERANCE, "{} q={q:?}: |J − J_fd| = {err:e}\nJ = {j}\nJ_fd = {fd}", robot.name());
        }
        // Also at home, where several presets are singular (stretched or folded).
        let q = robot.home();
        assert!(max_abs_diff(&robot.jacobian(&q).unwrap(), &fd_jacobian(&robot, &q, FD_STEP)) < FD_TOLERANCE);
    }
}

/// Closed form for the planar arm: column i is (−(y − yᵢ), x − xᵢ, 0, 0, 0, 1) where
/// (xᵢ, yᵢ) is joint i's position.
#[test]
fn planar3_jacobian_closed_form() {
    let robot = presets::get("planar3").unwrap();
    let q = [0.4f64, -1.1, -0.7];
    let (a1, a12, a123) = (q[0], q[0] + q[1], q[0] + q[1] + q[2]);
    let joints = [(0.0, 0.0), (a1.cos(), a1.sin()), (a1.cos() + a12.cos(), a1.sin() + a12.sin())];
    let (x, y) = (joints[2].0 + a123.cos(), joints[2].1 + a123.sin());
    let j = robot.jacobian(&q).unwrap();
    for (i, (xi, yi)) in joints.iter().enumerate() {
        let col = [-(y - yi), x - xi, 0.0, 0.0, 0.0, 1.0];
        for r in 0..6 {
            assert_relative_eq!(j[(r, i)], col[r], epsilon = 1e-12);
        }
    }
}

#[test]
fn last_frame_composed_with_tool_is_the_tool_pose() {
    let mut rng = Rng::new(0x5eed_0003);
    let mut robots = all_presets();
    robots.push(Robot::from_toml_str(ARM4_M_RAD).unwrap());
    robots.push(Robot::from_toml_str(&arm_mdh(ARM4_MDH)).unwrap());
    for robot in robots {
        for _ in 0..10 {
            let q = rng.joints(&robot);
            let frames = robot.frames(&q).unwrap();
            assert_eq!(frames.len(), robot.dof());
            let composed = frames.last().unwrap().to_homogeneous() * robot.tool().to_homogeneous();
            assert!(max_abs_diff(&composed, &pose(&robot, &q)) < 1e-12, "{}", robot.name());
            let mut out = vec![nalgebra::IsometryMatrix3::identity(); robot.dof()];
            let tool = robot.frames_into(&q, &mut out).unwrap();
            assert_eq!(out, frames);
            assert!(max_abs_diff(&tool.to_homogeneous(), &pose(&robot, &q)) < 1e-15);
        }
    }
}

#[test]
fn joint_positions_of_planar3_are_the_link_ends() {
    let robot = presets::get("planar3").unwrap();
    let pts = robot.joint_positions(&[FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2]).unwrap();
    let expected = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    assert_eq!(pts.len(), expected.len());
    for (p, e) in pts.iter().zip(expected) {
        assert_relative_eq!(p.coords, Vector3::from(e), epsilon = 1e-12);
    }
}

// ---------------------------------------------------------------------------------------
// Standard and modified DH descriptions of the same arm.
//
// Regrouping the standard-DH product
//   Π Rz(θᵢ)Tz(dᵢ)Tx(aᵢ)Rx(αᵢ) = [Rz(θ₁)Tz(d₁)]·[Rx(α₁)Tx(a₁)Rz(θ₂)Tz(d₂)] ⋯ [Tx(aₙ)Rx(αₙ)]
// (Tx and Rx commute) gives the MDH table: row i carries (a, α) of DH row i−1 (row 1: 0, 0),
// the same d and θ, and a tool Tx(aₙ)·Rx(αₙ) for the last link's length and twist.
// ---------------------------------------------------------------------------------------

/// Corke's PUMA 560 (standard DH), with a base and a tool.
const PUMA_DH: &str = r#"
name = "puma-dh"
convention = "dh"
length_unit = "m"
angle_unit = "deg"
base = { xyz = [0.1, -0.2, 0.3], rpy = [0, 0, 30] }
tool = { xyz = [0, 0.02, 0.1], rpy = [10, 0, 0] }
[[joints]]
d = 0.6718
alpha = 90
[[joints]]
a = 0.4318
[[joints]]
a = 0.0203
d = 0.15005
alpha = -90
[[joints]]
d = 0.4318
alpha = 90
[[joints]]
alpha = -90
[[joints]]
"#;

/// The same PUMA in modified DH; the last DH row has a = α = 0, so the tool is unchanged.
const PUMA_MDH: &str = r#"
name = "puma-mdh"
convention = "mdh"
length_unit = "m"
angle_unit = "deg"
base = { xyz = [0.1, -0.2, 0.3], rpy = [0, 0, 30] }
tool = { xyz = [0, 0.02, 0.1], rpy = [10, 0, 0] }
[[joints]]
d = 0.6718
[[joints]]
alpha = 90
[[joints]]
a = 0.4318
d = 0.15005
[[joints]]
a = 0.0203
alpha = -90
d = 0.4318
[[joints]]
alpha = 90
[[joints]]
alpha = -90
"#;

/// A 4-joint arm with θ offsets, a prismatic joint and a last link with length and twist,
/// standard DH, metres and radians (0.5235987755982988 = 30°, 0.7853981633974483 = 45°,
/// 1.5707963267948966 = 90°, 0.3490658503988659 = 20°, 0.17453292519943295 = 10°).
const ARM4_M_RAD: &str = r#"
name = "arm4"
convention = "dh"
length_unit = "m"
angle_unit = "rad"
base = { xyz = [0.05, 0.0, 0.1], rpy = [0.0, 0.0, 0.5235987755982988] }
[[joints]]
d = 0.2
a = 0.1
alpha = 1.5707963267948966
theta = 0.17453292519943295
limits = [-1.5707963267948966, 1.5707963267948966]
max_velocity = 0.5235987755982988
home = 0.17453292519943295
[[joints]]
kind = "prismatic"
d = 0.05
a = 0.5
alpha = -0.5235987755982988
theta = -0.3490658503988659
limits = [0.0, 0.3]
max_velocity = 0.25
home = 0.1
[[joints]]
a = 0.3
d = 0.02
alpha = 0.7853981633974483
limits = [-3.141592653589793, 3.141592653589793]
[[joints]]
a = 0.04
d = 0.07
alpha = 1.5707963267948966
theta = 0.7853981633974483
"#;

/// `ARM4_M_RAD` in millimetres and degrees.
const ARM4_MM_DEG: &str = r#"
name = "arm4"
convention = "dh"
length_unit = "mm"
angle_unit = "deg"
base = { xyz = [50, 0, 100], rpy = [0, 0, 30] }
[[joints]]
d = 200
a = 100
alpha = 90
theta = 10
limits = [-90, 90]
max_velocity = 30
home = 10
[[joints]]
kind = "prismatic"
d = 50
a = 500
alpha = -30
theta = -20
limits = [0, 300]
max_velocity = 250
home = 100
[[joints]]
a = 300
d = 20
alpha = 45
limits = [-180, 180]
[[joints]]
a = 40
d = 70
alpha = 90
theta = 45
"#;

/// `ARM4_M_RAD` in modified DH (degrees, millimetres): the (a, α) of each DH row moves one
/// row down, and the last (a, α) = (40 mm, 90°) becomes the tool. `{FLIP}` is replaced.
const ARM4_MDH: &str = r#"
name = "arm4-mdh"
convention = "mdh"
length_unit = "mm"
angle_unit = "deg"
base = { xyz = [50, 0, 100], rpy = [0, 0, 30] }
tool = { xyz = [40, 0, 0], rpy = [90, 0, 0] }
[[joints]]
d = 200
theta = 10
limits = [-90, 90]
{FLIP}
[[joints]]
kind = "prismatic"
a = 100
alpha = 90
d = 50
theta = -20
limits = [0, 300]
home = 100
{FLIP}
[[joints]]
a = 500
alpha = -30
d = 20
[[joints]]
a = 300
alpha = 45
d = 70
theta = 45
"#;

fn arm_mdh(template: &str) -> String {
    template.replace("{FLIP}", "")
}

#[test]
fn dh_and_mdh_descriptions_of_the_same_arm_give_the_same_tool_pose() {
    let mut rng = Rng::new(0x5eed_0004);
    let pairs = [
        (Robot::from_toml_str(PUMA_DH).unwrap(), Robot::from_toml_str(PUMA_MDH).unwrap()),
        (Robot::from_toml_str(ARM4_M_RAD).unwrap(), Robot::from_toml_str(&arm_mdh(ARM4_MDH)).unwrap()),
    ];
    for (dh, mdh) in &pairs {
        assert_eq!(mdh.convention(), reach::model::Convention::Mdh);
        for _ in 0..30 {
            let q = rng.joints(dh);
            let a = pose(dh, &q);
            assert!(max_abs_diff(&a, &pose(mdh, &q)) < 1e-12, "{} q={q:?}", dh.name());
            // Both agree with the plain product, and the Jacobians (same tool point) agree.
            assert!(max_abs_diff(&a, &dh_product(dh, &q)) < 1e-12);
            assert!(max_abs_diff(&pose(mdh, &q), &dh_product(mdh, &q)) < 1e-12);
            assert!(max_abs_diff(&dh.jacobian(&q).unwrap(), &mdh.jacobian(&q).unwrap()) < 1e-12);
            let fd = fd_jacobian(mdh, &q, FD_STEP);
            assert!(max_abs_diff(&mdh.jacobian(&q).unwrap(), &fd) < FD_TOLERANCE, "{} q={q:?}", mdh.name());
        }
    }
}

/// PUMA at q = 0 in modified DH, by hand (the same pose as the preset's, plus base and tool):
/// the rows give p = (0.4521, −0.15005, 1.1036) with R = I in the chain frame.
#[test]
fn puma_mdh_at_zero_by_hand() {
    let robot = Robot::from_toml_str(PUMA_MDH).unwrap();
    let base = tr(0.1, -0.2, 0.3) * common::rz(30f64.to_radians());
    let tool = tr(0.0, 0.02, 0.1) * rx(10f64.to_radians());
    let expected = base * tr(0.4521, -0.15005, 1.1036) * tool;
    assert!(max_abs_diff(&pose(&robot, &[0.0; 6]), &expected) < 1e-12);
}

// ---------------------------------------------------------------------------------------
// Units: the same arm in m/rad and mm/deg.
// ---------------------------------------------------------------------------------------

#[test]
fn millimetre_degree_and_metre_radian_files_describe_the_same_arm() {
    let (si, units_si) = Robot::from_toml_str_with_units(ARM4_M_RAD).unwrap();
    let (mm, units_mm) = Robot::from_toml_str_with_units(ARM4_MM_DEG).unwrap();
    assert_eq!((units_si.length.as_str(), units_si.angle.as_str()), ("m", "rad"));
    assert_eq!((units_mm.length.as_str(), units_mm.angle.as_str()), ("mm", "deg"));
    // Home, limits and speeds in SI: 10° = 0.17453 rad; 100 mm = 0.1 m; 30°/s; 250 mm/s.
    for robot in [&si, &mm] {
        let home = robot.home();
        assert_relative_eq!(home[0], 10f64.to_radians(), epsilon = 1e-15);
        assert_relative_eq!(home[1], 0.1, epsilon = 1e-15);
        let j = robot.joints();
        assert_relative_eq!(j[0].limits.lower, -FRAC_PI_2, epsilon = 1e-15);
        assert_relative_eq!(j[1].limits.upper, 0.3, epsilon = 1e-15);
        assert_relative_eq!(j[2].limits.upper, PI, epsilon = 1e-15);
        assert!(!j[3].limits.is_bounded());
        assert_relative_eq!(j[0].max_velocity.unwrap(), 30f64.to_radians(), epsilon = 1e-15);
        assert_relative_eq!(j[1].max_velocity.unwrap(), 0.25, epsilon = 1e-15);
        assert_relative_eq!(robot.base().translation.vector, Vector3::new(0.05, 0.0, 0.1), epsilon = 1e-15);
    }
    let mut rng = Rng::new(0x5eed_0005);
    for _ in 0..30 {
        let q = rng.joints(&si);
        assert!(max_abs_diff(&pose(&si, &q), &pose(&mm, &q)) < 1e-12, "q={q:?}");
        assert!(max_abs_diff(&si.jacobian(&q).unwrap(), &mm.jacobian(&q).unwrap()) < 1e-12);
    }
}

/// The welder6r preset (mm, deg) against the same table typed in m and rad.
#[test]
fn welder6r_in_metres_and_radians_matches_the_preset() {
    let text = presets::source("welder6r").unwrap();
    let robot_mm = presets::get("welder6r").unwrap();
    let si = r#"
name = "welder6r-si"
length_unit = "m"
angle_unit = "rad"
joints = [
  { alpha = 1.5707963267948966 },
  { a = 0.4 },
  { a = 0.3, alpha = 3.141592653589793 },
  { alpha = -1.5707963267948966 },
  { d = 0.2, alpha = 1.5707963267948966 },
  { d = 0.25, a = 0.05, alpha = 1.5707963267948966 },
]
"#;
    assert!(text.contains("length_unit = \"mm\""));
    let robot_m = Robot::from_toml_str(si).unwrap();
    let mut rng = Rng::new(0x5eed_0006);
    for _ in 0..20 {
        let q = rng.joints(&robot_mm);
        assert!(max_abs_diff(&pose(&robot_mm, &q), &pose(&robot_m, &q)) < 1e-12);
    }
}

// ---------------------------------------------------------------------------------------
// Flipped joints.
// ---------------------------------------------------------------------------------------

#[test]
fn flip_negates_the_joint_variable() {
    let plain = Robot::from_toml_str(&arm_mdh(ARM4_MDH)).unwrap();
    // Flip joint 1 (revolute) and joint 2 (prismatic); limits apply to the user's value, so
    // the prismatic joint's limits become [−300, 0] mm.
    let flipped_text = ARM4_MDH.replacen("limits = [-90, 90]\n{FLIP}", "limits = [-90, 90]\nflip = true", 1).replacen(
        "limits = [0, 300]\nhome = 100\n{FLIP}",
        "limits = [-300, 0]\nhome = -100\nflip = true",
        1,
    );
    assert!(!flipped_text.contains("{FLIP}"), "template changed");
    let flipped = Robot::from_toml_str(&flipped_text).unwrap();
    assert!(flipped.joints()[0].flip && flipped.joints()[1].flip && !flipped.joints()[2].flip);

    let mut rng = Rng::new(0x5eed_0007);
    for _ in 0..20 {
        let q = rng.joints(&flipped);
        let negated = [-q[0], -q[1], q[2], q[3]];
        assert!(max_abs_diff(&pose(&flipped, &q), &pose(&plain, &negated)) < 1e-12);
        assert!(max_abs_diff(&pose(&flipped, &q), &dh_product(&flipped, &q)) < 1e-12);
        let jf = flipped.jacobian(&q).unwrap();
        let jp = plain.jacobian(&negated).unwrap();
        for c in 0..4 {
            let sign = if c < 2 { -1.0 } else { 1.0 };
            assert!(max_abs_diff(&jf.column(c), &(jp.column(c) * sign)) < 1e-12, "column {c}");
        }
        assert!(max_abs_diff(&jf, &fd_jacobian(&flipped, &q, FD_STEP)) < FD_TOLERANCE);
        assert_eq!(flipped.first_joint_outside_limits(&q, 0.0), None);
    }
    // A flipped revolute joint at +90° points link 1 where the plain joint's −90° does.
    let q = [FRAC_PI_2, -0.1, 0.2, 0.3];
    assert!(max_abs_diff(&pose(&flipped, &q), &pose(&plain, &[-FRAC_PI_2, 0.1, 0.2, 0.3])) < 1e-12);
    assert!(max_abs_diff(&pose(&flipped, &q), &pose(&plain, &q)) > 1e-3);
    assert_eq!(flipped.first_joint_outside_limits(&[0.0, 0.1, 0.0, 0.0], 0.0), Some(1));
}

// ---------------------------------------------------------------------------------------
// Prismatic joints.
// ---------------------------------------------------------------------------------------

/// A SCARA arm: two horizontal links (0.5 m, 0.4 m), the second with a 180° twist so that the
/// quill (prismatic joint 3, offset 0.1 m) moves down, and a wrist roll with a 0.05 m flange.
const SCARA: &str = r#"
name = "scara"
length_unit = "mm"
angle_unit = "deg"
[[joints]]
a = 500
limits = [-150, 150]
[[joints]]
a = 400
alpha = 180
limits = [-150, 150]
[[joints]]
kind = "prismatic"
d = 100
limits = [0, 300]
[[joints]]
d = 50
"#;

/// By hand: A1 = Rz(q1)·Tx(0.5), A2 = Rz(q2)·Tx(0.4)·Rx(180°), A3 = Tz(0.1 + q3),
/// A4 = Rz(q4)·Tz(0.05). After A2 the z axis points down (−Z), so
/// p = (0.5·c1 + 0.4·c12, 0.5·s1 + 0.4·s12, −(0.1 + q3) − 0.05); the roll about −Z turns the
/// tool x axis to the angle φ = q1 + q2 − q4 in the XY plane; z = −Z.
/// Jacobian columns: joint 1 about Z at the origin: (−py, px, 0, 0, 0, 1); joint 2 about Z at
/// (0.5·c1, 0.5·s1): (−(py − 0.5·s1), px − 0.5·c1, 0, 0, 0, 1); joint 3 slides along −Z:
/// (0, 0, −1, 0, 0, 0); joint 4 turns about −Z through the tool point: (0, 0, 0, 0, 0, −1).
#[test]
fn prismatic_scara_fk_and_jacobian_by_hand() {
    let robot = Robot::from_toml_str(SCARA).unwrap();
    assert_relative_eq!(robot.joints()[2].limits.upper, 0.3, epsilon = 1e-15);
    for q in [[0.0f64, 0.0, 0.0, 0.0], [0.3, -0.8, 0.12, 1.1], [-2.0, 1.5, 0.29, -0.4]] {
        let (c1, s1) = (q[0].cos(), q[0].sin());
        let (c12, s12) = ((q[0] + q[1]).cos(), (q[0] + q[1]).sin());
        let p = [0.5 * c1 + 0.4 * c12, 0.5 * s1 + 0.4 * s12, -(0.1 + q[2]) - 0.05];
        let phi = q[0] + q[1] - q[3];
        let expected = frame([phi.cos(), phi.sin(), 0.0], [phi.sin(), -phi.cos(), 0.0], neg(Z), p);
        assert!(max_abs_diff(&pose(&robot, &q), &expected) < 1e-12, "q={q:?}");

        #[rustfmt::skip]
        let j_expected = nalgebra::Matrix6x4::new(
            -p[1], -(p[1] - 0.5 * s1), 0.0, 0.0,
            p[0], p[0] - 0.5 * c1, 0.0, 0.0,
            0.0, 0.0, -1.0, 0.0,
            0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0,
            1.0, 1.0, 0.0, -1.0,
        );
        let j = robot.jacobian(&q).unwrap();
        assert!(max_abs_diff(&j, &j_expected) < 1e-12, "q={q:?}\n{j}");
        assert!(max_abs_diff(&j, &fd_jacobian(&robot, &q, FD_STEP)) < FD_TOLERANCE);
    }
}

/// A prismatic joint in a modified-DH chain moves along its own z axis (z_i, not z_{i−1}).
#[test]
fn prismatic_joint_in_modified_dh() {
    let robot = Robot::from_toml_str(&arm_mdh(ARM4_MDH)).unwrap();
    let q0 = [0.2, 0.05, -0.4, 0.9];
    let mut q1 = q0;
    q1[1] += 0.1;
    let (t0, t1) = (pose(&robot, &q0), pose(&robot, &q1));
    // Moving joint 2 by 0.1 m translates the tool by 0.1·z₂ and leaves the rotation alone.
    let z2 = robot.frames(&q0).unwrap()[1].rotation.matrix().column(2).into_owned();
    let shift: Vector3<f64> = t1.fixed_view::<3, 1>(0, 3) - t0.fixed_view::<3, 1>(0, 3);
    assert_relative_eq!(shift, z2 * 0.1, epsilon = 1e-12);
    let r0: Matrix3<f64> = t0.fixed_view::<3, 3>(0, 0).into_owned();
    let r1: Matrix3<f64> = t1.fixed_view::<3, 3>(0, 0).into_owned();
    assert_relative_eq!(r0, r1, epsilon = 1e-12);
    let j = robot.jacobian(&q0).unwrap();
    assert_relative_eq!(j.fixed_view::<3, 1>(0, 1).into_owned(), z2, epsilon = 1e-12);
    assert_relative_eq!(j.fixed_view::<3, 1>(3, 1).into_owned(), Vector3::zeros(), epsilon = 1e-15);
}

// ---------------------------------------------------------------------------------------
// Manipulability.
// ---------------------------------------------------------------------------------------

/// For a square Jacobian Yoshikawa's measure √det(J·Jᵀ) is |det J|; for the planar arm's
/// two translational rows (x, y) of a 2-link arm it is l1·l2·|sin q2|.
#[test]
fn manipulability_matches_closed_forms() {
    use reach::kinematics::{JacobianAxes, Manipulability};
    let mut rng = Rng::new(0x5eed_0008);
    for name in ["puma560", "ur5", "welder6r", "spbu6"] {
        let robot = presets::get(name).unwrap();
        for _ in 0..10 {
            let q = rng.joints(&robot);
            let j = robot.jacobian(&q).unwrap();
            let det = nalgebra::Matrix6::from_iterator(j.iter().copied()).determinant().abs();
            let m = robot.manipulability(&q).unwrap();
            assert_relative_eq!(m.yoshikawa, det, max_relative = 1e-9, epsilon = 1e-12);
            assert_eq!(m.singular_values.len(), 6);
            assert!(m.singular_values.windows(2).all(|w| w[0] >= w[1]));
            assert_relative_eq!(m.condition, m.sigma_max / m.sigma_min, max_relative = 1e-12);
        }
    }
    let two_link = Robot::from_toml_str(
        "name = \"two\"\nlength_unit = \"m\"\nangle_unit = \"rad\"\njoints = [{ a = 0.7 }, { a = 0.4 }]\n",
    )
    .unwrap();
    for q2 in [0.3f64, -1.2, 2.5] {
        let j = two_link.jacobian(&[0.8, q2]).unwrap();
        let m = Manipulability::of(&j, JacobianAxes::Translation);
        assert_relative_eq!(m.yoshikawa, 0.7 * 0.4 * q2.sin().abs(), epsilon = 1e-12);
        assert_eq!(m.rank, 2);
    }
    // Stretched out (q2 = 0): singular, rank 1 in the translational rows.
    let m = Manipulability::of(&two_link.jacobian(&[0.8, 0.0]).unwrap(), JacobianAxes::Translation);
    assert!(m.yoshikawa.abs() < 1e-12 && m.rank == 1 && m.condition > 1e12);
    // PUMA with the wrist straight (q5 = 0) is singular: joints 4 and 6 are aligned.
    let puma = presets::get("puma560").unwrap();
    let m = puma.manipulability(&[0.1, 0.2, -0.3, 0.4, 0.0, 0.5]).unwrap();
    assert!(m.yoshikawa < 1e-12 && m.rank == 5, "{m:?}");
}
