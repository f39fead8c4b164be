//! `host-sim run` (the default command): a scene in closed loop with the plant, through the one
//! control pipeline the firmware runs (homing and arming first, see
//! [`crate::sim::closed_loop::prepare`]); a short summary, a CSV time series, SVG charts (force and
//! spin torque over the contact-state bands, the contact paths; [`charts`]) and
//! an `index.html` showing the summary and every chart. The CSV and the figures cover the scene,
//! from the arming on.

pub mod charts;
pub mod limit_path;
pub mod result;

use crate::atomic_file::AtomicFile;
use crate::sim::closed_loop::{self, prepare, simulate, ClosedLoopError, SetupError};
use crate::sim::scene::{Scene, SceneError, SurfaceSpec};
pub use result::{Row, RunResult};
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::surface::Surface;
use softfinger_core::control::controller::WithParts;
use softfinger_core::control::pipeline::{Pipeline, PipelineConfig};
use softfinger_core::{Fast, Math};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{ChartError, FileError};
use limit_path::LimitPathError;

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene could not be loaded.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene's configuration was rejected before the run.
    #[error(transparent)]
    Setup(#[from] ClosedLoopError),
    /// A stage of the run of the named scene failed.
    #[error("scene '{scene}': {source}")]
    InScene {
        /// Scene name.
        scene: String,
        /// The stage and its reason.
        source: SetupError,
    },
    /// The progress bar's template was rejected.
    #[error("progress bar: {0}")]
    Progress(indicatif::style::TemplateError),
    /// An output file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// The limit-surface chart of the run failed.
    #[error(transparent)]
    LimitPath(#[from] LimitPathError),
}

#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// A built-in scene name (finger-on-plane, finger-on-sphere, finger-in-bowl,
    /// finger-on-cylinder, finger-slide-twist) or a scene TOML file.
    #[arg(long, default_value = "finger-on-plane")]
    pub scene: String,
    /// Control rate, Hz (overrides the scene's).
    #[arg(long)]
    pub rate_hz: Option<f64>,
    /// Duration, s (overrides the scene's).
    #[arg(long)]
    pub duration_s: Option<f64>,
    /// Output folder for the CSV and the charts.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

impl Default for Args {
    fn default() -> Self {
        Args {
            scene: "finger-on-plane".into(),
            rate_hz: None,
            duration_s: None,
            out: PathBuf::from("out"),
        }
    }
}

/// The summary figures of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Seconds spent in each state: broken, rolling, sliding.
    pub time_in_state_s: [f64; 3],
    pub transitions: usize,
    pub max_force_n: f64,
    pub max_abs_tau_n_nm: f64,
    /// Length of the contact path on the object while touching, m.
    pub object_path_m: f64,
    /// Length of the contact path on the fingertip while touching, m.
    pub finger_path_m: f64,
    pub latched_fault_ticks: usize,
    pub non_finite_values: usize,
}

