//! What can go wrong on the GPU path, by kind, so a caller can tell a machine without a usable
//! adapter from a scene too big for it, a broken shader contract or a device that failed
//! mid-run. `Display` gives the message the command line prints.

use std::fmt;

/// A failure of the GPU path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GpuError {
    /// No adapter, none by the name asked for, or none that can run the solver.
    NoAdapter(String),
    /// The adapter was found but could not be opened.
    Open { adapter: String, message: String },
    /// The scene exceeds one of the adapter's limits (a binding size, a workgroup count).
    Limit { adapter: String, message: String },
    /// A kernel could not be built or bound: its shader and the host disagree.
    Kernel { kernel: String, message: String },
    /// The device failed while running, waiting or reading back.
    Device(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(m) | GpuError::Device(m) => f.write_str(m),
            GpuError::Open { adapter, message } => {
                write!(f, "could not open the adapter {adapter}: {message}")
            }
            GpuError::Limit { adapter, message } => {
                write!(f, "scene too big for adapter {adapter}: {message}")
            }
            GpuError::Kernel { kernel, message } => write!(f, "kernel {kernel}: {message}"),
        }
    }
}

impl std::error::Error for GpuError {}
