//! The classical method: Montana's rolling equations integrated in f64 by our adaptive Dormand–Prince
//! RK45 ([`crate::sim::reference`]), the way the paper's §3.1 used Matlab's `ode45`; its accuracy against the
//! closed form and its time per sample.
//!
//! Three ways of calling the integrator (all with the same RK45 and equations):
//! - [`Rk45Call::Restart`]: restart at every sample and land on the next; no step limit
//!   ([`ReferenceMethod::Rk45`]). On the paper scene one step spans a whole 10 ms sample.
//! - [`Rk45Call::PerSampleCall`]: emulates `ode45(f, [t_k, t_k + dt], y_k)` once per sample: Matlab's
//!   controller and its default `MaxStep = dt/10`, so at least 10 steps per sample
//!   ([`MontanaOptions::matlab_like_per_interval`]).
//! - [`Rk45Call::SingleCall`]: emulates one `ode45(f, 0:dt:T, y0)` over the whole second, outputs at the
//!   samples by the continuous extension ([`ReferenceMethod::MatlabOde45`]).

use nalgebra::UnitQuaternion;

use super::errors::PathErrors;
use super::timing::Case;
use super::ValidateError;
use crate::sim::reference::montana_paths::{self, MontanaOptions};
use crate::sim::reference::surface::Surface;
use crate::sim::reference::{reference_paths, ReferenceError, ReferenceMethod, ReferencePaths};

/// Matlab's `ode45` default tolerances (`RelTol`, `AbsTol`), which the paper used.
pub const ODE45_DEFAULTS: (f64, f64) = (1e-3, 1e-6);
/// Tolerances of the reference the validation compares against (`rtol`, `atol`): the reference module's
/// tests show it within 1e-12 m of the closed form on the paper scene.
pub const REFERENCE_TOLERANCES: (f64, f64) = (1e-12, 1e-14);
/// `atol / rtol` used when sweeping `rtol` (Matlab's default pair has this ratio).
pub const ATOL_PER_RTOL: f64 = 1e-3;

/// How the RK45 integration is called over the samples (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rk45Call {
    /// Restart at each sample, no step limit.
    Restart,
    /// One `ode45`-like call per sample (`MaxStep = dt/10`).
    PerSampleCall,
    /// One `ode45`-like call over the whole span.
    SingleCall,
}

impl Rk45Call {
    /// Short name used in row names: `restart`, `per-sample-call`, `single-call`.
    pub const fn name(self) -> &'static str {
        match self {
            Rk45Call::Restart => "restart",
            Rk45Call::PerSampleCall => "per-sample-call",
            Rk45Call::SingleCall => "single-call",
        }
    }

    /// One sentence for the human report.
    pub const fn describe(self) -> &'static str {
        match self {
            Rk45Call::Restart => "RK45 restarted at every sample, no step limit",
            Rk45Call::PerSampleCall => "ode45(f, [t_k, t_k+dt], y_k) per sample, MaxStep = dt/10",
            Rk45Call::SingleCall => "one ode45(f, 0:dt:T, y0) call, output by interpolation",
        }
    }

    /// The contact paths of a sphere of radius `radius` (m) rolling on the plane through `samples`
    /// spaced `dt` (s).
    pub fn paths(
        self,
        samples: &[UnitQuaternion<f64>],
        dt: f64,
        radius: f64,
        rtol: f64,
        atol: f64,
    ) -> Result<ReferencePaths, ValidateError> {
        let fail = |e: ReferenceError| ValidateError::Rk45 {
            call: self.name(),
            rtol,
            atol,
            source: e,
        };
        match self {
            Rk45Call::Restart => {
                reference_paths(ReferenceMethod::Rk45 { rtol, atol }, samples, dt, radius)
                    .map_err(fail)
            }
            Rk45Call::SingleCall => reference_paths(
                ReferenceMethod::MatlabOde45 { rtol, atol },
                samples,
                dt,
                radius,
            )
            .map_err(fail),
            Rk45Call::PerSampleCall => montana_paths::integrate(
                radius,
                Surface::Plane,
                [0.0, 0.0],
                samples,
                dt,
                &MontanaOptions::matlab_like_per_interval(rtol, atol, dt),
            )
            .map(|run| ReferencePaths::from_run(&run))
            .map_err(|e| fail(e.into())),
        }
    }
}

