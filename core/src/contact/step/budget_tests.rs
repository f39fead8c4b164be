//! One friction budget through the contact step: the rolling torsion spring gets what the
//! tangential load leaves of the static limit surface, a twist and a load in the same step are
//! judged together, the sliding proxy and the torsion spring slip together to the kinetic limit
//! surface, and [`Flags::SPIN_SATURATED`] says when the torque was limited. Closed forms: the
//! ellipse (|f_t|/(μ·f_N))² + (τ/τ_max)² ≤ 1 with τ_max = (3π/16)·μ·f_N·a, a = `patch_radius_m`
//! at f_N = `patch_ref_force_n` (2 N here, the 1 mm press of `pressed`).

use super::*;
extern crate std;
use super::step_rule_tests::{pressed, sample};
use crate::contact::surface::Plane;
use crate::math::Libm;
use std::eprintln;

const DT: f32 = 1e-4; // 10 kHz
const P: ContactParams = ContactParams::DEFAULT;
/// The 1 mm press: f_N = K·1 mm = 2 N = f_ref, so the patch radius is `patch_radius_m`.
const F_N: f32 = 2.0;
/// A sideways probe speed above the slip threshold, m/s.
const SLIP_V: f32 = 0.05;

fn model(p: ContactParams) -> ContactModel<Libm, Plane> {
    ContactModel::new(p, Plane::default(), Quat::IDENTITY, DT).unwrap()
}

fn twist(angle: f32) -> Quat {
    Quat::from_axis_angle::<Libm>(Vec3::Z, angle)
}

/// τ_max = (3π/16)·μ·f_N·a in f64 at the 1 mm press.
fn tau_max(mu: f32) -> f64 {
    3.0 * std::f64::consts::PI / 16.0 * mu as f64 * F_N as f64 * P.patch_radius_m as f64
}

/// Pressed 1 mm at the origin, the probe then `offset` m along +x (held still: a stuck load
/// K_t·offset), then twisted to `angle` rad about the normal in 1 mrad steps. Rolling throughout.
fn loaded_and_twisted(
    p: ContactParams,
    offset: f32,
    angle: f32,
) -> (ContactModel<Libm, Plane>, ContactOutput) {
    let mut m = model(p);
    let mut o = m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, 0.001), Vec3::ZERO));
    assert_eq!(o.reason, Reason::MadeContact);
    o = m.contact_step(&sample(Quat::IDENTITY, pressed(offset, 0.001), Vec3::ZERO));
    let n = (angle / 1e-3) as usize;
    for k in 1..=n {
        o = m.contact_step(&sample(
            twist(angle * k as f32 / n as f32),
            pressed(offset, 0.001),
            Vec3::ZERO,
        ));
        assert_eq!(o.state, ContactState::Rolling, "step {k}: {:?}", o.reason);
    }
    (m, o)
}

/// Twisted to 0.6 of the static torsional limit, then pushed sideways to 0.9 of the cone at the
/// slip speed: the contact slides. Returns the model, the wrist orientation, the probe velocity,
/// the probe's offset (m) and the sliding step's output.
fn slid_with_twist() -> (ContactModel<Libm, Plane>, Quat, Vec3, f32, ContactOutput) {
    let tau_s = tau_max(P.mu_s) as f32;
    let (mut m, _) = loaded_and_twisted(P, 0.0, 0.6 * tau_s / P.spin_stiffness);
    let q = twist(0.6 * tau_s / P.spin_stiffness);
    let v = Vec3::new(SLIP_V, 0.0, 0.0);
    m.contact_step(&sample(q, pressed(0.0, 0.001), v));
    let d = 0.9 * P.mu_s * F_N / P.tangential_stiffness;
    let o = m.contact_step(&sample(q, pressed(d, 0.001), v));
    (m, q, v, d, o)
}

#[test]
fn the_model_reports_its_tick() {
    assert_eq!(model(P).dt_s(), DT);
}

