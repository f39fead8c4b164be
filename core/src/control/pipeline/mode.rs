//! The pipeline's operating modes, and how the operator commands ([`crate::control::command`])
//! move between them.
//!
//! ```text
//!  power-up ──► Unhomed ──Home──► Homing ──stops found──► Disarmed ──Arm──► Armed (force ramps in)
//!                  ▲                 │ Disarm (abort)        ▲  ▲            │
//!                  └─────────────────┘                       │  └──Disarm────┘
//!  any latched fault, in any mode ──► Faulted ──ClearFaults──► Disarmed if still homed,
//!                                                              Unhomed otherwise (never Armed)
//! ```
//!
//! No force is ever rendered outside `Armed`; the bridges are driven only in `Homing` (the homing
//! procedure's bounded torque) and `Armed`.

/// Operating mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mode {
    /// Power-up: encoder zero unknown, drivers asleep, no torque.
    #[default]
    Unhomed,
    /// The homing procedure drives the arms to their stops with a bounded torque.
    Homing,
    /// Homed; drivers awake, PWM disabled: zero torque. The controller runs (outputs discarded).
    Disarmed,
    /// Rendering forces; after arming the force ramps in over the configured time.
    Armed,
    /// A fault latched: drivers asleep, zero torque, until `ClearFaults`.
    Faulted,
}

impl Mode {
    /// Small integer code for compact logs (0 = Unhomed … 4 = Faulted).
    pub const fn code(self) -> u8 {
        match self {
            Mode::Unhomed => 0,
            Mode::Homing => 1,
            Mode::Disarmed => 2,
            Mode::Armed => 3,
            Mode::Faulted => 4,
        }
    }

    /// Name for logs and reports.
    pub const fn name(self) -> &'static str {
        match self {
            Mode::Unhomed => "unhomed",
            Mode::Homing => "homing",
            Mode::Disarmed => "disarmed",
            Mode::Armed => "armed",
            Mode::Faulted => "faulted",
        }
    }
}
