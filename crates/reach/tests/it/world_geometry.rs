//! Scene files, shapes, clearances and the touching policy, against hand-derived values.

use nalgebra::Vector3;
use reach::model::{Convention, Joint, LinkGeometry, Robot, RobotSpec, presets};
use reach::world::{CollisionChecker, Scene, Shape, Touching, Verdict, WorldError};

/// A planar two-link arm in the x–y plane, 1 m links, capsule radius 0.1 m.
fn two_link() -> Robot {
    let mut spec = RobotSpec::new(
        "two",
        Convention::Dh,
        vec![Joint::revolute(1.0, 0.0, 0.0, 0.0), Joint::revolute(1.0, 0.0, 0.0, 0.0)],
    );
    spec.links = vec![LinkGeometry { radius: 0.1 }, LinkGeometry { radius: 0.1 }];
    Robot::new(spec).unwrap()
}

fn scene(body: &str) -> Result<Scene, WorldError> {
    Scene::from_toml_str(&format!("length_unit = \"m\"\nangle_unit = \"deg\"\n{body}"))
}

#[test]
fn clearances_of_every_shape() {
    // Arm straight along +x: links [0,1] and [1,2] on the x axis, radius 0.1.
    let robot = two_link();
    let s = scene(
        r#"
[[obstacles]]
name = "ball"
shape = "sphere"
center = [1.5, 1.0, 0.0]
radius = 0.5
[[obstacles]]
name = "pt"
shape = "point"
at = [0.5, -0.3, 0.0]
[[obstacles]]
name = "wall"
shape = "halfspace"
point = [2.5, 0, 0]
outward_normal = [-1, 0, 0]
[[obstacles]]
name = "crate"
shape = "aabb"
min = [0.2, 0.4, -1.0]
max = [0.8, 0.9, 1.0]
[[obstacles]]
name = "turned"
shape = "box"
center = [1.0, -1.0, 0.0]
half_extents = [0.3, 0.3, 0.3]
rpy = [0, 0, 45]
[[obstacles]]
name = "rod"
shape = "capsule"
a = [1.8, 0.0, 0.5]
b = [1.8, 0.0, 2.0]
radius = 0.05
[[obstacles]]
name = "panel"
shape = "rectangle"
center = [2.0, 0.0, -0.6]
half_extents = [0.2, 0.2]
"#,
    )
    .unwrap();
    let mut checker = CollisionChecker::new(&robot, &s);
    let report = checker.report(&[0.0, 0.0]).unwrap();
    let min = |name: &str| {
        report.links.iter().filter(|l| l.obstacle == name).map(|l| l.clearance_m).fold(f64::INFINITY, f64::min)
    };
    // Ball: centre 1 m above the x axis → 1 − 0.5 − 0.1.
    assert!((min("ball") - 0.4).abs() < 1e-12);
    // Point 0.3 below link 1 → 0.3 − 0.1.
    assert!((min("pt") - 0.2).abs() < 1e-12);
    // Wall x ≥ 2.5: tip at x = 2 → 0.5 − 0.1.
    assert!((min("wall") - 0.4).abs() < 1e-12);
    // Crate's lower face y = 0.4 over x ∈ [0.2, 0.8] → 0.4 − 0.1.
    assert!((min("crate") - 0.3).abs() < 1e-12);
    // Turned box: a corner points up at y = −1 + 0.3·√2.
    assert!((min("turned") - (1.0 - 0.3 * 2f64.sqrt() - 0.1)).abs() < 1e-12);
    // Rod: its end at z = 0.5 above x = 1.8 → 0.5 − 0.05 − 0.1.
    assert!((min("rod") - 0.35).abs() < 1e-12);
    // Panel (flat, z = −0.6) under the tip → 0.6 − 0.1.
    assert!((min("panel") - 0.5).abs() < 1e-12);
    assert_eq!(report.verdict, Verdict::Free);
    assert!((report.min_obstacle_clearance_m.unwrap() - 0.2).abs() < 1e-12);
}

