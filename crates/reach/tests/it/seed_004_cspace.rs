//! Seed 004 (Pritykin & Nefedov 2016): the configuration-space grid of the Varan arm with
//! q1 = 0 (notes 004 §4 A) and the reference counts of notes 004 §5.4.
//!
//! Conventions (notes 004 §5.4): 15° grid over the limit box, both limits included
//! (9 × 17 × 17 = 2601 nodes); the task zone θ (x_o4 > 500 mm, z_o4 > 0) is strict with a
//! 1e-6 mm tolerance (`tolerance::CONTACT`); links are bare segments; obstacles are closed
//! sets (touching collides) unless the scene says `touching = "open"`.
//! The paper prints no N values (they are only in its figures), so these are the notes'
//! derived regression counts under the reconstructed kinematics of notes 004 §2.2.

use reach::model::presets;
use reach::world::cspace::{GridSpec, NodeClass, classify_grid, classify_node};
use reach::world::{CollisionChecker, Scene, Touching};

fn grid(scene: &Scene) -> reach::world::cspace::CspaceGrid {
    let varan = presets::get("varan4").unwrap();
    classify_grid(&varan, scene, &GridSpec::new(4, 15f64.to_radians()).fix(0, 0.0)).unwrap()
}

fn layers(g: &reach::world::cspace::CspaceGrid) -> Vec<usize> {
    g.counts_by(1).iter().map(|c| c.allowed).collect()
}

fn scene(text: &str) -> Scene {
    Scene::from_toml_str(text).unwrap()
}

#[test]
fn no_obstacle_1041() {
    let g = grid(&scene(include_str!("../../../../examples/seed004_free.toml")));
    assert_eq!(g.counts.nodes, 2601);
    assert_eq!(g.counts.allowed, 1041);
    assert_eq!(layers(&g), [121, 142, 154, 160, 152, 132, 98, 58, 24]);
    // The grid lies inside the limit box; notes 004 §2.2: no self-intersection inside θ.
    assert_eq!(g.counts.outside_limits, 0);
    assert_eq!(g.counts.self_collision, 0);
    assert_eq!(g.counts.obstacle_collision, 0);
    assert_eq!(g.counts.outside_zone, 2601 - 1041);
}

#[test]
fn theta_boundary_nodes_are_excluded() {
    // Notes 004 §4 A step 4: (0, 0, 0) has z_o4 = 0 exactly, (30, −120, 120) has z_o4 = 0
    // analytically (−1.4e−13 mm in floating point): both are outside the strict zone θ.
    let g = grid(&scene(include_str!("../../../../examples/seed004_free.toml")));
    let index = |q2: f64, q3: f64, q4: f64| {
        let i = |v: f64, lo: f64| ((v - lo) / 15.0).round() as usize;
        (i(q2, 0.0) * 17 + i(q3, -120.0)) * 17 + i(q4, -120.0)
    };
    assert_eq!(g.classes[index(0.0, 0.0, 0.0)], NodeClass::OutsideZone);
    assert_eq!(g.classes[index(30.0, -120.0, 120.0)], NodeClass::OutsideZone);
    // (30, 0, 0): O4 = (1818.653, 1050) mm, well inside.
    assert_eq!(g.classes[index(30.0, 0.0, 0.0)], NodeClass::Allowed);
    let q = g.node(index(30.0, -120.0, 120.0));
    assert!((q[1].to_degrees() - 30.0).abs() < 1e-12 && (q[3].to_degrees() - 120.0).abs() < 1e-12);
}

#[test]
fn ceiling_1200_gives_635_closed_and_636_open() {
    let mut s = scene(include_str!("../../../../examples/seed004_ceiling.toml"));
    let g = grid(&s);
    assert_eq!(g.counts.allowed, 635);
    assert_eq!(layers(&g), [120, 111, 103, 83, 72, 61, 43, 26, 16]);
    // (q2, q3, q4) = (0, 90, 0): O4 = (900, 1200) touches the ceiling (notes 004 §8).
    s.touching = Touching::Open;
    let g = grid(&s);
    assert_eq!(g.counts.allowed, 636);
    assert_eq!(layers(&g)[0], 121);
}

