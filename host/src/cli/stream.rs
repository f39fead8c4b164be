//! `stream --seconds S --csv FILE`: the state stream to CSV, with a progress bar. If the device
//! goes away the stream reconnects and goes on (the gap is counted); the file is written only
//! when the run completes.

use super::connect;
use host_sim::atomic_file::AtomicFile;
use indicatif::{ProgressBar, ProgressStyle};
use softfinger_host::protocol::StateSample;
use softfinger_host::{flags, Device, LinkError};
use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Seconds of device time to record (at most 3600).
    #[arg(long)]
    pub seconds: f64,
    /// Output CSV file (written when the run completes).
    #[arg(long)]
    pub csv: PathBuf,
    /// Samples per second: the device's control rate divided by an integer (within 1 %).
    #[arg(long, default_value_t = 1000.0)]
    pub rate_hz: f64,
    /// Give up after this long without the device, s.
    #[arg(long, default_value_t = 10.0)]
    pub reconnect_s: f64,
}

const HEADER: &str = "t_s,tick,x_m,y_m,z_m,vx_m_s,vy_m_s,vz_m_s,fx_n,fy_n,fz_n,spin_torque_nm,contact,cx_m,cy_m,cz_m,mode,flags,flag_names,model_seq,tick_max_ns,tick_mean_ns,overruns,dropped";

fn row(s: &StateSample, rate_hz: f64) -> String {
    let [x, y, z] = s.probe_m;
    let [vx, vy, vz] = s.probe_vel_m_s;
    let [fx, fy, fz] = s.force_n;
    let [cx, cy, cz] = s.contact_point_m;
    format!(
        "{},{},{x},{y},{z},{vx},{vy},{vz},{fx},{fy},{fz},{},{},{cx},{cy},{cz},{},{:#x},{},{},{},{},{},{}",
        s.tick as f64 / rate_hz,
        s.tick,
        s.spin_torque_nm,
        s.contact.name(),
        s.mode.name(),
        s.flags,
        flags::describe(s.flags),
        s.model_seq,
        s.tick_stats.max_duration_ns,
        s.tick_stats.mean_duration_ns,
        s.tick_stats.overruns,
        s.dropped
    )
}

/// The stream divisor for `rate_hz` samples per second at `control_hz`.
pub fn divisor_for(control_hz: u32, rate_hz: f64, min: u16) -> Result<u16, String> {
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(format!("--rate-hz must be positive, got {rate_hz}"));
    }
    let exact = control_hz as f64 / rate_hz;
    let d = exact.round();
    if d < min.max(1) as f64 || d > u16::MAX as f64 || (exact - d).abs() > 0.01 * exact {
        return Err(format!(
            "--rate-hz {rate_hz} is not reachable at {control_hz} Hz (divisor {d})"
        ));
    }
    Ok(d as u16)
}

/// Wait for the device to come back; the time spent.
fn reconnect(dev: &mut Device, bar: &ProgressBar, limit_s: f64) -> Result<(), String> {
    let t0 = Instant::now();
    bar.set_message("device gone: reconnecting");
    loop {
        match dev.reconnect() {
            Ok(()) => {
                bar.set_message("");
                return Ok(());
            }
            Err(e) if t0.elapsed().as_secs_f64() > limit_s => {
                return Err(format!("device gone for {limit_s} s: {e}"))
            }
            Err(_) => std::thread::sleep(Duration::from_millis(200)),
        }
    }
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    if !(a.seconds.is_finite() && a.seconds > 0.0 && a.seconds <= 3600.0) {
        return Err(format!(
            "--seconds must be within (0, 3600], got {}",
            a.seconds
        ));
    }
    let mut dev = connect(spec).map_err(|e| e.to_string())?;
    let info = dev.info().map_err(|e| e.to_string())?;
    let divisor = divisor_for(info.control_rate_hz, a.rate_hz, info.min_stream_divisor)?;
    let rate = info.control_rate_hz as f64;
    let sample_hz = rate / divisor as f64;
    let wanted = (a.seconds * sample_hz).ceil() as u64;
    let mut file = AtomicFile::create(&a.csv).map_err(|e| format!("{}: {e}", a.csv.display()))?;
    writeln!(file.writer(), "{HEADER}").map_err(|e| e.to_string())?;
    let bar = ProgressBar::new(wanted);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} samples {elapsed} {msg}")
            .map_err(|e| e.to_string())?,
    );
    dev.set_stream(divisor).map_err(|e| e.to_string())?;
    let (mut got, mut gaps, mut missing, mut prev_tick) = (0u64, 0u64, 0u64, None::<u64>);
    let mut last_dropped = 0;
    while got < wanted {
        match dev.next_state(Duration::from_millis(500)) {
            Ok(Some(s)) => {
                if let Some(p) = prev_tick {
                    if s.tick != p + divisor as u64 {
                        gaps += 1;
                        missing += (s.tick.saturating_sub(p) / divisor as u64).saturating_sub(1);
                    }
                }
                prev_tick = Some(s.tick);
                last_dropped = s.dropped;
                writeln!(file.writer(), "{}", row(&s, rate)).map_err(|e| e.to_string())?;
                got += 1;
                bar.set_position(got);
            }
            Ok(None) => {}
            Err(LinkError::Disconnected) => reconnect(&mut dev, &bar, a.reconnect_s)?,
            Err(e) => return Err(e.to_string()),
        }
    }
    let _ = dev.set_stream(0);
    bar.finish_and_clear();
    file.commit()
        .map_err(|e| format!("{}: {e}", a.csv.display()))?;
    println!(
        "{got} samples at {sample_hz} Hz ({} s of device time) to {}; gaps {gaps} ({missing} samples missing), dropped by the device {last_dropped}, here {}",
        got as f64 / sample_hz,
        a.csv.display(),
        dev.states_dropped_here()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn divisors() {
        assert_eq!(divisor_for(10_000, 1000.0, 1), Ok(10));
        assert_eq!(divisor_for(10_000, 10_000.0, 1), Ok(1));
        assert!(divisor_for(10_000, 20_000.0, 1).is_err());
        assert!(divisor_for(10_000, 0.0, 1).is_err());
        assert!(divisor_for(10_000, 3000.0, 1).is_err(), "not a divisor");
        assert_eq!(divisor_for(10_000, 3333.0, 1), Ok(3), "within 1 %");
        assert!(divisor_for(10_000, 1000.0, 20).is_err());
    }
}
