//! Independent high-accuracy reference for sphere rolling contact: the paper's §3.1 validation, which
//! integrated the classical rolling equations with `ode45`, on the plane, a sphere, a bowl (the inside
//! of a sphere) and a cylinder.
//!
//! Two independent ways to get the contact paths of a sphere rolling without slipping, driven by sampled
//! orientations with a constant angular velocity between samples:
//! - [`closed_form`]: the exact paths (rotation-vector increments; sphere on plane, on a sphere or in a
//!   bowl; the cylinder has none);
//! - [`montana_paths`]: Montana's contact equations ([`montana`], on the charts of [`surface`]) integrated
//!   by our adaptive Dormand–Prince RK45 ([`rk45`]).
//!
//! [`scene`] builds the paper's input (and the same motion at other sampling rates). [`reference_paths`] is
//! the entry point for the `validate` and `chart` commands.
//!
//! Frames and units: the plane is `z = 0` of the fixed frame with its normal `+z` and the sphere above it;
//! orientation samples map the sphere's body frame to the fixed frame; all lengths in metres.

pub mod closed_form;
mod dopri5;
pub mod limit_surface;
pub mod montana;
pub mod montana_paths;
pub mod motions;
pub mod rk45;
pub mod rolling_ode;
pub mod scene;
pub mod surface;

use nalgebra::{UnitQuaternion, Vector3};

use montana_paths::MontanaOptions;
use rk45::Rk45Error;
use surface::Surface;

/// How the reference paths are computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceMethod {
    /// Exact closed form ([`closed_form`]).
    ClosedForm,
    /// Montana's equations integrated by RK45 with the same `rtol` and `atol` on every state component
    /// (angles in rad, plane coordinates in m), as Matlab's `ode45` with scalar tolerances. Other
    /// integrator settings as [`MontanaOptions::uniform`].
    Rk45 { rtol: f64, atol: f64 },
    /// Montana's equations integrated the way `ode45(f, 0:dt:T, y0)` would: a single adaptive integration
    /// over the whole span, the sample's input looked up by time inside `f`, outputs at the sample times by
    /// the continuous extension, Matlab's controller settings and `MaxStep = T/10`
    /// ([`MontanaOptions::matlab_like_single_call`]). Charts are not re-centred during the call, so long
    /// paths that reach a chart pole fail.
    MatlabOde45 { rtol: f64, atol: f64 },
}

/// The fixed body the sphere rolls on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ground {
    /// The plane `z = 0`; the first contact is at the origin.
    Plane,
    /// A fixed sphere of radius `radius` (m) centred at the origin; the first contact is at its top
    /// `(0, 0, radius)`.
    Sphere { radius: f64 },
    /// The inside of a fixed sphere (a bowl) of radius `radius` (m, larger than the rolling sphere's)
    /// centred at the origin; the first contact is at its bottom `(0, 0, −radius)`, normal `+z`.
    Bowl { radius: f64 },
    /// A fixed cylinder of radius `radius` (m) with its axis along `x` through the origin; the first
    /// contact is at `(0, 0, radius)`, normal `+z`. No closed form: [`ReferenceMethod::ClosedForm`] gives
    /// [`ReferenceError::NoClosedForm`].
    Cylinder { radius: f64 },
}

/// Work counters (all zero for the closed form).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReferenceStats {
    /// Accepted integration steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub f_evals: u64,
    /// Integration intervals (sampling intervals, or their pieces when a sample's rotation is large).
    pub intervals: u64,
    /// Chart re-centrings (including the initial one).
    pub recharts: u64,
}

/// Contact paths, one row per sample (the first row is the initial contact), in metres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReferencePaths {
    /// Contact point on the ground in the fixed frame: `(x, y, 0)` on the plane; on a ground sphere,
    /// bowl or cylinder, a point of that surface (origin at its centre, or on its axis).
    pub plane: Vec<[f64; 3]>,
    /// Contact point on the rolling sphere in the sphere's own frame (origin at its centre).
    pub sphere: Vec<[f64; 3]>,
    /// Work done.
    pub stats: ReferenceStats,
}

/// Why no reference could be computed.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ReferenceError {
    /// Non-positive or non-finite radius or sampling period, or a non-finite sample.
    #[error("non-positive or non-finite radius or sampling period, or a non-finite sample")]
    InvalidInput,
    /// The integrator failed (bad tolerances, or the step size collapsed).
    #[error("integration failed: {0}")]
    Integration(Rk45Error),
    /// [`ReferenceMethod::ClosedForm`] on a ground that has none (the cylinder).
    #[error("no closed form on this ground")]
    NoClosedForm,
}

