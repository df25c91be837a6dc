//! The `view` workflow: the states the viewer draws are the library's kinematics, the scene
//! and IK ghosts are the files' and the solver's, sizes are capped.

use reach::jobs::input::{Joints, MotionSample, Pose};
use reach::jobs::view::{MAX_VIEW_SAMPLES, ViewRequest, ViewRole, ViewShapeKind, view};
use reach::model::presets;

const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

fn example(name: &str) -> String {
    std::fs::read_to_string(format!("{REPO}/examples/{name}")).unwrap()
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn every_state_is_the_fk_of_its_sample() {
    let robot = presets::get("ur5").unwrap();
    let samples: Vec<MotionSample> = (0..=20)
        .map(|k| {
            let s = f64::from(k) / 20.0;
            MotionSample {
                t_s: 0.1 * f64::from(k),
                q_deg: vec![45.0 * s, -90.0 + 30.0 * s, 90.0 - 30.0 * s, 30.0 * s, 90.0, 0.0],
            }
        })
        .collect();
    let report = view(&robot, &ViewRequest { samples: Some(samples.clone()), ..ViewRequest::default() }).unwrap();
    assert_eq!(report.states.len(), 21);
    assert_eq!(report.samples_total, 21);
    assert!((report.duration_s - 2.0).abs() < 1e-12);
    assert_eq!(report.link_radii_m, vec![0.0; 7], "ur5 has no [[links]]: one zero radius per segment");
    for (state, sample) in report.states.iter().zip(&samples) {
        let q = Joints::Deg(sample.q_deg.clone()).si(&robot, "q").unwrap();
        let tool = robot.fk(&q).unwrap();
        assert!(close(&state.tool.xyz_m, tool.translation.vector.as_slice(), 1e-12));
        let frames = robot.frames(&q).unwrap();
        for (f, g) in state.frames.iter().zip(&frames) {
            assert!(close(&f.xyz_m, g.translation.vector.as_slice(), 1e-12));
        }
        assert_eq!(state.axes.len(), 6);
        // Joint 1 of the UR5 turns about the base z axis.
        assert!(close(&state.axes[0].direction, &[0.0, 0.0, 1.0], 1e-12));
    }
}

#[test]
fn a_long_motion_is_thinned_to_the_cap_keeping_its_ends() {
    let robot = presets::get("planar3").unwrap();
    let n = 3 * MAX_VIEW_SAMPLES + 1;
    let samples: Vec<MotionSample> =
        (0..n).map(|k| MotionSample { t_s: 0.01 * k as f64, q_deg: vec![0.01 * k as f64, 0.0, 0.0] }).collect();
    let report = view(&robot, &ViewRequest { samples: Some(samples), ..ViewRequest::default() }).unwrap();
    assert_eq!(report.states.len(), MAX_VIEW_SAMPLES);
    assert_eq!(report.samples_total, n);
    assert_eq!(report.states[0].t_s, 0.0);
    assert!((report.states[MAX_VIEW_SAMPLES - 1].t_s - 0.01 * (n - 1) as f64).abs() < 1e-12);
}

#[test]
fn scene_shapes_are_the_scene_files_in_si() {
    let robot = presets::get("varan4").unwrap();
    let request = ViewRequest {
        q: Some(Joints::Deg(vec![0.0, 30.0, -45.0, 10.0])),
        scene: Some(example("seed004_two_planes.toml")),
        ..ViewRequest::default()
    };
    let report = view(&robot, &request).unwrap();
    assert_eq!(report.shapes.len(), 3);
    assert_eq!(report.shapes[0].role, ViewRole::Obstacle);
    let ViewShapeKind::Box { center_m, half_extents_m, .. } = &report.shapes[0].kind else { panic!("not a box") };
    assert!(close(center_m, &[5.4, 0.0, 5.6], 1e-12) && close(half_extents_m, &[4.6, 10.0, 4.4], 1e-12));
    assert_eq!(report.shapes[1].name, "x > 500");
    assert_eq!(report.shapes[1].role, ViewRole::ToolZone);
    // {p : n·p ≤ offset} with n = (−1, 0, 0) through x = 0.5 m.
    let ViewShapeKind::HalfSpace { normal, offset_m } = &report.shapes[1].kind else { panic!("not a half-space") };
    assert!(close(normal, &[-1.0, 0.0, 0.0], 1e-12) && (offset_m + 0.5).abs() < 1e-12);
    assert_eq!(report.states.len(), 1);
    assert!(close(&report.states[0].q_deg, &[0.0, 30.0, -45.0, 10.0], 1e-12));
}

#[test]
fn ghosts_are_the_ik_solutions_and_reach_the_target() {
    let robot = presets::get("ur5").unwrap();
    let target = Pose::xyz_rpy_deg([0.4, 0.2, 0.3], [180.0, 0.0, 0.0]);
    let report = view(&robot, &ViewRequest { ik_target: Some(target), ..ViewRequest::default() }).unwrap();
    assert_eq!(report.ik_status.as_deref(), Some("ok"));
    assert_eq!(report.ghosts.len(), 8, "the UR5 has 8 branches for a generic pose");
    assert_eq!(report.ghosts.iter().filter(|g| g.chosen).count(), 1);
    for g in &report.ghosts {
        assert!(close(&g.state.tool.xyz_m, &[0.4, 0.2, 0.3], 1e-9), "{}: {:?}", g.branch, g.state.tool.xyz_m);
    }
    assert!(close(&report.ik_target.unwrap().xyz_m, &[0.4, 0.2, 0.3], 1e-15));
}

#[test]
fn a_task_is_planned_and_its_events_are_on_the_timeline() {
    let robot = presets::get("welder6r").unwrap();
    let request = ViewRequest { task: Some(example("seed003_welding.toml")), ..ViewRequest::default() };
    let report = view(&robot, &request).unwrap();
    let motions: Vec<_> = report.events.iter().filter(|e| e.code == "motion").collect();
    assert_eq!(motions.len(), 1);
    assert_eq!(motions[0].message, "weld P -> M");
    // Notes 003 §5.2: 943.928 mm at 1 mm/s; the −β configuration leaves θ4's range at
    // s = 618.1 mm (K7), tracked in the +β one, which stays feasible.
    let k7 = report.events.iter().find(|e| e.code == "K7").expect("a K7 event");
    assert!((k7.t_s - 618.1).abs() < 0.05, "{k7:?}");
    assert!(report.events.iter().all(|e| e.code != "infeasible"));
    assert!((report.duration_s - 943.928).abs() < 1e-3, "{}", report.duration_s);
    assert!(report.events.windows(2).all(|w| w[0].t_s <= w[1].t_s));
}

#[test]
fn bad_requests_name_their_field() {
    let robot = presets::get("ur5").unwrap();
    let both = ViewRequest {
        samples: Some(vec![MotionSample { t_s: 0.0, q_deg: vec![0.0; 6] }]),
        task: Some(example("seed003_welding.toml")),
        ..ViewRequest::default()
    };
    assert_eq!(view(&robot, &both).unwrap_err().to_string(), "task: give either samples or a task, not both");
    let outside = ViewRequest {
        samples: Some(vec![MotionSample { t_s: 0.0, q_deg: vec![0.0, 0.0, 0.0, 0.0, 0.0, 400.0] }]),
        ..ViewRequest::default()
    };
    let e = view(&robot, &outside).unwrap_err();
    assert_eq!(e.code(), "request");
    assert!(e.to_string().starts_with("samples: sample 0"), "{e}");
    let empty = ViewRequest { samples: Some(Vec::new()), ..ViewRequest::default() };
    assert_eq!(view(&robot, &empty).unwrap_err().to_string(), "samples: no sample");
}

#[test]
fn a_urdf_view_carries_its_document_and_meshes_for_the_robots_own_chain() {
    use reach::jobs::view::ViewUrdf;
    use reach::model::UrdfChain;
    let text = example("urdf/kuka_kr16_support/urdf/kr16_2.urdf");
    let tool0 = UrdfChain { base: None, tip: Some("tool0".into()) };
    let robot = reach::Robot::from_urdf_str(&text, &tool0).unwrap();
    let mut asked = Vec::new();
    let urdf = ViewUrdf::read(&text, &tool0, |f| {
        asked.push(f.to_string());
        Ok(vec![1, 2, 3])
    })
    .unwrap();
    assert_eq!(asked.len(), 7, "the visual meshes, each once: {asked:?}");
    assert!(asked.iter().all(|f| f.contains("/visual/")), "{asked:?}");
    assert_eq!((urdf.base_link.as_str(), urdf.tip_link.as_str()), ("base_link", "tool0"));
    assert_eq!(urdf.meshes[0].base64, "AQID");
    let report = view(&robot, &ViewRequest { urdf: Some(urdf), ..ViewRequest::default() }).unwrap();
    assert_eq!(report.urdf.as_ref().unwrap().meshes.len(), 7);

    // A document whose chain moves other joints than the robot's is refused.
    let link4 = UrdfChain { base: None, tip: Some("link_4".into()) };
    let short = ViewUrdf::read(&text, &link4, |_| Ok(Vec::new())).unwrap();
    let err = view(&robot, &ViewRequest { urdf: Some(short), ..ViewRequest::default() }).unwrap_err().to_string();
    assert!(err.starts_with("urdf: the chain base_link → link_4 moves joints [joint_a1"), "{err}");
    // The reader's error stops the reading.
    let failing = ViewUrdf::read(&text, &tool0, |f| Err(reach::Error::request("mesh", f.to_string())));
    assert!(failing.unwrap_err().to_string().contains("visual/base_link.dae"));
}

#[test]
fn a_cspace_section_is_the_cspace_grid_through_the_first_state() {
    use reach::jobs::view::ViewCspaceRequest;
    use reach::jobs::world::{CspaceRequest, cspace};
    let robot = presets::get("varan4").unwrap();
    let scene = example("seed004_ceiling.toml");
    let samples = vec![
        MotionSample { t_s: 0.0, q_deg: vec![0.0, 30.0, 0.0, 0.0] },
        MotionSample { t_s: 1.0, q_deg: vec![0.0, 60.0, -50.0, 12.5] },
    ];
    let request = ViewRequest {
        samples: Some(samples),
        scene: Some(scene.clone()),
        cspace: Some(ViewCspaceRequest { joints: [3, 2], step_deg: 10.0 }),
        ..ViewRequest::default()
    };
    let section = view(&robot, &request).unwrap().cspace.unwrap();
    let fix = [("q1".to_string(), 0.0), ("q4".to_string(), 0.0)].into_iter().collect();
    let grid = cspace(&robot, &CspaceRequest { scene, step_deg: 10.0, fix, fit: false, max_nodes: None }).unwrap();
    assert_eq!(section.joints, [2, 3]);
    assert_eq!(section.counts, grid.counts);
    assert_eq!(section.classes.len(), grid.counts.nodes);
    assert_eq!(section.axes_deg[0].len() * section.axes_deg[1].len(), grid.counts.nodes);
    let forbidden = section.classes.iter().filter(|&&c| c != 0).count();
    assert_eq!(forbidden, grid.counts.nodes - grid.counts.allowed);
    assert!(forbidden > 0 && grid.counts.allowed > 0);
    // The first joint varies slowest: the sections of `reach cspace` by q2 are the rows.
    let per_row = section.axes_deg[1].len();
    for (row, s) in grid.sections.iter().enumerate() {
        let allowed = section.classes[row * per_row..(row + 1) * per_row].iter().filter(|&&c| c == 0).count();
        assert_eq!(allowed, s.counts.allowed, "q2 = {}", s.value_deg);
    }
    assert!((section.off_section_deg - 12.5).abs() < 1e-9);

    let bad = ViewRequest { cspace: Some(ViewCspaceRequest { joints: [2, 2], step_deg: 5.0 }), ..request.clone() };
    assert!(view(&robot, &bad).unwrap_err().to_string().starts_with("cspace: joints 2 and 2"));
    let no_scene = ViewRequest { scene: None, ..request };
    assert_eq!(view(&robot, &no_scene).unwrap_err().to_string(), "cspace: needs a scene");
}