fn state_index(s: ContactState) -> usize {
    match s {
        ContactState::Broken => 0,
        ContactState::Rolling => 1,
        ContactState::Sliding => 2,
    }
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f64 {
    let d: f64 = (0..3).map(|i| (a[i] as f64 - b[i] as f64).powi(2)).sum();
    d.sqrt()
}

pub fn summarize(rows: &[Row], dt_s: f64) -> Summary {
    let mut s = Summary {
        time_in_state_s: [0.0; 3],
        transitions: 0,
        max_force_n: 0.0,
        max_abs_tau_n_nm: 0.0,
        object_path_m: 0.0,
        finger_path_m: 0.0,
        latched_fault_ticks: 0,
        non_finite_values: 0,
    };
    for (k, r) in rows.iter().enumerate() {
        s.time_in_state_s[state_index(r.state)] += dt_s;
        let values = r
            .probe_m
            .iter()
            .chain(&r.force_n)
            .chain(&r.duties)
            .chain([&r.tau_n_nm, &r.spin_rad]);
        s.non_finite_values += values.filter(|v| !v.is_finite()).count();
        let f = dist(r.force_n, [0.0; 3]);
        s.max_force_n = s.max_force_n.max(f);
        s.max_abs_tau_n_nm = s.max_abs_tau_n_nm.max(r.tau_n_nm.abs() as f64);
        if r.flags
            .intersects(softfinger_core::control::controller::LATCHING)
        {
            s.latched_fault_ticks += 1;
        }
        if k > 0 {
            let p = &rows[k - 1];
            if p.state != r.state {
                s.transitions += 1;
            } else if r.state != ContactState::Broken {
                s.object_path_m += dist(p.object_point_m, r.object_point_m);
                s.finger_path_m += dist(p.finger_point_m, r.finger_point_m);
            }
        }
    }
    s
}

/// Run `scene` with the contact model it names (`model`; [`softfinger_core::contact::parts`]).
fn run_named<M: Math, S: Surface>(
    scene: Scene,
    config: PipelineConfig<S>,
    ticks: u64,
) -> Result<RunResult, RunError> {
    let model = scene.model().map_err(ClosedLoopError::from)?;
    softfinger_core::with_parts!(model, P => run_with::<M, S, P>(scene, config, ticks))
}

fn run_with<M: Math, S: Surface, P: softfinger_core::contact::Parts>(
    scene: Scene,
    config: PipelineConfig<S>,
    ticks: u64,
) -> Result<RunResult, RunError> {
    let config = PipelineConfig {
        device: config.device,
        timing: config.timing,
        contact: config.contact,
        surface: WithParts::<S, P>::new(config.surface),
        object_origin_m: config.object_origin_m,
        log_rate_hz: config.log_rate_hz,
    };
    let in_scene = |source| RunError::InScene {
        scene: scene.name.clone(),
        source,
    };
    let mut pipe: Pipeline<M, WithParts<S, P>> =
        Pipeline::new(config).map_err(|e| in_scene(e.into()))?;
    let mut plant = closed_loop::plant(&scene, &config.contact).map_err(|e| in_scene(e.into()))?;
    let prepared = prepare(&mut pipe, &mut plant).map_err(|e| in_scene(e.into()))?;
    let dt = 1.0 / f64::from(config.timing.control_hz);
    let full_scale = config.timing.pwm_period_counts() as u16;
    let mut rows = Vec::with_capacity(ticks as usize);
    let bar = indicatif::ProgressBar::new(ticks);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ticks")
            .map_err(RunError::Progress)?,
    );
    bar.set_message(format!("run {}", scene.name));
    let spent = simulate(
        &mut pipe,
        &mut plant,
        ticks,
        |_, _| {},
        |k, _raw, out, pipe, p| {
            let contact = pipe.controller().contact();
            let truth = p.truth();
            let c = &out.control;
            rows.push(Row {
                t_s: (k + 1) as f64 * dt,
                phase: truth.hand_reference.phase.name(),
                state: c.state,
                flags: out.flags,
                probe_m: c.probe_m.to_array(),
                force_n: c.force_n.to_array(),
                tau_n_nm: c.tau_n_nm,
                spin_rad: contact.spin().accumulated_rad,
                object_point_m: contact.rolling().surface().contact_point().to_array(),
                finger_point_m: contact.rolling().finger_point().to_array(),
                normal: contact.rolling().surface().normal().to_array(),
                duties: out.bridges.duties(full_scale),
                hand_force_n: truth.hand_force_n,
            });
            if k % 1000 == 0 {
                bar.set_position(k);
            }
        },
    );
    bar.finish_and_clear();
    Ok(RunResult {
        scene,
        rows,
        ns_per_tick: spent.as_nanos() as f64 / ticks.max(1) as f64,
        prepared,
    })
}

/// Run a scene (no files written).
pub fn simulate_scene(args: &Args) -> Result<RunResult, RunError> {
    let mut scene = Scene::load(&args.scene)?;
    if let Some(r) = args.rate_hz {
        scene.rate_hz = r;
    }
    if let Some(d) = args.duration_s {
        scene.duration_s = d;
    }
    let scene = Scene::parse(&scene.to_toml(), &scene.name)?; // re-check the overrides
    let contact = closed_loop::contact_params(&scene)?;
    let ticks = (scene.duration_s * scene.rate_hz).round() as u64;
    match scene.surface {
        SurfaceSpec::Plane => {
            let cfg = closed_loop::plane_config(&scene, contact)?;
            run_named::<Fast, _>(scene, cfg, ticks)
        }
        SurfaceSpec::Sphere { radius_m } => {
            let cfg = closed_loop::sphere_config(&scene, contact, radius_m)?;
            run_named::<Fast, _>(scene, cfg, ticks)
        }
        SurfaceSpec::Bowl { radius_m } => {
            let cfg = closed_loop::bowl_config(&scene, contact, radius_m)?;
            run_named::<Fast, _>(scene, cfg, ticks)
        }
        SurfaceSpec::Cylinder { radius_m } => {
            let cfg = closed_loop::cylinder_config(&scene, contact, radius_m)?;
            run_named::<Fast, _>(scene, cfg, ticks)
        }
    }
}

