//! `host-sim chart`: speed against accuracy, as SVG charts (drawn in the style of
//! [`crate::chart`]).
//!
//! - `speed-accuracy.svg`: time per step (ns, log) against the largest contact-path error (mm, log), one
//!   panel per sampling rate ([`points::RATES_HZ`], the paper's motion for 1 s): every method × math
//!   backend and the classical RK45 at `rtol` 1e-3 … 1e-12, each point with its timing quartiles; the
//!   Pareto front of each rate as a staircase, ties kept where the timing spreads overlap.
//! - `index.html`: the printed summary and every chart ([`crate::chart::index_page`]).
//! - `fig3-trajectories.svg`: the paper's Fig. 3, contact paths on the plane and on the sphere, classical
//!   against ours (exact, rpy), as x-y and x-z projections.
//! - `mcu-speed-accuracy.svg`: instructions per step on the emulated Cortex-M4F (from `scripts/mcu-bench
//!   --json`, see [`mcu`]) against the same errors; skipped with a note when no such JSON exists.
//!
//! Errors: ours against the RK45 reference at `rtol` 1e-12, the classical points against the closed form
//! (the two references agree within ~1e-11 mm, see `validate`).

pub mod mcu;
pub mod panels;
pub mod pareto;
pub mod points;
pub mod surfaces;
pub mod trajectories;

use crate::error::{ChartError, FileError};
use crate::experiments::validate::ValidateError;
use std::fmt::Write;
use std::path::PathBuf;

use crate::experiments::validate::ours::{self, Backend, Variant};
use crate::experiments::validate::timing::Timing;
use crate::experiments::validate::{closed_form, reference_for};
use crate::sim::reference::scene::paper_scene;
use points::{Point, Series};
use softfinger_core::contact::decompose::Method;

/// Where `chart` looks for the MCU figures when `--mcu-json` is not given.
pub const DEFAULT_MCU_JSON: &str = "out/mcu-bench.json";

/// Command-line arguments.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output folder (created if missing).
    #[arg(long, default_value = "out/charts")]
    pub out: PathBuf,
    /// `scripts/mcu-bench --json` output for the MCU chart (default: out/mcu-bench.json if it exists).
    #[arg(long)]
    pub mcu_json: Option<PathBuf>,
    /// One short timing batch per point instead of 41 (fast; the times are then rough).
    #[arg(long)]
    pub quick: bool,
    /// Sampling rates for our points, Hz (default 100, 1000, 4000, 10000, 20000).
    #[arg(long, value_delimiter = ',')]
    pub rates_hz: Option<Vec<f64>>,
}

/// What `chart` produced.
#[derive(Clone, Debug)]
pub struct ChartReport {
    /// SVG files written.
    pub files: Vec<PathBuf>,
    /// The speed–accuracy points.
    pub points: Vec<Point>,
    /// Indices of `points` on each rate's Pareto front ([`panels::front`]), by rate then
    /// increasing time.
    pub front: Vec<usize>,
    /// The MCU points, if an mcu-bench JSON was found.
    pub mcu: Option<Vec<mcu::McuPoint>>,
    /// Notes for the user (e.g. a skipped chart).
    pub notes: Vec<String>,
}

/// Why the `chart` command failed.
#[derive(Debug, thiserror::Error)]
pub enum ChartCommandError {
    /// A sampling rate outside 1 Hz to 1 MHz.
    #[error("--rates-hz: every rate must be between 1 and 1e6 Hz")]
    Rates,
    /// The output folder could not be made.
    #[error(transparent)]
    File(#[from] FileError),
    /// A reference or a method's run failed.
    #[error(transparent)]
    Validate(#[from] ValidateError),
    /// A chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
}

/// Makes the charts.
pub fn run(args: &Args) -> Result<ChartReport, ChartCommandError> {
    let timing = if args.quick {
        Timing::QUICK
    } else {
        Timing::STANDARD
    };
    let rates = args
        .rates_hz
        .clone()
        .unwrap_or_else(|| points::RATES_HZ.to_vec());
    if rates
        .iter()
        .any(|r| !(r.is_finite() && *r >= 1.0 && *r <= 1e6))
    {
        return Err(ChartCommandError::Rates);
    }
    std::fs::create_dir_all(&args.out).map_err(FileError::on(&args.out, "cannot create"))?;
    let mut files = Vec::new();
    let mut notes = Vec::new();

    let pts = points::sweep(&rates, timing)?;
    let front = panels::front(&pts);
    let path = args.out.join("speed-accuracy.svg");
    crate::chart::style::write_svg(&path, &panels::svg(&pts)?)?;
    files.push(path);

    let path = args.out.join("fig3-trajectories.svg");
    crate::chart::style::write_svg(&path, &trajectories::svg(&fig3()?)?)?;
    files.push(path);

    let (_, surface_errors) = crate::experiments::validate::surfaces::run_with_series()?;
    let path = args.out.join("surfaces-validation.svg");
    crate::chart::style::write_svg(&path, &surfaces::svg(&surface_errors)?)?;
    files.push(path);

    let mcu_path = args
        .mcu_json
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_MCU_JSON));
    let mcu = if mcu_path.exists() {
        let entries = mcu::read(&mcu_path)?;
        let scene_rate = 1.0 / paper_scene().dt;
        let mcu_points = mcu::points(&entries, |v| {
            pts.iter()
                .find(|p| p.series == Series::Ours(v) && p.rate_hz == scene_rate)
                .map(|p| p.error_mm)
        });
        if mcu_points.is_empty() {
            notes.push(format!(
                "MCU chart skipped: {} has no rolling_plane_* / contact_step* entries for the 100 Hz scene",
                mcu_path.display()
            ));
            None
        } else {
            let path = args.out.join("mcu-speed-accuracy.svg");
            crate::chart::style::write_svg(&path, &mcu::svg(&mcu_points)?)?;
            files.push(path);
            Some(mcu_points)
        }
    } else {
        notes.push(format!(
            "MCU chart skipped: {} not found (make it with `scripts/mcu-bench --json > {}`, or pass --mcu-json FILE)",
            mcu_path.display(),
            DEFAULT_MCU_JSON
        ));
        None
    };
    let mut report = ChartReport {
        files,
        points: pts,
        front,
        mcu,
        notes,
    };
    let page = crate::chart::index_page::write(
        &args.out,
        "host-sim chart: speed against accuracy",
        &summary(&report),
        &report.files,
    )?;
    report.files.push(page);
    Ok(report)
}

