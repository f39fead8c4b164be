//! `host-sim stability`: where the methods fail, and how stable the loop is.
//!
//! Four experiments, each with its charts (SVG in `--out`) and a printed table:
//!
//! 1. [`decomp_map`]: error and failure map of every decomposition method × math backend over
//!    rotation magnitude and axis direction.
//! 2. [`drift`]: long-run drift of the rolling contact points in f32 against the f64 closed form.
//! 3. [`haptic`]: K_max of a sampled 1-DoF virtual wall against Colgate's passivity bound, with
//!    and without the firmware's tick of delay.
//! 4. [`chatter`]: state-machine transitions per second with a force on the friction cone.
//!
//! The tables are also written to `summary.txt` in the output folder.

pub mod chatter;
pub mod decomp_map;
pub mod drift;
pub mod encoder_cell;
pub mod haptic;
pub mod haptic_charts;
pub mod haptic_device;
pub mod haptic_present;
pub mod haptic_timing;
pub mod passivity_scene;
pub mod present;
pub mod table;

use crate::error::{ChartError, FileError, JsonError};
use haptic_device::DeviceRow;
use haptic_present::HapticJson;
use haptic_timing::TimingRow;
use passivity_scene::SceneDifference;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output folder for the charts and summary.txt (created if missing).
    #[arg(long, default_value = "out/stability")]
    pub out: PathBuf,
    /// Steps of the long-run drift experiment per method (10 kHz: 10⁷ steps = 1000 s).
    #[arg(long, default_value_t = 10_000_000)]
    pub drift_steps: u64,
    /// Seconds simulated per wall contact in the haptic experiment (sets its resolution).
    #[arg(long, default_value_t = haptic::RUN_SECONDS)]
    pub haptic_seconds: f64,
    /// Print the figures as one JSON object on stdout (`{"haptic": {...}}`); the tables then go
    /// to summary.txt only.
    #[arg(long)]
    pub json: bool,
    /// Run part 3 (haptic stability) only.
    #[arg(long)]
    pub haptic_only: bool,
    /// Skip part 3's closed-loop runs with the device plant (the device-wall K_max and the
    /// default scene with and without the passivity stage; about 10 s in a release build).
    #[arg(long)]
    pub skip_closed_loop: bool,
    /// State-machine steps per chatter configuration (10 kHz: 10⁵ steps = 10 s).
    #[arg(long, default_value_t = (chatter::RATE_HZ * chatter::DURATION_S) as u64)]
    pub chatter_steps: u64,
}

