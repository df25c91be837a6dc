//! The integration tests of `reach`, compiled as one test binary (`it`): one module per
//! area, the shared helpers in `common`, fixtures in `tests/data/`.
//!
//! Proptest keeps failing cases of `it/<module>.rs` in `tests/proptest-regressions/<module>.txt`
//! (its default `SourceParallel` layout, now that this directory has a `main.rs`); they are
//! replayed before new cases.

mod common;

mod bounds;

mod decide_detour;
mod decide_ik;
mod decide_mcdm;
mod decide_motion;
mod decide_sequence;
mod drive_model;
mod drive_output;
mod drive_schedule;
mod dynamics_energy;
mod dynamics_input;
mod dynamics_model;
mod dynamics_reference;
mod fuzz;
mod ik_branch;
mod ik_detect;
mod ik_from_geometry;
mod ik_numeric;
mod ik_round_trip;
mod ik_solve_into;
mod jobs_view;
mod kinematics_batch;
mod kinematics_presets;
mod kinematics_properties;
mod kinematics_reference;
mod model_errors;
mod model_joint_limits;
mod motion_blends;
mod motion_jerk;
mod motion_optimal;
mod motion_paths;
mod motion_profiles_timing;
mod motion_tracking;
mod seed_000_detour;
mod seed_000_log_loader;
mod seed_000_planar4;
mod seed_000_planar_ik;
mod seed_000_sensing;
mod seed_000_stepper;
mod seed_001_ik;
mod seed_001_motion;
mod seed_001_spbu6_fk;
mod seed_002_spherical_wrist;
mod seed_003_criteria;
mod seed_003_ik;
mod seed_003_tracking;
mod seed_003_welder6r_fk;
mod seed_004_approach;
mod seed_004_cspace;
mod seed_004_fit;
mod seed_004_ik_varan4;
mod urdf_import;
mod urdf_literal;
mod urdf_panda;
mod world_allowed_collisions;
mod world_bodies;
mod world_geometry;
mod world_moving;
mod world_planner;
mod world_rfunction;
mod world_sweep;