fn write_csv(path: &Path, rows: &[Row]) -> Result<(), FileError> {
    let mut f = AtomicFile::create(path).map_err(FileError::on(path, "cannot create"))?;
    let w = f.writer();
    let io = |e| FileError::on(path, "write failed")(e);
    writeln!(w, "t_s,phase,state,flags,probe_x_m,probe_y_m,probe_z_m,force_x_n,force_y_n,force_z_n,tau_n_nm,spin_rad,object_x_m,object_y_m,object_z_m,finger_x_m,finger_y_m,finger_z_m,duty0,duty1,duty2,hand_fx_n,hand_fy_n,hand_fz_n").map_err(io)?;
    for r in rows {
        let v = |a: [f32; 3]| format!("{},{},{}", a[0], a[1], a[2]);
        writeln!(
            w,
            "{:.6},{},{},{:#x},{},{},{},{},{},{},{},{},{},{}",
            r.t_s,
            r.phase,
            r.state.name(),
            r.flags.0,
            v(r.probe_m),
            v(r.force_n),
            r.tau_n_nm,
            r.spin_rad,
            v(r.object_point_m),
            v(r.finger_point_m),
            v(r.duties),
            r.hand_force_n[0],
            r.hand_force_n[1],
            r.hand_force_n[2]
        )
        .map_err(io)?;
    }
    f.commit().map_err(FileError::on(path, "cannot publish"))
}

/// The summary lines the command prints (and `index.html` shows).
fn summary_lines(
    res: &RunResult,
    s: &Summary,
    limit: Option<&crate::experiments::run::limit_path::LoadSummary>,
) -> Vec<String> {
    let dt = 1.0 / res.scene.rate_hz;
    let p = &res.prepared;
    let err = p
        .homing_error_counts
        .iter()
        .map(|e| e.abs())
        .max()
        .unwrap_or(0);
    let mut lines = vec![
        format!(
            "scene {} ({}), {} ticks at {} Hz, method {}, backend {}",
            res.scene.name,
            res.scene.description,
            res.rows.len(),
            res.scene.rate_hz,
            res.scene.method,
            Fast::NAME
        ),
        format!(
            "  session: homed at {:.3} s (homing error {} counts at most), armed at {:.3} s; the scene starts then",
            p.homed_at_s, err, p.armed_at_s
        ),
        format!(
            "  states: broken {:.2} s, rolling {:.2} s, sliding {:.2} s; {} transitions",
            s.time_in_state_s[0], s.time_in_state_s[1], s.time_in_state_s[2], s.transitions
        ),
        format!(
            "  max force {:.2} N (limit {} N); max |spin torque| {:.2} mN·m",
            s.max_force_n,
            softfinger_core::contact::params::ContactParams::DEFAULT.max_force_n,
            s.max_abs_tau_n_nm * 1e3
        ),
        format!(
            "  contact path: {:.2} mm on the object, {:.2} mm on the fingertip",
            s.object_path_m * 1e3,
            s.finger_path_m * 1e3
        ),
        format!(
            "  tick cost on this PC: {:.0} ns per pipeline tick ({:.2} % of the {:.0} µs period)",
            res.ns_per_tick,
            res.ns_per_tick * 1e-9 / dt * 100.0,
            dt * 1e6
        ),
        format!(
            "  faults latched: {} ticks; non-finite values: {}",
            s.latched_fault_ticks, s.non_finite_values
        ),
    ];
    if let Some(l) = limit {
        lines.push(format!(
            "  limit surface (1 = static ellipse): largest load {:.3} rolling, {:.3} sliding ({} ticks); twist used up to {:.3} of τ_max",
            l.max_rolling, l.max_sliding, l.sliding_ticks, l.max_twist
        ));
    }
    lines
}

pub fn main(args: &Args) -> Result<(), RunError> {
    let res = simulate_scene(args)?;
    let s = summarize(&res.rows, 1.0 / res.scene.rate_hz);
    std::fs::create_dir_all(&args.out).map_err(FileError::on(&args.out, "cannot create"))?;
    let csv = args.out.join("run.csv");
    write_csv(&csv, &res.rows)?;
    let mut files = vec![csv];
    files.extend(crate::experiments::run::charts::write(&args.out, &res)?);
    let limit = crate::experiments::run::limit_path::write_for_run(&args.out, &res)?;
    let lines = summary_lines(&res, &s, limit.as_ref().map(|l| &l.1));
    files.extend(limit.map(|l| l.0));
    let title = format!("host-sim run: {}", res.scene.name);
    let index = crate::chart::index_page::write(&args.out, &title, &lines.join("\n"), &files)?;
    files.push(index);
    for l in &lines {
        println!("{l}");
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_are_rechecked() {
        let a = Args {
            rate_hz: Some(100.0),
            ..Args::default()
        };
        let e = simulate_scene(&a).unwrap_err().to_string();
        assert!(e.contains("rate_hz"), "{e}");
    }
}
