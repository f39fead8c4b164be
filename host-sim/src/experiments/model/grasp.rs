//! `host-sim model --scene grasp`: which contact model the grasp needs ([`crate::experiments::grasp`], two soft
//! fingertips on simulated hands holding a free 0.1 kg sphere that is lifted and twisted).
//!
//! Every choice of [`softfinger_core::contact::parts`] applies to the grasp: each fingertip's
//! contact is the one-fingertip model run in the body's frame
//! ([`softfinger_core::grasp::FingertipContact`], `Grasp<M, S, P>`), so it has the same parts: the
//! spin torque with its torsional limit (`spin`; without it, a point contact with friction: the
//! grasp's `--torsion off` is the full model with k_z = 0, which `point-friction` and `rolling`
//! give at compile time), rolling of the contact point on both surfaces (`rolling`), and the limit
//! surface coupling twist and slide (`full`: the weight's tangential load takes from the torsional
//! budget).
//!
//! The scene is [`config`]: `host-sim grasp`'s defaults with a twist of [`TORQUE_NM`] about the
//! grasp axis. Each choice runs it in closed loop and is compared with the full model's run, each
//! contact tick by tick as [`super::ablation::difference`] compares a scene (the force each
//! fingertip is given, world frame; its spin torque; its contact point on the object, object
//! frame), held to the same [`super::yardstick`], the worse contact kept; beside that, whether the
//! object is held ([`crate::experiments::grasp::verdict`]) and how its slip and turn differ. Cost: instructions
//! per grasp tick on the emulated Cortex-M4F (the `grasp_tick_sphere_<model>` rows of
//! `mcu-bench/budget.json`, fast backend) and ns per grasp tick on this host (`Grasp::step`
//! replayed on the run's own inputs, [`replay_ns`]), every choice timed in the same invocation as
//! the full model, interleaved over [`TIMING_ROUNDS`] rounds (the least kept), and given as a
//! ratio to the full model's time.

use super::ablation::{difference, transitions, Difference, Run, Tick};
use super::{least_of, yardstick, ModelError, Report, Row};
use crate::experiments::grasp::simulate::{
    run_observed, ConfigError, GraspConfig, GraspRun, Shape, CYLINDER_RADIUS_M, SPHERE_RADIUS_M,
};
use crate::experiments::grasp::verdict::{judge, Verdict};
use softfinger_core::contact::surface::{Cylinder, Sphere, Surface};
use softfinger_core::contact::{ContactInput, ModelChoice, Parts};
use softfinger_core::grasp::{BodyState, Fingertip, Grasp, GraspStep, Wrench};
use softfinger_core::{Fast, Quat, Vec3};
use std::time::Instant;

/// The scene's name on the command line.
pub const SCENE: &str = "grasp";

/// The twist about the grasp axis, N·m: about half the two contacts' combined torsional limit at
/// the default grip (2·τ_max = 31.98 mN·m), with the 0.1 kg object's weight on them.
pub const TORQUE_NM: f64 = 0.015;

/// Rounds over which every choice is timed; the least time per choice is kept.
pub const TIMING_ROUNDS: usize = 15;

/// The ablation's grasp: `host-sim grasp`'s defaults (0.1 kg sphere of 30 mm, 5 N per finger,
/// μ_s 0.8, 20 mm lift, 1.5 s at 10 kHz) with the twist [`TORQUE_NM`].
pub fn config() -> GraspConfig {
    GraspConfig {
        torque_nm: TORQUE_NM,
        ..GraspConfig::default()
    }
}

/// One grasp tick's inputs: the fingertips and the external wrench.
pub type GraspInput = ([Option<Fingertip>; 2], Wrench);

