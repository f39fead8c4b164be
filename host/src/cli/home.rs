//! `home [--no-wait] [--timeout-s S]`: start homing and wait for its outcome (progress on
//! stderr; homed, or failed with the reason and a non-zero exit).

use super::{connect, refusal};
use indicatif::{ProgressBar, ProgressStyle};
use softfinger_host::flags;
use softfinger_host::protocol::{DeviceStatus, Mode};
use softfinger_host::Device;
use std::time::{Duration, Instant};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Return once the device has started homing (`softfinger status` shows the outcome).
    #[arg(long)]
    pub no_wait: bool,
    /// Give up waiting after this long, s.
    #[arg(long, default_value_t = 15.0)]
    pub timeout_s: f64,
}

/// What one status says about a homing that was started.
#[derive(Debug, PartialEq)]
pub enum Outcome {
    /// Still homing.
    Running,
    /// Homed: disarmed, the encoder zero set.
    Homed,
    /// Homing ended in another mode: why.
    Failed(String),
}

/// The outcome shown by `st`.
pub fn outcome(st: &DeviceStatus) -> Outcome {
    match st.mode {
        Mode::Homing => Outcome::Running,
        Mode::Disarmed => Outcome::Homed,
        mode => {
            let why: Vec<String> = flags::raised(st.flags | st.latched)
                .map(|(n, m)| format!("{n} ({m})"))
                .collect();
            Outcome::Failed(format!(
                "the device is {}{}",
                mode.name(),
                if why.is_empty() {
                    String::new()
                } else {
                    format!(": {}", why.join(", "))
                }
            ))
        }
    }
}

/// Wait for the homing started on `d` to end, with a spinner; the time it took.
pub fn wait(d: &mut Device, timeout_s: f64) -> Result<f64, String> {
    let t0 = Instant::now();
    let bar = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} homing {elapsed} {msg}") {
        bar.set_style(style);
    }
    loop {
        let st = d.status().map_err(|e| format!("home: {e}"))?;
        let took = t0.elapsed().as_secs_f64();
        match outcome(&st) {
            Outcome::Running if took > timeout_s => {
                bar.finish_and_clear();
                return Err(format!(
                    "home: still homing after {timeout_s} s (`softfinger status` shows the outcome)"
                ));
            }
            Outcome::Running => bar.tick(),
            Outcome::Homed => {
                bar.finish_and_clear();
                return Ok(took);
            }
            Outcome::Failed(why) => {
                bar.finish_and_clear();
                return Err(format!("homing failed after {took:.1} s: {why}"));
            }
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    if !(a.timeout_s.is_finite() && a.timeout_s > 0.0) {
        return Err(format!("--timeout-s must be positive, got {}", a.timeout_s));
    }
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    if let Err(e) = d.home() {
        // Homing already running (another `home --no-wait`): wait for that one.
        let homing = matches!(d.status(), Ok(st) if st.mode == Mode::Homing);
        if !homing || a.no_wait {
            return Err(refusal::message("home", e, &mut d));
        }
        eprintln!("homing is already in progress: waiting for it");
    }
    if a.no_wait {
        println!("homing started (it takes a few seconds; `softfinger status` shows the mode)");
        return Ok(());
    }
    let took = wait(&mut d, a.timeout_s)?;
    println!("homed in {took:.1} s");
    Ok(())
}
