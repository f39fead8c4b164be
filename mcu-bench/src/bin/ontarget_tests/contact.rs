//! The contact pipeline's closed forms: the torsional friction limit, the spin spring of eq. (1),
//! the state machine's contact rule, and the normal force and NaN guard of the full contact step.

use crate::accuracy::Accuracy;
use core::hint::black_box as bb;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::spin::{torsion_limit, SpinSpring};
use softfinger_core::contact::state::{next_state, ContactState, Reason, StateInputs};
use softfinger_core::contact::surface::Plane;
use softfinger_core::contact::{ContactInput, ContactModel};
use softfinger_core::{Flags, Quat, Vec3};
use softfinger_mcu_bench::check::Checker;

/// Backend-independent checks (no math kernels involved).
pub fn checks(c: &mut Checker) {
    // τ_max = (3π/16)·μ·f_N·a; 3π/16 = 0.589048623. Measured exact on the target; bound 2 ulp
    // (2.4e-7 relative), an ulp argument.
    let tau = torsion_limit(bb(0.8), bb(2.0), bb(0.005));
    let expected = 0.589_048_6 * 0.8 * 2.0 * 0.005;
    c.close(
        "torsion limit (3pi/16) mu fN a",
        tau,
        expected,
        expected * 2.4e-7,
    );
    c.ok(
        "torsion limit is 0 without normal force",
        torsion_limit(bb(0.8), bb(0.0), bb(0.005)) == 0.0,
    );

    // Eq. (1) inside the limit: τ = k_z·Σδφ (two windings of 0.1 rad at k_z = 0.01 N·m/rad).
    let mut s = SpinSpring::default();
    s.update(bb(0.1), 0.01, 1.0);
    let (t, sat) = s.update(bb(0.1), 0.01, 1.0);
    // Measured exact; bound 1 ulp of 0.002 (2.3e-10 N·m), an ulp argument.
    c.close(
        "spin spring, elastic: tau = k_z (0.1 + 0.1)",
        t,
        0.002,
        2.3e-10,
    );
    c.ok("spin spring, elastic: not saturated", !sat);
    // Beyond the limit the torque stays at τ_max with the sign of the twist.
    let (t, sat) = s.update(bb(-5.0), 0.01, 0.001);
    c.ok(
        "spin spring, beyond the limit: tau = -tau_max, saturated",
        t == -0.001 && sat,
    );
    let (t, _) = s.update(bb(f32::NAN), 0.01, 0.001);
    c.ok("spin spring, NaN twist ignored", t.is_finite());

    // Broken → rolling when the normal force exceeds f_make after the re-contact dwell; kept
    // broken right after a break.
    let p = ContactParams::DEFAULT.state_params();
    let touching = StateInputs {
        normal_force_n: 2.0,
        gap_m: -0.001,
        time_in_state_s: 1.0,
        ..StateInputs::default()
    };
    let just_broken = StateInputs {
        time_in_state_s: 0.0,
        ..touching
    };
    c.ok(
        "state machine: no re-contact within the dwell",
        next_state(bb(ContactState::Broken), &bb(just_broken), &p)
            == (ContactState::Broken, Reason::Kept),
    );
    c.ok(
        "state machine: broken -> rolling on contact",
        next_state(bb(ContactState::Broken), &bb(touching), &p)
            == (ContactState::Rolling, Reason::MadeContact),
    );
    let apart = StateInputs {
        gap_m: 0.01,
        ..StateInputs::default()
    };
    c.ok(
        "state machine: rolling -> broken when apart without force",
        next_state(bb(ContactState::Rolling), &bb(apart), &p)
            == (ContactState::Broken, Reason::Separated),
    );
}

/// The full contact step with backend `M`.
pub fn step_checks<M: Accuracy>(c: &mut Checker) {
    let params = ContactParams::DEFAULT;
    let Ok(mut model) =
        ContactModel::<M, Plane>::new(params, Plane::default(), Quat::IDENTITY, 1.0e-4)
    else {
        c.ok("ContactModel::new accepts the default parameters", false);
        return;
    };
    // The fingertip centre 1 mm below contact height presses 1 mm into the plane at rest: the first
    // step makes contact and renders f = k_n·1 mm = 2000 N/m · 0.001 m = 2 N along the normal +z,
    // no tangential force (the anchor is placed under the probe). Tolerance: the 1 mm depth is
    // 0.01 − 0.009 in f32 (0.009 rounded by ≤ 4.7e-10 m), i.e. 1e-6 N. Measured 2.4e-7 N with every
    // backend; bound 3x, 7.2e-7 N.
    let input = ContactInput {
        q: Quat::IDENTITY,
        probe_m: Vec3::new(0.002, -0.001, params.fingertip_radius_m - 0.001),
        probe_vel: Vec3::ZERO,
    };
    let out = model.contact_step(&bb(input));
    c.ok(
        "contact step: made contact",
        out.state == ContactState::Rolling && out.reason == Reason::MadeContact,
    );
    c.close_all(
        "contact step: normal force k_n * 1 mm",
        &out.force_n.to_array(),
        &[0.0, 0.0, 2.0],
        7.2e-7,
    );
    c.ok(
        "contact step: no spin torque without twist",
        out.tau_n_nm == 0.0,
    );
    // The contact point is under the probe: (x, y, 0) of the probe, exactly.
    c.ok(
        "contact step: contact point under the probe",
        out.object_point_m == Vec3::new(0.002, -0.001, 0.0),
    );

    // Non-finite input: zero force, flagged, state kept.
    let bad = ContactInput {
        q: Quat::new(f32::NAN, 0.0, 0.0, 0.0),
        ..input
    };
    let out = model.contact_step(&bb(bad));
    c.ok(
        "contact step, NaN orientation: zero force, NON_FINITE_INPUT, state kept",
        out.force_n == Vec3::ZERO
            && out.tau_n_nm == 0.0
            && out.flags.contains(Flags::NON_FINITE_INPUT)
            && model.state() == ContactState::Rolling,
    );
    let bad = ContactInput {
        probe_vel: Vec3::new(0.0, f32::INFINITY, 0.0),
        ..input
    };
    let out = model.contact_step(&bb(bad));
    c.ok(
        "contact step, infinite velocity: zero force, NON_FINITE_INPUT",
        out.force_n == Vec3::ZERO && out.flags.contains(Flags::NON_FINITE_INPUT),
    );
}