/// One choice's grasp run: each contact's ticks (as a scene's [`Run`]), the verdict on the object
/// and the host time per grasp tick.
#[derive(Clone, Debug)]
pub struct GraspChoiceRun {
    /// Contact 0 and contact 1, each as a one-contact run.
    pub contacts: [Run; 2],
    /// Held or not, slip and turn after settling.
    pub verdict: Verdict,
    /// The run itself.
    pub run: GraspRun,
    /// Each tick's inputs, to replay the run for timing.
    pub inputs: Vec<GraspInput>,
    /// Host time per grasp tick replaying `inputs` ([`replay_ns`]), ns; NaN until timed.
    pub host_ns: f64,
}

/// Host time per grasp tick (`Grasp::step` alone) of a grasp with contacts of `choice` built as
/// [`crate::experiments::grasp::simulate::run`] builds it and stepped on `inputs`, ns (one pass). The grasp is
/// deterministic, so the replay is the closed-loop run itself, without the hands and the clock
/// read around each tick.
pub fn replay_ns(
    config: &GraspConfig,
    choice: ModelChoice,
    inputs: &[GraspInput],
) -> Result<f64, ConfigError> {
    fn on<S: Surface, P: Parts>(
        config: &GraspConfig,
        surface: S,
        q0: Quat,
        inputs: &[GraspInput],
    ) -> Result<f64, ConfigError> {
        let state = BodyState {
            q: q0,
            ..BodyState::default()
        };
        let cp = config.contact_params();
        let mut g = Grasp::<Fast, S, P>::with_parts(
            config.body_params(),
            state,
            surface,
            [cp; 2],
            Vec3::ZERO,
            (1.0 / config.rate_hz) as f32,
        )
        .map_err(|e| ConfigError::Grasp(e.to_string()))?;
        let t0 = Instant::now();
        for (tips, ext) in inputs {
            std::hint::black_box(g.step(std::hint::black_box(*tips), std::hint::black_box(*ext)));
        }
        Ok(t0.elapsed().as_nanos() as f64 / inputs.len().max(1) as f64)
    }
    softfinger_core::with_parts!(choice, P => match config.shape {
        Shape::Sphere => on::<_, P>(config, Sphere::new(SPHERE_RADIUS_M), Quat::IDENTITY, inputs),
        Shape::Cylinder => {
            // As the scene: the cylinder's axis (body x) turned to world z.
            let q = Quat::from_axis_angle::<Fast>(Vec3::Y, -core::f32::consts::FRAC_PI_2);
            on::<_, P>(config, Cylinder::new(CYLINDER_RADIUS_M), q, inputs)
        }
    })
}

/// Run `config` with both contacts of `choice` (not yet timed).
pub fn run_choice(
    config: &GraspConfig,
    choice: ModelChoice,
) -> Result<GraspChoiceRun, ConfigError> {
    let n = (config.duration_s * config.rate_hz).round() as usize;
    let mut ticks: [Vec<Tick>; 2] = [Vec::with_capacity(n), Vec::with_capacity(n)];
    let mut inputs = Vec::with_capacity(n);
    let observe = |tips: &[Option<Fingertip>; 2], ext: &Wrench, s: &GraspStep| {
        inputs.push((*tips, *ext));
        for (c, t) in s.contacts.iter().zip(ticks.iter_mut()) {
            t.push(Tick {
                state: c.output.state,
                force_n: c.on_fingertip.force_n.to_array().map(f64::from),
                tau_nm: f64::from(c.output.tau_n_nm),
                object_point_m: c.output.object_point_m.to_array().map(f64::from),
                input: ContactInput::default(),
            });
        }
    };
    let run = softfinger_core::with_parts!(choice, P => run_observed::<P>(config, observe)?);
    let verdict = judge(&run);
    let [t0, t1] = ticks;
    let as_run = |ticks| Run {
        choice,
        ticks,
        host_ns_per_step: f64::NAN,
    };
    Ok(GraspChoiceRun {
        contacts: [as_run(t0), as_run(t1)],
        verdict,
        run,
        inputs,
        host_ns: f64::NAN,
    })
}

