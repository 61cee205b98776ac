//! What foldsim writes for other tools to run it: the FMU archive (`foldsim export fmu`,
//! docs/interop.md). The FMU's binary is the `fmu/` crate, a thin face of
//! [`crate::session::Session`]; this layer chooses its variables, writes its model
//! description and packs the archive.
//!
//! - [`fmu`]: the variables, `modelDescription.xml`, the archive.

pub mod fmu;