impl From<Rk45Error> for ReferenceError {
    fn from(e: Rk45Error) -> Self {
        ReferenceError::Integration(e)
    }
}

/// Contact paths of a sphere of radius `radius` (m) rolling on the plane `z = 0`, for orientation samples
/// spaced `dt` (s) with a constant angular velocity between samples.
pub fn reference_paths(
    method: ReferenceMethod,
    samples: &[UnitQuaternion<f64>],
    dt: f64,
    radius: f64,
) -> Result<ReferencePaths, ReferenceError> {
    reference_paths_on(Ground::Plane, method, samples, dt, radius)
}

/// As [`reference_paths`], on any [`Ground`].
pub fn reference_paths_on(
    ground: Ground,
    method: ReferenceMethod,
    samples: &[UnitQuaternion<f64>],
    dt: f64,
    radius: f64,
) -> Result<ReferencePaths, ReferenceError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let ground_ok = match ground {
        Ground::Plane => true,
        Ground::Sphere { radius: big } | Ground::Cylinder { radius: big } => positive(big),
        Ground::Bowl { radius: big } => positive(big) && big > radius,
    };
    let samples_ok = samples
        .iter()
        .all(|q| q.coords.iter().all(|c| c.is_finite()));
    if !(positive(dt) && positive(radius) && ground_ok && samples_ok) {
        return Err(ReferenceError::InvalidInput);
    }
    let span = dt * samples.len().saturating_sub(1) as f64;
    let integration = match method {
        ReferenceMethod::ClosedForm => None,
        ReferenceMethod::Rk45 { rtol, atol } => Some(MontanaOptions::uniform(rtol, atol)),
        ReferenceMethod::MatlabOde45 { rtol, atol } => Some(
            MontanaOptions::matlab_like_single_call(rtol, atol, span.max(dt)),
        ),
    };
    match integration {
        None => {
            let paths = match ground {
                Ground::Plane => closed_form::sphere_on_plane(samples, radius),
                Ground::Sphere { radius: big } => {
                    closed_form::sphere_on_sphere(samples, radius, big, &Vector3::z_axis())
                }
                Ground::Bowl { radius: big } => closed_form::sphere_in_bowl(samples, radius, big),
                Ground::Cylinder { .. } => return Err(ReferenceError::NoClosedForm),
            };
            Ok(ReferencePaths {
                plane: rows(&paths.object),
                sphere: rows(&paths.finger),
                stats: ReferenceStats::default(),
            })
        }
        Some(opts) => {
            let object = match ground {
                Ground::Plane => Surface::Plane,
                Ground::Sphere { radius: big } => {
                    Surface::sphere_centred(big, &Vector3::z_axis(), &Vector3::x())
                }
                Ground::Bowl { radius: big } => {
                    Surface::bowl_centred(big, &-Vector3::z_axis(), &Vector3::x())
                }
                Ground::Cylinder { radius: big } => Surface::Cylinder { radius: big },
            };
            let run = montana_paths::integrate(radius, object, [0.0, 0.0], samples, dt, &opts)?;
            Ok(ReferencePaths::from_run(&run))
        }
    }
}

impl ReferencePaths {
    /// The paths and counters of a Montana integration run.
    pub fn from_run(run: &montana_paths::MontanaRun) -> Self {
        let s = run.stats;
        ReferencePaths {
            plane: rows(&run.paths.object),
            sphere: rows(&run.paths.finger),
            stats: ReferenceStats {
                steps: s.rk.accepted,
                rejected: s.rk.rejected,
                f_evals: s.rk.f_evals,
                intervals: s.rk.intervals,
                recharts: s.recharts,
            },
        }
    }
}

/// Points as `[x, y, z]` rows.
fn rows(v: &[Vector3<f64>]) -> Vec<[f64; 3]> {
    v.iter().map(|p| [p.x, p.y, p.z]).collect()
}

/// Largest absolute difference per axis between two equally long paths (m); the paper reports its
/// validation this way ("0.004 mm, 0.004 mm, 0.001 mm along x, y, z"). Rows beyond the shorter path are
/// ignored.
pub fn max_abs_diff_per_axis(a: &[[f64; 3]], b: &[[f64; 3]]) -> [f64; 3] {
    let mut m = [0.0f64; 3];
    for (p, q) in a.iter().zip(b) {
        for i in 0..3 {
            m[i] = m[i].max((p[i] - q[i]).abs());
        }
    }
    m
}

/// Largest Euclidean distance between corresponding rows (m).
pub fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod curved_tests;
#[cfg(test)]
mod tests;
