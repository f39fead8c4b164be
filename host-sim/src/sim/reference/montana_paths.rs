//! Contact paths by integrating Montana's equations ([`super::montana`]) with the adaptive RK45
//! ([`super::rk45`]) over a sequence of orientation samples, the classical way the paper's §3.1 computed its
//! reference with `ode45`.
//!
//! The angular velocity is constant within each sampling interval (zero-order hold, see [`super::scene`]).
//! By default ([`Schedule::RestartEachSample`]) the integrator restarts at each sample time and lands
//! exactly on the next; [`Schedule::SingleCall`] instead emulates one `ode45` call over the whole span with
//! output at the sample times. The orientation itself is never integrated: it is encoded by the contact
//! coordinates `(α_f, α_o, ψ)`.
//!
//! Chart singularities: the sphere charts are singular at their poles. Before the first interval both
//! sphere charts are centred on the contact with the contact moving along the chart's equator
//! ([`Contact::rechart`]). With [`Schedule::RestartEachSample`], at a sample time or between equal
//! sub-intervals of a sampling interval, the charts are re-centred again whenever the contact's latitude
//! exceeds [`MontanaOptions::rechart_latitude`].
//! A sampling interval whose rotation exceeds [`MontanaOptions::max_travel`] is split into equal
//! sub-intervals (same constant input, so the split does not change the solution); the contact travels at
//! most `|ω|·dt` on either sphere per interval, so the latitude stays below `rechart_latitude + max_travel`.

use nalgebra::{Rotation3, UnitQuaternion};

use super::closed_form::ContactPaths;
use super::montana::{AngularVelocity, Contact, State};
use super::rk45::{ErrorScale, Options, Rk45, Rk45Error, Stats};
use super::scene::{body_increments, object_increments};
use super::surface::Surface;

/// Which form of the per-interval angular velocity drives the equations (both are exact; they differ in how
/// the input enters `ω` in the contact frame: through `α_f` or through `α_o` and `ψ`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputFrame {
    /// `ω_b = log(q_k⁻¹ q_{k+1})/dt` in the finger's body frame (constant over the interval).
    FingerBody,
    /// `ω_O = log(q_{k+1} q_k⁻¹)/dt` in the object frame (constant over the interval).
    Object,
}

/// Settings of a Montana integration run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MontanaOptions {
    /// Integrator settings for the state `[α_f1, α_f2, α_o1, α_o2, ψ]` (rad for angles, m for plane
    /// coordinates).
    pub rk: Options<5>,
    /// Frame of the input angular velocity.
    pub input: InputFrame,
    /// Largest rotation (rad) integrated without a chance to re-chart.
    pub max_travel: f64,
    /// Latitude (rad) beyond which the sphere charts are re-centred.
    pub rechart_latitude: f64,
    /// How the integration is split over the samples.
    pub schedule: Schedule,
}

/// How the integrator meets the sample times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Schedule {
    /// Restart at every sample time and land exactly on the next (the input is constant within each
    /// integration, so the solver never steps across a change of input). Charts are re-centred as needed.
    RestartEachSample,
    /// One integration over the whole span, the input looked up by time inside `f`, outputs at the sample
    /// times by the continuous extension: what `ode45(f, 0:dt:T, y0)` does. Steps may straddle sample
    /// times (input changes). The charts are centred once at the start and never re-centred, so a path
    /// reaching a chart pole (latitude ±π/2) fails or loses accuracy; `max_travel` and
    /// `rechart_latitude` are not used.
    SingleCall,
}

impl MontanaOptions {
    /// Uniform `rtol`, `atol` on all components, body-frame input, `max_travel` 0.25 rad,
    /// `rechart_latitude` 0.5 rad (so `cos(latitude) ≥ cos 0.75 ≈ 0.73`: the metric stays well conditioned).
    pub fn uniform(rtol: f64, atol: f64) -> Self {
        Self {
            rk: Options::uniform(rtol, atol),
            input: InputFrame::FingerBody,
            max_travel: 0.25,
            rechart_latitude: 0.5,
            schedule: Schedule::RestartEachSample,
        }
    }

    /// Closer to calling Matlab's `ode45(f, [t_k, t_k + dt], y_k)` once per sampling interval with scalar
    /// `RelTol = rtol`, `AbsTol = atol`: Matlab's error scale `max(atol, rtol·|y|)`, safety 0.8, shrink
    /// factor ≥ 0.1, growth ≤ 5, `MaxStep = dt/10` (its default, a tenth of the span), a fresh starting step
    /// on every interval. Still different from Matlab: the starting step is Hairer's (Matlab uses its own
    /// one-evaluation estimate) and repeated rejections shrink by the controller rather than halving.
    pub fn matlab_like_per_interval(rtol: f64, atol: f64, dt: f64) -> Self {
        let mut o = Self::uniform(rtol, atol);
        o.rk.scale = ErrorScale::MatlabMax;
        o.rk.safety = 0.8;
        o.rk.fac_min = 0.1;
        o.rk.fac_max = 5.0;
        o.rk.h_max = dt / 10.0;
        o.rk.reuse_step = false;
        o
    }

