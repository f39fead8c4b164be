//! The ablation: a scene run in closed loop once per contact model choice
//! ([`softfinger_core::contact::parts`]), each run compared tick by tick with the full model's
//! run of the same scene (the same hand script, plant and operator session), and each choice's
//! contact step timed on the host on the full run's own contact inputs.

use crate::experiments::model::yardstick::{
    force_threshold_n, torque_threshold_nm, PATH_THRESHOLD_MM, PERCEPTION_WINDOW_S, TIME_SHIFT_S,
};
use crate::sim::closed_loop::{self, prepare, simulate, SetupError};
use crate::sim::scene::{Scene, SurfaceSpec};
use softfinger_core::contact::params::{ContactParams, ParamError, ParamsChange};
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::surface::Surface;
use softfinger_core::contact::{
    ContactInput, ContactModel, ContactOutput, Full, ModelChoice, Parts,
};
use softfinger_core::control::controller::{ContactStage, Environment};
use softfinger_core::control::pipeline::{Pipeline, PipelineConfig};
use softfinger_core::validate::Checked;
use softfinger_core::{Fast, Math, Quat, Vec3};
use std::marker::PhantomData;
use std::time::Instant;

/// The contact model of parts `P` that keeps the last input it was given (so the run can be
/// replayed on the host for timing). Forwards everything else.
#[derive(Clone, Copy, Debug)]
pub struct Recorded<M: Math, S: Surface, P: Parts> {
    /// The model.
    pub model: ContactModel<M, S, P>,
    /// The contact input of the last step.
    pub last: ContactInput,
}

impl<M: Math, S: Surface, P: Parts> ContactStage for Recorded<M, S, P> {
    fn step(&mut self, input: &ContactInput) -> ContactOutput {
        self.last = *input;
        self.model.contact_step(input)
    }
    fn restart(&mut self) {
        self.model.restart();
    }
    fn set_contact_params(
        &mut self,
        p: &Checked<ContactParams>,
    ) -> Result<ParamsChange, ParamError> {
        self.model.set_contact_params(p)
    }
    fn params(&self) -> &ContactParams {
        self.model.params()
    }
    fn state(&self) -> ContactState {
        self.model.state()
    }
    fn contact_point_m(&self) -> Vec3 {
        ContactStage::contact_point_m(&self.model)
    }
}

/// Surface `S` with the model of parts `P`, recorded.
#[derive(Clone, Copy, Debug)]
pub struct RecordedScene<S: Surface, P: Parts>(pub S, PhantomData<P>);

impl<S: Surface, P: Parts> Environment for RecordedScene<S, P> {
    type Stage<M: Math> = Recorded<M, S, P>;
    fn stage<M: Math>(
        &self,
        contact: ContactParams,
        dt_s: f32,
    ) -> Result<Self::Stage<M>, ParamError> {
        Ok(Recorded {
            model: ContactModel::with_parts(contact, self.0, Quat::IDENTITY, dt_s)?,
            last: ContactInput::default(),
        })
    }
}

/// One tick of a run, from the arming on.
#[derive(Clone, Copy, Debug)]
pub struct Tick {
    /// Contact state after the tick.
    pub state: ContactState,
    /// Rendered force, base frame, N.
    pub force_n: [f64; 3],
    /// Spin torque, N·m.
    pub tau_nm: f64,
    /// Contact point on the object, object frame, m.
    pub object_point_m: [f64; 3],
    /// What the contact step was given this tick.
    pub input: ContactInput,
}

/// A scene run with one model.
#[derive(Clone, Debug)]
pub struct Run {
    /// The model.
    pub choice: ModelChoice,
    /// Every tick.
    pub ticks: Vec<Tick>,
    /// Host time per contact step on the full run's inputs, ns (least of [`TIMING_REPEATS`]
    /// passes).
    pub host_ns_per_step: f64,
}

/// Timed passes over the inputs per choice; the least is kept.
pub const TIMING_REPEATS: usize = 5;

