//! Adaptive Dormand–Prince 5(4) integrator ("RK45", the method behind Matlab's `ode45`), f64.
//!
//! The state is a fixed-size array `[f64; N]`. One [`Rk45`] value integrates a system over a sequence of
//! intervals `[t_k, t_{k+1}]`, each ending exactly at `t_{k+1}`; the right-hand side is a new closure for every
//! interval, so an input that is constant within each sampling interval (a zero-order hold) is simply captured
//! by that interval's closure. [`Rk45::integrate_dense`] additionally returns the solution at requested
//! times inside one integration (Matlab's `tspan` output) through Matlab's continuous extension.
//!
//! Method (Dormand & Prince 1980; Hairer, Nørsett, Wanner, *Solving ODEs I*, §II.4–II.5):
//! - 7 stages with the First-Same-As-Last property: the last stage of an accepted step is `f(t+h, y+h·Σ b_i k_i)`
//!   and is reused as the first stage of the next step, so an accepted step costs 6 new evaluations. At the
//!   start of every interval the first stage is evaluated afresh, because the input (and so `f`) changes there.
//! - The step is advanced with the 5th-order solution (local extrapolation); the difference to the embedded
//!   4th-order solution is the error estimate `err_i = h·Σ e_j k_{j,i}`.
//! - Error norm (max-norm, like Matlab): `‖err‖ = max_i |err_i| / sc_i`. With [`ErrorScale::Sum`] (default)
//!   `sc_i = atol_i + rtol_i·max(|y_i|, |y_new_i|)`; with [`ErrorScale::MatlabMax`] it is Matlab's
//!   `sc_i = max(atol_i, rtol_i·max(|y_i|, |y_new_i|))` (the two differ by at most a factor of 2).
//! - A step is accepted when `‖err‖ ≤ 1`. The next step is `h·clamp(safety·‖err‖^(-1/5), fac_min, fac_max)`;
//!   right after a rejection the step may not grow (Hairer's rule; Matlab does the same).
//! - The step that would reach within 10 % of the interval end is stretched or shortened to land exactly on
//!   it (Matlab's rule `1.1·h ≥ t_end − t`), so every interval ends exactly at its end time.
//! - The first step of the first interval (and of every interval when [`Options::reuse_step`] is false) is
//!   chosen by Hairer's starting-step algorithm (one extra evaluation of `f`). Otherwise the step proposed at
//!   the end of the previous interval is reused.
//!
//! Counters ([`Stats`]) record accepted and rejected steps and every evaluation of `f`.

use super::dopri5::combine;
pub use super::dopri5::{dopri5_step, integrate_fixed, interpolate, Step};

/// How the per-component error scale combines `atol` and `rtol`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorScale {
    /// `atol + rtol·max(|y|, |y_new|)` (Hairer's form).
    Sum,
    /// `max(atol, rtol·max(|y|, |y_new|))` (Matlab `ode45` with `NormControl` off).
    MatlabMax,
}

/// Integrator settings. Tolerances are per component, in the units of that component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options<const N: usize> {
    /// Relative tolerance per component (dimensionless, > 0).
    pub rtol: [f64; N],
    /// Absolute tolerance per component (units of the component, > 0).
    pub atol: [f64; N],
    /// How `atol` and `rtol` combine into the error scale.
    pub scale: ErrorScale,
    /// Safety factor of the step-size controller (Hairer 0.9, Matlab 0.8).
    pub safety: f64,
    /// Smallest factor by which one step may shrink the next (0.2 here; Matlab 0.1 on a first failure).
    pub fac_min: f64,
    /// Largest factor by which one step may grow the next (5 like Matlab; Hairer uses 10).
    pub fac_max: f64,
    /// Largest step (units of t). Matlab's default is a tenth of the span given to `ode45`.
    pub h_max: f64,
    /// Most step attempts allowed within one call of [`Rk45::integrate`].
    pub max_attempts: u64,
    /// Start each interval with the step proposed at the end of the previous one (true), or run the
    /// starting-step selection afresh on every interval (false, which is what calling `ode45` once per
    /// sampling interval does).
    pub reuse_step: bool,
}

impl<const N: usize> Options<N> {
    /// The same `rtol` and `atol` for every component; other settings at their defaults
    /// (sum scale, safety 0.9, factors 0.2..5, unlimited step, step reused across intervals).
    pub fn uniform(rtol: f64, atol: f64) -> Self {
        Self {
            rtol: [rtol; N],
            atol: [atol; N],
            scale: ErrorScale::Sum,
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 5.0,
            h_max: f64::INFINITY,
            max_attempts: 1_000_000,
            reuse_step: true,
        }
    }
}

/// Work counters, accumulated over all intervals integrated by one [`Rk45`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Evaluations of the right-hand side.
    pub f_evals: u64,
    /// Intervals integrated.
    pub intervals: u64,
}

