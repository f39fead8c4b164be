//! `host-sim pil`: processor in the loop. The firmware built for the emulated board
//! (`softfinger-pil`, QEMU mps2-an386) runs its real interrupt-driven loop in lock step with this
//! crate's plant; its outputs are compared tick by tick with the same control sequence run
//! in-process against the same plant; its defmt log is decoded against its ELF.
//!
//! `scripts/pil` builds the firmware and this tool and runs it; see that script for the options.

mod error;
pub mod faults;
pub mod link_check;
mod link_client;
mod link_model;
mod link_report;
mod link_settings;
pub mod operator;
pub mod qemu;
pub mod reference;
pub mod report;
pub mod session;
pub mod telemetry;
mod verdict;
pub mod views;
pub mod wire;

use crate::error::{FileError, JsonError};
use crate::sim::closed_loop;
use crate::sim::scene::{Scene, SurfaceSpec};
pub use error::PilError;
use faults::Fault;
pub use link_client::LinkError;
use report::{FaultReport, Summary, REPORT_KEYS};
use softfinger_core::contact::params::ContactParams;
use std::path::{Path, PathBuf};
use std::time::Duration;
use verdict::{check, judge};

/// Longest run: the board's 32-bit 25 MHz time base wraps after 171.8 s.
pub const MAX_DURATION_S: f64 = 150.0;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene: a built-in name or a TOML file (plane scenes with the default contact parameters:
    /// the firmware renders those).
    #[arg(long, default_value = "finger-on-plane")]
    pub scene: String,
    /// Control rate, Hz (default: the scene's); 25 MHz must be a multiple of it.
    #[arg(long)]
    pub rate_hz: Option<u32>,
    /// Simulated seconds of the scene after arming (default: the scene's duration); homing and
    /// arming come first.
    #[arg(long)]
    pub duration_s: Option<f64>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    /// What to write from the decoded telemetry.
    #[command(flatten)]
    pub views: TelemetryViews,
    /// Keep the raw defmt log the board wrote.
    #[arg(long)]
    pub defmt_raw: Option<PathBuf>,
    /// Inject a fault.
    #[arg(long, value_enum, default_value = "none")]
    pub fault: Fault,
    /// When to inject it: simulated seconds after the scene starts (homed and armed).
    #[arg(long, default_value_t = 1.0)]
    pub fault_at_s: f64,
    /// Fail (exit 2) on any overrun, any difference from the in-process run, a fault not
    /// handled, or a tick over the budget.
    #[arg(long)]
    pub check: bool,
    /// Instead of the scene run: the firmware's host link over the board's UART0 (hello, device
    /// info, stream, bad frames, home, arm; see `pil::link_check`). Fails (exit 2) on any failed
    /// check.
    #[arg(long)]
    pub link_check: bool,
    /// The board runs the local-model build (`firmware/pil` with `--features local-model`, the
    /// scene of the STM32 build's host-link builds); the in-process reference then runs the same
    /// scene (`reference::firmware_config`). Without it: the default build's fixed plane.
    #[arg(long)]
    pub local_model: bool,
    /// Play the scripted application session (`softfinger_app::scripted_app`): a state stream at
    /// 2 kHz from power-up, once armed a local model every 1 ms and a contact-parameter change
    /// every 100 ms, applied by the tick as a host link's commands are on the board and through
    /// `Pipeline::link_command` in the in-process run, at the same ticks.
    #[arg(long)]
    pub app_session: bool,
    /// Instruction budget file (JSON: tolerance_percent, baseline {rate: {name: instructions}}).
    #[arg(long)]
    pub budget: Option<PathBuf>,
    /// The firmware ELF for the emulated board.
    #[arg(
        long,
        default_value = "firmware/pil/target/thumbv7em-none-eabihf/release/softfinger-pil"
    )]
    pub elf: PathBuf,
    /// The QEMU executable.
    #[arg(long, default_value = "qemu-system-arm")]
    pub qemu: String,
    /// Wall-clock limit for QEMU, s.
    #[arg(long, default_value_t = 600)]
    pub timeout_s: u64,
}

/// The files written from decoded telemetry, each when asked for.
#[derive(Debug, Default, clap::Args)]
pub struct TelemetryViews {
    /// Write the decoded telemetry records as CSV.
    #[arg(long)]
    pub telemetry_csv: Option<PathBuf>,
    /// Chart the telemetry's rendered force (SVG).
    #[arg(long)]
    pub chart: Option<PathBuf>,
    /// Write the telemetry's wrist orientations as `host-sim replay` input.
    #[arg(long)]
    pub replay_csv: Option<PathBuf>,
}