/// Run `scene` in closed loop with the model of parts `P` on `surface` (object frame origin
/// `origin`).
fn run_closed<S: Surface, P: Parts>(
    scene: &Scene,
    contact: ContactParams,
    config: PipelineConfig<S>,
) -> Result<Vec<Tick>, SetupError> {
    let cfg = PipelineConfig {
        device: config.device,
        timing: config.timing,
        contact,
        surface: RecordedScene::<S, P>(config.surface, PhantomData),
        object_origin_m: config.object_origin_m,
        log_rate_hz: config.log_rate_hz,
    };
    let mut pipe: Pipeline<Fast, RecordedScene<S, P>> = Pipeline::new(cfg)?;
    let mut plant = closed_loop::plant(scene, &contact)?;
    prepare(&mut pipe, &mut plant)?;
    let n = (scene.duration_s * scene.rate_hz).round() as u64;
    let mut ticks = Vec::with_capacity(n as usize);
    simulate(
        &mut pipe,
        &mut plant,
        n,
        |_, _| {},
        |_, _, out, pipe, _| {
            let rec = pipe.controller().contact();
            let c = &out.control;
            let p = rec.model.rolling().surface().contact_point();
            ticks.push(Tick {
                state: c.state,
                force_n: c.force_n.to_array().map(f64::from),
                tau_nm: c.tau_n_nm as f64,
                object_point_m: p.to_array().map(f64::from),
                input: rec.last,
            });
        },
    );
    Ok(ticks)
}

/// Host time per contact step of the model of parts `P` on `inputs`, ns (one pass).
fn time_steps<S: Surface, P: Parts>(
    contact: ContactParams,
    surface: S,
    dt_s: f32,
    inputs: &[ContactInput],
) -> Result<f64, ParamError> {
    let mut m = ContactModel::<Fast, S, P>::with_parts(contact, surface, Quat::IDENTITY, dt_s)?;
    let t0 = Instant::now();
    for i in inputs {
        std::hint::black_box(m.contact_step(std::hint::black_box(i)));
    }
    Ok(t0.elapsed().as_nanos() as f64 / inputs.len().max(1) as f64)
}

/// Run one choice on a surface (not yet timed).
fn run_choice<S: Surface, P: Parts>(
    scene: &Scene,
    contact: ContactParams,
    config: PipelineConfig<S>,
    choice: ModelChoice,
) -> Result<Run, SetupError> {
    Ok(Run {
        choice,
        ticks: run_closed::<S, P>(scene, contact, config)?,
        host_ns_per_step: f64::NAN,
    })
}

/// Host time per contact step of `choice` on `inputs`, ns (one timed pass).
fn time_choice<S: Surface>(
    choice: ModelChoice,
    contact: ContactParams,
    surface: S,
    dt_s: f32,
    inputs: &[ContactInput],
) -> Result<f64, ParamError> {
    softfinger_core::with_parts!(choice, P => time_steps::<S, P>(contact, surface, dt_s, inputs))
}

/// The full model's run and the runs of `choices` on one surface (a `Full` among `choices` is
/// that run again). Every choice is then timed on the full run's contact inputs, the choices
/// interleaved over [`TIMING_REPEATS`] rounds (the least time of each is kept), so a load that
/// comes and goes on the host touches them alike.
fn runs_on<S: Surface>(
    scene: &Scene,
    contact: ContactParams,
    config: PipelineConfig<S>,
    choices: &[ModelChoice],
    timed: bool,
) -> Result<(Run, Vec<Run>), SetupError> {
    let mut full = run_choice::<S, Full>(scene, contact, config, ModelChoice::Full)?;
    let mut runs = Vec::new();
    for &c in choices {
        runs.push(if c == ModelChoice::Full {
            full.clone()
        } else {
            softfinger_core::with_parts!(c, P => run_choice::<S, P>(scene, contact, config, c)?)
        });
    }
    let inputs: Vec<ContactInput> = full.ticks.iter().map(|t| t.input).collect();
    let dt_s = 1.0 / scene.rate_hz as f32;
    let in_scene = |source| {
        SetupError::from(crate::sim::closed_loop::ClosedLoopError::Contact {
            scene: scene.name.clone(),
            source,
        })
    };
    for _ in 0..if timed { TIMING_REPEATS } else { 0 } {
        for r in runs.iter_mut().chain(std::iter::once(&mut full)) {
            let ns =
                time_choice(r.choice, contact, config.surface, dt_s, &inputs).map_err(in_scene)?;
            // NaN (not yet timed) gives way to the time.
            r.host_ns_per_step = r.host_ns_per_step.min(ns);
        }
    }
    Ok((full, runs))
}

