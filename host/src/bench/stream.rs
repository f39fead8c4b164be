//! The stream and round-trip phases.

use super::BenchConfig;
use crate::{Device, LinkError, Target};
use serde::Serialize;
use std::time::{Duration, Instant};

/// The state stream at 1 kHz.
#[derive(Clone, Debug, Serialize)]
pub struct StreamReport {
    /// Samples received.
    pub samples: u64,
    /// Wall time from the first to the last sample, s.
    pub seconds: f64,
    /// samples / seconds.
    pub rate_hz: f64,
    /// Places where the tick did not advance by exactly the divisor.
    pub gaps: u64,
    /// Samples missing at those places.
    pub missing: u64,
    /// Longest wait between two samples on arrival, ms.
    pub max_interarrival_ms: f64,
    /// Samples the device could not queue for this client.
    pub device_dropped: u32,
    /// Device ticks that ran more than 1 ms late.
    pub overruns: u32,
}

/// Round trips of `Ping` (request to acknowledgement).
#[derive(Clone, Debug, Serialize)]
pub struct RttReport {
    pub n: usize,
    pub median_us: f64,
    pub p99_us: f64,
    pub max_us: f64,
}

/// Stream at 1 kHz for `seconds` on a connection of its own.
pub fn stream(target: &Target, seconds: f64, cfg: &BenchConfig) -> Result<StreamReport, LinkError> {
    let mut d = Device::connect(target)?;
    let info = d.info()?;
    let divisor = (info.control_rate_hz / 1000).max(1) as u16;
    d.set_stream(divisor)?;
    let t_end = Instant::now() + Duration::from_secs_f64(seconds);
    let (mut samples, mut gaps, mut missing) = (0u64, 0u64, 0u64);
    let (mut first, mut last_at, mut prev) = (None::<Instant>, None::<Instant>, None::<u64>);
    let mut max_gap = Duration::ZERO;
    let mut last = None;
    while Instant::now() < t_end {
        cfg.check_stop()?;
        let Some(s) = d.next_state(Duration::from_millis(200))? else {
            continue;
        };
        let now = Instant::now();
        first.get_or_insert(now);
        if let Some(t) = last_at {
            max_gap = max_gap.max(now - t);
        }
        last_at = Some(now);
        if let Some(p) = prev {
            if s.tick != p + divisor as u64 {
                gaps += 1;
                missing += (s.tick.saturating_sub(p) / divisor as u64).saturating_sub(1);
            }
        }
        prev = Some(s.tick);
        samples += 1;
        last = Some(s);
    }
    d.set_stream(0)?;
    let seconds = match (first, last_at) {
        (Some(a), Some(b)) => (b - a).as_secs_f64(),
        _ => 0.0,
    };
    Ok(StreamReport {
        samples,
        seconds,
        rate_hz: if seconds > 0.0 {
            (samples - 1) as f64 / seconds
        } else {
            0.0
        },
        gaps,
        missing,
        max_interarrival_ms: max_gap.as_secs_f64() * 1e3,
        device_dropped: last.map_or(0, |s| s.dropped),
        overruns: last.map_or(0, |s| s.tick_stats.overruns),
    })
}

/// `n` pings on a connection of its own, one at a time.
pub fn rtt(target: &Target, n: usize, cfg: &BenchConfig) -> Result<RttReport, LinkError> {
    let mut d = Device::connect(target)?;
    let mut us: Vec<f64> = Vec::with_capacity(n);
    for _ in 0..n {
        cfg.check_stop()?;
        us.push(d.ping()?.as_secs_f64() * 1e6);
    }
    us.sort_by(f64::total_cmp);
    let q = |p: f64| {
        us.get(((us.len() as f64 * p) as usize).min(us.len().saturating_sub(1)))
            .copied()
            .unwrap_or(0.0)
    };
    Ok(RttReport {
        n,
        median_us: q(0.5),
        p99_us: q(0.99),
        max_us: us.last().copied().unwrap_or(0.0),
    })
}
