//! `session [--seconds S]`: hold the device armed. Homes it if needed, arms it on this
//! connection (whose heartbeat keeps the device's watchdog fed), reports every change of mode
//! or latched flag, and disarms when it ends (Ctrl-C or `--seconds`). Other commands (`stream`,
//! `params`, `scene`) run beside it on their own connections.

use super::{connect, interrupt, stream};
use softfinger_host::flags;
use std::time::{Duration, Instant};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// End after this many seconds (default: at Ctrl-C).
    #[arg(long)]
    pub seconds: Option<f64>,
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    if let Some(s) = a.seconds {
        if !(s.is_finite() && s > 0.0) {
            return Err(format!("--seconds must be positive, got {s}"));
        }
    }
    interrupt::install();
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    stream::arm_here(&mut d)?;
    println!("armed; holding the device (Ctrl-C disarms and ends)");
    let t0 = Instant::now();
    let mut seen = None;
    let result = loop {
        if interrupt::requested() || a.seconds.is_some_and(|s| t0.elapsed().as_secs_f64() >= s) {
            break Ok(());
        }
        match d.status() {
            Ok(st) => {
                let now = (st.mode, st.flags & flags::HOLD_FORCE_DOWN.0, st.latched);
                if seen != Some(now) {
                    if seen.is_some() {
                        let f = flags::describe(now.1 | now.2);
                        println!(
                            "mode {}{}",
                            st.mode.name(),
                            if f.is_empty() {
                                String::new()
                            } else {
                                format!(", {f}")
                            }
                        );
                    }
                    seen = Some(now);
                }
            }
            Err(e) => break Err(format!("session: {e}")),
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let _ = d.disarm();
    println!("disarmed");
    result
}
