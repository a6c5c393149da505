//! The studio as a library and as a server: sessions, routes, and what no other page may do.
//! One test crate per concept, each module a former crate of its own: compiled and
//! linked once (see tests/run).

#[path = "common/hostile_inputs.rs"]
mod hostile_inputs;
#[path = "common/scratch.rs"]
mod scratch;
#[path = "common/studio.rs"]
mod studio_process;

#[path = "studio/session.rs"]
mod session;
#[path = "studio/studio_http.rs"]
mod studio_http;
#[path = "studio/studio_security.rs"]
mod studio_security;
#[path = "studio/studio_server.rs"]
mod studio_server;
