//! `bench`: the link measurements on a loopback virtual device (see the library's `bench`).

use softfinger_host::bench::{self, BenchConfig};
use softfinger_host::Target;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Stream phase, s.
    #[arg(long, default_value_t = 60.0)]
    pub seconds: f64,
    /// Round trips to time.
    #[arg(long, default_value_t = 5000)]
    pub pings: usize,
    /// Seconds of each local-model pattern.
    #[arg(long, default_value_t = 2.0)]
    pub model_seconds: f64,
    /// As JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    let ok = |v: f64| v.is_finite() && v > 0.0 && v <= 3600.0;
    if !ok(a.seconds) || !ok(a.model_seconds) || a.pings == 0 {
        return Err("--seconds and --model-seconds must be within (0, 3600], --pings > 0".into());
    }
    let target: Target = spec
        .parse()
        .map_err(|e: softfinger_host::LinkError| e.to_string())?;
    // Ctrl-C ends the phases early; the device is still put back as found (exit 130).
    super::interrupt::install();
    let cfg = BenchConfig {
        stream_s: a.seconds,
        pings: a.pings,
        model_s: a.model_seconds,
        stop: Some(super::interrupt::flag()),
        ..BenchConfig::default()
    };
    let r = bench::run(&target, &cfg).map_err(|e| e.to_string())?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    let s = &r.stream;
    println!(
        "stream: {} samples in {:.2} s = {:.1} Hz; gaps {} ({} missing); longest wait {:.2} ms; dropped by the device {}; device overruns {}",
        s.samples, s.seconds, s.rate_hz, s.gaps, s.missing, s.max_interarrival_ms, s.device_dropped, s.overruns
    );
    let t = &r.rtt;
    println!(
        "round trip (ping -> ack, {} while streaming): median {:.0} us, p99 {:.0} us, max {:.0} us",
        t.n, t.median_us, t.p99_us, t.max_us
    );
    let (b, c) = (&r.bad_input, &r.bad_input.counted);
    println!(
        "bad input ({} garbage bytes + {} each of truncated, oversized, wrong-version, wrong-CRC): counted {} (cobs {} crc {} version {} decode {} oversized {}), answered {}, bad client still usable: {}",
        b.garbage_bytes, b.crafted_each, c.rx_errors, c.rx_cobs, c.rx_crc, c.rx_version, c.rx_decode, c.rx_oversized, b.answered, b.still_usable
    );
    let m = &r.models;
    println!(
        "local models (hand pressing, mean |F| {:.2} N): still max |dF|/tick {:.4} N; {} updates at {:.0} Hz ({} refused, last applied: {}) max |dF|/tick {:.4} N; {} jumps of {:.1} N max |dF|/tick {:.4} N; ticks {} seen, {} missing",
        m.mean_force_n, m.max_step_still_n, m.stream_updates, m.stream_rate_hz, m.stream_refused, m.last_applied,
        m.max_step_stream_n, m.jumps, m.jump_force_n, m.max_step_jumps_n, m.ticks_seen, m.ticks_missing
    );
    let w = &r.watchdog;
    println!(
        "watchdog {} ms: |F| {:.2} N faded to 0 in {:.1} ms after COMM_TIMEOUT; latched until re-armed: {}; recovered after re-arm: {}",
        w.timeout_ms, w.force_before_n, w.fade_ms, w.latched, w.recovered
    );
    let b = &r.restored;
    println!(
        "device left as found: {} (mode {} -> {}, parameters {}, model {}, watchdog {}){}",
        if b.complete() { "yes" } else { "no" },
        b.mode_found,
        b.mode_left,
        b.params_restored,
        b.model_restored,
        b.watchdog_restored,
        if b.notes.is_empty() {
            String::new()
        } else {
            format!("; {}", b.notes.join("; "))
        }
    );
    Ok(())
}