/// Why an integration stopped.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum Rk45Error {
    /// A tolerance is not finite and positive, or a controller setting is out of range.
    #[error("a tolerance is not finite and positive, or a controller setting is out of range")]
    InvalidOptions,
    /// The interval end is before its start, or a bound is not finite.
    #[error("the interval end is before its start, or a bound is not finite")]
    InvalidInterval,
    /// The right-hand side returned a non-finite value at the start of an interval (time `t`).
    #[error("the right-hand side is not finite at t = {t} s")]
    NonFinite { t: f64 },
    /// The step size fell below the round-off limit at time `t`.
    #[error("the step size {h:e} s fell below the round-off limit at t = {t} s")]
    StepTooSmall { t: f64, h: f64 },
    /// More than `max_attempts` step attempts in one interval; stopped at time `t`.
    #[error("too many step attempts in one interval, stopped at t = {t} s")]
    TooManySteps { t: f64 },
}

/// Adaptive Dormand–Prince integrator carrying its step-size proposal and counters across intervals.
#[derive(Clone, Debug)]
pub struct Rk45<const N: usize> {
    opts: Options<N>,
    stats: Stats,
    h_next: Option<f64>,
}

impl<const N: usize> Rk45<N> {
    /// Checks the options: tolerances finite and > 0, `0 < safety ≤ 1`, `0 < fac_min < 1 < fac_max`,
    /// `h_max > 0`.
    pub fn new(opts: Options<N>) -> Result<Self, Rk45Error> {
        let tol_ok = opts
            .rtol
            .iter()
            .chain(opts.atol.iter())
            .all(|v| v.is_finite() && *v > 0.0);
        let ctl_ok = opts.safety > 0.0
            && opts.safety <= 1.0
            && opts.fac_min > 0.0
            && opts.fac_min < 1.0
            && opts.fac_max > 1.0
            && opts.fac_max.is_finite()
            && opts.h_max > 0.0;
        if tol_ok && ctl_ok {
            Ok(Self {
                opts,
                stats: Stats::default(),
                h_next: None,
            })
        } else {
            Err(Rk45Error::InvalidOptions)
        }
    }

    /// Counters accumulated so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Per-component error scale for states `a` and `b`.
    fn scale(&self, i: usize, a: f64, b: f64) -> f64 {
        let rel = self.opts.rtol[i] * a.abs().max(b.abs());
        match self.opts.scale {
            ErrorScale::Sum => self.opts.atol[i] + rel,
            ErrorScale::MatlabMax => self.opts.atol[i].max(rel),
        }
    }

    /// Max-norm of `v` scaled by the error scale at `(y, y)`.
    fn norm_at(&self, v: &[f64; N], y: &[f64; N]) -> f64 {
        (0..N)
            .map(|i| (v[i] / self.scale(i, y[i], y[i])).abs())
            .fold(0.0, f64::max)
    }