/// A stuck tangential load of 0.6 of the cone leaves the torsion spring √(1 − 0.6²) = 0.8 of the
/// static torsional limit; no load leaves all of it. Twisting 1 rad saturates either. Measured
/// relative error of the torque 1.78e-7 (no load) and 2.62e-7 (load 0.6), f32 rounding; bounds
/// 3x: 5.4e-7 and 7.8e-7. The load's force measured exact (relative error 0): bound 2 ulp
/// (2.4e-7), an ulp argument.
#[test]
fn a_tangential_load_shrinks_the_static_torsion_limit() {
    for (load, bound) in [(0.0f32, 5.4e-7), (0.6, 7.8e-7)] {
        let offset = load * P.mu_s * F_N / P.tangential_stiffness;
        let (_, o) = loaded_and_twisted(P, offset, 1.0);
        let f_t = (o.force_n.x as f64).hypot(o.force_n.y as f64);
        assert!(
            (f_t / (load * P.mu_s * F_N) as f64 - 1.0).abs() < 2.4e-7 || load == 0.0,
            "{f_t}"
        );
        let expected = tau_max(P.mu_s) * (1.0 - (load as f64).powi(2)).sqrt();
        let err = (o.tau_n_nm as f64 / expected - 1.0).abs();
        eprintln!(
            "load {load}: τ {} expected {expected:e}, error {err:e}",
            o.tau_n_nm
        );
        assert!(err < bound, "load {load}: τ {} vs {expected}", o.tau_n_nm);
        assert!(o.flags.contains(Flags::SPIN_SATURATED));
    }
}

/// The rolling → sliding rule sees the twist of this very step added to the spring's: with the
/// spring at 0.6 of τ_max and a load of 0.75 of the cone (0.75² + 0.6² < 1.05², rolling kept),
/// a further twist in the same step that brings the trial torque to 0.9 of τ_max slides
/// (0.75² + 0.9² > 1.05²) and one to 0.7 does not (0.75² + 0.7² = 1.0525 < 1.05² = 1.1025).
/// The held spring's torque: measured 2.98e-7 off 0.6 τ_max (relative); bound 3x, 9e-7.
#[test]
fn a_twist_and_a_load_in_the_same_step_share_the_budget() {
    let tau_s = tau_max(P.mu_s) as f32;
    let held = 0.6 * tau_s / P.spin_stiffness;
    for (to, slides) in [(0.7f32, false), (0.9, true)] {
        let (mut m, o) = loaded_and_twisted(P, 0.0, held);
        assert!((o.tau_n_nm / tau_s - 0.6).abs() < 9e-7, "{}", o.tau_n_nm);
        let d = 0.75 * P.mu_s * F_N / P.tangential_stiffness;
        let v = Vec3::new(SLIP_V, 0.0, 0.0);
        m.contact_step(&sample(twist(held), pressed(0.0, 0.001), v));
        let q = twist(to * tau_s / P.spin_stiffness);
        let o = m.contact_step(&sample(q, pressed(d, 0.001), v));
        assert_slides(&o, slides, &std::format!("to {to}"));
    }
}

/// Sliding with a twist held: the trial (K_t·d, k_z·φ_el) is outside the kinetic ellipse, and the
/// proxy and the spring slip together to its closest point (the projection of
/// [`crate::contact::limit_surface::project`], tested against a brute-force search there): the force and
/// torque rendered are the trial's scaled by (s_f, s_τ), on the ellipse, with SPIN_SATURATED.
/// The next step, the probe moving on at the same speed, finds the proxy where the slip left it:
/// the same force, same direction. Measured: the lateral force is exactly 0 (the probe moves
/// along x); the force's scale exact and the point exactly on the ellipse (|on − 1| = 0), bounds
/// 2 ulp (2.4e-7, an ulp argument); the torque's scale 3.58e-7 off, bound 3x, 1.1e-6; the next
/// step's force 1.57e-3 off the last (the probe moved one tick), bound 3x, 4.7e-3.
#[test]
fn sliding_proxy_and_torsion_spring_slip_together_onto_the_kinetic_ellipse() {
    let tau_s = tau_max(P.mu_s) as f32;
    let (mut m, q, v, d, o) = slid_with_twist();
    assert_eq!(o.state, ContactState::Sliding);
    let (f_max, t_max) = (P.mu_k * F_N, tau_max(P.mu_k) as f32);
    let trial_tau = 0.6 * tau_s;
    let (sf, st) = crate::contact::limit_surface::project(
        P.tangential_stiffness * d,
        trial_tau,
        f_max,
        t_max,
        P.tangential_stiffness,
        P.spin_stiffness,
    );
    assert!(sf < 0.99 && st < 0.99, "both slip: {sf} {st}");
    let f_t = -o.force_n.x; // the proxy trails the probe: the force points back along −x
    assert_eq!(o.force_n.y, 0.0);
    assert!(
        (f_t / (sf * P.tangential_stiffness * d) - 1.0).abs() < 2.4e-7,
        "{f_t} vs scale {sf}"
    );
    assert!(
        (o.tau_n_nm / (st * trial_tau) - 1.0).abs() < 1.1e-6,
        "{} vs scale {st}",
        o.tau_n_nm
    );
    let on = (f_t / f_max).powi(2) + (o.tau_n_nm / t_max).powi(2);
    eprintln!("on-ellipse error {:e}, sf {sf}, st {st}", on - 1.0);
    assert!((on - 1.0).abs() < 2.4e-7, "{on}");
    assert!(o.flags.contains(Flags::SPIN_SATURATED));
    let next = m.contact_step(&sample(q, pressed(d + SLIP_V * DT, 0.001), v));
    assert_eq!(next.state, ContactState::Sliding);
    assert!(
        (next.force_n.x / o.force_n.x - 1.0).abs() < 4.7e-3,
        "{:?} then {:?}",
        o.force_n,
        next.force_n
    );
}