impl TelemetryViews {
    /// Write the asked-for files from the telemetry `rows` (ticks at `rate_hz`).
    fn write(&self, rows: &[Vec<(String, String)>], rate_hz: u32) -> Result<(), PilError> {
        if let Some(path) = &self.telemetry_csv {
            telemetry::write_csv(path, rows, rate_hz)?;
        }
        if let Some(path) = &self.chart {
            views::force_chart(path, rows, rate_hz)?;
        }
        if let Some(path) = &self.replay_csv {
            views::replay_csv(path, rows, rate_hz)?;
        }
        Ok(())
    }
}

/// `host-sim pil-decode`: a raw defmt log (e.g. RTT bytes captured from the STM32 build) decoded
/// against its ELF.
#[derive(Debug, clap::Args)]
pub struct DecodeArgs {
    /// The firmware ELF the log came from.
    #[arg(long)]
    pub elf: PathBuf,
    /// The raw log: rzCOBS-encoded defmt frames.
    #[arg(long)]
    pub log: PathBuf,
    /// What to write from the decoded telemetry.
    #[command(flatten)]
    pub views: TelemetryViews,
    /// The control rate the records' ticks count at, Hz (for the t_s column).
    #[arg(long, default_value_t = 10_000)]
    pub rate_hz: u32,
}

fn read(path: &Path) -> Result<Vec<u8>, FileError> {
    std::fs::read(path).map_err(FileError::on(path, "cannot read"))
}

/// `host-sim pil-decode`.
pub fn decode_main(args: &DecodeArgs) -> Result<(), PilError> {
    if args.rate_hz == 0 {
        return Err(PilError::DecodeRate);
    }
    let log = telemetry::decode(&read(&args.elf)?, &read(&args.log)?)?;
    for f in &log.frames {
        println!("{:<5} {}", f.level, f.message);
    }
    let rows = telemetry::telemetry_rows(&log);
    args.views.write(&rows, args.rate_hz)?;
    if let Some(path) = &args.views.telemetry_csv {
        eprintln!(
            "wrote {} telemetry records to {}",
            rows.len(),
            path.display()
        );
    }
    if log.malformed > 0 {
        return Err(PilError::Malformed(log.malformed));
    }
    Ok(())
}

/// The run's settings from the arguments and the scene.
fn settings(args: &Args, scene: &Scene) -> Result<session::Settings, PilError> {
    let rate_hz = args.rate_hz.unwrap_or(scene.rate_hz as u32);
    if !(1_000..=20_000).contains(&rate_hz) || 25_000_000 % rate_hz != 0 {
        return Err(PilError::Rate(rate_hz));
    }
    let timing = closed_loop::board_timing(f64::from(rate_hz))?;
    let duration_s = args.duration_s.unwrap_or(scene.duration_s);
    if !(duration_s.is_finite() && duration_s > 0.0 && duration_s <= MAX_DURATION_S) {
        return Err(PilError::Duration(duration_s));
    }
    if args.fault != Fault::None
        && !(args.fault_at_s.is_finite() && (0.0..duration_s).contains(&args.fault_at_s))
    {
        return Err(PilError::FaultAt {
            at_s: args.fault_at_s,
            duration_s,
        });
    }
    Ok(session::Settings {
        timing,
        scene_ticks: (duration_s * f64::from(rate_hz)).round() as u64,
        fault: args.fault,
        fault_offset: (args.fault_at_s * f64::from(rate_hz)).round() as u64,
        app_session: args.app_session,
    })
}

/// The scene, checked against what the firmware renders.
fn load_scene(name: &str) -> Result<(Scene, ContactParams), PilError> {
    let scene = Scene::load(name)?;
    if scene.surface != SurfaceSpec::Plane {
        return Err(PilError::NotPlane(scene.name));
    }
    let contact = closed_loop::contact_params(&scene)?;
    if contact != ContactParams::DEFAULT {
        return Err(PilError::NotDefaultContact(scene.name));
    }
    Ok((scene, contact))
}

/// A fresh, empty work directory for one run.
fn work_dir() -> Result<PathBuf, FileError> {
    let dir = std::env::temp_dir().join(format!("softfinger-pil-{}", std::process::id()));
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(FileError::on(&dir, "cannot remove"))?;
    }
    std::fs::create_dir_all(&dir).map_err(FileError::on(&dir, "cannot create"))?;
    Ok(dir)
}

