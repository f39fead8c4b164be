//! The virtual device's event log: one line on stdout per connection opened or closed, mode
//! change, local model or contact parameters set, and fault or watchdog flag raised, each
//! starting with the device time (`[   12.345 s]`, the control tick over the control rate).

use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::local_model::{LocalModelSpec, ModelKind};
use softfinger_core::Flags;
use softfinger_protocol::flag_names;
use softfinger_protocol::Mode;
use std::fmt::Arguments;
use std::io::Write;
use std::sync::{Arc, Mutex};

/// Where the log's lines go.
pub type LogSink = Arc<Mutex<dyn Write + Send>>;

/// The log at a control rate, into a sink (none: silent).
#[derive(Clone)]
pub struct EventLog {
    rate_hz: f32,
    out: Option<LogSink>,
}

impl std::fmt::Debug for EventLog {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EventLog")
            .field("rate_hz", &self.rate_hz)
            .field("silent", &self.out.is_none())
            .finish()
    }
}

impl EventLog {
    /// Flags of a tick logged when they rise (besides the latched faults): the watchdog, the
    /// model's age, refused models and parameters, failed homing.
    pub const NOTED: Flags = Flags(
        Flags::COMM_TIMEOUT.0
            | Flags::MODEL_STALE.0
            | Flags::MODEL_REJECTED.0
            | Flags::PARAM_REJECTED.0
            | Flags::HOMING_FAILED.0,
    );

    /// A log at `rate_hz` control ticks per second into `out` (stdout, a buffer in tests);
    /// silent for `None`.
    pub fn new(rate_hz: f32, out: Option<LogSink>) -> EventLog {
        EventLog { rate_hz, out }
    }

    /// The line for `msg` at control tick `tick`.
    pub fn format(&self, tick: u64, msg: Arguments<'_>) -> String {
        format!("[{:10.3} s] {msg}", tick as f64 / f64::from(self.rate_hz))
    }

    /// Write `msg` at `tick` as one line (a failing sink is ignored: the log never stops the
    /// device).
    pub fn line(&self, tick: u64, msg: Arguments<'_>) {
        if let Some(out) = &self.out {
            if let Ok(mut w) = out.lock() {
                let _ = writeln!(w, "{}", self.format(tick, msg));
                let _ = w.flush();
            }
        }
    }

    /// The mode changed from `from` to `to`; `flags` of that tick say why when it failed.
    pub fn mode(&self, tick: u64, from: Mode, to: Mode, flags: Flags) {
        let why = match (from, to) {
            (Mode::Homing, Mode::Disarmed) => " (homed)".to_string(),
            (Mode::Homing, _) if flags.contains(Flags::HOMING_FAILED) => {
                " (homing failed)".to_string()
            }
            (_, Mode::Faulted) => format!(" ({})", names(flags.0)),
            _ => String::new(),
        };
        self.line(
            tick,
            format_args!("mode {} -> {}{why}", from.name(), to.name()),
        );
    }

    /// Flags newly raised (`bits`), in mode `mode`.
    pub fn flags_raised(&self, tick: u64, bits: u32, mode: Mode) {
        for (name, meaning) in flag_names::raised(bits) {
            self.line(
                tick,
                format_args!("{name} ({meaning}); mode {}", mode.name()),
            );
        }
    }

    /// Client `id` set the local model `m`.
    pub fn model(&self, tick: u64, id: u32, m: &LocalModelSpec) {
        let p = m.pose.position_m;
        self.line(
            tick,
            format_args!(
                "model {} from connection {id}: {} at ({:.1}, {:.1}, {:.1}) mm, {} N/m, mu {}/{}",
                m.seq,
                shape(&m.kind),
                p.x * 1e3,
                p.y * 1e3,
                p.z * 1e3,
                m.stiffness_n_per_m,
                m.mu_s,
                m.mu_k
            ),
        );
    }

    /// Client `id` set the contact parameters `p`.
    pub fn params(&self, tick: u64, id: u32, p: &ContactParams) {
        self.line(
            tick,
            format_args!(
                "contact parameters from connection {id}: stiffness {} N/m, damping {} N·s/m, mu {}/{}, spin {} N·m/rad, force limit {} N",
                p.normal_stiffness, p.normal_damping, p.mu_s, p.mu_k, p.spin_stiffness, p.max_force_n
            ),
        );
    }
}

/// A surface's kind and size, e.g. `sphere r 50.0 mm`.
pub fn shape(k: &ModelKind) -> String {
    match k {
        ModelKind::Plane => "plane".into(),
        ModelKind::Sphere { radius_m } => format!("sphere r {:.1} mm", radius_m * 1e3),
        ModelKind::Bowl { radius_m } => format!("bowl r {:.1} mm", radius_m * 1e3),
        ModelKind::Cylinder { radius_m } => format!("cylinder r {:.1} mm", radius_m * 1e3),
    }
}

fn names(bits: u32) -> String {
    let v: Vec<&str> = flag_names::raised(bits).map(|(n, _)| n).collect();
    if v.is_empty() {
        "no flag".into()
    } else {
        v.join("|")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_start_with_the_device_time() {
        let log = EventLog::new(10_000.0, None);
        assert_eq!(
            log.format(123_450, format_args!("mode a -> b")),
            "[    12.345 s] mode a -> b"
        );
        assert_eq!(
            shape(&ModelKind::Sphere { radius_m: 0.05 }),
            "sphere r 50.0 mm"
        );
    }
}
