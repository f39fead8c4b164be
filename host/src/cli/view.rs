//! `view`: a live panel of the device state, redrawn 10 times a second in the terminal (one line
//! per refresh when the output is not a terminal). Ctrl-C ends it.

use super::connect;
use softfinger_host::protocol::{LinkCounters, StateSample};
use softfinger_host::{flags, LinkError};
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Stop after this many seconds (default: until Ctrl-C).
    #[arg(long)]
    pub seconds: Option<f64>,
}

/// A horizontal bar of `v` on a scale of ±`full`, `width` characters each side.
fn bar(v: f32, full: f32, width: usize) -> String {
    let x = if v.is_finite() {
        (v.abs() / full).min(1.0)
    } else {
        0.0
    };
    let n = (x * width as f32).round() as usize;
    let (l, r) = if v < 0.0 {
        (
            format!("{}{}", " ".repeat(width - n), "█".repeat(n)),
            " ".repeat(width),
        )
    } else {
        (
            " ".repeat(width),
            format!("{}{}", "█".repeat(n), " ".repeat(width - n)),
        )
    };
    format!("{l}│{r}")
}

fn panel(s: &StateSample, c: &LinkCounters, rate_hz: f64, max_force: f32, hz: f64) -> String {
    let mm = |v: [f32; 3]| format!("{:8.2} {:8.2} {:8.2}", v[0] * 1e3, v[1] * 1e3, v[2] * 1e3);
    let f = s.force_n;
    let fmag = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let mut out = String::new();
    out += &format!(
        " softfinger   t {:9.3} s   mode {:<9}  contact {:<8}  model {}\n\n",
        s.tick as f64 / rate_hz,
        s.mode.name(),
        s.contact.name(),
        s.model_seq
    );
    out += &format!(" probe     mm {}\n", mm(s.probe_m));
    out += &format!(" velocity mm/s{}\n", mm(s.probe_vel_m_s));
    out += &format!(" contact   mm {}\n\n", mm(s.contact_point_m));
    for (k, name) in ["Fx", "Fy", "Fz"].iter().enumerate() {
        out += &format!(" {name} {:7.3} N {}\n", f[k], bar(f[k], max_force, 25));
    }
    out += &format!(" |F| {:6.3} N {}\n", fmag, bar(fmag, max_force, 25));
    out += &format!(" spin torque {:8.3} mN·m\n\n", s.spin_torque_nm * 1e3);
    out += &format!(
        " flags  {}\n",
        if s.flags == 0 {
            "-".into()
        } else {
            flags::describe(s.flags)
        }
    );
    out += &format!(
        " tick   max {} ns  mean {} ns  overruns {}   stream {:.0} Hz, dropped {}\n",
        s.tick_stats.max_duration_ns,
        s.tick_stats.mean_duration_ns,
        s.tick_stats.overruns,
        hz,
        s.dropped
    );
    out += &format!(
        " link   rx {} frames, {} errors   tx {} frames, {} dropped   {} connections\n",
        c.rx_frames, c.rx_errors, c.tx_frames, c.tx_dropped, c.connections
    );
    out
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    let mut dev = connect(spec).map_err(|e| e.to_string())?;
    let info = dev.info().map_err(|e| e.to_string())?;
    let rate = info.control_rate_hz as f64;
    let divisor = super::stream::divisor_for(info.control_rate_hz, 100.0, info.min_stream_divisor)?;
    dev.set_stream(divisor).map_err(|e| e.to_string())?;
    let tty = std::io::stdout().is_terminal();
    let t0 = Instant::now();
    let mut counters = dev.counters().map_err(|e| e.to_string())?;
    let mut last_counters = Instant::now();
    let (mut n, mut window) = (0u32, Instant::now());
    let mut hz = 0.0;
    let mut latest = None;
    while a.seconds.is_none_or(|s| t0.elapsed().as_secs_f64() < s) {
        let frame_end = Instant::now() + Duration::from_millis(100);
        while let Some(left) = frame_end.checked_duration_since(Instant::now()) {
            match dev.next_state(left) {
                Ok(Some(s)) => {
                    latest = Some(s);
                    n += 1;
                }
                Ok(None) => break,
                Err(LinkError::Disconnected) => {
                    println!(
                        "{}device gone: reconnecting...",
                        if tty { "\x1b[2J\x1b[H" } else { "" }
                    );
                    std::thread::sleep(Duration::from_millis(300));
                    let _ = dev.reconnect();
                    break;
                }
                Err(e) => return Err(e.to_string()),
            }
        }
        if window.elapsed() >= Duration::from_secs(1) {
            hz = n as f64 / window.elapsed().as_secs_f64();
            (n, window) = (0, Instant::now());
        }
        if last_counters.elapsed() >= Duration::from_secs(1) {
            if let Ok(c) = dev.counters() {
                counters = c;
            }
            last_counters = Instant::now();
        }
        let Some(s) = latest else { continue };
        let text = panel(&s, &counters, rate, info.max_force_n, hz);
        let mut out = std::io::stdout().lock();
        if tty {
            let _ = write!(out, "\x1b[2J\x1b[H{text}");
        } else {
            let first = text.lines().next().unwrap_or_default().trim().to_string();
            let _ = writeln!(out, "{first}  F {:?}", s.force_n);
        }
        let _ = out.flush();
    }
    let _ = dev.set_stream(0);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_are_symmetric_and_saturate() {
        assert_eq!(bar(0.0, 1.0, 3), "   │   ");
        assert_eq!(bar(0.5, 1.0, 4), "    │██  ");
        assert_eq!(bar(-2.0, 1.0, 2), "██│  ");
        assert_eq!(bar(f32::NAN, 1.0, 2), "  │  ");
    }
}
