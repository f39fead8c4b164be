//! `softfinger._native`: the Python package's Rust half (pyo3, abi3). `softfinger/__init__.py`
//! re-exports it; the type stubs are `softfinger/__init__.pyi`.
//!
//! - [`device`]: `Device`, one connection to a device ([`softfinger_host::Device`]);
//! - [`replay`]: `replay`, recorded orientations through the core's rolling model (the same
//!   computation as `host-sim replay`, without the simulator);
//! - [`errors`]: the exceptions.

use pyo3::prelude::*;

mod arrays;
mod device;
mod errors;
mod replay;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<device::Device>()?;
    m.add_function(wrap_pyfunction!(replay::replay, m)?)?;
    m.add("Error", py.get_type::<errors::Error>())?;
    m.add("LinkError", py.get_type::<errors::LinkError>())?;
    m.add("DeviceRefused", py.get_type::<errors::DeviceRefused>())?;
    Ok(())
}
