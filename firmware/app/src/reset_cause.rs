//! Why the MCU last reset, from the reset flags a board reads at start-up (on the STM32G474:
//! RCC_CSR, cleared after reading). Logged at boot and reported in the host link's device info.

/// The reset flags as read, board-independent (RM0440 §7.4.28 RCC_CSR on the STM32G474).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResetFlags {
    /// Low-power reset (LPWRRSTF).
    pub low_power: bool,
    /// Window watchdog (WWDGRSTF).
    pub window_watchdog: bool,
    /// Independent watchdog (IWDGRSTF): a hung tick or thread-mode task, or a fault handler
    /// waiting for the watchdog.
    pub independent_watchdog: bool,
    /// Software reset (SFTRSTF): `SCB::sys_reset`, a debugger's reset, the bootloader.
    pub software: bool,
    /// Option-byte loading (OBLRSTF).
    pub option_bytes: bool,
    /// Brown-out or power-on (BORRSTF).
    pub brown_out: bool,
    /// The NRST pin (PINRSTF): the reset button, the ST-LINK; also set with every other cause,
    /// since the chip drives NRST low while it resets.
    pub pin: bool,
}

/// The one cause reported: the most specific flag set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ResetCause {
    PowerOn,
    Pin,
    Software,
    IndependentWatchdog,
    WindowWatchdog,
    LowPower,
    OptionBytes,
    /// No flag set (flags cleared without a reset since, e.g. a debugger's core-only reset).
    Unknown,
}

impl ResetCause {
    /// The most specific cause among `flags`: NRST only when no other flag is set (every reset
    /// drives NRST), a watchdog before software (a fault handler never resets by software).
    pub fn from_flags(flags: ResetFlags) -> ResetCause {
        if flags.independent_watchdog {
            ResetCause::IndependentWatchdog
        } else if flags.window_watchdog {
            ResetCause::WindowWatchdog
        } else if flags.low_power {
            ResetCause::LowPower
        } else if flags.software {
            ResetCause::Software
        } else if flags.option_bytes {
            ResetCause::OptionBytes
        } else if flags.brown_out {
            ResetCause::PowerOn
        } else if flags.pin {
            ResetCause::Pin
        } else {
            ResetCause::Unknown
        }
    }

    /// A short lower-case name, as the device info carries it.
    pub fn name(self) -> &'static str {
        match self {
            ResetCause::PowerOn => "power-on",
            ResetCause::Pin => "reset-pin",
            ResetCause::Software => "software",
            ResetCause::IndependentWatchdog => "watchdog",
            ResetCause::WindowWatchdog => "window-watchdog",
            ResetCause::LowPower => "low-power",
            ResetCause::OptionBytes => "option-bytes",
            ResetCause::Unknown => "unknown",
        }
    }
}
