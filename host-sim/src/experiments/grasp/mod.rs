//! `host-sim grasp`: two soft fingertips, driven by simulated hands squeezing with a set grip
//! force, hold a free object that is lifted and twisted about the grasp axis (the core's
//! [`softfinger_core::grasp`]). Prints a summary (or JSON with `--json`) and writes charts and an
//! `index.html` into `--out`.
//!
//! | file | what |
//! | --- | --- |
//! | [`hand`] | the simulated hand driving one fingertip |
//! | [`devices`] | the same scene on two device plants, each running the control pipeline, the object stepped by the application |
//! | [`simulate`] | the scene: configuration, the run, one sample per tick |
//! | [`verdict`] | held / slip / turn after settling |
//! | [`sweep`] | the twist sweep across the combined torsional limit, torsion on and off |
//! | [`charts`] | the SVG charts |

pub mod charts;
pub mod devices;
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

/// What drives the fingertips.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PlantKind {
    /// Ideal hands: force sources on point-mass fingertips, the object in the same loop.
    Ideal,
    /// Two device plants, each running the control pipeline on the object as its local model;
    /// the object stepped by the application at `--model-hz` over a link of `--latency-ms`.
    Devices,
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
    /// What drives the fingertips: ideal hands, or two device plants with the control pipeline.
    #[arg(long, value_enum, default_value_t = PlantKind::Ideal)]
    pub plant: PlantKind,
    /// With `--plant devices`: the rate the application sends each device its model, Hz
    /// (divides 10000; the object is stepped at 1 kHz, or at this rate when faster).
    #[arg(long, default_value_t = 1000.0)]
    pub model_hz: f64,
    /// With `--plant devices`: the link's one-way delay, each way, ms.
    #[arg(long, default_value_t = 0.0)]
    pub latency_ms: f64,
    /// With `--plant devices`: send the body's pose as it is, not predicted ahead by the delay
    /// until the device renders it.
    #[arg(long)]
    pub no_predict: bool,
    /// With `--plant devices`: where the application's object takes its contact forces from.
    #[arg(long, value_enum, default_value_t = devices::ObjectDesign::HostContacts)]
    pub object: devices::ObjectDesign,
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
    /// What the devices add (only with `--plant devices`).
    pub devices: Option<devices::DeviceFigures>,
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
        devices: None,
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
    let (run, figures) = match args.plant {
        PlantKind::Ideal => (simulate::run(&config)?, None),
        PlantKind::Devices => {
            let link = devices::LinkConfig {
                model_hz: args.model_hz,
                latency_ms: args.latency_ms,
                predict: !args.no_predict,
                design: args.object,
            };
            let (run, f) = devices::run(&config, &link)?;
            (run, Some(f))
        }
    };
    let v = verdict::judge(&run);
    let mut r = report(&run, &v);
    let mut text_extra = String::new();
    if let Some(f) = &figures {
        text_extra = format!(
            "\non two device plants (the control pipeline at 10000 Hz, the object at {} Hz with {:?}, link delay {} ms each way, pose predicted {:.2} ms ahead): \
             normal forces {:.2} N and {:.2} N, combined torsional limit there {:.2} mN·m; jitter {:.2} um, force step at model updates {:.4} N (between {:.4} N), armed throughout: {}, latched {}",
            f.link.model_hz,
            f.link.design,
            f.link.latency_ms,
            f.link.lead_s() * 1e3,
            f.normal_force_n[0],
            f.normal_force_n[1],
            f.combined_tau_max_nm * 1e3,
            f.jitter_um,
            f.force_step_at_update_n,
            f.force_step_between_n,
            f.armed_throughout,
            f.latched
        );
    }
    r.devices = figures;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| GraspCmdError::OutDir(args.out.display().to_string(), e))?;
    let hysteresis = f64::from(config.contact_params().tolerances.hysteresis);
    let mut files = charts::write_all(&args.out, &run, hysteresis)?;
    // The sweep is of ideal fingertips (each of its runs on devices would home two plants).
    if args.sweep_points >= 2 && args.plant == PlantKind::Ideal {
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
    let text = summary(&r) + &text_extra;
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
