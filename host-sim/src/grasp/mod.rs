//! `host-sim grasp`: two soft fingertips, driven by simulated hands squeezing with a set grip
//! force, hold a free object that is lifted and twisted about the grasp axis (the core's
//! [`softfinger_core::grasp`]). Prints a summary (or JSON with `--json`) and writes charts and an
//! `index.html` into `--out`.
//!
//! | file | what |
//! | --- | --- |
//! | [`hand`] | the simulated hand driving one fingertip |
//! | [`simulate`] | the scene: configuration, the run, one sample per tick |
//! | [`verdict`] | held / slip / turn after settling |
//! | [`sweep`] | the twist sweep across the combined torsional limit, torsion on and off |
//! | [`charts`] | the SVG charts |

pub mod charts;
pub mod hand;
pub mod simulate;
pub mod sweep;
pub mod verdict;

use crate::error::{ChartError, JsonError};
use simulate::{ConfigError, GraspConfig, GraspRun, Shape};
use std::path::PathBuf;
use verdict::Verdict;

/// Why `host-sim grasp` failed.
#[derive(Debug, thiserror::Error)]
pub enum GraspCmdError {
    /// An option was rejected.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A chart or the index could not be written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// The JSON could not be serialised.
    #[error(transparent)]
    Json(#[from] JsonError),
    /// The output folder could not be made.
    #[error("{0}: {1}")]
    OutDir(String, std::io::Error),
}

/// Torsion on (soft fingers) or off (point contacts).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum OnOff {
    /// Soft-finger contacts with torsion.
    On,
    /// Point contacts: no spin torque.
    Off,
}

#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Object mass, kg.
    #[arg(long, default_value_t = 0.1)]
    pub mass_kg: f64,
    /// Each hand's squeeze, N.
    #[arg(long, default_value_t = 5.0)]
    pub grip_n: f64,
    /// Static friction coefficient of both contacts (kinetic: 0.75 of it).
    #[arg(long, default_value_t = 0.8)]
    pub mu_s: f64,
    /// External torque about the grasp axis, N·m (ramped in over the first 0.1 s).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub torque_nm: f64,
    /// Soft-finger torsion at both contacts.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub torsion: OnOff,
    /// Run length, s.
    #[arg(long, default_value_t = 1.5)]
    pub duration_s: f64,
    /// The object.
    #[arg(long, value_enum, default_value_t = Shape::Sphere)]
    pub shape: Shape,
    /// Gravity, m/s².
    #[arg(long, default_value_t = 9.81)]
    pub gravity_m_s2: f64,
    /// How far the hands lift the object (from 0.3 s over 1 s), mm.
    #[arg(long, default_value_t = 20.0, allow_negative_numbers = true)]
    pub lift_mm: f64,
    /// Control rate, Hz.
    #[arg(long, default_value_t = 10_000.0)]
    pub rate_hz: f64,
    /// Open both hands at this time, s.
    #[arg(long)]
    pub release_s: Option<f64>,
    /// Points of the twist sweep (torsion on and off, 0 to 2x the combined limit; 0: no sweep).
    #[arg(long, default_value_t = 13)]
    pub sweep_points: usize,
    /// Folder for the charts and index.html.
    #[arg(long, default_value = "out/grasp")]
    pub out: PathBuf,
    /// Print JSON instead of the summary.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The scene configuration these options ask for.
    pub fn config(&self) -> GraspConfig {
        GraspConfig {
            shape: self.shape,
            mass_kg: self.mass_kg,
            grip_n: self.grip_n,
            mu_s: self.mu_s,
            torque_nm: self.torque_nm,
            torsion: self.torsion == OnOff::On,
            gravity_m_s2: self.gravity_m_s2,
            lift_mm: self.lift_mm,
            duration_s: self.duration_s,
            rate_hz: self.rate_hz,
            release_s: self.release_s,
        }
    }
}