#[test]
fn penetration_is_negative_and_collides() {
    let robot = two_link();
    let s = scene("[[obstacles]]\nname = \"b\"\nshape = \"aabb\"\nmin = [0.4, -0.5, -0.5]\nmax = [0.6, 0.5, 0.5]\n")
        .unwrap();
    let mut c = CollisionChecker::new(&robot, &s);
    let r = c.report(&[0.0, 0.0]).unwrap();
    // The link axis passes through the box centre: deepest point 0.1 inside (x half-width);
    // minus the radius: −0.2.
    let link1 = r.links.iter().find(|l| l.link == 1).unwrap();
    assert!((link1.clearance_m + 0.2).abs() < 1e-12, "{link1:?}");
    assert_eq!(c.check(&[0.0, 0.0]).unwrap(), Verdict::Obstacle { link: 1, obstacle: 0 });
    // Turned 90°: the arm points along +y, away from the box (distance 0.4 − 0.1 − ... ).
    assert!(c.check(&[std::f64::consts::FRAC_PI_2, 0.0]).unwrap().is_free());
}

#[test]
fn touching_policy() {
    // Bare segments (no radius) and a point exactly on link 1.
    let robot = presets::get("planar3").unwrap();
    let mut s = scene("[[obstacles]]\nshape = \"point\"\nat = [0.5, 0.0, 0.0]\n").unwrap();
    let q = [0.0, 0.0, 0.0];
    assert_eq!(CollisionChecker::new(&robot, &s).check(&q).unwrap(), Verdict::Obstacle { link: 1, obstacle: 0 });
    s.touching = Touching::Open;
    assert!(CollisionChecker::new(&robot, &s).check(&q).unwrap().is_free());
}

#[test]
fn self_collision_of_folded_arm() {
    // planar3 folded: q = (0, −180°+ε…): links 1 and 3 overlap when both joints fold by 180°.
    let robot = presets::get("planar3").unwrap();
    let s = Scene::new();
    let mut c = CollisionChecker::new(&robot, &s);
    let pi = std::f64::consts::PI;
    // Link 1 along +x, link 2 back along −x, link 3 along +x again: links 1 and 3 coincide.
    assert_eq!(c.check(&[0.0, -pi, -pi]).unwrap(), Verdict::SelfCollision { link_a: 1, link_b: 3 });
    // Open Z shape: link 3 is 1·sin(90°) = 1 m from link 1.
    let r = c.report(&[0.0, -pi / 2.0, -pi / 2.0]).unwrap();
    assert_eq!(r.self_pairs.len(), 1);
    assert!((r.self_pairs[0].clearance_m - 1.0).abs() < 1e-12);
    assert!(r.verdict.is_free());
}

#[test]
fn degenerate_shapes_are_named() {
    let cases = [
        ("[[obstacles]]\nname = \"s\"\nshape = \"sphere\"\ncenter = [0,0,0]\nradius = 0\n", "sphere", "radius"),
        (
            "[[obstacles]]\nname = \"s\"\nshape = \"capsule\"\na = [0,0,0]\nb = [1,0,0]\nradius = -1\n",
            "capsule",
            "radius",
        ),
        ("[[obstacles]]\nname = \"s\"\nshape = \"aabb\"\nmin = [1,0,0]\nmax = [0,1,1]\n", "aabb", "min"),
        (
            "[[obstacles]]\nname = \"s\"\nshape = \"box\"\ncenter = [0,0,0]\nhalf_extents = [1,0,1]\n",
            "box",
            "half_extents",
        ),
        ("[[obstacles]]\nname = \"s\"\nshape = \"sphere\"\ncenter = [nan,0,0]\nradius = 1\n", "sphere", "center"),
        (
            "[[obstacles]]\nname = \"s\"\nshape = \"halfspace\"\npoint = [0,0,0]\noutward_normal = [0,0,0]\n",
            "halfspace",
            "outward_normal",
        ),
        ("[[obstacles]]\nname = \"s\"\nshape = \"sphere\"\ncenter = [0,0,0]\n", "sphere", "missing field `radius`"),
        (
            "[[obstacles]]\nname = \"s\"\nshape = \"sphere\"\ncenter = [0,0,0]\nradius = 1\nmin = [0,0,0]\n",
            "sphere",
            "`min`",
        ),
        ("[[obstacles]]\nname = \"s\"\nshape = \"cone\"\n", "cone", "unknown shape"),
        (
            "[[obstacles]]\nname = \"s\"\nshape = \"rectangle\"\ncenter = [0,0,0]\nhalf_extents = [1,1,1]\n",
            "rectangle",
            "2 values",
        ),
    ];
    for (body, shape, needle) in cases {
        let e = scene(body).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, WorldError::Shape { .. }), "{body}: {msg}");
        assert!(msg.contains(shape) && msg.contains(needle) && msg.contains("`s`"), "{body}: {msg}");
    }
    // Unknown top-level field and bad syntax: parse errors with a line number.
    let e = scene("colour = \"red\"\n").unwrap_err();
    assert!(matches!(e, WorldError::Parse { line: 3, .. }), "{e}");
    let e = Scene::from_toml_str("length_unit = \n").unwrap_err();
    assert!(matches!(e, WorldError::Parse { .. }), "{e}");
    // Built in code: NaN rejected too.
    assert!(Scene::new().with_obstacle("n", Shape::Point { at: Vector3::new(f64::NAN, 0.0, 0.0) }).is_err());
}