#[test]
fn ceiling_800_touching_layer() {
    // Notes 004 §5.4: z ≥ 800 gives 257 (closed) / 264 (open); the q2 = 30 layer is 44 / 51.
    let text = include_str!("../../../../examples/seed004_ceiling.toml").replace("[0, 0, 1200]", "[0, 0, 800]");
    let mut s = scene(&text);
    let g = grid(&s);
    assert_eq!(g.counts.allowed, 257);
    assert_eq!(layers(&g), [70, 50, 44, 45, 44, 0, 0, 0, 4]);
    s.touching = Touching::Open;
    let g = grid(&s);
    assert_eq!(g.counts.allowed, 264);
    assert_eq!(layers(&g)[2], 51);
}

#[test]
fn two_planes_769_and_the_other_reading_782() {
    let s = scene(include_str!("../../../../examples/seed004_two_planes.toml"));
    let g = grid(&s);
    assert_eq!(g.counts.allowed, 769);
    assert_eq!(layers(&g), [120, 121, 113, 95, 86, 82, 75, 53, 24]);
    let mut open = s.clone();
    open.touching = Touching::Open;
    assert_eq!(grid(&open).counts.allowed, 773);
    // The other side of Δ: the quadrant {z ≥ 1200, x ≤ 800} → 782 (notes 004 §5.4).
    let text = include_str!("../../../../examples/seed004_two_planes.toml")
        .replace("min = [800, -10000, 1200]", "min = [-10000, -10000, 1200]")
        .replace("max = [10000, 10000, 10000]", "max = [800, 10000, 10000]");
    let g = grid(&scene(&text));
    assert_eq!(g.counts.allowed, 782);
    assert_eq!(layers(&g), [121, 131, 134, 117, 105, 84, 48, 26, 16]);
}

#[test]
fn rectangle_fig_2c_reading() {
    // Notes 004 §5.4: the rectangle [500, 900] × [800, 850] mm gives 790 (closed) / 791 (open)
    // with 102 nodes in the q2 = 60 layer. Written as a planar shape would have no
    // thickness; the zone is a solid 2-D rectangle, so it is an (x, z) box thick in y.
    let text = include_str!("../../../../examples/seed004_two_planes.toml")
        .replace("min = [800, -10000, 1200]", "min = [500, -1000, 800]")
        .replace("max = [10000, 10000, 10000]", "max = [900, 1000, 850]");
    let mut s = scene(&text);
    let g = grid(&s);
    assert_eq!(g.counts.allowed, 790);
    assert_eq!(layers(&g)[4], 102);
    s.touching = Touching::Open;
    assert_eq!(grid(&s).counts.allowed, 791);
}

#[test]
fn union_reading_of_theta_is_not_what_the_counts_use() {
    // Notes 004 D3: as a union, {x > 500} ∪ {z > 0} would admit 2523 nodes. With one zone
    // entry only (z > 0) the count must be at least the intersection's 1041 and at most 2523.
    let text = include_str!("../../../../examples/seed004_free.toml");
    let only_z = &text[..text.find("[[tool_zone]]\nname = \"x > 500\"").unwrap()].to_string();
    let z_part = &text[text.find("[[tool_zone]]\nname = \"z > 0\"").unwrap()..];
    let g = grid(&scene(&format!("{only_z}{z_part}")));
    assert!(g.counts.allowed > 1041 && g.counts.allowed <= 2523, "{}", g.counts.allowed);
}

#[test]
fn progress_hook_counts_every_node_once_per_chunk_and_changes_nothing() {
    use reach::world::cspace::{PROGRESS_CHUNK, classify_grid, classify_grid_with_progress};
    use std::sync::Mutex;
    let varan = reach::model::presets::get("varan4").unwrap();
    let scene = reach::world::Scene::from_toml_str(include_str!("../../../../examples/seed004_ceiling.toml")).unwrap();
    let spec = reach::world::cspace::GridSpec::new(4, 3f64.to_radians()).fix(0, 0.0);
    let calls = Mutex::new(Vec::new());
    let with = classify_grid_with_progress(&varan, &scene, &spec, &|done, total| {
        calls.lock().unwrap().push((done, total));
    })
    .unwrap();
    let plain = classify_grid(&varan, &scene, &spec).unwrap();
    assert_eq!(with, plain);
    let nodes = plain.counts.nodes;
    assert_eq!(nodes, 41 * 81 * 81);
    let mut calls = calls.into_inner().unwrap();
    assert_eq!(calls.len(), nodes.div_ceil(PROGRESS_CHUNK));
    assert!(calls.iter().all(|&(_, total)| total == nodes));
    calls.sort_unstable();
    // `done` values are distinct running totals ending at the node count.
    assert!(calls.windows(2).all(|w| w[0].0 < w[1].0));
    assert_eq!(calls.last().unwrap().0, nodes);
}