/// The JSON `host-sim grasp --json` prints.
#[derive(Debug, serde::Serialize)]
pub struct Report {
    /// True when the grasp did not slip after settling in the first 0.2 s.
    pub held: bool,
    /// Largest displacement of the object relative to the fingertips' midpoint after settling, mm.
    pub slip_mm: f64,
    /// Largest rotation of the object about the grasp axis relative to the fingertips after settling, rad.
    pub rotation_rad: f64,
    /// Each contact's torsional limit at the grip force, N·m, as the model computes it.
    pub tau_max_nm: [f64; 2],
    /// Each contact's tangential friction limit at the grip force (μ_s·F_grip), N.
    pub f_max_n: [f64; 2],
    /// The closed form of the lift: the grip holds the weight when 2·μ_s·F_grip > m·g (N each side).
    pub lift_capacity_n: f64,
    /// The weight m·g, N.
    pub weight_n: f64,
    /// Whether any tick produced a non-finite value.
    pub non_finite: bool,
    /// The flags raised in any tick (hex).
    pub flags: String,
    /// Host time per grasp tick (both contacts and the body), ns.
    pub tick_ns: f64,
    /// The configuration run.
    pub config: GraspConfig,
    /// The twist sweep (none with `--sweep-points` below 2).
    pub twist_sweep: Option<TwistSweep>,
}

/// The twist sweep of the report: torques from 0 to twice the combined torsional limit, no
/// gravity and no lift, torsion on and off.
#[derive(Debug, serde::Serialize)]
pub struct TwistSweep {
    /// Both contacts' torsional limit at the grip, N·m.
    pub combined_limit_nm: f64,
    /// Torsion on: each torque's verdict.
    pub torsion_on: Vec<sweep::SweepPoint>,
    /// Torsion off.
    pub torsion_off: Vec<sweep::SweepPoint>,
}

/// The report of a run and its verdict.
pub fn report(run: &GraspRun, v: &Verdict) -> Report {
    let c = &run.config;
    let flags = run.samples.iter().fold(0u32, |a, s| a | s.flags.0);
    Report {
        held: v.held,
        slip_mm: v.slip_mm,
        rotation_rad: v.rotation_rad,
        tau_max_nm: run.tau_max_nm,
        f_max_n: run.f_max_n,
        lift_capacity_n: run.f_max_n[0] + run.f_max_n[1],
        weight_n: c.mass_kg * c.gravity_m_s2,
        non_finite: v.non_finite,
        flags: format!("{flags:#x}"),
        tick_ns: run.tick_ns,
        config: *c,
        twist_sweep: None,
    }
}

/// The summary lines.
pub fn summary(r: &Report) -> String {
    let c = &r.config;
    format!(
        "grasp: {:?}, {} kg, grip {} N per finger, mu_s {}, torque {} N·m about the grasp axis, torsion {}, {} s at {} Hz\n\
         held: {} (after 0.2 s: slip {:.4} mm, turn {:.5} rad; limits 0.1 mm, 0.01 rad)\n\
         limits per contact at the grip: f_max {:.3} N, tau_max {:.3} mN·m; lift needs m·g = {:.3} N < 2·mu_s·F = {:.3} N; twist needs |torque| < {:.3} mN·m\n\
         flags {}, non-finite values: {}; host time per grasp tick {:.0} ns",
        c.shape,
        c.mass_kg,
        c.grip_n,
        c.mu_s,
        c.torque_nm,
        if c.torsion { "on" } else { "off" },
        c.duration_s,
        c.rate_hz,
        r.held,
        r.slip_mm,
        r.rotation_rad,
        r.f_max_n[0],
        r.tau_max_nm[0] * 1e3,
        r.weight_n,
        r.lift_capacity_n,
        (r.tau_max_nm[0] + r.tau_max_nm[1]) * 1e3,
        r.flags,
        r.non_finite,
        r.tick_ns,
    )
}

/// `host-sim grasp`.
pub fn main(args: &Args) -> Result<(), GraspCmdError> {
    let config = args.config();
    let run = simulate::run(&config)?;
    let v = verdict::judge(&run);
    let mut r = report(&run, &v);
    std::fs::create_dir_all(&args.out)
        .map_err(|e| GraspCmdError::OutDir(args.out.display().to_string(), e))?;
    let hysteresis = f64::from(config.contact_params().tolerances.hysteresis);
    let mut files = charts::write_all(&args.out, &run, hysteresis)?;
    if args.sweep_points >= 2 {
        let (on, off, limit) = sweep::sweep(&config, args.sweep_points, 2.0)?;
        let f = args.out.join("twist_sweep.svg");
        charts::twist_sweep(&f, &on, &off, limit)?;
        files.push(f);
        r.twist_sweep = Some(TwistSweep {
            combined_limit_nm: limit,
            torsion_on: on,
            torsion_off: off,
        });
    }
    let text = summary(&r);
    crate::chart::index_page::write(
        &args.out,
        "softfinger: two soft fingertips hold an object",
        &text,
        &files,
    )?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&r).map_err(JsonError)?);
    } else {
        println!("{text}");
        println!("charts and index.html in {}", args.out.display());
    }
    Ok(())
}
