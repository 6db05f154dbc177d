//! What `glint drivers` concludes of each driver (docs/drivers.md): how a
//! probe ended ([`probe`]), the verdict on its image against the CPU f64
//! reference ([`verdict`]), a failing scene shrunk by its objects
//! ([`shrink`]) and the reproducer a driver's bug tracker asks for
//! ([`repro`]). The command (the binary's cli/drivers/) runs the probes,
//! each in a child process, and writes the tables; this is what it judges
//! them by.

mod error;
pub mod probe;
pub mod repro;
pub mod shrink;
pub mod tree;
pub mod verdict;

pub use error::DriversError;
pub use probe::{Ended, Identity, ProbeReport, Seen, IMAGE};
pub use verdict::Verdict;
