//! `stream --seconds S --csv FILE`: the state stream to CSV, with a progress bar.
//!
//! - The file is written only when the run ends (through a hidden temporary file, removed on an
//!   error or Ctrl-C).
//! - A recording in which the device was not rendering (not armed, or armed with its force held
//!   at zero by a latched watchdog timeout or a stale model) is written, but the command says
//!   so on stderr and exits non-zero unless `--allow-idle`. `--arm` homes (if needed) and arms
//!   the device on the stream's own connection, which keeps the watchdog fed, and disarms it at
//!   the end.
//! - If the device goes away the stream reconnects and goes on (the gap is counted). If it
//!   restarted meanwhile (its tick went back), the stream stops: a file holds one device session.

use super::{connect, home, interrupt, refusal};
use host_sim::atomic_file::AtomicFile;
use indicatif::{ProgressBar, ProgressStyle};
use softfinger_host::protocol::{Mode, StateSample};
use softfinger_host::{flags, Device, LinkError};
use std::collections::BTreeMap;
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
    /// Home the device if it is not homed, arm it on this connection for the recording, and
    /// disarm it at the end.
    #[arg(long)]
    pub arm: bool,
    /// Succeed even if the device was not rendering force during the recording (unhomed,
    /// disarmed, faulted, or armed with a latched watchdog timeout or a stale model).
    #[arg(long)]
    pub allow_idle: bool,
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

/// Why the device was not rendering force in sample `s` (`None`: it was): its mode when not
/// armed, else the flags that hold the force down.
pub fn idle_reason(s: &StateSample) -> Option<String> {
    if s.mode != Mode::Armed {
        return Some(format!("mode {}", s.mode.name()));
    }
    let held = s.flags & flags::HOLD_FORCE_DOWN.0;
    (held != 0).then(|| format!("armed with {} latched", flags::describe(held)))
}

/// Samples counted by why they were idle.
#[derive(Debug, Default)]
pub struct IdleCount {
    by_reason: BTreeMap<String, u64>,
}

impl IdleCount {
    /// Count `s`.
    pub fn add(&mut self, s: &StateSample) {
        if let Some(r) = idle_reason(s) {
            *self.by_reason.entry(r).or_default() += 1;
        }
    }

    /// Idle samples in all.
    pub fn total(&self) -> u64 {
        self.by_reason.values().sum()
    }

