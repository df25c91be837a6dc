//! The integration tests of `reach-serve`, compiled as one test binary (`it`): the router
//! in-process (`api`), restarts of the state (`durability`), seed 003's operator dialogue (`operator`), the socket and WebSocket
//! (`socket`). Helpers in `common`.

mod common;

mod api;
mod durability;
mod limits;
mod operator;
mod recovery;
mod socket;
mod world;