/// Why the stability command failed.
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    /// An option out of range (its message names it).
    #[error("{0}")]
    Option(&'static str),
    /// Part 3 found no passive wall at 10 kHz.
    #[error("part 3: no passive wall found at 10 kHz")]
    NoPassiveWall,
    /// A device-wall run failed (the device-wall module's message).
    #[error(transparent)]
    DeviceWall(#[from] haptic_device::DeviceWallError),
    /// The default scene could not be run.
    #[error(transparent)]
    Scene(#[from] passivity_scene::PassivitySceneError),
    /// A chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// summary.txt or the output folder could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// The JSON could not be serialised.
    #[error(transparent)]
    Json(#[from] JsonError),
}

fn check(args: &Args) -> Result<(), StabilityError> {
    let bad = |m| Err(StabilityError::Option(m));
    if args.drift_steps == 0 {
        return bad("--drift-steps must be at least 1");
    }
    if !(args.haptic_seconds.is_finite() && args.haptic_seconds >= 0.1) {
        return bad("--haptic-seconds must be at least 0.1");
    }
    if args.chatter_steps == 0 {
        return bad("--chatter-steps must be at least 1");
    }
    Ok(())
}

pub fn main(args: &Args) -> Result<(), StabilityError> {
    check(args)?;
    let out = &args.out;
    std::fs::create_dir_all(out).map_err(FileError::on(out, "cannot create"))?;
    let start = Instant::now();
    let started = std::time::SystemTime::now();
    let mut summary = Summary {
        print: !args.json,
        text: String::new(),
    };
    if !args.haptic_only {
        decomposition_part(out, &mut summary)?;
        drift_part(args, &mut summary)?;
    }
    let haptic_json = haptic_part(args, &mut summary)?;
    if !args.haptic_only {
        chatter_part(args, &mut summary)?;
    }
    summary.emit(format!(
        "host-sim stability: total {:.1} s; charts and summary.txt in {}",
        start.elapsed().as_secs_f64(),
        out.display()
    ));
    write_summary(&out.join("summary.txt"), &summary.text)?;
    crate::chart::index_page::write(
        out,
        "host-sim stability",
        &summary.text,
        &charts_in(out, started)?,
    )?;
    if args.json {
        let v = serde_json::json!({ "haptic": haptic_json });
        println!("{}", serde_json::to_string_pretty(&v).map_err(JsonError)?);
    }
    Ok(())
}

/// The run's tables and notes: printed as they come (unless the JSON goes to stdout) and kept
/// for summary.txt.
struct Summary {
    print: bool,
    text: String,
}

impl Summary {
    fn emit(&mut self, s: String) {
        if self.print {
            println!("{s}");
        }
        self.text += &s;
        self.text.push('\n');
    }
}

/// Part 1: where each decomposition fails, charts and tables.
fn decomposition_part(out: &Path, summary: &mut Summary) -> Result<(), StabilityError> {
    let t = Instant::now();
    let grid = decomp_map::Grid::DEFAULT;
    let maps = decomp_map::sweep_all(&grid);
    present::decomp_charts(out, &grid, &maps)?;
    summary.emit(present::decomp_table(&grid, &maps).render());
    summary.emit(present::decomp_failures(&grid, &maps));
    summary.emit(format!("(part 1: {:.1} s)\n", t.elapsed().as_secs_f64()));
    Ok(())
}

/// Part 2: f32 drift over `--drift-steps` per method and backend, with a progress bar.
fn drift_part(args: &Args, summary: &mut Summary) -> Result<(), StabilityError> {
    let t = Instant::now();
    let total = args.drift_steps * (decompose_methods() * drift::DRIFT_BACKENDS.len()) as u64;
    let pb = indicatif::ProgressBar::new(total);
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "drift {bar:40} {percent:>3}% {human_pos}/{human_len} steps, eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let runs = drift::run_all(args.drift_steps, Some(&pb));
    pb.finish_and_clear();
    present::drift_charts(&args.out, &runs)?;
    summary.emit(present::drift_table(&runs).render());
    summary.emit(format!("(part 2: {:.1} s)\n", t.elapsed().as_secs_f64()));
    Ok(())
}

/// Part 3: haptic stability of the virtual wall (rates, delays, impact), and unless skipped the
/// closed-loop runs with the device plant; returns its JSON figures.
fn haptic_part(args: &Args, summary: &mut Summary) -> Result<HapticJson, StabilityError> {
    let out = &args.out;
    let t = Instant::now();
    let device = haptic::Device::DEFAULT;
    let rows = haptic::run_all(&device, 0.0, args.haptic_seconds);
    haptic_charts::haptic_charts(out, &device, &rows)?;
    summary.emit(haptic_present::haptic_table(&device, &rows, args.haptic_seconds).render());
    summary.emit(haptic_present::haptic_notes(&device, args.haptic_seconds));
    let timing = haptic_timing::run_all(&device, args.haptic_seconds);
    let at10 = timing.iter().find(|r| r.rate_hz == 10_000.0);
    let (delay10, k10) = at10
        .and_then(|r| r.at_multiple.as_ref().map(|m| (r.delay_ticks, m.0)))
        .ok_or(StabilityError::NoPassiveWall)?;
    let imp = haptic_timing::impact(&device, 10_000.0, delay10, k10);
    haptic_charts::timing_chart(out, &device, &timing)?;
    haptic_charts::impact_chart(out, &device, &imp)?;
    summary.emit(haptic_present::timing_table(&device, &timing, args.haptic_seconds).render());
    summary.emit(haptic_present::impact_notes(&imp));
    let (device_rows, scene_diff) = if args.skip_closed_loop {
        (Vec::new(), None)
    } else {
        let (device_rows, scene_diff) = closed_loop_part(&timing, summary)?;
        (device_rows, Some(scene_diff))
    };
    let mut haptic_json = haptic_present::haptic_json(&timing, &imp, device_rows);
    haptic_json.default_scene = scene_diff;
    summary.emit(format!("(part 3: {:.1} s)\n", t.elapsed().as_secs_f64()));
    Ok(haptic_json)
}

/// Part 3's closed-loop runs: the device-wall rows at 10 kHz and above, and the default scene
/// with the passivity stage on against observing only.
fn closed_loop_part(
    timing: &[TimingRow],
    summary: &mut Summary,
) -> Result<(Vec<DeviceRow>, SceneDifference), StabilityError> {
    let device_rows = timing
        .iter()
        .filter(|r| r.rate_hz >= 10_000.0)
        .map(|r| haptic_device::row(r.rate_hz, r.delay_ticks))
        .collect::<Result<Vec<_>, _>>()
        .map_err(StabilityError::DeviceWall)?;
    summary.emit(haptic_present::device_table(&device_rows).render());
    let scene_diff = passivity_scene::compare()?;
    summary.emit(format!(
        "Default scene with the passivity stage on vs observing only ({} ticks): largest force difference {:e} N (largest force {:.2} N), observed energy into the user from {:e} to {:e} J, {} ticks damped.\n",
        scene_diff.ticks,
        scene_diff.max_force_difference_n,
        scene_diff.max_force_n,
        scene_diff.min_observed_energy_j,
        scene_diff.max_observed_energy_j,
        scene_diff.damped_ticks
    ));
    Ok((device_rows, scene_diff))
}

/// Part 4: state chatter over `--chatter-steps` per configuration.
fn chatter_part(args: &Args, summary: &mut Summary) -> Result<(), StabilityError> {
    let t = Instant::now();
    let ch = chatter::run_all(args.chatter_steps);
    present::chatter_chart(&args.out, &ch)?;
    summary.emit(present::chatter_table(&ch, args.chatter_steps).render());
    summary.emit(format!("(part 4: {:.1} s)\n", t.elapsed().as_secs_f64()));
    Ok(())
}

/// summary.txt, written whole or not at all.
fn write_summary(path: &Path, text: &str) -> Result<(), FileError> {
    let mut f = crate::atomic_file::AtomicFile::create(path)
        .map_err(FileError::on(path, "cannot create"))?;
    std::io::Write::write_all(f.writer(), text.as_bytes())
        .map_err(FileError::on(path, "write failed"))?;
    f.commit().map_err(FileError::on(path, "cannot publish"))
}

/// The SVG charts this run wrote in `out` (modified since `started`; older ones of another run
/// are left out), by name, and summary.txt, for the index page.
fn charts_in(out: &Path, started: std::time::SystemTime) -> Result<Vec<PathBuf>, FileError> {
    let fresh = |e: &std::fs::DirEntry| {
        e.metadata()
            .and_then(|m| m.modified())
            .is_ok_and(|t| t >= started)
    };
    let mut v: Vec<PathBuf> = std::fs::read_dir(out)
        .map_err(FileError::on(out, "cannot read"))?
        .filter_map(|e| e.ok().filter(fresh).map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .collect();
    v.sort();
    v.insert(0, out.join("summary.txt"));
    Ok(v)
}

fn decompose_methods() -> usize {
    softfinger_core::contact::decompose::Method::ALL.len()
}
