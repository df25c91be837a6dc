//! One module per command. Each has an `…Args` struct (clap) and a `run` function that
//! checks and computes everything first and writes to `out` last, so that an error leaves
//! stdout empty.

pub mod demo;
pub mod fk;
pub mod jacobian;
pub mod robot_show;
pub mod robots;