/// One classical run: its settings, its error against the closed form, its time.
#[derive(Clone, Debug, PartialEq)]
pub struct Rk45Run {
    /// How the integrator was called.
    pub call: Rk45Call,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance (rad for angles, m for plane coordinates).
    pub atol: f64,
    /// Error against the closed form.
    pub errors: PathErrors,
    /// Median wall-clock time per sample (ns): a whole integration over the scene divided by its number
    /// of sampling intervals. `None` when not timed.
    pub ns_per_step: Option<f64>,
    /// Work counters of the run.
    pub stats: crate::sim::reference::ReferenceStats,
}

/// A scene as the classical runs need it.
#[derive(Clone, Copy, Debug)]
pub struct SceneRef<'a> {
    /// Orientation samples.
    pub samples: &'a [UnitQuaternion<f64>],
    /// Sampling period, s.
    pub dt: f64,
    /// Sphere radius, m.
    pub radius: f64,
    /// The closed-form paths of this scene.
    pub closed: &'a ReferencePaths,
}

/// Runs `call` at (`rtol`, `atol`) on `scene` and measures its error against the closed form (not yet
/// timed).
pub fn run(
    scene: SceneRef<'_>,
    call: Rk45Call,
    rtol: f64,
    atol: f64,
) -> Result<Rk45Run, ValidateError> {
    let paths = call.paths(scene.samples, scene.dt, scene.radius, rtol, atol)?;
    let errors = PathErrors::between(
        &paths.plane,
        &paths.sphere,
        &scene.closed.plane,
        &scene.closed.sphere,
    );
    Ok(Rk45Run {
        call,
        rtol,
        atol,
        errors,
        ns_per_step: None,
        stats: paths.stats,
    })
}

impl Rk45Run {
    /// A timing case: the whole integration over `scene`, per sampling interval.
    pub fn case<'a>(&self, scene: SceneRef<'a>) -> Case<'a> {
        let (call, rtol, atol) = (self.call, self.rtol, self.atol);
        Case::new(scene.samples.len().saturating_sub(1), move || {
            call.paths(scene.samples, scene.dt, scene.radius, rtol, atol)
        })
    }
}

/// The `rtol` values tried by [`matched`], loosest first: 1e-3 down to 1e-12 in half decades.
pub fn rtol_ladder() -> impl Iterator<Item = f64> {
    (0..=18).map(|k| 1e-3 * 10f64.powf(-0.5 * k as f64))
}

/// The loosest `rtol` of [`rtol_ladder`] (with `atol = rtol·ATOL_PER_RTOL`) at which `call`'s error
/// against the closed form is at most `target_mm` (not yet timed); `Ok(None)` if even the tightest misses.
pub fn matched(
    scene: SceneRef<'_>,
    call: Rk45Call,
    target_mm: f64,
) -> Result<Option<Rk45Run>, ValidateError> {
    for rtol in rtol_ladder() {
        let r = run(scene, call, rtol, rtol * ATOL_PER_RTOL)?;
        if r.errors.max_mm() <= target_mm {
            return Ok(Some(r));
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ladder_runs_from_ode45_defaults_to_the_reference_tolerance() {
        let l: Vec<f64> = rtol_ladder().collect();
        assert_eq!(l.len(), 19);
        assert_eq!(l[0], ODE45_DEFAULTS.0);
        // Measured 1 ulp off (2.2e-16, the ladder's powers of ten); bound 4 ulp.
        assert!((l[18] / REFERENCE_TOLERANCES.0 - 1.0).abs() <= 4.0 * f64::EPSILON);
        assert!(l.windows(2).all(|w| w[1] < w[0]));
        // Matlab's default pair keeps the sweep's atol/rtol ratio.
        assert_eq!(ODE45_DEFAULTS.1, ODE45_DEFAULTS.0 * ATOL_PER_RTOL);
    }
}