/// The full model's run of `scene` and the runs of `choices`, in their order; timed on the host
/// when `timed` (otherwise their `host_ns_per_step` is NaN).
pub fn runs(
    scene: &Scene,
    choices: &[ModelChoice],
    timed: bool,
) -> Result<(Run, Vec<Run>), SetupError> {
    let contact = closed_loop::contact_params(scene)?;
    match scene.surface {
        SurfaceSpec::Plane => {
            let cfg = closed_loop::plane_config(scene, contact)?;
            runs_on(scene, contact, cfg, choices, timed)
        }
        SurfaceSpec::Sphere { radius_m } => {
            let cfg = closed_loop::sphere_config(scene, contact, radius_m)?;
            runs_on(scene, contact, cfg, choices, timed)
        }
        SurfaceSpec::Bowl { radius_m } => {
            let cfg = closed_loop::bowl_config(scene, contact, radius_m)?;
            runs_on(scene, contact, cfg, choices, timed)
        }
        SurfaceSpec::Cylinder { radius_m } => {
            let cfg = closed_loop::cylinder_config(scene, contact, radius_m)?;
            runs_on(scene, contact, cfg, choices, timed)
        }
    }
}

/// How a choice's run differs from the full model's.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Difference {
    /// Largest |ΔF| over the ticks, N.
    pub max_force_diff_n: f64,
    /// RMS of |ΔF|, N.
    pub rms_force_diff_n: f64,
    /// Largest |Δτn|, mN·m.
    pub max_torque_diff_mnm: f64,
    /// RMS of Δτn, mN·m.
    pub rms_torque_diff_mnm: f64,
    /// Largest distance between the contact points on the object, mm.
    pub max_path_diff_mm: f64,
    /// Ticks whose contact state differs.
    pub state_diff_ticks: usize,
    /// The same as a percentage of the ticks.
    pub state_diff_percent: f64,
    /// State transitions of this run (the full run's are in its own row).
    pub transitions: usize,
    /// The same states in the same order as the full run (timing left out).
    pub same_state_sequence: bool,
    /// Largest ratio of the averaged force difference to its yardstick (≤ 1: not felt), each
    /// tick matched within ±[`TIME_SHIFT_S`] ([`shifted_ratio`]).
    pub force_ratio: f64,
    /// Largest ratio of the averaged torque difference to its yardstick.
    pub torque_ratio: f64,
    /// Largest ratio of the contact-path difference to its yardstick.
    pub path_ratio: f64,
}

impl Difference {
    /// Not felt on this device: the force and path ratios at most 1, and the torque ratio too
    /// when the device displays the torque ([`crate::experiments::model::yardstick::DEVICE_DISPLAYS_TORQUE`]).
    pub fn within_yardstick(&self) -> bool {
        self.within(crate::experiments::model::yardstick::DEVICE_DISPLAYS_TORQUE)
    }

    /// The force and path ratios at most 1, and the torque ratio too when `torque_displayed`.
    pub fn within(&self, torque_displayed: bool) -> bool {
        self.force_ratio <= 1.0
            && self.path_ratio <= 1.0
            && (!torque_displayed || self.torque_ratio <= 1.0)
    }
}

