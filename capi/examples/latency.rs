//! What a state sample costs from its arrival to `sf_latest_state`, through the C ABI.
//!
//! `cargo run --release -p softfinger-c --example latency -- tcp:127.0.0.1:7700 [samples]`
//!
//! Streams at 1 kHz and polls `sf_latest_state` in a busy loop; for each new sample, the time
//! from when the library's reader thread read the bytes that completed it (its arrival) to the
//! first `sf_latest_state` that returned it; and the duration of an `sf_latest_state` call.
//! Prints the median and the 99th percentile of each, in microseconds.

use softfinger::{sf_close, sf_latest_state, sf_open, sf_set_stream, sf_state, sf_strerror};
use std::ffi::{CStr, CString};
use std::time::{Duration, Instant};

fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let target = args.next().unwrap_or_else(|| "tcp:127.0.0.1:7700".into());
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(5000);
    let c_target = CString::new(target.clone()).expect("a target without NUL");
    let mut err = 0;
    // SAFETY: a NUL-terminated target and a valid `err`; the handle is closed once at the end.
    unsafe {
        let dev = sf_open(c_target.as_ptr(), &mut err);
        if dev.is_null() {
            let why = CStr::from_ptr(sf_strerror(err)).to_string_lossy();
            eprintln!("latency: cannot open {target}: {why}");
            std::process::exit(1);
        }
        assert_eq!(sf_set_stream(dev, 1000.0), 0, "stream at 1 kHz");
        let (mut to_visible, mut call) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let mut last = 0;
        let deadline = Instant::now() + Duration::from_secs(n as u64 / 500 + 10);
        let mut s = sf_state::default();
        while to_visible.len() < n && Instant::now() < deadline {
            let t0 = Instant::now();
            let got = sf_latest_state(dev, &mut s);
            let t1 = Instant::now();
            if got != 1 {
                continue;
            }
            call.push((t1 - t0).as_secs_f64() * 1e6);
            if let Some(l) = softfinger::latest_with_arrival(dev) {
                // The sample just returned is this one if the count did not move meanwhile.
                if l.count != last && l.sample.tick == s.tick {
                    last = l.count;
                    to_visible.push((t1.saturating_duration_since(l.arrived)).as_secs_f64() * 1e6);
                }
            }
        }
        sf_close(dev);
        if to_visible.is_empty() {
            eprintln!("latency: no samples");
            std::process::exit(1);
        }
        let (m1, p1) = (
            percentile(&mut to_visible, 0.5),
            percentile(&mut to_visible, 0.99),
        );
        let (m2, p2) = (percentile(&mut call, 0.5), percentile(&mut call, 0.99));
        println!(
            "latency: {} samples; arrival -> sf_latest_state: median {m1:.2} us, p99 {p1:.2} us; \
             one sf_latest_state call: median {m2:.3} us, p99 {p2:.3} us",
            to_visible.len()
        );
    }
}
