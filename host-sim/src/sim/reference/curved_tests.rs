//! The Montana-form references for the bowl and the cylinder against the two other independent
//! references: the Cartesian RK45 of the rolling constraint ([`super::rolling_ode`]) and, where one
//! exists, the closed form ([`super::closed_form`]: the bowl; the cylinder's two principal rolling
//! directions). Figures: `cargo test -p host-sim reference::curved_tests -- --nocapture`.

use super::motions::{cube_axes, motion};
use super::rolling_ode::{self, Object};
use super::*;
use nalgebra::Vector3;

const RHO: f64 = 0.01;
const BIG: f64 = 0.05;
const TIGHT: ReferenceMethod = ReferenceMethod::Rk45 {
    rtol: 1e-12,
    atol: 1e-14,
};

fn worst(a: &ReferencePaths, object: &[[f64; 3]], finger: &[[f64; 3]]) -> f64 {
    max_distance(&a.plane, object).max(max_distance(&a.sphere, finger))
}

/// Worst distance (m) of the Montana reference from the Cartesian one and from the closed form (0 if
/// none) over the 26 axes, fixed and wandering, for one step size.
fn worst_over_axes(ground: Ground, object: Object, step: f64, n: usize) -> (f64, f64) {
    let (mut cart, mut closed) = (0.0f64, 0.0f64);
    for axis in cube_axes() {
        for wander in [false, true] {
            let qs = motion(&axis, step, n, wander);
            let m = reference_paths_on(ground, TIGHT, &qs, 0.01, RHO).unwrap();
            let c = rolling_ode::integrate(object, RHO, &qs, 0.01, 1e-12).unwrap();
            cart = cart.max(worst(&m, &c.object, &c.finger));
            if let Ok(cf) = reference_paths_on(ground, ReferenceMethod::ClosedForm, &qs, 0.01, RHO)
            {
                closed = closed.max(worst(&m, &cf.plane, &cf.sphere));
            }
        }
    }
    eprintln!("{ground:?}, step {step} rad: Montana vs Cartesian {cart:.2e} m, vs closed form {closed:.2e} m");
    (cart, closed)
}

#[test]
fn bowl_montana_matches_cartesian_and_closed_form_on_every_axis() {
    // Measured (this test, 52 motions per step): vs Cartesian 3.5e-16 m (0.02 rad steps) and
    // 7.8e-15 m (0.6 rad steps); vs the closed form 3.5e-16 m and 7.8e-15 m. Asserted 1.2e-15 m and
    // 2.4e-14 m. A wrong sign of the bowl's curvature (rolling as on the outside) is off by mm.
    let g = Ground::Bowl { radius: BIG };
    let (c, f) = worst_over_axes(g, Object::Bowl(BIG), 0.02, 40);
    assert!(c < 1.2e-15 && f < 1.2e-15, "{c:e} {f:e}");
    let (c, f) = worst_over_axes(g, Object::Bowl(BIG), 0.6, 12);
    assert!(c < 2.4e-14 && f < 2.4e-14, "{c:e} {f:e}");
}

#[test]
fn cylinder_montana_matches_cartesian_on_every_axis() {
    // Measured: 3.6e-16 m (0.02 rad steps), 1.2e-14 m (0.6 rad steps); asserted 1.2e-15 m and 3.7e-14 m.
    let g = Ground::Cylinder { radius: BIG };
    let (c, _) = worst_over_axes(g, Object::Cylinder(BIG), 0.02, 40);
    assert!(c < 1.2e-15, "{c:e}");
    let (c, _) = worst_over_axes(g, Object::Cylinder(BIG), 0.6, 12);
    assert!(c < 3.7e-14, "{c:e}");
}