    /// Hairer's starting step (Solving ODEs I, §II.4), with this integrator's norm. One evaluation of `f`.
    ///
    /// The first probe `h0 = 0.01·‖y0‖/‖f0‖` (the step that changes `y` by 1 % of its size) only means
    /// something when `y0` is larger than its own error scale. When every component of `y0` lies within
    /// its tolerance of zero (`‖y0‖ < 1`) the state is zero at the requested accuracy and the probe is
    /// the fixed `1e-6`, as Hairer's code does for `y0 = 0`. (Hairer's test is `‖y0‖ < 1e-5`: then a state
    /// that is zero but for a round-off residue, such as a contact angle of −5.6e-17 rad against
    /// `atol = 1e-14`, gives `‖y0‖ = 5.6e-3`, a probe of ~1e-19 s for `‖f0‖ ~ 1e14`, and a start below
    /// the round-off limit of `t`: `StepTooSmall` before the first step.)
    fn initial_step<F>(
        &mut self,
        f: &mut F,
        t0: f64,
        y0: &[f64; N],
        f0: &[f64; N],
        span: f64,
    ) -> f64
    where
        F: FnMut(f64, &[f64; N]) -> [f64; N],
    {
        let d0 = self.norm_at(y0, y0);
        let d1 = self.norm_at(f0, y0);
        let h0 = if d0 < 1.0 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(span)
        .min(self.opts.h_max);
        let y1 = combine(y0, h0, &[(1.0, f0)]);
        let f1 = f(t0 + h0, &y1);
        self.stats.f_evals += 1;
        let mut diff = [0.0; N];
        for (i, d) in diff.iter_mut().enumerate() {
            *d = f1[i] - f0[i];
        }
        let d2 = self.norm_at(&diff, y0) / h0;
        let dmax = d1.max(d2);
        let h1 = if !dmax.is_finite() {
            h0
        } else if dmax <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dmax).powf(1.0 / 5.0)
        };
        (100.0 * h0).min(h1).min(span).min(self.opts.h_max)
    }

    /// Integrates `y' = f(t, y)` from `t0` to exactly `t1` (`t1 ≥ t0`), overwriting `y` with `y(t1)`.
    /// On error `y` holds the last accepted state.
    pub fn integrate<F>(
        &mut self,
        f: F,
        t0: f64,
        t1: f64,
        y: &mut [f64; N],
    ) -> Result<(), Rk45Error>
    where
        F: FnMut(f64, &[f64; N]) -> [f64; N],
    {
        self.integrate_observed(f, t0, t1, y, |_, _, _, _, _| {})
    }

    /// As [`Rk45::integrate`], and also returns the solution at each of `times` (ascending, within
    /// `[t0, t1]`; others are skipped) in `out`, like Matlab's `ode45` given a `tspan` of more than two
    /// points: a time that coincides with a step end gets that step's solution, any other time the
    /// continuous extension ([`interpolate`]) of the step containing it.
    pub fn integrate_dense<F>(
        &mut self,
        f: F,
        t0: f64,
        t1: f64,
        y: &mut [f64; N],
        times: &[f64],
        out: &mut Vec<[f64; N]>,
    ) -> Result<(), Rk45Error>
    where
        F: FnMut(f64, &[f64; N]) -> [f64; N],
    {
        let mut pending = times
            .iter()
            .copied()
            .filter(|&t| t >= t0 && t <= t1)
            .peekable();
        while pending.next_if(|&t| t == t0).is_some() {
            out.push(*y);
        }
        self.integrate_observed(f, t0, t1, y, |t, t_new, h, y_old, step| {
            while let Some(tau) = pending.next_if(|&tau| tau <= t_new) {
                if tau == t_new {
                    out.push(step.y_new);
                } else {
                    out.push(interpolate(y_old, h, step, (tau - t) / h));
                }
            }
        })
    }

    /// The adaptive loop; `observe(t, t_new, h, y_old, step)` is called after every accepted step from `t`
    /// to `t_new` (`= t + h`, exactly `t1` for the last step).
    fn integrate_observed<F, O>(
        &mut self,
        mut f: F,
        t0: f64,
        t1: f64,
        y: &mut [f64; N],
        mut observe: O,
    ) -> Result<(), Rk45Error>
    where
        F: FnMut(f64, &[f64; N]) -> [f64; N],
        O: FnMut(f64, f64, f64, &[f64; N], &Step<N>),
    {
        if !(t0.is_finite() && t1.is_finite()) || t1 < t0 {
            return Err(Rk45Error::InvalidInterval);
        }
        self.stats.intervals += 1;
        let span = t1 - t0;
        if span == 0.0 {
            return Ok(());
        }
        let mut k1 = f(t0, y);
        self.stats.f_evals += 1;
        if k1.iter().any(|v| !v.is_finite()) {
            return Err(Rk45Error::NonFinite { t: t0 });
        }
        let mut h = match (self.opts.reuse_step, self.h_next) {
            (true, Some(h)) => h.min(self.opts.h_max),
            _ => self.initial_step(&mut f, t0, y, &k1, span),
        };
        let mut t = t0;
        let mut rejected_last = false;
        let mut attempts: u64 = 0;
        loop {
            let remaining = t1 - t;
            let last = 1.1 * h >= remaining;
            if last {
                h = remaining;
            }
            let h_min = 16.0 * f64::EPSILON * t.abs().max(t1.abs()).max(f64::MIN_POSITIVE);
            if h < h_min {
                return Err(Rk45Error::StepTooSmall { t, h });
            }
            attempts += 1;
            if attempts > self.opts.max_attempts {
                return Err(Rk45Error::TooManySteps { t });
            }
            let step = dopri5_step(&mut f, t, y, h, &k1);
            let (y_new, err_vec, k7) = (step.y_new, step.err, step.k[6]);
            self.stats.f_evals += 6;
            let err = (0..N)
                .map(|i| (err_vec[i] / self.scale(i, y[i], y_new[i])).abs())
                .fold(
                    0.0,
                    |a: f64, b| if b.is_nan() { f64::NAN } else { a.max(b) },
                );
            let finite = err.is_finite() && k7.iter().chain(y_new.iter()).all(|v| v.is_finite());
            if finite && err <= 1.0 {
                self.stats.accepted += 1;
                observe(t, if last { t1 } else { t + h }, h, y, &step);
                *y = y_new;
                k1 = k7;
                let mut fac = if err == 0.0 {
                    self.opts.fac_max
                } else {
                    (self.opts.safety * err.powf(-0.2)).clamp(self.opts.fac_min, self.opts.fac_max)
                };
                if rejected_last {
                    fac = fac.min(1.0);
                }
                rejected_last = false;
                let h_prop = (h * fac).min(self.opts.h_max);
                if last {
                    self.h_next = Some(h_prop);
                    return Ok(());
                }
                t += h;
                h = h_prop;
            } else {
                self.stats.rejected += 1;
                let fac = if finite {
                    (self.opts.safety * err.powf(-0.2)).max(self.opts.fac_min)
                } else {
                    self.opts.fac_min
                };
                h *= fac.min(1.0);
                rejected_last = true;
            }
        }
    }
}

#[cfg(test)]
#[path = "rk45_tests.rs"]
mod tests;
