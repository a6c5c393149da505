//! Machines and materials as data: a plotter's or cutter's profile (`machines/*.toml`:
//! protocol, connection, media, tools and their dash codes, the steps for the maker's own
//! software) and a sheet's material (`materials/*.toml`) laid over it, each checked
//! against the range of every key when read. Sending a job to the machine is `plotter`'s.

mod lookup;
pub mod material;
mod profile;
mod protocol;

pub use material::{known_materials, Material, MaterialError};
pub use profile::{
    known_machines, search_path, Machine, MachineError, MAX_PEN, MIN_DASH_MM, STANDARD_BAUDS,
};
pub use protocol::{
    line_bytes_per_second, AxisOrder, Connection, FlowMode, Protocol, SerialLine,
    DEVICE_BYTES_PER_S,
};
