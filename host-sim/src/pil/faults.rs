//! Faults injected in the processor-in-the-loop run, and how the plant side sees them.
//!
//! Firmware-side faults (`panic`, `hang`) are asked of the board at boot (its test hook injects
//! them in the tick); plant-side faults (`encoder-glitch`, `driver-fault`, `log-stall`) are made by
//! the host and mirrored in the in-process reference, so those runs must still match it tick by
//! tick.

use clap::ValueEnum;
use serde::Serialize;
use softfinger_core::control::pipeline::RawInput;

/// A fault to inject `--fault-at-s` after the scene starts (the device homed and armed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fault {
    /// No fault.
    None,
    /// `panic!` inside the control tick: the outputs must go off and stay off.
    Panic,
    /// The control tick never returns: the watchdog resets the MCU, outputs off meanwhile.
    Hang,
    /// The host stops reading the defmt log: frames are dropped, the tick never waits.
    LogStall,
    /// Motor 0's raw encoder count jumps by [`GLITCH_COUNTS`] for one sample.
    EncoderGlitch,
    /// The drivers' nFAULT line is asserted from then on.
    DriverFault,
}

/// The jump of the encoder glitch, counts (over the firmware's glitch threshold at any rate).
pub const GLITCH_COUNTS: u16 = 4000;

impl Fault {
    /// The code the board's test hook understands (0: nothing for the board to do).
    pub fn board_code(self) -> u32 {
        match self {
            Fault::Panic => 1,
            Fault::Hang => 2,
            _ => 0,
        }
    }

    /// The in-process reference reproduces this fault (plant-side faults).
    pub fn mirrored_in_reference(self) -> bool {
        !matches!(self, Fault::Panic | Fault::Hang)
    }

    /// The fault should take the outputs off for good.
    pub fn expects_outputs_off(self) -> bool {
        !matches!(self, Fault::None | Fault::LogStall)
    }

    /// Apply a plant-side fault to tick `tick`'s raw sample; `at_tick` is the fault's tick, once
    /// known (the scene has started).
    pub fn edit_sample(self, tick: u64, at_tick: Option<u64>, raw: &mut RawInput) {
        let Some(at) = at_tick else {
            return;
        };
        match self {
            Fault::EncoderGlitch if tick == at => {
                raw.counts[0] = raw.counts[0].wrapping_add(GLITCH_COUNTS)
            }
            Fault::DriverFault if tick >= at => raw.driver_fault = true,
            _ => {}
        }
    }
}
