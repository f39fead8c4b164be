//! The controller tick on target: pressing the default plane renders the wall force through the
//! motors, and a driver fault gives zero duties with the drivers disabled.

use crate::accuracy::Accuracy;
use core::hint::black_box as bb;
use softfinger_core::contact_state::ContactState;
use softfinger_core::controller::{Controller, ControllerConfig, TickInput, TickOutput};
use softfinger_core::surface::Plane;
use softfinger_core::{Flags, Vec3};
use softfinger_mcu_bench::check::Checker;
use softfinger_mcu_bench::rig::counts_at;

/// `accurate`: whether the backend's kinematics are accurate enough for the force check (libm and
/// fast; micromath's 6 % sqrt moves the forward kinematics by ~0.7 mm, i.e. ~1.4 N on this wall,
/// so for it only the safety properties are checked).
pub fn checks<M: Accuracy>(c: &mut Checker, accurate: bool) {
    let config = ControllerConfig::default_plane();
    let Ok(mut ctrl) = Controller::<M, Plane>::new(config) else {
        c.ok("controller accepts the default plane configuration", false);
        return;
    };
    let touching =
        config.object_origin_m + Vec3::new(0.0, 0.0, config.contact.fingertip_radius_m - 0.001);
    let Some(counts) = counts_at(&config.device, touching, [0; 3]) else {
        c.ok("the pressing pose is reachable", false);
        return;
    };
    let input = TickInput {
        counts,
        ..TickInput::default()
    };
    let mut out = TickOutput::default();
    for _ in 0..5 {
        out = ctrl.tick(&bb(input));
    }
    let max_duty = config.limits.max_duty;
    c.ok(
        "pressing: drivers enabled, duties finite and within the limit",
        out.enable
            && out
                .duties
                .iter()
                .all(|d| d.is_finite() && d.abs() <= max_duty),
    );
    if accurate {
        // 1 mm into the 2000 N/m plane: 2 N along +z. Encoder quantisation moves the probe by up to
        // ~13 µm per count per axis (±0.05 N); at this pose the error measures 5.73e-4 N (libm and
        // fast, as on the host): bound 3x, 1.7e-3 N.
        c.ok(
            "pressing: rolling contact",
            out.state == ContactState::Rolling,
        );
        c.close(
            "pressing: wall force k_n * 1 mm = 2 N",
            out.force_n.z,
            2.0,
            1.7e-3,
        );
        c.ok(
            "pressing: the motors are driven",
            out.duties.iter().any(|d| d.abs() > 1.0e-3),
        );
    }

    // A driver fault: zero duties, drivers disabled, latched.
    let out = ctrl.tick(&bb(TickInput {
        driver_fault: true,
        ..input
    }));
    c.ok(
        "driver fault: zero duties, disabled, DRIVER_FAULT latched",
        out.duties == [0.0; 3]
            && !out.enable
            && ctrl.latched_faults().contains(Flags::DRIVER_FAULT),
    );
    let out = ctrl.tick(&bb(input));
    c.ok(
        "driver fault stays latched until cleared",
        !out.enable && out.duties == [0.0; 3],
    );
}