/// Both contacts' differences as one: the larger maximum and ratio, the RMS over both, the state
/// ticks and transitions summed (the percentage of both contacts' `ticks` each).
pub fn combine(a: &Difference, b: &Difference, ticks: usize) -> Difference {
    let rms = |x: f64, y: f64| ((x * x + y * y) / 2.0).sqrt();
    let state_diff_ticks = a.state_diff_ticks + b.state_diff_ticks;
    Difference {
        max_force_diff_n: a.max_force_diff_n.max(b.max_force_diff_n),
        rms_force_diff_n: rms(a.rms_force_diff_n, b.rms_force_diff_n),
        max_torque_diff_mnm: a.max_torque_diff_mnm.max(b.max_torque_diff_mnm),
        rms_torque_diff_mnm: rms(a.rms_torque_diff_mnm, b.rms_torque_diff_mnm),
        max_path_diff_mm: a.max_path_diff_mm.max(b.max_path_diff_mm),
        state_diff_ticks,
        state_diff_percent: 100.0 * state_diff_ticks as f64 / (2 * ticks.max(1)) as f64,
        transitions: a.transitions + b.transitions,
        same_state_sequence: a.same_state_sequence && b.same_state_sequence,
        force_ratio: a.force_ratio.max(b.force_ratio),
        torque_ratio: a.torque_ratio.max(b.torque_ratio),
        path_ratio: a.path_ratio.max(b.path_ratio),
    }
}

/// One row of the grasp's table.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GraspRow {
    /// What a scene's row has: `instructions` per grasp tick, `host_ns_per_step` per grasp tick,
    /// the differences of the worse contact, within the yardstick or not.
    #[serde(flatten)]
    pub row: Row,
    /// Host time per grasp tick over the full model's, in the same invocation (NaN untimed).
    pub host_ratio: f64,
    /// The object held ([`crate::experiments::grasp::verdict`]).
    pub held: bool,
    /// The object's slip after settling, mm.
    pub slip_mm: f64,
    /// The object's turn about the grasp axis after settling, degrees.
    pub turn_deg: f64,
    /// |slip − the full model's slip|, mm.
    pub slip_diff_mm: f64,
    /// |turn − the full model's turn|, degrees.
    pub turn_diff_deg: f64,
    /// Within the yardstick on this device, and held when the full model holds: a model the grasp
    /// may run.
    pub good_enough: bool,
    /// The same on a device that also displayed the spin torque.
    pub good_enough_torque_displayed: bool,
}

/// The grasp's answer.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GraspReport {
    /// [`SCENE`].
    pub scene: &'static str,
    /// `"grasp"`: the rows are per grasp tick (two contacts and the body), not per contact step.
    pub kind: &'static str,
    /// The object's surface.
    pub surface: &'static str,
    /// The cheapest choice (M4F instructions per grasp tick; ties: fewer parts) within the
    /// yardstick on this device that holds the object when the full model holds it.
    pub least_model: &'static str,
    /// The same on a device that also displayed the spin torque.
    pub least_model_torque_displayed: &'static str,
    /// Whether this device displays the spin torque.
    pub device_displays_torque: bool,
    /// The model `host-sim grasp` runs: the full model.
    pub named_model: &'static str,
    /// The named model is good enough (the full model against itself: always).
    pub named_within_yardstick: bool,
    /// The full model holds the object.
    pub full_held: bool,
    /// Transitions of the full model's run, both contacts.
    pub full_transitions: usize,
    /// The scene run.
    pub config: GraspConfig,
    /// Both contacts' torsional limits at the grip, summed, N·m.
    pub combined_tau_max_nm: f64,
    /// The yardstick and its sources.
    pub yardstick: &'static str,
    /// One row per choice, fewest parts first.
    pub rows: Vec<GraspRow>,
}

