//! `softfinger.replay`: recorded fingertip orientations through the core's rolling model, the
//! computation of `host-sim replay` (conventions in its module doc, `host-sim/src/experiments/replay.rs`)
//! on arrays instead of CSV files, with the core alone (libm backend, f32). The tests compare
//! the two on the same input value for value.

use crate::arrays::Columns;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::spin::{torsion_limit, SpinSpring};
use softfinger_core::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::{Flags, Libm, Quat};

/// Largest accepted |‖q‖ − 1| (as `host-sim replay`).
const NORM_TOLERANCE: f64 = 1e-3;

/// One output row.
struct Row {
    t_s: f64,
    object: [f32; 3],
    finger: [f32; 3],
    spin_rad: f32,
    tau_n_nm: f32,
    state: &'static str,
}

fn state_name(flags: Flags) -> &'static str {
    if flags.contains(Flags::SINGULAR) {
        "singular"
    } else if flags.contains(Flags::GIMBAL_LOCK) {
        "gimbal-lock"
    } else {
        "rolling"
    }
}

fn run<S: Surface>(
    surface: S,
    t_s: &[f64],
    q: &[[f64; 4]],
    method: Method,
    radius_m: f32,
    normal_force_n: f32,
) -> Vec<Row> {
    let params = ContactParams::DEFAULT;
    let tau_max = torsion_limit(params.mu_s, normal_force_n, params.patch_radius_m);
    let to_q = |q: &[f64; 4]| Quat::new(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32);
    let mut rolling = Rolling::new(surface, radius_m, to_q(&q[0]), method);
    let mut spin = SpinSpring::default();
    let mut rows = Vec::with_capacity(q.len());
    let row = |t_s, r: &Rolling<S>, spin: &SpinSpring, tau_n_nm, state| {
        let p = r.surface().contact_point();
        let f = r.finger_point();
        Row {
            t_s,
            object: [p.x, p.y, p.z],
            finger: [f.x, f.y, f.z],
            spin_rad: spin.accumulated_rad,
            tau_n_nm,
            state,
        }
    };
    rows.push(row(t_s[0], &rolling, &spin, 0.0, "rolling"));
    for (t, qk) in t_s.iter().zip(q).skip(1) {
        let step = rolling.step::<Libm>(to_q(qk));
        let (tau, _) = spin.update(step.angles.phi, params.spin_stiffness, tau_max);
        rows.push(row(*t, &rolling, &spin, tau, state_name(step.flags)));
    }
    rows
}

fn bad(msg: String) -> PyErr {
    PyValueError::new_err(msg)
}

/// Check the samples as `host-sim replay` checks its input; quaternions normalised.
fn checked(t_s: &[f64], quats: &[Vec<f64>]) -> PyResult<Vec<[f64; 4]>> {
    if t_s.is_empty() {
        return Err(bad("t_s is empty (at least one sample is needed)".into()));
    }
    if quats.len() != t_s.len() {
        return Err(bad(format!(
            "quats has {} rows, t_s {} (one quaternion per time)",
            quats.len(),
            t_s.len()
        )));
    }
    let mut out = Vec::with_capacity(quats.len());
    let mut prev = f64::NEG_INFINITY;
    for (i, (t, q)) in t_s.iter().zip(quats).enumerate() {
        if !t.is_finite() {
            return Err(bad(format!("t_s[{i}] is not finite: {t}")));
        }
        if *t < prev {
            return Err(bad(format!("t_s[{i}] = {t} goes back (after {prev})")));
        }
        prev = *t;
        let q: [f64; 4] = q.as_slice().try_into().map_err(|_| {
            bad(format!(
                "quats[{i}] has {} components, expected 4 (w, x, y, z)",
                q.len()
            ))
        })?;
        if q.iter().any(|c| !c.is_finite()) {
            return Err(bad(format!("quats[{i}] is not finite: {q:?}")));
        }
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        if norm == 0.0 {
            return Err(bad(format!("quats[{i}] is zero")));
        }
        if (norm - 1.0).abs() > NORM_TOLERANCE {
            return Err(bad(format!(
                "quats[{i}] has norm {norm:.6}, off unity by more than {NORM_TOLERANCE}"
            )));
        }
        out.push(q.map(|c| c / norm));
    }
    Ok(out)
}

