//! The fault campaign: a table of scenarios, each a closed-loop run of the plant and the one
//! control pipeline with one fault or disturbance injected ([`Scenario::setup`]), and a judge
//! that says whether the safe state (or, for disturbances that are not faults, bounded and sane
//! behaviour) was reached in time ([`Scenario::judge`]).
//!
//! Common scene: the default touch script (approach 0.5 s, press 0.3 s, roll 1 s, twist 1 s,
//! slide 1 s, lift-off 0.5 s) on the plane z = −0.175 m, the Omega-like device on the STM32G474
//! board timing at 10 kHz, the `Fast` math backend. Most scenarios start after the operator's
//! session (homed, armed, see [`crate::sim::closed_loop::prepare`]) and inject at t = 1.2 s (tick
//! 12 000), mid-roll with the fingertip pressed on the surface; the pipeline scenarios
//! ([`super::pipeline_cases`]) start at power-up.
//!
//! In every scenario the rendered force stays within `max_force_n`, the force the motors actually
//! exert (from the plant's currents) within `max_force_n` × [`PLANT_FORCE_MARGIN`], no output is
//! NaN, and the bridges never drive the wrong way (plant truth).

use super::closed_loop::{scene_config, ClosedLoop, Pipe, Trace};
use super::FaultsError;
use crate::sim::closed_loop::SetupError;
use crate::sim::plant::{HandScript, Plant, PlantParams, TouchScript};
use serde::Serialize;
use softfinger_core::contact::surface::Plane;
use softfinger_core::control::controller::TickLimits;
use softfinger_core::control::output_guard::LATCHING;
use softfinger_core::control::pipeline::{PipelineConfig, RawInput};
use softfinger_core::Flags;

/// Control rate of the campaign, Hz (the board timing's).
pub const RATE_HZ: f64 = 10_000.0;
/// Tick of the injection: t = 1.2 s, mid-roll.
pub const K_INJECT: u64 = 12_000;
/// The motors' force may exceed the rendered limit by this factor: the duty is computed from the
/// counts of tick k and acts from the next PWM period through the winding's L/R = 0.11 ms lag and
/// a filtered back-EMF estimate, so the current follows the command with a transient error.
pub const PLANT_FORCE_MARGIN: f64 = 1.1;

/// One scenario's result.
#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    pub name: &'static str,
    /// What was done to the loop.
    pub injection: &'static str,
    /// What "survived" means for this scenario.
    pub criterion: &'static str,
    pub survived: bool,
    /// Why it failed (empty when survived), or notes.
    pub detail: String,
    pub ticks: u64,
    pub inject_tick: Option<u64>,
    /// First tick the fault's flag was raised.
    pub detect_tick: Option<u64>,
    /// First tick of zero torque held to the end.
    pub safe_tick: Option<u64>,
    pub max_rendered_force_n: f64,
    pub max_plant_force_n: f64,
    /// Largest arm torque during homing, N·m (0 when the run does not home).
    pub max_homing_torque_nm: f64,
    pub nan_outputs: usize,
    /// Wrong-direction drive at the plant over the run, s.
    pub wrong_direction_s: f64,
    /// Contact states visited (in order of first visit).
    pub states: Vec<&'static str>,
    /// Operating modes visited (in order of first visit).
    pub modes: Vec<&'static str>,
}

pub type Act = Box<dyn FnMut(u64, &mut Pipe, &mut Plant)>;
pub type Inject = Box<dyn FnMut(u64, &mut RawInput)>;

pub fn no_act() -> Act {
    Box::new(|_, _, _| {})
}

pub fn no_inject() -> Inject {
    Box::new(|_, _| {})
}

/// Where a scenario's tick 0 is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// After the operator's session: homed and armed, the script at its start.
    Armed,
    /// Power-up: unhomed, drivers asleep.
    PowerUp,
}

/// A scenario's run.
pub struct Setup {
    pub config: PipelineConfig<Plane>,
    pub plant: PlantParams,
    pub script: HandScript,
    pub ticks: u64,
    pub start: Start,
    pub act: Act,
    pub inject: Inject,
}

/// What everything shares: the touch scene, its configuration and its thresholds.
#[derive(Clone, Copy, Debug)]
pub struct Ctx {
    pub touch: TouchScript,
    pub base: PipelineConfig<Plane>,
    pub plant: PlantParams,
    pub per_tick: TickLimits,
    pub limit_n: f64,
}

impl Ctx {
    pub fn new() -> Ctx {
        let touch = TouchScript::default();
        let base = scene_config(&touch);
        Ctx {
            touch,
            base,
            plant: PlantParams::OMEGA_LIKE,
            per_tick: base.device.limits.per_tick(base.timing.control_hz as f32),
            limit_n: base.contact.max_force_n as f64,
        }
    }

    /// A setup of the touch scene from the armed start with no hooks.
    pub fn plain(&self, script: HandScript, ticks: u64) -> Setup {
        Setup {
            config: self.base,
            plant: self.plant,
            script,
            ticks,
            start: Start::Armed,
            act: no_act(),
            inject: no_inject(),
        }
    }

    /// The whole touch script plus 0.2 s, in ticks.
    pub fn full(&self) -> u64 {
        ((self.touch.script().duration_s() + 0.2) * RATE_HZ) as u64
    }
}

impl Default for Ctx {
    fn default() -> Self {
        Ctx::new()
    }
}

/// A judge's verdict.
pub struct Judged {
    pub survived: bool,
    pub detail: String,
    pub inject_tick: Option<u64>,
    pub detect_tick: Option<u64>,
}

