//! The closed-loop hold scene of `host-sim creep` and of [`super::hold_quantisation`]: the plant
//! with a hand that arms clear of the plane, presses 1 mm at the workspace centre and holds, and the
//! pipeline homed and armed; and where the held finger's anchor sits. Units: m, s; positions in the
//! device base frame, the anchor in the object frame.

use crate::sim::closed_loop::{self, SetupError};
use crate::sim::plant::{HandScript, Phase, Plant, PlantParams, Waypoint};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::surface::{Plane, Surface};
use softfinger_core::control::pipeline::{BoardTiming, Pipeline, PipelineConfig};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Math, Vec3};

/// The rolled contact point on the plane (object frame, m): where the held finger's anchor sits.
pub fn anchor_point<M: Math>(ctrl: &Pipeline<M, Plane>) -> Vec3 {
    ctrl.controller()
        .contact()
        .rolling()
        .surface()
        .contact_point()
}

/// Clearance of the fingertip above the plane where the hold scene arms, m: the device refuses
/// `Arm` with the probe inside the surface (at the old 2 mm it was refused, `InsideSurface`); the
/// default touch script's 20 mm, from which the default scene arms.
pub const ARM_CLEARANCE_M: f64 = 0.020;
/// The hold scene's approach from [`ARM_CLEARANCE_M`] to 2 mm above the plane (where it armed
/// before the device refused `Arm` inside the surface), s: the press starts this long after `Arm`.
pub const APPROACH_S: f64 = 0.5;

/// The closed-loop hold scene: the plant with a hand that arms with the fingertip
/// [`ARM_CLEARANCE_M`] above the plane, approaches to 2 mm above it in [`APPROACH_S`], presses 1 mm
/// at the workspace centre in 0.5 s with the wrist at [`super::rest_orientation`]'s angles, then holds for
/// `hold_s`, its reference
/// moving along base `x` at `drift_m_per_s` (0: still; a test hook standing for a slow walk of the
/// probe relative to the anchor), and the pipeline homed, the hand grasped and armed.
pub fn hold_scene<M: Math>(
    contact: ContactParams,
    hold_s: f64,
    drift_m_per_s: f64,
) -> Result<(Pipeline<M, Plane>, Plant), SetupError> {
    let top = closed_loop::surface_top_z_m();
    let c = DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M;
    let wrist = [0.3, -0.2, 0.1];
    let armed_at = [c.x as f64, c.y as f64, top + 0.01 + ARM_CLEARANCE_M];
    let above = [c.x as f64, c.y as f64, top + 0.012];
    let pressed = [c.x as f64, c.y as f64, top + 0.01 - 0.001];
    let held_end = [pressed[0] + drift_m_per_s * hold_s, pressed[1], pressed[2]];
    let script = HandScript::new(Waypoint {
        position_m: armed_at,
        wrist_rad: wrist,
    })
    .then(
        Phase::Approach,
        APPROACH_S,
        Waypoint {
            position_m: above,
            wrist_rad: wrist,
        },
    )
    .then(
        Phase::Press,
        0.5,
        Waypoint {
            position_m: pressed,
            wrist_rad: wrist,
        },
    )
    .then(
        Phase::Hold,
        hold_s,
        Waypoint {
            position_m: held_end,
            wrist_rad: wrist,
        },
    );
    let mut plant = Plant::new(OMEGA_LIKE.params, PlantParams::OMEGA_LIKE, script)?;
    let config = PipelineConfig {
        device: OMEGA_LIKE,
        timing: BoardTiming::STM32G474_10KHZ,
        contact,
        surface: Plane::default(),
        object_origin_m: Vec3::new(0.0, 0.0, top as f32),
        log_rate_hz: softfinger_core::control::telemetry::DEFAULT_LOG_RATE_HZ,
    };
    let mut ctrl: Pipeline<M, Plane> = Pipeline::new(config)?;
    // The operator's session first (home, grasp, arm); the script starts when armed.
    closed_loop::prepare(&mut ctrl, &mut plant)?;
    Ok((ctrl, plant))
}