impl GraspReport {
    /// As a scene's [`Report`] (for the cost-against-difference chart).
    pub fn as_report(&self) -> Report {
        Report {
            scene: self.scene.to_string(),
            surface: self.surface,
            least_model: self.least_model,
            least_model_torque_displayed: self.least_model_torque_displayed,
            device_displays_torque: self.device_displays_torque,
            named_model: self.named_model,
            named_within_yardstick: self.named_within_yardstick,
            full_transitions: self.full_transitions,
            yardstick: self.yardstick,
            rows: self.rows.iter().map(|r| r.row.clone()).collect(),
        }
    }
}

/// Instructions per grasp tick of `model` on the sphere (fast backend), from the budget.
pub fn instructions(model: ModelChoice) -> Option<u32> {
    super::budget_instructions(&format!("grasp_tick_sphere_{}", model.name()))
}

/// Run `choices` (and the full model) on `config`; each timed over [`TIMING_ROUNDS`] interleaved
/// rounds when `timed` (else once). Returns (full, one run per choice).
pub fn runs(
    config: &GraspConfig,
    choices: &[ModelChoice],
    timed: bool,
) -> Result<(GraspChoiceRun, Vec<GraspChoiceRun>), ConfigError> {
    let mut full = run_choice(config, ModelChoice::Full)?;
    let others: Vec<ModelChoice> = choices
        .iter()
        .copied()
        .filter(|&c| c != ModelChoice::Full)
        .collect();
    let mut rest = others
        .iter()
        .map(|&c| run_choice(config, c))
        .collect::<Result<Vec<_>, _>>()?;
    // Every run replayed on its own inputs, the choices interleaved round by round (a load that
    // comes and goes touches them alike); the least time of each kept.
    for _ in 0..if timed { TIMING_ROUNDS } else { 0 } {
        for r in rest.iter_mut().chain(std::iter::once(&mut full)) {
            let ns = replay_ns(config, r.contacts[0].choice, &r.inputs)?;
            // NaN (not yet timed) gives way to the time.
            r.host_ns = r.host_ns.min(ns);
        }
    }
    // A `Full` among `choices` is the full run itself.
    let mut rest = rest.into_iter();
    let runs = choices
        .iter()
        .map(|&c| {
            if c == ModelChoice::Full {
                Some(full.clone())
            } else {
                rest.next()
            }
        })
        .collect::<Option<Vec<_>>>()
        .expect("one run per choice");
    Ok((full, runs))
}

/// The report from the full run and the choices' runs.
pub fn report(config: &GraspConfig, full: &GraspChoiceRun, runs: &[GraspChoiceRun]) -> GraspReport {
    let deg = f64::to_degrees;
    let rows: Vec<GraspRow> = runs
        .iter()
        .map(|r| {
            let choice = r.contacts[0].choice;
            let d0 = difference(&r.contacts[0], &full.contacts[0], config.rate_hz);
            let d1 = difference(&r.contacts[1], &full.contacts[1], config.rate_hz);
            let ticks = r.contacts[0].ticks.len().min(full.contacts[0].ticks.len());
            let diff = combine(&d0, &d1, ticks);
            let holds = r.verdict.held || !full.verdict.held;
            GraspRow {
                row: Row {
                    model: choice.name(),
                    instructions: instructions(choice),
                    host_ns_per_step: r.host_ns,
                    diff,
                    within_yardstick: diff.within_yardstick(),
                    within_yardstick_torque_displayed: diff.within(true),
                },
                host_ratio: r.host_ns / full.host_ns,
                held: r.verdict.held,
                slip_mm: r.verdict.slip_mm,
                turn_deg: deg(r.verdict.rotation_rad),
                slip_diff_mm: (r.verdict.slip_mm - full.verdict.slip_mm).abs(),
                turn_diff_deg: deg((r.verdict.rotation_rad - full.verdict.rotation_rad).abs()),
                good_enough: holds && diff.within_yardstick(),
                good_enough_torque_displayed: holds && diff.within(true),
            }
        })
        .collect();
    let plain: Vec<Row> = rows.iter().map(|r| r.row.clone()).collect();
    let ok = |f: fn(&GraspRow) -> bool| {
        let good: Vec<bool> = rows.iter().map(f).collect();
        least_of(&plain, |r| {
            plain
                .iter()
                .position(|p| p.model == r.model)
                .is_some_and(|k| good[k])
        })
    };
    let named = ModelChoice::Full.name();
    GraspReport {
        scene: SCENE,
        kind: "grasp",
        surface: config_surface(config),
        least_model: ok(|r| r.good_enough),
        least_model_torque_displayed: ok(|r| r.good_enough_torque_displayed),
        device_displays_torque: yardstick::DEVICE_DISPLAYS_TORQUE,
        named_model: named,
        named_within_yardstick: rows.iter().any(|r| r.row.model == named && r.good_enough),
        full_held: full.verdict.held,
        full_transitions: transitions(&full.contacts[0].ticks)
            + transitions(&full.contacts[1].ticks),
        config: *config,
        combined_tau_max_nm: full.run.tau_max_nm[0] + full.run.tau_max_nm[1],
        yardstick: yardstick::STATEMENT,
        rows,
    }
}

