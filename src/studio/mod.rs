//! The studio: the paper's interactive design system (§5) as a local web app served by the
//! binary. The user drags vertices of the 3D form with the mouse; the solver keeps every
//! chosen condition while it follows (null-space step and Newton correction, §3); the
//! crease pattern and the flat-folded x-ray are drawn beside it.
//!
//! ```text
//! browser page (embedded assets) ⇄ HTTP ⇄ server ──> api ──> hub (mailbox) ──> session
//!                                                                          uses │
//!                                          io, generate, solver, fab, pipeline <─┘
//! ```
//! It binds 127.0.0.1 only and holds no geometry of its own.

pub mod api;
mod assets;
mod frame;
mod http;
pub mod hub;
mod server;
pub mod session;

pub use assets::THREE_VERSION;
pub use hub::Hub;
pub use server::{Studio, StudioError, StudioOptions};
pub use session::{Command, Refusal, Reply, Session};
