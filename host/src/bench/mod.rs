//! Link measurements on the virtual device over loopback (`softfinger bench`, and the
//! integration tests with short durations): the state stream's rate and gaps, command round
//! trips, local-model updates without force steps, the watchdog's fade, and bad input from one
//! client while the others go on.
//!
//! Phases: (1) one client streams at 1 kHz for `stream_s` while a second pings and a third sends
//! bad frames of every kind; (2) a fourth client holds the simulated hand pressed on the surface,
//! arms, streams every tick and sends local models: still, at 1 kHz, and as 1 mm jumps;
//! (3) it enables the watchdog and goes silent. Then the device is put back as found
//! ([`restore`]: parameters, model, watchdog, hand and mode), also after a failed phase.

mod bad_input;
mod models;
mod restore;
mod stream;

pub use bad_input::{run as bad_input_phase, BadInputReport};
pub use models::{run as models_phase, ModelReport, WatchdogReport};
pub use restore::{restore, snapshot, RestoreReport, Snapshot};
pub use stream::{rtt as rtt_phase, stream as stream_phase, RttReport, StreamReport};

use crate::{Device, LinkError, Target};
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::time::Duration;

/// What a run stopped by [`BenchConfig::stop`] says.
pub const INTERRUPTED: &str = "interrupted before the end";

/// Durations and counts of a run.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Stream phase, s.
    pub stream_s: f64,
    /// Round trips to time.
    pub pings: usize,
    /// Seconds of each local-model pattern (still, 1 kHz stream, jumps).
    pub model_s: f64,
    /// Watchdog timeout, ms.
    pub watchdog_ms: u16,
    /// Set (for example by a Ctrl-C handler) to end the run early: every phase polls it, the
    /// device is put back as found, and [`run`] returns an error saying so.
    pub stop: Option<&'static AtomicBool>,
}

impl BenchConfig {
    /// An error ([`INTERRUPTED`]) once [`BenchConfig::stop`] is set.
    pub fn check_stop(&self) -> Result<(), LinkError> {
        match self.stop {
            Some(f) if f.load(Relaxed) => Err(LinkError::Context(INTERRUPTED.into())),
            _ => Ok(()),
        }
    }

    /// Sleep `d`, waking every 20 ms to [`BenchConfig::check_stop`].
    pub fn sleep(&self, d: Duration) -> Result<(), LinkError> {
        let end = std::time::Instant::now() + d;
        while let Some(left) = end.checked_duration_since(std::time::Instant::now()) {
            self.check_stop()?;
            std::thread::sleep(left.min(Duration::from_millis(20)));
        }
        self.check_stop()
    }
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            stream_s: 60.0,
            pings: 5000,
            model_s: 2.0,
            watchdog_ms: 100,
            stop: None,
        }
    }
}

/// Everything measured.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub stream: StreamReport,
    pub rtt: RttReport,
    pub bad_input: BadInputReport,
    pub models: ModelReport,
    pub watchdog: WatchdogReport,
    pub restored: RestoreReport,
}

/// True for a loopback TCP target (the benchmark refuses anything else).
pub fn is_loopback(target: &Target) -> bool {
    match target {
        Target::Tcp(a) => a
            .rsplit_once(':')
            .is_some_and(|(h, _)| matches!(h, "127.0.0.1" | "localhost" | "[::1]")),
        _ => false,
    }
}

/// Name the phase in an error.
fn ctx(phase: &'static str) -> impl Fn(LinkError) -> LinkError {
    move |e| LinkError::Context(format!("{phase}: {e}"))
}

/// Join a bench thread; a panic becomes an error.
fn join<T>(h: std::thread::ScopedJoinHandle<'_, Result<T, LinkError>>) -> Result<T, LinkError> {
    h.join()
        .unwrap_or_else(|_| Err(LinkError::Protocol("a bench thread panicked".into())))
}

/// Run every phase against `target` (a loopback virtual device).
pub fn run(target: &Target, cfg: &BenchConfig) -> Result<BenchReport, LinkError> {
    if !is_loopback(target) {
        return Err(LinkError::BadTarget(format!(
            "{target}: the benchmark runs on a loopback virtual device only"
        )));
    }
    let mut keeper = Device::connect(target)?;
    let rate = keeper.info()?.control_rate_hz;
    let found = restore::snapshot(&mut keeper).map_err(ctx("reading the device's state"))?;
    drop(keeper);
    let phases = || {
        let (stream, rtt, bad_input) = std::thread::scope(|s| {
            let streamer =
                s.spawn(|| stream::stream(target, cfg.stream_s, cfg).map_err(ctx("stream")));
            let pinger =
                s.spawn(|| stream::rtt(target, cfg.pings, cfg).map_err(ctx("round trips")));
            let bad = s.spawn(|| {
                bad_input::run(target, cfg.stream_s / 2.0, cfg).map_err(ctx("bad input"))
            });
            Ok::<_, LinkError>((join(streamer)?, join(pinger)?, join(bad)?))
        })?;
        let (models, watchdog) = models::run(target, rate, cfg).map_err(ctx("local models"))?;
        Ok::<_, LinkError>((stream, rtt, bad_input, models, watchdog))
    };
    let result = phases();
    // Back as found, whatever happened (the keeper's connection may have gone with the device).
    let mut d = match Device::connect(target) {
        Ok(d) => d,
        Err(e) => return result.and(Err(ctx("restoring the device")(e))),
    };
    let restored = restore::restore(&mut d, &found).map_err(ctx("restoring the device"));
    if cfg.check_stop().is_err() {
        // Interrupted: the phases' results are partial; say whether the device is as found.
        let left = match &restored {
            Ok(r) if r.complete() => "the device was put back as found".to_string(),
            Ok(r) => format!("the device was NOT fully put back: {r:?}"),
            Err(e) => format!("the device could not be put back: {e}"),
        };
        return Err(LinkError::Context(format!("{INTERRUPTED}; {left}")));
    }
    let (stream, rtt, bad_input, models, watchdog) = result?;
    Ok(BenchReport {
        stream,
        rtt,
        bad_input,
        models,
        watchdog,
        restored: restored?,
    })
}