fn config_surface(config: &GraspConfig) -> &'static str {
    match config.shape {
        crate::experiments::grasp::simulate::Shape::Sphere => "sphere",
        crate::experiments::grasp::simulate::Shape::Cylinder => "cylinder",
    }
}

/// Every choice on [`config`], timed when `timed`.
pub fn ablate(timed: bool) -> Result<GraspReport, ModelError> {
    let c = config();
    let (full, rest) = runs(&c, &ModelChoice::ALL, timed).map_err(in_grasp)?;
    Ok(report(&c, &full, &rest))
}

fn in_grasp(e: ConfigError) -> ModelError {
    ModelError::Grasp(e.to_string())
}

/// The table and the answer, as text.
pub fn table(r: &GraspReport) -> String {
    let c = &r.config;
    let mut t = format!(
        "scene {} ({} {} kg, grip {} N per finger, mu_s {}, lift {} mm, twist {} mN·m of the combined \
         torsional limit {:.2} mN·m): least model {} (on a device that displayed the spin torque: {}); \
         `host-sim grasp` runs {}; the full model {} the object\n",
        r.scene,
        r.surface,
        c.mass_kg,
        c.grip_n,
        c.mu_s,
        c.lift_mm,
        c.torque_nm * 1e3,
        r.combined_tau_max_nm * 1e3,
        r.least_model,
        r.least_model_torque_displayed,
        r.named_model,
        if r.full_held { "holds" } else { "drops" },
    );
    t += &format!(
        "{:<15} {:>6} {:>8} {:>6} {:>5} {:>8} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>8} {:>7} {:>7} {:>7} {:>6} {:>8}\n",
        "model", "instr", "host ns", "ratio", "held", "slip mm", "turn deg", "dslip mm", "dturn deg",
        "max dF N", "rms dF N", "max dT mNm", "path mm", "F/JND", "T/JND", "P/JND", "felt", "felt(+T)"
    );
    for row in &r.rows {
        let d = &row.row.diff;
        t += &format!(
            "{:<15} {:>6} {:>8.0} {:>6.3} {:>5} {:>8.4} {:>8.3} {:>9.4} {:>9.3} {:>9.4} {:>10.4} {:>10.4} {:>8.4} {:>7.2} {:>7.2} {:>7.2} {:>6} {:>8}\n",
            row.row.model,
            row.row.instructions.map_or("-".to_string(), |n| n.to_string()),
            row.row.host_ns_per_step,
            row.host_ratio,
            if row.held { "yes" } else { "no" },
            row.slip_mm,
            row.turn_deg,
            row.slip_diff_mm,
            row.turn_diff_deg,
            d.max_force_diff_n,
            d.rms_force_diff_n,
            d.max_torque_diff_mnm,
            d.max_path_diff_mm,
            d.force_ratio,
            d.torque_ratio,
            d.path_ratio,
            if row.good_enough { "no" } else { "yes" },
            if row.good_enough_torque_displayed { "no" } else { "yes" },
        );
    }
    t += &format!(
        "(felt: over the yardstick, or dropping an object the full model holds; full model: {} \
         transitions over both contacts; instructions per grasp tick on the M4F, fast backend; \
         host ns per grasp tick replayed, least of {} interleaved rounds) {}\n",
        r.full_transitions, TIMING_ROUNDS, r.yardstick
    );
    t
}