#[test]
fn units_are_converted() {
    let s = Scene::from_toml_str(
        "length_unit = \"mm\"\nangle_unit = \"rad\"\n[[obstacles]]\nshape = \"sphere\"\ncenter = [1000, 0, 0]\nradius = 250\n",
    )
    .unwrap();
    assert_eq!(s.obstacles[0].shape, Shape::Sphere { center: Vector3::new(1.0, 0.0, 0.0), radius: 0.25 });
    assert_eq!(s.obstacles[0].name, "obstacle1");
}

#[test]
fn nan_joint_vector_is_an_error() {
    let robot = two_link();
    let s = Scene::new();
    assert!(CollisionChecker::new(&robot, &s).check(&[f64::NAN, 0.0]).is_err());
    assert!(CollisionChecker::new(&robot, &s).check(&[0.0]).is_err());
}

/// The fast check (broad phase, box early outs) agrees with the exact clearances of the
/// report on 600 random UR5 configurations among shapes placed within its reach.
#[test]
fn fast_check_agrees_with_exact_clearances() {
    let ur5 = presets::get("ur5").unwrap();
    let robot = Robot::new(RobotSpec { links: vec![LinkGeometry { radius: 0.03 }; 6], ..ur5.spec().clone() }).unwrap();
    let s = scene(
        r#"
[[obstacles]]
shape = "sphere"
center = [0.4, 0.2, 0.3]
radius = 0.1
[[obstacles]]
shape = "box"
center = [-0.3, 0.3, 0.4]
half_extents = [0.1, 0.15, 0.05]
rpy = [20, 30, 40]
[[obstacles]]
shape = "aabb"
min = [0.1, -0.6, -0.1]
max = [0.4, -0.3, 0.2]
[[obstacles]]
shape = "capsule"
a = [-0.4, -0.4, 0.0]
b = [-0.4, -0.4, 0.8]
radius = 0.05
[[obstacles]]
shape = "rectangle"
center = [0.0, 0.5, 0.6]
half_extents = [0.2, 0.1]
rpy = [45, 0, 0]
[[obstacles]]
shape = "point"
at = [0.3, 0.3, 0.6]
"#,
    )
    .unwrap();
    let mut checker = CollisionChecker::new(&robot, &s);
    let mut seed = 99_u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 * std::f64::consts::PI - std::f64::consts::PI
    };
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..600 {
        let q: Vec<f64> = (0..6).map(|_| rnd()).collect();
        let report = checker.report(&q).unwrap();
        if report.self_pairs.iter().any(|p| p.colliding) {
            continue;
        }
        let exact = report.links.iter().any(|l| l.clearance_m <= reach::tolerance::CONTACT);
        let fast = matches!(checker.check(&q).unwrap(), Verdict::Obstacle { .. });
        assert_eq!(fast, exact, "{q:?}");
        if exact { hits += 1 } else { misses += 1 }
    }
    // Both outcomes occur, so the comparison means something.
    assert!(hits > 20 && misses > 20, "{hits} {misses}");
}