    /// `mode unhomed: 412, armed with comm-timeout latched: 9`.
    pub fn describe(&self) -> String {
        let v: Vec<String> = self
            .by_reason
            .iter()
            .map(|(r, n)| format!("{r}: {n}"))
            .collect();
        v.join(", ")
    }
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

/// Wait for the device to come back.
fn reconnect(dev: &mut Device, bar: &ProgressBar, limit_s: f64) -> Result<(), String> {
    let t0 = Instant::now();
    bar.set_message("device gone: reconnecting");
    loop {
        if interrupt::requested() {
            return Err("interrupted".into());
        }
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

/// Home (if not homed) and arm on `dev`.
pub fn arm_here(dev: &mut Device) -> Result<(), String> {
    let st = dev.status().map_err(|e| format!("status: {e}"))?;
    if matches!(st.mode, Mode::Unhomed) {
        eprintln!("the device is unhomed: homing first");
        dev.home().map_err(|e| refusal::message("home", e, dev))?;
        home::wait(dev, 15.0)?;
    } else if st.mode == Mode::Homing {
        home::wait(dev, 15.0)?;
    }
    dev.arm().map_err(|e| refusal::message("arm", e, dev))
}

/// How the recording loop ended.
enum End {
    Complete,
    /// The device restarted: device times of the last sample before and the first after, s.
    Restarted(f64, f64),
    Interrupted,
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    if !(a.seconds.is_finite() && a.seconds > 0.0 && a.seconds <= 3600.0) {
        return Err(format!(
            "--seconds must be within (0, 3600], got {}",
            a.seconds
        ));
    }
    interrupt::install();
    let mut dev = connect(spec).map_err(|e| e.to_string())?;
    let info = dev.info().map_err(|e| e.to_string())?;
    let divisor = divisor_for(info.control_rate_hz, a.rate_hz, info.min_stream_divisor)?;
    let rate = info.control_rate_hz as f64;
    let sample_hz = rate / divisor as f64;
    let wanted = (a.seconds * sample_hz).ceil() as u64;
    if a.arm {
        arm_here(&mut dev)?;
    }
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
    let mut idle = IdleCount::default();
    let end = loop {
        if interrupt::requested() {
            break End::Interrupted;
        }
        if got >= wanted {
            break End::Complete;
        }
        match dev.next_state(Duration::from_millis(200)) {
            Ok(Some(s)) => {
                if let Some(p) = prev_tick {
                    if s.tick <= p {
                        break End::Restarted(p as f64 / rate, s.tick as f64 / rate);
                    }
                    if s.tick != p + divisor as u64 {
                        gaps += 1;
                        missing += ((s.tick - p) / divisor as u64).saturating_sub(1);
                    }
                }
                prev_tick = Some(s.tick);
                last_dropped = s.dropped;
                let before = idle.total();
                idle.add(&s);
                if idle.total() != before && before == 0 {
                    bar.set_message(format!(
                        "device not rendering ({})",
                        idle_reason(&s).unwrap_or_default()
                    ));
                }
                writeln!(file.writer(), "{}", row(&s, rate)).map_err(|e| e.to_string())?;
                got += 1;
                bar.set_position(got);
            }
            Ok(None) => {}
            Err(LinkError::Disconnected) => {
                if let Err(e) = reconnect(&mut dev, &bar, a.reconnect_s) {
                    if interrupt::requested() {
                        break End::Interrupted;
                    }
                    return Err(e);
                }
            }
            Err(e) => return Err(e.to_string()),
        }
    };
    let _ = dev.set_stream(0);
    if a.arm {
        let _ = dev.disarm();
    }
    bar.finish_and_clear();
    let csv = a.csv.display();
    match end {
        End::Interrupted => {
            drop(file);
            return Err(format!("interrupted: nothing written to {csv}"));
        }
        End::Restarted(before, after) => {
            file.commit().map_err(|e| format!("{csv}: {e}"))?;
            return Err(format!(
                "the device restarted during the stream (device time went back from {before:.3} s to {after:.3} s): a file holds one device session, so the stream stopped; the {got} samples before the restart are in {csv}"
            ));
        }
        End::Complete => {}
    }
    file.commit().map_err(|e| format!("{csv}: {e}"))?;
    println!(
        "{got} samples at {sample_hz} Hz ({} s of device time) to {csv}; gaps {gaps} ({missing} samples missing), dropped by the device {last_dropped}, here {}",
        got as f64 / sample_hz,
        dev.states_dropped_here()
    );
    if idle.total() > 0 && !a.allow_idle {
        return Err(format!(
            "the device was not rendering force in {} of {got} samples ({}); {csv} is written, its force columns are zero there. Arm on the stream's own connection (`stream --arm`) or keep `softfinger session` running; --allow-idle accepts such a recording",
            idle.total(),
            idle.describe()
        ));
    }
    if idle.total() > 0 {
        eprintln!(
            "note: the device was not rendering force in {} of {got} samples ({})",
            idle.total(),
            idle.describe()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_core::Flags;

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

    #[test]
    fn idle_is_any_mode_but_armed_or_a_held_force() {
        let armed = StateSample {
            mode: Mode::Armed,
            flags: Flags::OUTPUT_LIMITED.0,
            ..StateSample::default()
        };
        assert_eq!(idle_reason(&armed), None, "a limited force is rendered");
        let timed_out = StateSample {
            flags: (Flags::COMM_TIMEOUT | Flags::OUTPUT_LIMITED).0,
            ..armed
        };
        assert_eq!(
            idle_reason(&timed_out).as_deref(),
            Some("armed with comm-timeout latched")
        );
        let mut n = IdleCount::default();
        for mode in [Mode::Unhomed, Mode::Homing, Mode::Disarmed, Mode::Faulted] {
            let s = StateSample { mode, ..armed };
            assert!(idle_reason(&s).unwrap().contains(mode.name()));
            n.add(&s);
        }
        n.add(&timed_out);
        n.add(&armed);
        assert_eq!(n.total(), 5);
    }
}
