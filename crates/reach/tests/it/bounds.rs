//! Bounded resources and cancellation at the library's job layer (issue 12): sizes over
//! their cap are refused as `Error::Request` naming the field, the size and the cap, before
//! anything is allocated; a set `reach::Cancel` stops the numeric solver and the grid.

use reach::jobs::ik::{IkRequest, ik, ik_with_cancel};
use reach::jobs::input::Pose;
use reach::jobs::world::{CspaceRequest, cspace, cspace_with_cancel};
use reach::world::WorldError;
use reach::world::cspace::{DEFAULT_MAX_NODES, MAX_NODES};
use reach::{Cancel, Error};

fn varan() -> reach::Robot {
    reach::model::presets::get("varan4").unwrap()
}

fn grid(step_deg: f64, max_nodes: Option<usize>) -> CspaceRequest {
    CspaceRequest {
        scene: include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/seed004_free.toml")).to_string(),
        step_deg,
        fix: [("q1".to_string(), 0.0)].into(),
        fit: false,
        max_nodes,
    }
}

fn request_field(e: Error) -> (String, String) {
    match e {
        Error::Request { field, reason } => (field, reason),
        e => panic!("not a request error: {e}"),
    }
}

#[test]
fn cspace_grid_over_its_cap_names_step_size_and_cap() {
    let (field, reason) = request_field(cspace(&varan(), &grid(1e-9, None)).unwrap_err());
    assert_eq!(field, "step_deg");
    assert!(reason.contains(&DEFAULT_MAX_NODES.to_string()) && reason.contains("nodes"), "{reason}");
    let (field, reason) = request_field(cspace(&varan(), &grid(15.0, Some(2600))).unwrap_err());
    assert_eq!(field, "step_deg");
    assert!(reason.contains("2601 nodes") && reason.contains("cap of 2600"), "{reason}");
    assert_eq!(cspace(&varan(), &grid(15.0, Some(2601))).unwrap().counts.nodes, 2601);
    for bad in [0, MAX_NODES + 1] {
        assert_eq!(request_field(cspace(&varan(), &grid(15.0, Some(bad))).unwrap_err()).0, "max_nodes");
    }
}

#[test]
fn a_set_cancel_stops_the_grid() {
    let cancel = Cancel::new();
    cancel.cancel();
    let e = cspace_with_cancel(&varan(), &grid(15.0, None), &|_, _| {}, &cancel).unwrap_err();
    assert!(matches!(e, Error::World(WorldError::Cancelled)), "{e}");
}

fn panda_request(restarts: usize) -> IkRequest {
    let mut request = IkRequest::new(Pose::xyz_rpy_deg([0.4, 0.0, 0.4], [180.0, 0.0, 0.0]));
    request.numeric.restarts = Some(restarts);
    request
}

#[test]
fn untimed_numeric_ik_is_capped_and_a_budget_lifts_the_cap() {
    let panda = reach::model::presets::get("panda").unwrap();
    let (field, reason) = request_field(ik(&panda, &panda_request(1_000_000_000)).unwrap_err());
    assert_eq!(field, "numeric.restarts");
    assert!(reason.contains("1000000000 starts") && reason.contains("1000000"), "{reason}");
    // 5000 × 200 = the cap exactly.
    assert!(ik(&panda, &panda_request(5000)).is_ok());
    let mut timed = panda_request(1_000_000_000);
    timed.numeric.time_budget_s = Some(0.05);
    assert!(ik(&panda, &timed).is_ok());
}

#[test]
fn a_set_cancel_ends_a_huge_timed_solve() {
    let panda = reach::model::presets::get("panda").unwrap();
    let mut request = panda_request(1_000_000_000);
    request.numeric.time_budget_s = Some(86_400.0);
    let cancel = Cancel::new();
    cancel.cancel();
    // Ends at once: every start stops at its first iteration.
    let report = ik_with_cancel(&panda, &request, &cancel).unwrap();
    assert_eq!(report.found, 0);
}
