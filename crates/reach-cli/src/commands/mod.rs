//! One module per command. Each has an `…Args` struct (clap) and a `run` function that
//! checks and computes everything first and writes to `out` last, so that an error leaves
//! stdout empty.

pub mod approach;
pub mod avoid;
pub mod check;
pub mod cspace;
pub mod cspace_render;
pub mod demo;
pub mod drive;
pub mod dynamics;
pub mod fk;
pub mod ik;
mod ik_render;
pub mod jacobian;
pub mod job;
pub mod move_cmd;
pub mod move_render;
pub mod path;
pub mod plan;
pub mod retime;
pub mod robot_show;
pub mod robots;
pub mod sense;
pub mod serve;
pub mod tasks;
pub mod tasks_render;
pub mod view;