/// Sliding without a twist limits the force only: the torque, zero, was not limited, so no
/// SPIN_SATURATED. The force on the kinetic cone: measured 1.19e-7 relative (1 ulp); bound 3x,
/// 3.6e-7.
#[test]
fn sliding_without_a_twist_is_not_spin_saturated() {
    let mut m = model(P);
    m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, 0.001), Vec3::ZERO));
    let v = Vec3::new(SLIP_V, 0.0, 0.0);
    m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, 0.001), v));
    let d = 1.5 * P.mu_s * F_N / P.tangential_stiffness;
    let o = m.contact_step(&sample(Quat::IDENTITY, pressed(d, 0.001), v));
    assert_eq!(o.state, ContactState::Sliding);
    assert!(
        (-o.force_n.x / (P.mu_k * F_N) - 1.0).abs() < 3.6e-7,
        "{:?}",
        o.force_n
    );
    assert_eq!(o.tau_n_nm, 0.0);
    assert!(!o.flags.contains(Flags::SPIN_SATURATED), "{:?}", o.flags);
}

/// SPIN_SATURATED is raised only while the normal force is above ε_f (below it the contact is
/// about to break and its torque limit is meaningless): a saturated spring at f_N = ε_f exactly
/// is not flagged, at f_N one ulp above ε_f it is.
#[test]
fn spin_saturation_is_flagged_only_above_the_force_threshold() {
    // f_N of a 4 µm press, as the step computes it (read from a first run).
    let shallow = |p: ContactParams| {
        let (mut m, _) = loaded_and_twisted(p, 0.0, 1.0);
        m.contact_step(&sample(twist(1.0), pressed(0.0, 4e-6), Vec3::ZERO))
    };
    let f_n = shallow(P).force_n.z;
    assert!(f_n > 0.0 && f_n < P.tolerances.force_eps_n, "{f_n}");
    for (eps, flagged) in [(f_n, false), (f_n.next_down(), true)] {
        let mut p = P;
        p.tolerances.force_eps_n = eps;
        let o = shallow(p);
        assert_eq!(o.state, ContactState::Rolling, "{:?}", o.reason);
        assert_eq!(o.force_n.z, f_n);
        assert_eq!(
            o.flags.contains(Flags::SPIN_SATURATED),
            flagged,
            "ε_f {eps}"
        );
    }
}

/// Sliding with a twist, then one tick with the probe's position and the wrist held (its velocity
/// input unchanged, so the contact stays sliding): the trial is where the last slip left it, on
/// or inside the kinetic ellipse, so nothing slips and the torque is not flagged as limited; the torque stays what the slip left.
#[test]
fn a_still_tick_after_a_slip_limits_nothing() {
    let (mut m, q, v, d, slid) = slid_with_twist();
    assert!(slid.flags.contains(Flags::SPIN_SATURATED));
    let o = m.contact_step(&sample(q, pressed(d, 0.001), v));
    assert_eq!(o.state, ContactState::Sliding);
    assert!(!o.flags.contains(Flags::SPIN_SATURATED), "{:?}", o.flags);
    assert_eq!(o.tau_n_nm, slid.tau_n_nm);
}
