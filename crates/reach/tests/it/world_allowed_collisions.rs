//! The scene's allowed-collision list: link pairs exempt from the self-collision check.

use reach::model::{LinkGeometry, Robot, RobotSpec, presets};
use reach::world::{CollisionChecker, PairSurvey, Scene, Verdict};

/// The UR5's stick figure with capsules of one radius on every link, instead of the preset's
/// body.
fn ur5(radius: f64) -> Robot {
    let ur5 = presets::get("ur5").unwrap();
    let links = vec![LinkGeometry { radius }; 6];
    let spec = RobotSpec { links, bodies: Vec::new(), disabled_collisions: Vec::new(), ..ur5.spec().clone() };
    Robot::new(spec).unwrap()
}

const HOME: [f64; 6] = [0.0; 6];

#[test]
fn ur5_home_collides_without_the_list_and_not_with_it() {
    let robot = ur5(0.05);
    let bare = Scene::new();
    // The wrist_1 and wrist_3 capsules overlap by 5.35 mm at home: a false self-collision.
    let v = CollisionChecker::new(&robot, &bare).check(&HOME).unwrap();
    assert_eq!(v, Verdict::SelfCollision { link_a: 4, link_b: 6 });
    let exempt = Scene::new().with_allowed_self_collision("wrist_1", "wrist_3");
    let mut checker = CollisionChecker::try_new(&robot, &exempt).unwrap();
    assert_eq!(checker.check(&HOME).unwrap(), Verdict::Free);
    let report = checker.report(&HOME).unwrap();
    let pair = report.self_pairs.iter().find(|p| p.link_a == 4 && p.link_b == 6).unwrap();
    assert!(pair.exempt && !pair.colliding && pair.clearance_m < 0.0, "{pair:?}");
    assert!(report.self_pairs.iter().filter(|p| !(p.link_a == 4 && p.link_b == 6)).all(|p| !p.exempt));
    // The exemption covers that pair only: with 6 cm capsules elbow–wrist_2 (links 3 and 5,
    // 9.15 mm apart at home) overlap too and still collide.
    let thick = ur5(0.06);
    let v = CollisionChecker::try_new(&thick, &exempt).unwrap().check(&HOME).unwrap();
    assert_eq!(v, Verdict::SelfCollision { link_a: 3, link_b: 5 });
}

#[test]
fn the_list_is_read_from_the_scene_file_by_name_or_number() {
    let robot = ur5(0.05);
    for pair in [r#"["wrist_1", "wrist_3"]"#, r#"["link6", "link4"]"#] {
        let text = format!("length_unit = \"m\"\nallowed_self_collisions = [{pair}]\n");
        let scene = Scene::from_toml_str(&text).unwrap();
        assert_eq!(scene.allowed_self_collisions.len(), 1);
        assert_eq!(CollisionChecker::try_new(&robot, &scene).unwrap().check(&HOME).unwrap(), Verdict::Free);
    }
}

#[test]
fn unknown_or_repeated_links_are_errors() {
    let robot = ur5(0.05);
    let scene = Scene::new().with_allowed_self_collision("wrist_1", "wrist_9");
    let e = CollisionChecker::try_new(&robot, &scene).unwrap_err().to_string();
    assert!(e.contains("unknown link `wrist_9`") && e.contains("wrist_3"), "{e}");
    // The infallible constructor reports it on every query instead of ignoring it.
    let mut c = CollisionChecker::new(&robot, &scene);
    assert!(c.check(&HOME).is_err());
    assert!(c.report(&HOME).is_err());
    for bad in [("link0", "wrist_1"), ("link8", "wrist_1"), ("elbow", "elbow")] {
        let scene = Scene::new().with_allowed_self_collision(bad.0, bad.1);
        assert!(CollisionChecker::try_new(&robot, &scene).is_err(), "{bad:?}");
    }
    // An entry of three names is an error naming the entry.
    let e = Scene::from_toml_str("length_unit = \"m\"\nallowed_self_collisions = [[\"a\", \"b\", \"c\"]]\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("two link names") && e.contains("entry 1"), "{e}");
}

#[test]
fn survey_finds_the_always_colliding_wrist_pair() {
    // MoveIt setup-assistant style: 2000 random configurations within the limits; the pair
    // whose capsules overlap by construction collides in every one of them.
    let robot = ur5(0.05);
    let scene = Scene::new();
    let mut checker = CollisionChecker::new(&robot, &scene);
    let survey = checker.survey_self_collisions(2000, 42).unwrap();
    assert_eq!(survey.len(), 10, "{survey:?}"); // non-adjacent pairs of 6 links
    let always: Vec<_> = survey.iter().filter(|p| p.always()).collect();
    assert_eq!(always.len(), 1, "{survey:?}");
    assert_eq!((always[0].link_a, always[0].link_b), (4, 6));
    assert_eq!((always[0].name_a.as_str(), always[0].name_b.as_str()), ("wrist_1", "wrist_3"));
    // The other pairs really do collide sometimes, or never: they stay checked.
    assert!(survey.iter().any(|p| !p.always() && !p.never()));
    assert!(survey.iter().any(PairSurvey::never));
    assert!(survey.iter().all(|p| p.samples == 2000 && p.colliding <= 2000));
    // Reproducible, and the suggested list frees the home configuration.
    assert_eq!(checker.survey_self_collisions(2000, 42).unwrap(), survey);
    let listed = always.iter().fold(Scene::new(), |s, p| s.with_allowed_self_collision(&p.name_a, &p.name_b));
    assert_eq!(CollisionChecker::try_new(&robot, &listed).unwrap().check(&HOME).unwrap(), Verdict::Free);
    assert!(checker.survey_self_collisions(0, 1).is_err());
}

#[test]
fn robots_of_64_or_more_joints_without_a_list_are_checked_without_overflow() {
    // Regression: the exemption mask was read with `mask >> j`, which overflows (and panics in
    // debug builds) for link indices of 64 and more.
    let joints: Vec<_> = (0..70)
        .map(|k| {
            let mut j = reach::model::Joint::revolute(0.1, 0.0, 0.0, 0.0);
            j.name = format!("j{k}");
            j
        })
        .collect();
    let spec = RobotSpec {
        links: vec![LinkGeometry { radius: 0.01 }; 70],
        ..RobotSpec::new("long", reach::model::Convention::Dh, joints)
    };
    let robot = Robot::new(spec).unwrap();
    let q = vec![0.0; 70];
    // Straight along x: neighbouring links touch only at their shared joint, nothing collides.
    let scene = Scene::new();
    let mut checker = CollisionChecker::try_new(&robot, &scene).unwrap();
    assert_eq!(checker.check(&q).unwrap(), Verdict::Free);
    // Folded back on itself every joint (θ = π): links far apart in the chain overlap, and the
    // check reports a self-collision instead of panicking.
    let folded = vec![std::f64::consts::PI; 70];
    assert!(matches!(checker.check(&folded).unwrap(), Verdict::SelfCollision { .. }));
}