/// Trailing mean over `n` ticks of `f(tick)`.
fn averaged<const K: usize>(
    ticks: &[Tick],
    n: usize,
    f: impl Fn(&Tick) -> [f64; K],
) -> Vec<[f64; K]> {
    let mut out = Vec::with_capacity(ticks.len());
    let mut sum = [0.0; K];
    for (k, t) in ticks.iter().enumerate() {
        let v = f(t);
        for i in 0..K {
            sum[i] += v[i];
        }
        if k >= n {
            let old = f(&ticks[k - n]);
            for i in 0..K {
                sum[i] -= old[i];
            }
        }
        let m = (k + 1).min(n) as f64;
        out.push(sum.map(|s| s / m));
    }
    out
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Transitions of a run.
pub fn transitions(ticks: &[Tick]) -> usize {
    ticks
        .windows(2)
        .filter(|w| w[0].state != w[1].state)
        .count()
}

/// `run` against `full` (same scene, same number of ticks), at `rate_hz`.
pub fn difference(run: &Run, full: &Run, rate_hz: f64) -> Difference {
    let (a, b) = (&run.ticks, &full.ticks);
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let (mut max_f, mut sum_f2, mut max_t, mut sum_t2, mut max_p) =
        (0.0f64, 0.0, 0.0f64, 0.0, 0.0f64);
    let mut state_diff = 0;
    for (x, y) in a.iter().zip(b) {
        let df = norm(sub(x.force_n, y.force_n));
        let dt = (x.tau_nm - y.tau_nm).abs();
        let dp = norm(sub(x.object_point_m, y.object_point_m));
        max_f = max_f.max(df);
        sum_f2 += df * df;
        max_t = max_t.max(dt);
        sum_t2 += dt * dt;
        max_p = max_p.max(dp);
        state_diff += usize::from(x.state != y.state);
    }
    let w = ((PERCEPTION_WINDOW_S * rate_hz).round() as usize).max(1);
    let shift = (TIME_SHIFT_S * rate_hz).round() as usize;
    let fa = averaged(a, w, |t| t.force_n);
    let fb = averaged(b, w, |t| t.force_n);
    let ta = averaged(a, w, |t| [t.tau_nm]);
    let tb = averaged(b, w, |t| [t.tau_nm]);
    let force_ratio = shifted_ratio(&fa, &fb, shift, |x, y| {
        norm(sub(x, y)) / force_threshold_n(norm(y))
    });
    let torque_ratio = shifted_ratio(&ta, &tb, shift, |x, y| {
        (x[0] - y[0]).abs() / torque_threshold_nm(y[0])
    });
    let pa: Vec<[f64; 3]> = a.iter().map(|t| t.object_point_m).collect();
    let pb: Vec<[f64; 3]> = b.iter().map(|t| t.object_point_m).collect();
    let path_ratio = shifted_ratio(&pa, &pb, shift, |x, y| {
        norm(sub(x, y)) * 1e3 / PATH_THRESHOLD_MM
    });
    let nf = n.max(1) as f64;
    Difference {
        max_force_diff_n: max_f,
        rms_force_diff_n: (sum_f2 / nf).sqrt(),
        max_torque_diff_mnm: max_t * 1e3,
        rms_torque_diff_mnm: (sum_t2 / nf).sqrt() * 1e3,
        max_path_diff_mm: max_p * 1e3,
        state_diff_ticks: state_diff,
        state_diff_percent: 100.0 * state_diff as f64 / nf,
        transitions: transitions(a),
        same_state_sequence: state_sequence(a) == state_sequence(b),
        force_ratio,
        torque_ratio,
        path_ratio,
    }
}

/// The states a run passes through, in order, each once per visit (timing left out).
pub fn state_sequence(ticks: &[Tick]) -> Vec<ContactState> {
    let mut s: Vec<ContactState> = Vec::new();
    for t in ticks {
        if s.last() != Some(&t.state) {
            s.push(t.state);
        }
    }
    s
}

/// The largest over the ticks of `ratio` between a tick of one run and the closest (least
/// `ratio`) tick of the other within ±`shift` ticks, taken both ways (`ratio(x, y)`: `x` from
/// `a`, `y` the full run's `b`, whose value sets the threshold).
pub fn shifted_ratio<T: Copy>(a: &[T], b: &[T], shift: usize, ratio: impl Fn(T, T) -> f64) -> f64 {
    let n = a.len().min(b.len());
    let mut worst = 0.0f64;
    for k in 0..n {
        let (lo, hi) = (k.saturating_sub(shift), (k + shift + 1).min(n));
        let ab = (lo..hi)
            .map(|j| ratio(a[k], b[j]))
            .fold(f64::INFINITY, f64::min);
        let ba = (lo..hi)
            .map(|j| ratio(a[j], b[k]))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(ab).max(ba);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step of 1 N that one run takes `lag` ticks after the other: within ±`shift` ticks it is
    /// the same step (ratio 0); one tick beyond, the step's size shows (ratio 1 for a threshold of
    /// 1 N).
    #[test]
    fn a_shift_within_the_window_is_no_difference_and_one_beyond_is() {
        let step =
            |lag: usize| -> Vec<f64> { (0..100).map(|k| f64::from(k >= 50 + lag)).collect() };
        let ratio = |x: f64, y: f64| (x - y).abs();
        assert_eq!(shifted_ratio(&step(5), &step(0), 5, ratio), 0.0);
        assert_eq!(shifted_ratio(&step(0), &step(5), 5, ratio), 0.0);
        assert_eq!(shifted_ratio(&step(6), &step(0), 5, ratio), 1.0);
        assert_eq!(shifted_ratio(&step(0), &step(6), 5, ratio), 1.0);
        // No shift allowed: the tick-by-tick difference.
        assert_eq!(shifted_ratio(&step(1), &step(0), 0, ratio), 1.0);
        // A difference in size is not hidden by any shift.
        let half: Vec<f64> = step(0).iter().map(|v| v * 0.5).collect();
        assert_eq!(shifted_ratio(&half, &step(0), 50, ratio), 0.5);
    }
}