#[test]
fn axis_index_walks_the_nodes_row_major() {
    use reach::world::cspace::{CspaceGrid, GridCounts};
    // One fixed joint and three swept ones of 2, 3 and 2 values: 12 nodes, the first joint
    // varying slowest. The classes mark the position on the q3 axis.
    let axes = vec![vec![0.5], vec![1.0, 2.0], vec![3.0, 4.0, 5.0], vec![6.0, 7.0]];
    let class = [NodeClass::Allowed, NodeClass::OutsideZone, NodeClass::ObstacleCollision];
    let mut classes = Vec::new();
    let mut expected = Vec::new();
    for (a, _) in axes[0].iter().enumerate() {
        for (b, _) in axes[1].iter().enumerate() {
            for (c, _) in axes[2].iter().enumerate() {
                for (d, _) in axes[3].iter().enumerate() {
                    classes.push(class[c]);
                    expected.push([a, b, c, d]);
                }
            }
        }
    }
    let g = CspaceGrid { axes: axes.clone(), classes, counts: GridCounts::default() };
    for (i, k) in expected.iter().enumerate() {
        for (j, &kj) in k.iter().enumerate() {
            assert_eq!(g.axis_index(i, j), Some(kj), "node {i}, joint {j}");
        }
        assert_eq!(g.axis_index(i, 4), None);
        assert_eq!(g.node(i), (0..4).map(|j| axes[j][k[j]]).collect::<Vec<f64>>(), "node {i}");
    }
    let by_q3 = g.counts_by(2);
    assert_eq!(by_q3.len(), 3);
    for (c, counts) in by_q3.iter().enumerate() {
        assert_eq!(counts.nodes, 4, "{by_q3:?}");
        let own = [counts.allowed, counts.outside_zone, counts.obstacle_collision];
        assert_eq!(own.iter().sum::<usize>(), 4);
        assert_eq!(own[c], 4, "{by_q3:?}");
    }
    assert!(g.counts_by(4).is_empty());
    // A grid with an empty axis has no node: no index, and no panic.
    let empty = CspaceGrid { axes: vec![vec![1.0], vec![]], classes: vec![], counts: GridCounts::default() };
    assert_eq!(empty.axis_index(0, 1), None);
    assert!(empty.node(0)[1].is_nan());
}

/// The grid reuses the outer joints' link frames between nodes and tests each axis value
/// against the limits once: every node still gets `classify_node`'s class, node by node, on
/// 5° grids of the three example scenes, a grid whose ranges leave the limits (nodes outside
/// them between checked ones) and a grid sweeping all four joints.
#[test]
fn grid_classes_are_the_per_node_classes() {
    let varan = presets::get("varan4").unwrap();
    let d = f64::to_radians;
    let wide = GridSpec {
        ranges: vec![None, Some((d(-10.0), d(130.0))), Some((d(-140.0), d(125.0))), Some((d(-125.0), d(140.0)))],
        ..GridSpec::new(4, d(7.0)).fix(0, 0.0)
    };
    let all_four = GridSpec::new(4, d(20.0));
    let mut seen = [0_usize; 5];
    for (text, spec) in [
        (include_str!("../../../../examples/seed004_free.toml"), GridSpec::new(4, d(5.0)).fix(0, 0.0)),
        (include_str!("../../../../examples/seed004_ceiling.toml"), GridSpec::new(4, d(5.0)).fix(0, 0.0)),
        (include_str!("../../../../examples/seed004_two_planes.toml"), GridSpec::new(4, d(5.0)).fix(0, 0.0)),
        (include_str!("../../../../examples/seed004_two_planes.toml"), wide),
        (include_str!("../../../../examples/seed004_ceiling.toml"), all_four),
    ] {
        let s = scene(text);
        let g = classify_grid(&varan, &s, &spec).unwrap();
        let mut checker = CollisionChecker::new(&varan, &s);
        for (i, class) in g.classes.iter().enumerate() {
            let q = g.node(i);
            assert_eq!(*class, classify_node(&mut checker, &q).unwrap(), "node {i} at {q:?}");
            seen[*class as usize] += 1;
        }
    }
    // Every class but self-collision occurs (varan4's links do not reach each other here).
    assert!(seen.iter().enumerate().all(|(k, n)| k == NodeClass::SelfCollision as usize || *n > 100), "{seen:?}");
}
