//! The exceptions: `softfinger.Error`, and under it `LinkError` (the connection: cannot open,
//! no answer, closed, bad target, ...) and `DeviceRefused` (the device said no; `.code` is its
//! error code's name, e.g. `"WrongMode"`). Bad arguments are `ValueError`.

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use softfinger_host::LinkError as HostError;

create_exception!(
    softfinger,
    Error,
    PyException,
    "Base of the softfinger errors."
);
create_exception!(
    softfinger,
    LinkError,
    Error,
    "The link to the device failed: it could not be opened, did not answer in time, closed, or answered something unexpected."
);
create_exception!(
    softfinger,
    DeviceRefused,
    Error,
    "The device refused a request; `.code` is the name of its error code (e.g. \"WrongMode\")."
);

/// The Python exception of a failed exchange.
pub fn to_py(e: HostError) -> PyErr {
    match e {
        HostError::Refused(code) | HostError::Rejected { code, .. } => Python::attach(|py| {
            let name = format!("{code:?}");
            let err = DeviceRefused::new_err(e.to_string());
            // Setting an attribute on a fresh exception object cannot fail short of memory.
            let _ = err.value(py).setattr("code", name);
            err
        }),
        HostError::BadTarget(_) => PyValueError::new_err(e.to_string()),
        other => LinkError::new_err(other.to_string()),
    }
}