/// Replay recorded fingertip orientations through the core's rolling model, as
/// `host-sim replay` does, and return its output columns as numpy arrays.
///
/// `t_s`: N times, s, non-decreasing. `quats`: N x 4 unit quaternions `(w, x, y, z)` mapping
/// the fingertip's body frame to the object's frame (norm within 1e-3 of 1; normalised).
/// `method`: `"exact"`, `"rpy"` or `"paper-verbatim"`. `surface`: `"plane"`, `"sphere"`,
/// `"bowl"` or `"cylinder"` (radius `object_radius_m`). `radius_m`: the fingertip's radius, m.
/// `normal_force_n`: the nominal normal force of the torsional friction limit, N.
///
/// Returns a dict with the columns of `host-sim replay`'s CSV: `t_s`, `plane_x_m`,
/// `plane_y_m`, `sphere_x_m`, `sphere_y_m`, `sphere_z_m`, `spin_rad`, `tau_n_nm`, `state`
/// (strings: `rolling`, `singular`, `gimbal-lock`), `object_x_m`, `object_y_m`, `object_z_m`,
/// `finger_x_m`, `finger_y_m`, `finger_z_m`. Raises `ValueError` for bad input.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (
    t_s, quats, method = "exact", surface = "plane", radius_m = 0.01,
    object_radius_m = 0.05, normal_force_n = 1.0
))]
pub fn replay<'py>(
    py: Python<'py>,
    t_s: Vec<f64>,
    quats: Vec<Vec<f64>>,
    method: &str,
    surface: &str,
    radius_m: f64,
    object_radius_m: f64,
    normal_force_n: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let method = Method::from_name(method).ok_or_else(|| {
        bad(format!(
            "method must be exact, rpy or paper-verbatim, got '{method}'"
        ))
    })?;
    if !(radius_m.is_finite() && radius_m > 0.0) {
        return Err(bad(format!(
            "radius_m must be a positive number, got {radius_m}"
        )));
    }
    if !(normal_force_n.is_finite() && normal_force_n >= 0.0) {
        return Err(bad(format!(
            "normal_force_n must be a non-negative number, got {normal_force_n}"
        )));
    }
    if !(object_radius_m.is_finite() && object_radius_m > 0.0) {
        return Err(bad(format!(
            "object_radius_m must be a positive number, got {object_radius_m}"
        )));
    }
    if surface == "bowl" && object_radius_m <= radius_m {
        return Err(bad(format!(
            "object_radius_m ({object_radius_m}) must be larger than radius_m ({radius_m}) for a bowl"
        )));
    }
    let q = checked(&t_s, &quats)?;
    let (r, f, big) = (
        radius_m as f32,
        normal_force_n as f32,
        object_radius_m as f32,
    );
    let rows = py.detach(|| match surface {
        "plane" => Ok(run(Plane::default(), &t_s, &q, method, r, f)),
        "sphere" => Ok(run(Sphere::new(big), &t_s, &q, method, r, f)),
        "bowl" => Ok(run(Bowl::new(big), &t_s, &q, method, r, f)),
        "cylinder" => Ok(run(Cylinder::new(big), &t_s, &q, method, r, f)),
        other => Err(format!(
            "surface must be plane, sphere, bowl or cylinder, got '{other}'"
        )),
    });
    let rows = rows.map_err(bad)?;
    if let Some(r) = rows.iter().find(|r| {
        r.object
            .iter()
            .chain(&r.finger)
            .chain([&r.spin_rad, &r.tau_n_nm])
            .any(|v| !v.is_finite())
    }) {
        return Err(PyValueError::new_err(format!(
            "internal error: non-finite output at t = {} s",
            r.t_s
        )));
    }
    let c = Columns::new(py)?;
    let col = |f: fn(&Row) -> f32| rows.iter().map(|r| f64::from(f(r))).collect::<Vec<f64>>();
    c.f64("t_s", rows.iter().map(|r| r.t_s).collect())?;
    c.f64("plane_x_m", col(|r| r.object[0]))?;
    c.f64("plane_y_m", col(|r| r.object[1]))?;
    c.f64("sphere_x_m", col(|r| r.finger[0]))?;
    c.f64("sphere_y_m", col(|r| r.finger[1]))?;
    c.f64("sphere_z_m", col(|r| r.finger[2]))?;
    c.f64("spin_rad", col(|r| r.spin_rad))?;
    c.f64("tau_n_nm", col(|r| r.tau_n_nm))?;
    c.str("state", rows.iter().map(|r| r.state).collect())?;
    c.f64("object_x_m", col(|r| r.object[0]))?;
    c.f64("object_y_m", col(|r| r.object[1]))?;
    c.f64("object_z_m", col(|r| r.object[2]))?;
    c.f64("finger_x_m", col(|r| r.finger[0]))?;
    c.f64("finger_y_m", col(|r| r.finger[1]))?;
    c.f64("finger_z_m", col(|r| r.finger[2]))?;
    Ok(c.into_dict())
}
