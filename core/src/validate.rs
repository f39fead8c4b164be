//! Shared parameter validation: the one error type every layer's parameters are rejected with
//! ([`ParamError`], naming the field) and the range checks they are made of. Nothing is clamped
//! silently. Sits just above the device's hardware description, whose own error
//! ([`DeviceParamError`]) it wraps, and below the contact model and the control layer.

use crate::device::hardware::DeviceParamError;

/// Why a parameter set was rejected. Each variant names the offending field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamError {
    /// The field is NaN or ±inf.
    NotFinite(&'static str),
    /// The field must be > 0.
    NotPositive(&'static str),
    /// The field must be ≥ 0.
    Negative(&'static str),
    /// The field is outside its documented range.
    OutOfRange(&'static str),
    /// μ_k must not exceed μ_s.
    KineticAboveStatic,
    /// The device parameters were rejected.
    Device(DeviceParamError),
}

impl core::fmt::Display for ParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ParamError::NotFinite(n) => write!(f, "{n} is not finite"),
            ParamError::NotPositive(n) => write!(f, "{n} must be > 0"),
            ParamError::Negative(n) => write!(f, "{n} must be >= 0"),
            ParamError::OutOfRange(n) => write!(f, "{n} is out of range"),
            ParamError::KineticAboveStatic => write!(f, "mu_k must not exceed mu_s"),
            ParamError::Device(e) => write!(f, "device parameters: {e}"),
        }
    }
}

impl core::error::Error for ParamError {}

/// Check `v` is finite and > 0.
pub fn positive(name: &'static str, v: f32) -> Result<(), ParamError> {
    if !v.is_finite() {
        Err(ParamError::NotFinite(name))
    } else if v <= 0.0 {
        Err(ParamError::NotPositive(name))
    } else {
        Ok(())
    }
}

/// Check `v` is finite and ≥ 0.
pub fn non_negative(name: &'static str, v: f32) -> Result<(), ParamError> {
    if !v.is_finite() {
        Err(ParamError::NotFinite(name))
    } else if v < 0.0 {
        Err(ParamError::Negative(name))
    } else {
        Ok(())
    }
}

/// Check `v` is finite and at most `max` (the upper end of its documented range).
pub fn at_most(name: &'static str, v: f32, max: f32) -> Result<(), ParamError> {
    if !v.is_finite() {
        Err(ParamError::NotFinite(name))
    } else if v > max {
        Err(ParamError::OutOfRange(name))
    } else {
        Ok(())
    }
}

/// A value that passed its type's validation (`ContactParams::checked`,
/// `LocalModelSpec::checked`): only this crate makes one, so a stage or the control tick can take
/// it without checking again. The firmware checks a host's command where it arrives, in thread
/// mode, and the tick only applies it (`crate::control::command::CheckedCommand`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checked<T>(T);

impl<T> Checked<T> {
    /// Mark `value` as checked: only after its validation passed.
    pub(crate) const fn assume_checked(value: T) -> Checked<T> {
        Checked(value)
    }

    /// The checked value.
    pub fn get(&self) -> &T {
        &self.0
    }

    /// The checked value, by value.
    pub fn into_inner(self) -> T {
        self.0
    }
}

impl<T> core::ops::Deref for Checked<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}
