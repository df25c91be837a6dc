//! The integration tests of `reach-serve`, compiled as one test binary (`it`): the router
//! in-process (`api`), restarts of the state (`durability`), the socket and WebSocket
//! (`socket`). Helpers in `common`.

mod common;

mod api;
mod durability;
mod socket;
mod world;