/// Run the board against the plant; returns the trace and the raw defmt log.
fn run_board(
    args: &Args,
    plant: &crate::sim::plant::Plant,
    s: &session::Settings,
) -> Result<(session::Trace, Vec<u8>), PilError> {
    if !args.elf.is_file() {
        return Err(PilError::NoElf(args.elf.clone()));
    }
    let (elf, dir, limit) = emulator_setup(args)?;
    let result = (|| {
        let mut emu = qemu::Emulator::start(&args.qemu, &elf, &dir, limit)?;
        let served = session::run(&mut emu, plant.clone(), s);
        let status = emu.finish();
        let trace = served?;
        let status = status?;
        if !trace.done || !status.success() {
            return Err(PilError::Unfinished {
                status,
                samples: trace.samples,
                qemu: std::fs::read_to_string(dir.join("qemu.stderr"))
                    .map(|e| format!("; QEMU: {}", e.trim()))
                    .unwrap_or_default(),
                log: last_log_lines(&args.elf, &dir.join(qemu::DEFMT_LOG)),
            });
        }
        Ok((trace, read(&dir.join(qemu::DEFMT_LOG))?))
    })();
    clean_up(result, dir)
}

/// The ELF's absolute path, a fresh work directory and QEMU's wall-clock limit, for one run.
fn emulator_setup(args: &Args) -> Result<(PathBuf, PathBuf, Duration), PilError> {
    let elf = args
        .elf
        .canonicalize()
        .map_err(FileError::on(&args.elf, "cannot resolve"))?;
    Ok((elf, work_dir()?, Duration::from_secs(args.timeout_s)))
}

/// `result` of a run in `dir`: the directory removed on success, kept and named on failure.
fn clean_up<T>(result: Result<T, PilError>, dir: PathBuf) -> Result<T, PilError> {
    match result {
        Ok(r) => {
            let _ = std::fs::remove_dir_all(&dir);
            Ok(r)
        }
        Err(e) => Err(PilError::WorkDirKept {
            source: Box::new(e),
            dir,
        }),
    }
}

/// The board's last log messages, for an error report (empty if none decode).
fn last_log_lines(elf: &Path, raw: &Path) -> String {
    let (Ok(elf), Ok(raw)) = (read(elf), read(raw)) else {
        return String::new();
    };
    let Ok(log) = telemetry::decode(&elf, &raw) else {
        return String::new();
    };
    let n = log.frames.len();
    let lines: Vec<String> = log.frames[n.saturating_sub(5)..]
        .iter()
        .map(|f| format!("{} {}", f.level, f.message))
        .collect();
    if lines.is_empty() {
        String::new()
    } else {
        format!("; board log ends: {}", lines.join(" | "))
    }
}

/// `host-sim pil --link-check`: the host link on the emulated board; the report on stdout.
fn link_main(args: &Args) -> Result<(), PilError> {
    let (scene, contact) = load_scene(&args.scene)?;
    let s = settings(args, &scene)?;
    let plant = closed_loop::plant(&scene, &contact)?;
    let (elf, dir, limit) = emulator_setup(args)?;
    let run = link_check::run(&args.qemu, &elf, &dir, limit, plant, &s);
    let (trace, report) = clean_up(run, dir)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report).map_err(JsonError)?
        );
    } else {
        for (what, ok, detail) in &report.checks {
            println!("{} {what}: {detail}", if *ok { "ok  " } else { "FAIL" });
        }
        println!(
            "{} state frames decoded, {} undecodable here; board served {} samples",
            report.states, report.rx_errors_here, trace.samples
        );
    }
    if !trace.done {
        return Err(PilError::NotFinished);
    }
    if !report.passed() || report.rx_errors_here != 0 {
        return Err(PilError::LinkCheckFailed);
    }
    Ok(())
}

