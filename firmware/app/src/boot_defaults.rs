//! What the stored settings change at boot, on the firmware and the virtual device alike.
//!
//! - `watchdog.timeout_ms`: the communication watchdog's timeout a host's `Arm` turns on
//!   ([`Pipeline::set_host_watchdog`]). 0 keeps the built-in
//!   [`HOST_WATCHDOG_S`](softfinger_core::control::pipeline::HOST_WATCHDOG_S): a host that arms
//!   always holds a watchdog (the lost-link rule), so "off" is not a choice for it. A device
//!   armed from its button, with no host, has none, as before.
//! - `stream.rate_hz`: the state stream the link starts with, before any `SetStream` (0: off).
//!   The rate becomes the control rate's divisor, rounded to the nearest, and never faster than
//!   the link's fastest stream (the firmware's [`crate::stream::min_stream_divisor`]).
//!
//! Not applied: the calibration (`calibration.*`). Its homing offsets and wrist zero are counts
//! of incremental encoders, which start from zero at every power-up, so a zero from an earlier
//! power cycle does not hold: the device homes at every power-up and keeps the stored record for
//! the host's bench tools. The contact-parameter presets are selected by an application
//! (`config get` reads them); the device starts on its built-in contact parameters, the
//! default plane a device nobody talks to renders.

use softfinger_core::contact::params::ParamError;
use softfinger_core::control::controller::Environment;
use softfinger_core::control::pipeline::Pipeline;
use softfinger_core::math::Math;
use softfinger_store::Settings;

/// The stored settings' boot-time effects.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BootDefaults {
    /// The host watchdog's timeout, s; `None`: the built-in one.
    pub host_watchdog_s: Option<f32>,
    /// The stream's rate at boot, Hz (0: off).
    pub stream_rate_hz: u16,
}

impl BootDefaults {
    /// A device without stored settings: the built-in watchdog, no stream.
    pub const BUILT_IN: BootDefaults = BootDefaults {
        host_watchdog_s: None,
        stream_rate_hz: 0,
    };

    /// The effects of `settings` (the ones the boot loaded, or the defaults it fell back to).
    pub fn of(settings: &Settings) -> BootDefaults {
        let ms = settings.watchdog.timeout_ms;
        BootDefaults {
            host_watchdog_s: (ms != 0).then(|| f32::from(ms) / 1000.0),
            stream_rate_hz: settings.stream.rate_hz,
        }
    }

    /// Set `pipeline`'s host watchdog. A timeout the pipeline refuses (the store validates the
    /// same range, so only a store written by other code) leaves the built-in one, and says why.
    pub fn apply<M: Math, E: Environment>(
        &self,
        pipeline: &mut Pipeline<M, E>,
    ) -> Result<(), ParamError> {
        match self.host_watchdog_s {
            Some(t) => pipeline.set_host_watchdog(t),
            None => Ok(()),
        }
    }

    /// The stream divisor at `control_rate_hz` (0: off): `control / rate` rounded to the
    /// nearest, at least `min_divisor` (the link's fastest stream).
    pub fn stream_divisor(&self, control_rate_hz: u32, min_divisor: u16) -> u16 {
        if self.stream_rate_hz == 0 {
            return 0;
        }
        let rate = u32::from(self.stream_rate_hz);
        let d = (control_rate_hz + rate / 2) / rate;
        let d = d.clamp(1, u32::from(u16::MAX)) as u16;
        d.max(min_divisor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(timeout_ms: u16, rate_hz: u16) -> BootDefaults {
        let mut s = Settings::default();
        s.watchdog.timeout_ms = timeout_ms;
        s.stream.rate_hz = rate_hz;
        BootDefaults::of(&s)
    }

    #[test]
    fn the_default_settings_change_nothing_but_the_watchdog_they_name() {
        let d = BootDefaults::of(&Settings::default());
        assert_eq!(d.host_watchdog_s, Some(0.2));
        assert_eq!(d.stream_divisor(10_000, 5), 0);
        assert_eq!(with(0, 0), BootDefaults::BUILT_IN);
    }

    #[test]
    fn stream_rates_round_to_the_nearest_divisor_never_past_the_fastest() {
        assert_eq!(with(200, 1000).stream_divisor(10_000, 5), 10);
        assert_eq!(with(200, 1).stream_divisor(10_000, 5), 10_000);
        // 10 000 / 1 333 = 7.502 rounds up to 8; / 1 334 = 7.496 down to 7.
        assert_eq!(with(200, 1333).stream_divisor(10_000, 5), 8);
        assert_eq!(with(200, 1334).stream_divisor(10_000, 5), 7);
        // Above 2 kHz: the link's fastest stream (divisor 5 at 10 kHz, 10 at 20 kHz).
        assert_eq!(with(200, 2001).stream_divisor(10_000, 5), 5);
        assert_eq!(with(200, 10_000).stream_divisor(20_000, 10), 10);
        assert_eq!(with(200, 2000).stream_divisor(20_000, 10), 10);
        // A link without that limit (the virtual device's): the rate itself.
        assert_eq!(with(200, 10_000).stream_divisor(10_000, 1), 1);
        assert_eq!(with(200, 3333).stream_divisor(10_000, 1), 3);
    }
}
