//! What the device is doing now ([`DeviceStatus`], answered to [`crate::Request::GetStatus`]),
//! and which value of a refused request was out of range ([`FieldRange`], in
//! [`crate::DeviceMsg::Rejected`]).

use crate::info::Text;
use crate::model::LocalModel;
use crate::state::Mode;
use serde::{Deserialize, Serialize};

/// The device's mode, flags and the local model in force.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeviceStatus {
    /// Control tick since the device started (time = tick / control rate).
    pub tick: u64,
    /// Operating mode.
    pub mode: Mode,
    /// `softfinger_core::Flags` bits raised in the last tick (latched ones included).
    pub flags: u32,
    /// Faults latched by the output guard until `ClearFaults` (`softfinger_core::Flags` bits).
    pub latched: u32,
    /// The local model in force (its pose in the device base frame).
    pub model: LocalModel,
}

/// A value the device refused: the field's wire name (as in [`crate::ContactParamsWire`]) and
/// the range it accepts, `min ..= max` (`min` itself excluded when `min_exclusive`), in the
/// field's unit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FieldRange {
    /// The field's name, e.g. `normal_stiffness`.
    pub field: Text<24>,
    /// Smallest accepted value.
    pub min: f32,
    /// True when `min` itself is refused (the field must be above it).
    pub min_exclusive: bool,
    /// Largest accepted value.
    pub max: f32,
}