/// `host-sim model --scene grasp`.
pub fn main(args: &super::Args) -> Result<(), ModelError> {
    if args.check {
        // The grasp runs the full model: its check is the full model against itself, run twice.
        let c = config();
        let (full, named) = runs(&c, &[ModelChoice::Full], false).map_err(in_grasp)?;
        let r = report(&c, &full, &named);
        let row = &r.rows[0];
        if !row.good_enough {
            return Err(ModelError::Exceeds {
                scene: SCENE.to_string(),
                model: r.named_model,
                force_ratio: row.row.diff.force_ratio,
                torque_ratio: row.row.diff.torque_ratio,
                path_ratio: row.row.diff.path_ratio,
            });
        }
        println!(
            "{SCENE}: `host-sim grasp` runs the full model, the reference \
             (`host-sim model --scene {SCENE}` names the least model)"
        );
        return Ok(());
    }
    let r = ablate(true)?;
    if let Some(path) = &args.svg {
        let dropped: Vec<&str> = r
            .rows
            .iter()
            .filter(|row| r.full_held && !row.held)
            .map(|row| row.row.model)
            .collect();
        crate::experiments::model::chart::write_for(
            path,
            &r.as_report(),
            "instructions per grasp tick, two contacts and the body (emulated Cortex-M4F, fast backend)",
            &dropped,
        )?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&r).map_err(crate::error::JsonError)?
        );
    } else {
        print!("{}", table(&r));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diff(max_f: f64, rms_f: f64, state_ticks: usize, ratio: f64, same: bool) -> Difference {
        Difference {
            max_force_diff_n: max_f,
            rms_force_diff_n: rms_f,
            max_torque_diff_mnm: max_f,
            rms_torque_diff_mnm: rms_f,
            max_path_diff_mm: max_f,
            state_diff_ticks: state_ticks,
            state_diff_percent: 100.0 * state_ticks as f64 / 1000.0,
            transitions: 2,
            same_state_sequence: same,
            force_ratio: ratio,
            torque_ratio: ratio,
            path_ratio: ratio,
        }
    }

    /// Two contacts' differences: the worse maximum and ratio, the RMS over both, the states
    /// counted over both contacts' ticks.
    #[test]
    fn both_contacts_count_the_worse_one_decides() {
        let d = combine(
            &diff(1.0, 3.0, 10, 0.5, true),
            &diff(2.0, 4.0, 0, 1.5, false),
            1000,
        );
        assert_eq!(d.max_force_diff_n, 2.0);
        assert_eq!(d.max_path_diff_mm, 2.0);
        assert!((d.rms_force_diff_n - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(d.state_diff_ticks, 10);
        assert!((d.state_diff_percent - 0.5).abs() < 1e-12, "{d:?}");
        assert_eq!((d.transitions, d.same_state_sequence), (4, false));
        assert_eq!((d.force_ratio, d.path_ratio), (1.5, 1.5));
        assert!(!d.within_yardstick());
        let none = combine(
            &diff(0.0, 0.0, 0, 0.0, true),
            &diff(0.0, 0.0, 0, 0.0, true),
            0,
        );
        assert_eq!(none.state_diff_percent, 0.0);
        assert!(none.within_yardstick());
    }
}
