//! The integration tests of `reach-cli`, compiled as one test binary (`it`): one
//! module per area, the shared helpers in `common`.

mod common;

mod cli;
mod cli_approach;
mod cli_bounds;
mod cli_decide;
mod cli_drive;
mod cli_fuzz;
mod cli_ik;
mod cli_issue35;
mod cli_move;
mod cli_plot;
mod cli_retime;
mod cli_sense;
mod cli_serve;
mod cli_urdf;
mod cli_view;
mod cli_world;
mod readme_tour;
