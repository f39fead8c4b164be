//! The board interface as the app sees it (`crate::board`): the shared traits, and this board's
//! fail-safe items.

pub use crate::hw::{emergency_stop, BASEPRI_BELOW_TICK};
pub use crate::interface::*;
