//! The passivity stage's damper limit on the device plant's 3x wall: for each limit, the late
//! peak to peak of the 0.6 s run (`haptic_device::run`, the figure `host-sim stability` reports)
//! and the largest 0.1 s peak to peak over the last second of a 2 s run (`envelope`).
//!
//! `cargo run --release -p host-sim --example damper_limit -- RATE_HZ DELAY_TICKS FINE LIMIT...`
//! (FINE: the motor encoder's resolution as a multiple of the device's; LIMIT in N·s/m), e.g.
//! `... -- 10000 0.247 16 50 56 60 100`. The wall is 3 × the largest passive one at that rate and
//! delay on the device's own encoder, as in `host-sim stability`.

use host_sim::experiments::stability::{encoder_cell, haptic_device as hd};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err("usage: damper_limit RATE_HZ DELAY_TICKS FINE LIMIT...".into());
    }
    let rate_hz: f64 = args[0].parse()?;
    let delay_ticks: f64 = args[1].parse()?;
    let fine: u32 = args[2].parse()?;
    let base = hd::DeviceLoop::omega_like(rate_hz, delay_ticks, false);
    let k = 3.0 * hd::kmax(&base)?.ok_or("no largest passive wall in the sweep")?;
    println!("rate {rate_hz} Hz, delay {delay_ticks} ticks, encoder x{fine}, wall {k:.0} N/m");
    for limit in &args[3..] {
        let l = hd::DeviceLoop {
            passivity: true,
            motor_counts_per_rev: base.motor_counts_per_rev * fine,
            damper_limit_n_s_per_m: limit.parse()?,
            ..base
        };
        let short = hd::run(&l, k)?;
        let (env, _) = hd::envelope(&l, k)?;
        let long = encoder_cell::late_max_m(&env).ok_or("short envelope")?;
        println!(
            "limit {limit:>6} N·s/m: 0.6 s run late {:7.3} µm; 2 s run, last second {:7.3} µm",
            short.late_amp_m * 1e6,
            long * 1e6
        );
    }
    Ok(())
}