/// `host-sim pil`.
pub fn main(args: &Args) -> Result<(), PilError> {
    if args.app_session && (args.link_check || !args.local_model) {
        return Err(PilError::AppSessionNeedsLocalModel);
    }
    if args.link_check {
        return link_main(args);
    }
    let (scene, contact) = load_scene(&args.scene)?;
    let s = settings(args, &scene)?;
    let plant = closed_loop::plant(&scene, &contact)?;
    let (trace, raw) = run_board(args, &plant, &s)?;
    if let Some(path) = &args.defmt_raw {
        std::fs::write(path, &raw).map_err(FileError::on(path, "cannot write"))?;
    }
    if trace.homing_timed_out {
        return Err(PilError::HomingTimedOut);
    }
    let scene = Scene {
        rate_hz: f64::from(s.rate_hz()),
        ..scene
    };
    let config = closed_loop::plane_config(&scene, contact)?;
    let reference = if args.local_model {
        // The scene's plane is where the firmware's initial model is (checked in `pil::tests`).
        reference::run(
            &plant,
            reference::firmware_config(config.timing, contact),
            &s,
            &trace.prev_write_done,
        )?
    } else {
        reference::run(&plant, config, &s, &trace.prev_write_done)?
    };
    let log = telemetry::decode(&read(&args.elf)?, &raw)?;
    let rows = telemetry::telemetry_rows(&log);
    args.views.write(&rows, s.rate_hz())?;
    let summary = summarize(&scene, &s, &trace, &reference, &log, &rows);
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&summary).map_err(JsonError)?
        );
    } else {
        summary.print();
    }
    if args.check {
        check(&summary, args.budget.as_deref())?;
    }
    Ok(())
}

/// Assemble the summary.
fn summarize(
    scene: &Scene,
    s: &session::Settings,
    trace: &session::Trace,
    reference: &reference::RefRun,
    log: &telemetry::Log,
    rows: &[Vec<(String, String)>],
) -> Summary {
    let figure = |name: &str| {
        let key = REPORT_KEYS.iter().position(|k| *k == name).unwrap_or(0) as u16 + 1;
        trace.reports.get(&key).copied().unwrap_or(0)
    };
    // Panic and hang cannot be mirrored: compare the ticks before the fault only.
    let fault_tick = s.fault_tick(trace.scene_start);
    let limit = match fault_tick {
        Some(t) if !s.fault.mirrored_in_reference() => t,
        _ => u64::MAX,
    };
    let full_scale = f64::from(s.timing.pwm_period_counts());
    let (compared, identical, max_diff, first) =
        report::compare(trace, &reference.ticks, limit, full_scale);
    let dt = 1.0 / f64::from(s.rate_hz());
    let field = |row: &[(String, String)], name: &str| {
        row.iter()
            .find(|(c, _)| c == name)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    let ticks_of: Vec<f64> = rows
        .iter()
        .map(|r| field(r, "tick").parse().unwrap_or(0.0))
        .collect();
    let states: Vec<String> = rows.iter().map(|r| field(r, "state")).collect();
    let record_dt = |i: usize| match (ticks_of.get(i), ticks_of.get(i + 1)) {
        (Some(a), Some(b)) if b > a => (b - a) * dt,
        _ => 0.0,
    };
    let mut fault: FaultReport = report::observe_fault(trace, s.fault, fault_tick);
    let period_instructions = qemu::INSTRUCTIONS_PER_SECOND / u64::from(s.rate_hz());
    let summary = Summary {
        scene: scene.name.clone(),
        rate_hz: s.rate_hz(),
        icount_shift: qemu::ICOUNT_SHIFT,
        instructions_per_second: qemu::INSTRUCTIONS_PER_SECOND,
        period_instructions,
        ticks: figure("ticks"),
        overruns: figure("overruns"),
        max_tick_instructions: figure("max_tick_instructions"),
        max_start_latency_instructions: figure("max_start_latency_instructions"),
        scene_start_tick: trace.scene_start,
        scene_start_tick_in_process: reference.scene_start,
        compared_ticks: compared,
        identical_ticks: identical,
        max_duty_diff: max_diff,
        first_difference_tick: first,
        board_late_writes: trace.late_writes_seen(s.timing.pwm_period_counts()),
        defmt_frames: figure("defmt_frames"),
        defmt_drops: figure("defmt_drops"),
        defmt_malformed: log.malformed,
        telemetry_records: rows.len(),
        telemetry_drops: rows
            .iter()
            .map(|r| field(r, "dropped_before").parse::<u64>().unwrap_or(0))
            .sum(),
        watchdog_resets: trace.resets.len(),
        contact_state_s: report::state_time(
            states
                .iter()
                .enumerate()
                .map(|(i, st)| (st.as_str(), record_dt(i))),
        ),
        contact_state_s_in_process: report::state_time(
            reference.ticks.iter().map(|r| (r.state.name(), dt)),
        ),
        output: report::OutputReport::of(trace, &s.timing),
        fault: fault.clone(),
    };
    fault.handled = judge(&summary, s);
    Summary { fault, ..summary }
}

#[cfg(test)]
mod tests;