    /// Closer to Matlab's `ode45(f, 0:dt:T, y0)` with scalar `RelTol = rtol`, `AbsTol = atol`, over a span
    /// of `span` seconds: [`Schedule::SingleCall`], Matlab's error scale, safety 0.8, shrink factor ≥ 0.1,
    /// growth ≤ 5, `MaxStep = span/10`. Same remaining differences as
    /// [`MontanaOptions::matlab_like_per_interval`].
    pub fn matlab_like_single_call(rtol: f64, atol: f64, span: f64) -> Self {
        let mut o = Self::matlab_like_per_interval(rtol, atol, span);
        o.schedule = Schedule::SingleCall;
        o
    }
}

/// Work done by a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MontanaStats {
    /// Integrator counters (`intervals` counts sub-intervals).
    pub rk: Stats,
    /// Chart re-centrings, including the initial one.
    pub recharts: u64,
}

/// Result of a run: the paths and the orientation encoded by the contact coordinates at each sample.
#[derive(Clone, Debug, PartialEq)]
pub struct MontanaRun {
    /// Contact points, one per sample.
    pub paths: ContactPaths,
    /// `R = C_o R_ψ3 C_fᵀ` at each sample (finger body → object frame).
    pub orientations: Vec<Rotation3<f64>>,
    /// Work counters.
    pub stats: MontanaStats,
}

/// Integrates the rolling of a finger sphere of radius `finger_radius` (m) on `object`, starting at the
/// object's chart point `alpha_o0` with orientation `samples[0]`, through all `samples` spaced `dt` (s).
pub fn integrate(
    finger_radius: f64,
    object: Surface,
    alpha_o0: [f64; 2],
    samples: &[UnitQuaternion<f64>],
    dt: f64,
    opts: &MontanaOptions,
) -> Result<MontanaRun, Rk45Error> {
    let mut rk = Rk45::new(opts.rk)?;
    let mut out = MontanaRun {
        paths: ContactPaths::default(),
        orientations: Vec::with_capacity(samples.len()),
        stats: MontanaStats::default(),
    };
    let Some(q0) = samples.first() else {
        return Ok(out);
    };
    let (mut contact, mut s) =
        Contact::start(finger_radius, object, alpha_o0, &q0.to_rotation_matrix());
    let inputs: Vec<AngularVelocity> = match opts.input {
        InputFrame::FingerBody => body_increments(samples)
            .iter()
            .map(|inc| AngularVelocity::FingerBody(inc / dt))
            .collect(),
        InputFrame::Object => object_increments(samples)
            .iter()
            .map(|inc| AngularVelocity::Object(inc / dt))
            .collect(),
    };
    let Some(first_input) = inputs.first() else {
        out.record(&contact, &s);
        return Ok(out);
    };
    contact.rechart(&mut s, first_input);
    out.stats.recharts += 1;
    match opts.schedule {
        Schedule::RestartEachSample => {
            out.record(&contact, &s);
            for (k, w) in inputs.iter().enumerate() {
                let t_start = k as f64 * dt;
                let t_end = (k + 1) as f64 * dt;
                let rotation = match w {
                    AngularVelocity::FingerBody(v) | AngularVelocity::Object(v) => v.norm() * dt,
                };
                let pieces = (rotation / opts.max_travel).ceil().max(1.0) as usize;
                for j in 0..pieces {
                    if contact.pole_proximity(&s) > opts.rechart_latitude {
                        contact.rechart(&mut s, w);
                        out.stats.recharts += 1;
                    }
                    let ta = t_start + (t_end - t_start) * (j as f64 / pieces as f64);
                    let tb = if j + 1 == pieces {
                        t_end
                    } else {
                        t_start + (t_end - t_start) * ((j + 1) as f64 / pieces as f64)
                    };
                    let c = contact;
                    rk.integrate(
                        |_t, y: &State| c.rates(y, &c.omega_contact(y, w)),
                        ta,
                        tb,
                        &mut s,
                    )?;
                }
                out.record(&contact, &s);
            }
        }
        Schedule::SingleCall => {
            let times: Vec<f64> = (0..samples.len()).map(|k| k as f64 * dt).collect();
            let t_end = (samples.len() - 1) as f64 * dt;
            let last = inputs.len() - 1;
            let c = contact;
            let mut states = Vec::with_capacity(samples.len());
            rk.integrate_dense(
                |t, y: &State| {
                    // The sample interval containing t (right-continuous), as a lookup in `f` would do.
                    let k = ((t / dt).floor().max(0.0) as usize).min(last);
                    c.rates(y, &c.omega_contact(y, &inputs[k]))
                },
                0.0,
                t_end,
                &mut s,
                &times,
                &mut states,
            )?;
            for st in &states {
                out.record(&contact, st);
            }
        }
    }
    out.stats.rk = rk.stats();
    Ok(out)
}