#[test]
fn curved_grounds_on_the_validate_motion() {
    // 10 s at 1 kHz of `host-sim validate`'s roll-and-spin motion. Measured: Montana vs Cartesian
    // 4.7e-15 m (bowl), 4.7e-15 m (cylinder); Montana vs the bowl's closed form 4.9e-16 m. Asserted
    // 1.5e-14 m and 1.5e-15 m.
    let s = crate::experiments::validate::surfaces::samples();
    let dt = 1.0 / crate::experiments::validate::surfaces::RATE_HZ;
    for (g, o) in [
        (Ground::Bowl { radius: BIG }, Object::Bowl(BIG)),
        (Ground::Cylinder { radius: BIG }, Object::Cylinder(BIG)),
    ] {
        let m = reference_paths_on(g, TIGHT, &s, dt, RHO).unwrap();
        let c = rolling_ode::integrate(o, RHO, &s, dt, 1e-12).unwrap();
        let d = worst(&m, &c.object, &c.finger);
        eprintln!(
            "{g:?} validate motion: Montana vs Cartesian {d:.2e} m, {:?}",
            m.stats
        );
        assert!(d < 1.5e-14, "{g:?}: {d:e}");
        assert!(m.stats.recharts >= 1);
    }
    let g = Ground::Bowl { radius: BIG };
    let m = reference_paths_on(g, TIGHT, &s, dt, RHO).unwrap();
    let cf = reference_paths_on(g, ReferenceMethod::ClosedForm, &s, dt, RHO).unwrap();
    let d = worst(&m, &cf.plane, &cf.sphere);
    eprintln!("bowl validate motion: Montana vs closed form {d:.2e} m");
    assert!(d < 1.5e-15, "{d:e}");
}

#[test]
fn cylinder_principal_directions_have_closed_forms() {
    // Rolling by θ about the cylinder's axis (x): in the y-z plane this is a circle of radius r on a
    // circle of radius R, so the contact turns by κθ about x, κ = r/(R + r) (the sphere-on-sphere rule).
    // Rolling about y: the contact runs along the flat direction like on a plane, by r·θ along +x.
    // Montana at rtol 1e-12 against these exact points; measured 3.6e-18 m and 3.5e-18 m, asserted
    // 1.1e-17 m.
    let g = Ground::Cylinder { radius: BIG };
    let theta = 1.2;
    let about = |axis: Vector3<f64>| -> Vec<UnitQuaternion<f64>> {
        (0..=12)
            .map(|k| UnitQuaternion::from_scaled_axis(axis * (theta * k as f64 / 12.0)))
            .collect()
    };
    let kappa = RHO / (BIG + RHO);
    let qs = about(Vector3::x());
    let m = reference_paths_on(g, TIGHT, &qs, 0.01, RHO).unwrap();
    let n = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), kappa * theta) * Vector3::z();
    let d_axis = (Vector3::from(*m.plane.last().unwrap()) - n * BIG).norm();
    let qs = about(Vector3::y());
    let m = reference_paths_on(g, TIGHT, &qs, 0.01, RHO).unwrap();
    let d_flat =
        (Vector3::from(*m.plane.last().unwrap()) - Vector3::new(RHO * theta, 0.0, BIG)).norm();
    eprintln!("cylinder closed forms: about the axis {d_axis:.2e} m, along it {d_flat:.2e} m");
    assert!(
        d_axis < 1.1e-17 && d_flat < 1.1e-17,
        "{d_axis:e} {d_flat:e}"
    );
    // The two directions really differ (the curvature depends on the rolling direction): the contact
    // travels R·κθ = 10 mm around the axis but r·θ = 12 mm along it.
    assert!((BIG * kappa * theta - RHO * theta).abs() > 1.5e-3);
}

#[test]
fn bowl_and_cylinder_inputs_are_checked() {
    let qs = motion(&Vector3::x(), 0.1, 5, false);
    // A bowl no larger than the fingertip has no rolling contact (relative curvature 1/ρ − 1/R ≤ 0).
    for big in [RHO, 0.5 * RHO, 0.0, f64::NAN] {
        assert_eq!(
            reference_paths_on(Ground::Bowl { radius: big }, TIGHT, &qs, 0.01, RHO),
            Err(ReferenceError::InvalidInput)
        );
    }
    assert_eq!(
        reference_paths_on(Ground::Cylinder { radius: -1.0 }, TIGHT, &qs, 0.01, RHO),
        Err(ReferenceError::InvalidInput)
    );
    assert_eq!(
        reference_paths_on(
            Ground::Cylinder { radius: BIG },
            ReferenceMethod::ClosedForm,
            &qs,
            0.01,
            RHO
        ),
        Err(ReferenceError::NoClosedForm)
    );
    // Starting points and normals as `host-sim replay --surface` (bowl bottom, cylinder top).
    // Measured exact (the first sample is the identity): asserted equal.
    let b = reference_paths_on(Ground::Bowl { radius: BIG }, TIGHT, &qs, 0.01, RHO).unwrap();
    assert_eq!(b.plane[0], [0.0, 0.0, -BIG]);
    assert_eq!(b.sphere[0], [0.0, 0.0, -RHO]);
    let c = reference_paths_on(Ground::Cylinder { radius: BIG }, TIGHT, &qs, 0.01, RHO).unwrap();
    assert_eq!(c.plane[0], [0.0, 0.0, BIG]);
}