/// A verdict from failure reasons (survived when there are none) and a note.
pub fn judged(
    fails: Vec<String>,
    inject: Option<u64>,
    detect: Option<u64>,
    note: String,
) -> Judged {
    Judged {
        survived: fails.is_empty(),
        detail: if fails.is_empty() {
            note
        } else {
            fails.join("; ")
        },
        inject_tick: inject,
        detect_tick: detect,
    }
}

/// One row of the campaign table.
pub struct Scenario {
    pub name: &'static str,
    pub injection: &'static str,
    pub criterion: &'static str,
    /// A fault or disturbance is injected (counted in the summary's `injected`).
    pub injected: bool,
    pub setup: fn(&Ctx) -> Setup,
    pub judge: fn(&Trace, &ClosedLoop, &Ctx) -> Judged,
}

fn run(s: Setup) -> Result<(Trace, ClosedLoop), SetupError> {
    let mut lp = match s.start {
        Start::Armed => ClosedLoop::new(s.config, s.plant, s.script)?,
        Start::PowerUp => ClosedLoop::powered(s.config, s.plant, s.script)?,
    };
    let (mut act, mut inject) = (s.act, s.inject);
    let mut trace = Trace::default();
    trace.records.reserve(s.ticks as usize);
    for _ in 0..s.ticks {
        let r = lp.tick(&mut *act, &mut *inject);
        trace.records.push(r);
    }
    Ok((trace, lp))
}

fn first_visits<T: PartialEq + Copy>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for s in items {
        if !v.contains(&s) {
            v.push(s);
        }
    }
    v
}

/// The homing torque may exceed its limit by this factor: the duty is set from the quasi-static
/// motor model and the winding current overshoots it while the arm decelerates at the stop.
pub const HOMING_TORQUE_MARGIN: f64 = 1.2;

/// The checks every scenario shares: bounded forces and homing torque, no NaN, no
/// wrong-direction drive.
fn common_failures(trace: &Trace, ctx: &Ctx) -> Vec<String> {
    let limit = ctx.limit_n;
    let mut f = Vec::new();
    let homing_limit = f64::from(ctx.base.device.homing.max_torque_nm) * HOMING_TORQUE_MARGIN;
    if trace.max_homing_torque_nm() > homing_limit {
        f.push(format!(
            "homing torque {:.3} N·m > {homing_limit:.3} N·m",
            trace.max_homing_torque_nm()
        ));
    }
    // The rescale to max_force_n rounds in f32: a few ulps above is the limit itself.
    if trace.max_rendered_n() > limit * (1.0 + 1e-6) {
        f.push(format!(
            "rendered {:.3} N > {limit} N",
            trace.max_rendered_n()
        ));
    }
    if trace.max_plant_n() > limit * PLANT_FORCE_MARGIN {
        f.push(format!(
            "motors exert {:.3} N > {:.1} N",
            trace.max_plant_n(),
            limit * PLANT_FORCE_MARGIN
        ));
    }
    if trace.nan_outputs() > 0 {
        f.push(format!("{} NaN outputs", trace.nan_outputs()));
    }
    let wrong = trace.records.last().map_or(0.0, |r| r.wrong_direction_s);
    if wrong > 0.0 {
        f.push(format!("{wrong:.2e} s of wrong-direction drive"));
    }
    f
}

/// A latching fault whose condition first holds at `expect_detect`: flagged then, safe then.
pub fn latch_failures(trace: &Trace, flag: Flags, expect_detect: u64) -> Vec<String> {
    let mut f = Vec::new();
    let before = trace
        .records
        .iter()
        .find(|r| r.k < expect_detect && r.out.flags.intersects(LATCHING));
    if let Some(r) = before {
        f.push(format!("latched {:?} early at tick {}", r.out.flags, r.k));
    }
    match trace.first_flag(flag, 0) {
        Some(k) if k == expect_detect => {}
        other => f.push(format!("{flag:?} at {other:?}, expected {expect_detect}")),
    }
    match trace.safe_from() {
        Some(k) if k <= expect_detect => {}
        other => f.push(format!("safe from {other:?}, expected {expect_detect}")),
    }
    f
}

/// No fault latched over the run.
pub fn no_latch(trace: &Trace) -> Vec<String> {
    match trace.records.iter().find(|r| !r.out.latched.is_empty()) {
        Some(r) => vec![format!(
            "spurious fault {:?} at tick {}",
            r.out.latched, r.k
        )],
        None => Vec::new(),
    }
}

/// Run one scenario and judge it. `Err` only if it could not be set up.
pub fn run_scenario(s: &Scenario, ctx: &Ctx) -> Result<Outcome, FaultsError> {
    let setup = (s.setup)(ctx);
    let ticks = setup.ticks;
    let (trace, lp) = run(setup).map_err(|source| FaultsError::Setup {
        scenario: s.name,
        source,
    })?;
    let mut j = (s.judge)(&trace, &lp, ctx);
    let common = common_failures(&trace, ctx);
    if !common.is_empty() {
        j.detail = if j.survived {
            common.join("; ")
        } else {
            format!("{}; {}", j.detail, common.join("; "))
        };
        j.survived = false;
    }
    Ok(Outcome {
        name: s.name,
        injection: s.injection,
        criterion: s.criterion,
        survived: j.survived,
        detail: j.detail,
        ticks,
        inject_tick: j.inject_tick,
        detect_tick: j.detect_tick,
        safe_tick: trace.safe_from(),
        max_rendered_force_n: trace.max_rendered_n(),
        max_plant_force_n: trace.max_plant_n(),
        max_homing_torque_nm: trace.max_homing_torque_nm(),
        nan_outputs: trace.nan_outputs(),
        wrong_direction_s: trace.records.last().map_or(0.0, |r| r.wrong_direction_s),
        states: first_visits(trace.states().map(|s| s.name())),
        modes: first_visits(trace.records.iter().map(|r| r.out.mode.name())),
    })
}