impl MontanaRun {
    fn record(&mut self, c: &Contact, s: &State) {
        self.paths.object.push(c.object_point(s));
        self.paths.finger.push(c.finger_point(s));
        self.orientations.push(c.orientation(s));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::reference::closed_form;
    use crate::sim::reference::scene::{paper_scene, rotation_vector};
    use nalgebra::{Unit, Vector3};

    fn max_dist(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
        assert_eq!(a.len(), b.len());
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).norm())
            .fold(0.0, f64::max)
    }

    #[test]
    fn encoded_orientation_follows_the_samples() {
        // The orientation is never integrated directly; at tight tolerance the one encoded by (α_f, α_o, ψ)
        // must match every sample. rtol 1e-12 on O(1) angles: global angle error ~1e-11 rad over
        // 100 intervals (as in the RK45 tests, err ≲ 10·tol per unit of accumulated motion); measured
        // 2.19e-13 rad at worst over the 101 samples; bound 3×: 6.6e-13 rad.
        let s = paper_scene();
        let run = integrate(
            s.radius,
            Surface::Plane,
            [0.0, 0.0],
            &s.samples,
            s.dt,
            &MontanaOptions::uniform(1e-12, 1e-14),
        )
        .unwrap();
        assert_eq!(run.orientations.len(), 101);
        for (r, q) in run.orientations.iter().zip(&s.samples) {
            let diff = rotation_vector(&UnitQuaternion::from_rotation_matrix(
                &(r.inverse() * q.to_rotation_matrix()),
            ));
            assert!(diff.norm() < 6.6e-13, "{}", diff.norm());
        }
    }

    #[test]
    fn body_and_object_inputs_give_the_same_paths() {
        // Two exact formulations of the same input; both integrated at rtol 1e-12 with lengths of 1e-2 m:
        // each is within ~1e-14 m of the truth (see the cross-check in `reference`). Measured 6.3e-15 m
        // apart on the plane, 2.1e-15 m on the sphere; bounds 3×.
        let s = paper_scene();
        let run = |input| {
            let mut o = MontanaOptions::uniform(1e-12, 1e-14);
            o.input = input;
            integrate(s.radius, Surface::Plane, [0.0, 0.0], &s.samples, s.dt, &o).unwrap()
        };
        let (a, b) = (run(InputFrame::FingerBody), run(InputFrame::Object));
        assert!(max_dist(&a.paths.object, &b.paths.object) < 1.9e-14);
        assert!(max_dist(&a.paths.finger, &b.paths.finger) < 6.3e-15);
    }

    /// A 10 mm fingertip on the plane through `samples` (10 ms apart) at rtol 1e-12: the run and its
    /// largest distances (m) from the closed form, object and fingertip points.
    fn tight_on_plane(samples: &[UnitQuaternion<f64>]) -> (MontanaRun, f64, f64) {
        let opts = MontanaOptions::uniform(1e-12, 1e-14);
        let run = integrate(0.01, Surface::Plane, [0.0, 0.0], samples, 0.01, &opts).unwrap();
        let exact = closed_form::sphere_on_plane(samples, 0.01);
        let object = max_dist(&run.paths.object, &exact.object);
        let finger = max_dist(&run.paths.finger, &exact.finger);
        (run, object, finger)
    }

    #[test]
    fn long_path_needs_recharts_and_stays_exact() {
        // 10 s of the paper's motion (1000 intervals, ~60 rad of rotation): the contact circles the sphere,
        // so the charts must be re-centred many times; the paths must still match the closed form. Error
        // grows with the path (~10× the 1 s case; measured 5.2e-13 m plane, 2.2e-14 m sphere); bounds
        // 3×: 1.6e-12 m and 6.5e-14 m.
        let rate = crate::sim::reference::scene::paper_body_rate();
        let samples = crate::sim::reference::scene::constant_body_rate_samples(
            &UnitQuaternion::identity(),
            &rate,
            100.0,
            10.0,
        );
        let (run, object, finger) = tight_on_plane(&samples);
        assert!(run.stats.recharts > 5, "{:?}", run.stats);
        assert!(
            object < 1.6e-12 && finger < 6.5e-14,
            "{object:e} {finger:e}"
        );
    }

    #[test]
    fn big_rotations_per_sample_are_split() {
        // 1 rad per sample about a tilted axis: intervals are split into ≥ 4 pieces and the result is still
        // the closed form (rtol 1e-12; measured 2.3e-14 m plane, 1.2e-15 m sphere; bounds 3×: 6.8e-14 m
        // and 3.7e-15 m).
        let axis = Unit::new_normalize(Vector3::new(1.0, 0.5, 0.3));
        let samples: Vec<_> = (0..=12)
            .map(|k| UnitQuaternion::from_axis_angle(&axis, k as f64))
            .collect();
        let (run, object, finger) = tight_on_plane(&samples);
        assert!(run.stats.rk.intervals >= 4 * 12);
        assert!(
            object < 6.8e-14 && finger < 3.7e-15,
            "{object:e} {finger:e}"
        );
    }

    #[test]
    fn sphere_on_sphere_matches_closed_form() {
        // Fingertip (10 mm) on a 50 mm sphere, starting on top; the paper's motion. rtol 1e-12: measured
        // 1.57e-15 m on the object sphere, 5.3e-16 m on the fingertip; bounds 3×: 4.7e-15 m, 1.6e-15 m.
        let s = paper_scene();
        let big = 0.05;
        let object = Surface::sphere_centred(big, &Vector3::z_axis(), &Vector3::x());
        let run = integrate(
            s.radius,
            object,
            [0.0, 0.0],
            &s.samples,
            s.dt,
            &MontanaOptions::uniform(1e-12, 1e-14),
        )
        .unwrap();
        let exact = closed_form::sphere_on_sphere(&s.samples, s.radius, big, &Vector3::z_axis());
        assert!(max_dist(&run.paths.object, &exact.object) < 4.7e-15);
        assert!(max_dist(&run.paths.finger, &exact.finger) < 1.6e-15);
    }

    #[test]
    fn single_call_emulation() {
        // One `ode45`-like call over [0, 1] s with output at the 101 sample times. At rtol 1e-12 the steps
        // are short (~5 per sample) and the 4th-order interpolant is as accurate as the steps (measured
        // 5.7e-15 m plane, 7.2e-15 m sphere). At Matlab's defaults (rtol 1e-3, atol 1e-6) a step may span
        // ~7 samples (~0.4 rad of rotation) and the angle states (|y| ~ 1 rad) may carry ~1e-3 rad of
        // local error, i.e. ~1e-5 m on a 1e-2 m sphere per step; 15 steps (measured 5.45e-5 m plane,
        // 3.12e-5 m sphere). The global error scales with the tolerance: at rtol 1e-6, measured 1.01e-8 m
        // plane, 1.04e-8 m sphere. Every bound is 3× its own measurement. The error must shrink as the
        // tolerance shrinks.
        let s = paper_scene();
        let exact = closed_form::sphere_on_plane(&s.samples, s.radius);
        let mut prev = f64::INFINITY;
        for (rtol, atol, bound_plane, bound_sphere) in [
            (1e-3, 1e-6, 1.6e-4, 9.3e-5),
            (1e-6, 1e-9, 3.0e-8, 3.1e-8),
            (1e-12, 1e-14, 1.7e-14, 2.1e-14),
        ] {
            let o = MontanaOptions::matlab_like_single_call(rtol, atol, 1.0);
            let run =
                integrate(s.radius, Surface::Plane, [0.0, 0.0], &s.samples, s.dt, &o).unwrap();
            assert_eq!(run.paths.object.len(), 101);
            assert_eq!(run.stats.rk.intervals, 1);
            let dp = max_dist(&run.paths.object, &exact.object);
            let ds = max_dist(&run.paths.finger, &exact.finger);
            eprintln!(
                "single call rtol {rtol:e} atol {atol:e}: plane {:.3e} mm, sphere {:.3e} mm, {:?}",
                dp * 1e3,
                ds * 1e3,
                run.stats
            );
            assert!(
                dp < bound_plane && ds < bound_sphere,
                "rtol {rtol}: {dp} {ds}"
            );
            assert!(dp.max(ds) < prev);
            prev = dp.max(ds);
        }
    }

    #[test]
    fn empty_and_single_sample() {
        let o = MontanaOptions::uniform(1e-6, 1e-9);
        let run = integrate(0.01, Surface::Plane, [0.0, 0.0], &[], 0.01, &o).unwrap();
        assert!(run.paths.object.is_empty());
        let q = UnitQuaternion::from_scaled_axis(Vector3::new(0.1, 0.2, 0.3));
        let run = integrate(0.01, Surface::Plane, [0.0, 0.0], &[q], 0.01, &o).unwrap();
        assert_eq!(run.paths.object, vec![Vector3::zeros()]);
        // Measured 3.1e-19 m (round-off of the one rotation, below an ulp of 0.01 m); bound 3×.
        assert!((run.paths.finger[0] - q.inverse() * Vector3::new(0.0, 0.0, -0.01)).norm() < 1e-18);
    }
}
