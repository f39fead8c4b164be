//! Every surface against the RK45 integration of the rolling constraint
//! ([`crate::reference::rolling_ode`]): the core's closed-form rolling updates (exact method) on
//! the plane, the sphere, the bowl and the cylinder, 10 s at 1 kHz of a smooth roll-and-spin
//! motion, fingertip radius 10 mm, object radius 50 mm.

use crate::reference::rolling_ode::{integrate, Object};
use nalgebra::UnitQuaternion;
use softfinger_core::decompose::Method;
use softfinger_core::rolling::Rolling;
use softfinger_core::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::{Fast, Libm, Math, Quat};

/// Fingertip radius, m.
pub const FINGER_R: f64 = 0.01;
/// Object radius (sphere, bowl, cylinder), m.
pub const OBJECT_R: f64 = 0.05;
/// Sampling rate, Hz, and duration, s.
pub const RATE_HZ: f64 = 1000.0;
pub const DURATION_S: f64 = 10.0;

/// One surface's result.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SurfaceRow {
    pub surface: &'static str,
    pub backend: &'static str,
    /// Largest distance from the reference over the run, object and fingertip contact points, mm.
    pub object_max_error_mm: f64,
    pub finger_max_error_mm: f64,
}

/// The motion: a roll about a slowly turning tangent axis (≈0.6 rad/s) with a spin (≈0.4 rad/s).
pub fn samples() -> Vec<UnitQuaternion<f64>> {
    let n = (DURATION_S * RATE_HZ) as usize + 1;
    (0..n)
        .map(|k| {
            let t = k as f64 / RATE_HZ;
            UnitQuaternion::from_euler_angles(
                0.6 * (0.5 * t).sin(),
                0.25 * t - 0.3 * (0.3 * t).sin(),
                0.4 * t,
            )
        })
        .collect()
}

fn ours<M: Math, S: Surface>(
    surface: S,
    s: &[UnitQuaternion<f64>],
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let q = |u: &UnitQuaternion<f64>| Quat::new(u.w as f32, u.i as f32, u.j as f32, u.k as f32);
    let mut r = Rolling::new(surface, FINGER_R as f32, q(&s[0]), Method::Exact);
    let mut obj = Vec::with_capacity(s.len());
    let mut fin = Vec::with_capacity(s.len());
    let mut push = |r: &Rolling<S>| {
        let p = r.surface.contact_point();
        let f = r.finger_point();
        obj.push([p.x as f64, p.y as f64, p.z as f64]);
        fin.push([f.x as f64, f.y as f64, f.z as f64]);
    };
    push(&r);
    for u in &s[1..] {
        let _ = r.step::<M>(q(u));
        push(&r);
    }
    (obj, fin)
}

fn max_dist(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

/// Every surface with the libm and fast backends.
pub fn run() -> Result<Vec<SurfaceRow>, String> {
    let s = samples();
    let dt = 1.0 / RATE_HZ;
    let big = OBJECT_R as f32;
    let mut rows = Vec::new();
    let objects = [
        ("plane", Object::Plane),
        ("sphere", Object::Sphere(OBJECT_R)),
        ("bowl", Object::Bowl(OBJECT_R)),
        ("cylinder", Object::Cylinder(OBJECT_R)),
    ];
    for (name, object) in objects {
        let reference = integrate(object, FINGER_R, &s, dt, 1e-10)
            .map_err(|e| format!("rolling reference on the {name}: {e:?}"))?;
        for backend in ["libm", "fast"] {
            let (o, f) = match (object, backend) {
                (Object::Plane, "libm") => ours::<Libm, _>(Plane::default(), &s),
                (Object::Plane, _) => ours::<Fast, _>(Plane::default(), &s),
                (Object::Sphere(_), "libm") => ours::<Libm, _>(Sphere::new(big), &s),
                (Object::Sphere(_), _) => ours::<Fast, _>(Sphere::new(big), &s),
                (Object::Bowl(_), "libm") => ours::<Libm, _>(Bowl::new(big), &s),
                (Object::Bowl(_), _) => ours::<Fast, _>(Bowl::new(big), &s),
                (Object::Cylinder(_), "libm") => ours::<Libm, _>(Cylinder::new(big), &s),
                (Object::Cylinder(_), _) => ours::<Fast, _>(Cylinder::new(big), &s),
            };
            rows.push(SurfaceRow {
                surface: name,
                backend,
                object_max_error_mm: 1e3 * max_dist(&o, &reference.object),
                finger_max_error_mm: 1e3 * max_dist(&f, &reference.finger),
            });
        }
    }
    Ok(rows)
}

/// The rows as a text table.
pub fn table(rows: &[SurfaceRow]) -> String {
    let mut out = format!(
        "\nSurfaces: exact method vs RK45 of the rolling constraint (rtol 1e-10), {DURATION_S} s at {RATE_HZ} Hz, r = {} mm, R = {} mm\n{:<10} {:<8} {:>18} {:>18}\n",
        FINGER_R * 1e3,
        OBJECT_R * 1e3,
        "surface",
        "backend",
        "object max (mm)",
        "finger max (mm)"
    );
    for r in rows {
        out += &format!(
            "{:<10} {:<8} {:>18.3e} {:>18.3e}\n",
            r.surface, r.backend, r.object_max_error_mm, r.finger_max_error_mm
        );
    }
    out
}