/// The paper scene's paths for Fig. 3: the RK45 reference, ours exact/libm and rpy/libm.
fn fig3() -> Result<trajectories::Trajectories, ChartCommandError> {
    let scene = paper_scene();
    let closed = closed_form(&scene)?;
    let reference = reference_for(&scene, &closed)?.paths;
    let samples = ours::to_f32(&scene.samples);
    let mut runs = vec![trajectories::Run {
        name: "classical: Montana's equations, RK45 (f64, rtol 1e-12)".to_string(),
        plane: reference.plane,
        sphere: reference.sphere,
    }];
    for method in [Method::Exact, Method::Rpy] {
        let v = Variant {
            method,
            backend: Backend::Libm,
        };
        let p = v.paths(&samples, scene.radius as f32);
        runs.push(trajectories::Run {
            name: format!("ours: {} (f32)", v.name()),
            plane: p.plane,
            sphere: p.sphere,
        });
    }
    Ok(trajectories::Trajectories { runs })
}

/// The printed summary: files, the plotted points (front marked), the MCU points, notes.
pub fn summary(r: &ChartReport) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Speed vs accuracy points (* = on its rate's Pareto front; ns/step median, q1-q3 over the rounds):"
    );
    let _ = writeln!(
        out,
        "  {:<28} {:>9} {:>8} {:>10} {:>21} {:>12}",
        "series", "rate", "rtol", "ns/step", "q1-q3", "max err (mm)"
    );
    for (i, p) in r.points.iter().enumerate() {
        let mark = if r.front.contains(&i) { "*" } else { " " };
        let _ = writeln!(
            out,
            "{mark} {:<28} {:>9} {:>8} {:>10.1} {:>21} {:>12.2e}",
            p.series.name(),
            panels::rate_label(p.rate_hz),
            p.rtol.map_or("-".to_string(), |r| format!("{r:.0e}")),
            p.ns_per_step,
            format!("{:.1}-{:.1}", p.ns_quartiles.0, p.ns_quartiles.1),
            p.error_mm
        );
    }
    let _ = writeln!(
        out,
        "\nPareto front per rate, by increasing time (points whose timing quartiles overlap and \
         whose errors are equal are both kept):"
    );
    for &i in &r.front {
        let p = &r.points[i];
        let _ = writeln!(
            out,
            "  {} @ {}{}: {:.1} ns/step, {:.2e} mm",
            p.series.name(),
            panels::rate_label(p.rate_hz),
            p.rtol.map_or(String::new(), |r| format!(", rtol {r:.0e}")),
            p.ns_per_step,
            p.error_mm
        );
    }
    if let Some(m) = &r.mcu {
        let front = mcu::front(m);
        let _ = writeln!(
            out,
            "\nMCU points (instructions per call, error on the 100 Hz scene; * = rolling-step front):"
        );
        for (i, p) in m.iter().enumerate() {
            let mark = if front.contains(&i) { "*" } else { " " };
            let _ = writeln!(
                out,
                "{mark} {:<24} {:<10} {:>8.0} {:>12.2e}",
                p.name,
                p.variant.backend.name(),
                p.instructions,
                p.error_mm
            );
        }
    }
    for n in &r.notes {
        let _ = writeln!(out, "\nnote: {n}");
    }
    let _ = writeln!(out, "\nWrote:");
    for f in &r.files {
        let _ = writeln!(out, "  {}", f.display());
    }
    out
}

/// The command.
pub fn main(args: &Args) -> Result<(), ChartCommandError> {
    let r = run(args)?;
    print!("{}", summary(&r));
    Ok(())
}
