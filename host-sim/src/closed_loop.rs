//! The closed loop: the core's controller against the plant, coupled only by encoder counts in and
//! PWM duties out, exactly as on the MCU.
//!
//! Each tick: `counts = plant.counts()`, an optional injection hook edits the tick input (faults,
//! noise), `out = controller.tick(input)`, then `plant.step_with_enable(out.duties, out.enable, T)`.
//! The plant applies the duties one tick late (its output latch), like the firmware.

use crate::plant::{HandScript, Plant, PlantError, PlantParams, TouchScript};
use crate::scene::{Scene, SurfaceSpec};
use softfinger_core::controller::{Controller, ControllerConfig, TickInput, TickOutput};
use softfinger_core::delta::DeltaGeometry;
use softfinger_core::device::DeviceParams;
use softfinger_core::params::ContactParams;
use softfinger_core::surface::{Plane, Sphere, Surface};
use softfinger_core::{Math, Vec3};
use std::time::{Duration, Instant};

/// Height (base frame, m) of the plane, or of the sphere's top, in every built-in scene: 10 mm
/// below the workspace centre, so a 10 mm fingertip touches with its centre there.
pub fn surface_top_z_m() -> f64 {
    DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.z as f64 - 0.010
}

/// The scene's contact parameters: the defaults with the scene's overrides.
pub fn contact_params(scene: &Scene) -> Result<ContactParams, String> {
    let c = &scene.contact;
    let d = ContactParams::DEFAULT;
    let p = ContactParams {
        method: scene.method()?,
        fingertip_radius_m: c.fingertip_radius_m.unwrap_or(d.fingertip_radius_m),
        normal_stiffness: c.normal_stiffness.unwrap_or(d.normal_stiffness),
        normal_damping: c.normal_damping.unwrap_or(d.normal_damping),
        tangential_stiffness: c.tangential_stiffness.unwrap_or(d.tangential_stiffness),
        tangential_damping: c.tangential_damping.unwrap_or(d.tangential_damping),
        mu_s: c.mu_s.unwrap_or(d.mu_s),
        mu_k: c.mu_k.unwrap_or(d.mu_k),
        spin_stiffness: c.spin_stiffness.unwrap_or(d.spin_stiffness),
        ..d
    };
    p.validate()
        .map_err(|e| format!("scene '{}': contact parameters: {e}", scene.name))?;
    Ok(p)
}

/// The hand script of a scene: the plant's touch script over the scene's surface.
pub fn touch_script(scene: &Scene, contact: &ContactParams) -> HandScript {
    let s = &scene.script;
    let d = TouchScript::default();
    TouchScript {
        surface_z_m: surface_top_z_m(),
        fingertip_radius_m: contact.fingertip_radius_m as f64,
        press_depth_m: s.press_depth_m.unwrap_or(d.press_depth_m),
        roll_rad: s.roll_rad.unwrap_or(d.roll_rad),
        twist_rad: s.twist_rad.unwrap_or(d.twist_rad),
        slide_m: s.slide_m.unwrap_or(d.slide_m),
        clearance_m: s.clearance_m.unwrap_or(d.clearance_m),
        ..d
    }
    .script()
}

/// The plant for a scene (Omega-like device, a hand following the scene's script).
pub fn plant(scene: &Scene, contact: &ContactParams) -> Result<Plant, PlantError> {
    Plant::new(
        DeviceParams::OMEGA_LIKE,
        PlantParams::OMEGA_LIKE,
        touch_script(scene, contact),
    )
}

/// The controller configuration for a plane scene.
pub fn plane_config(scene: &Scene, contact: ContactParams) -> ControllerConfig<Plane> {
    ControllerConfig {
        rate_hz: scene.rate_hz as f32,
        contact,
        object_origin_m: Vec3::new(0.0, 0.0, surface_top_z_m() as f32),
        ..ControllerConfig::default_plane()
    }
}

/// The controller configuration for a sphere scene: the object frame's origin is the sphere's
/// centre, below the surface top.
pub fn sphere_config(
    scene: &Scene,
    contact: ContactParams,
    radius_m: f64,
) -> ControllerConfig<Sphere> {
    let base = ControllerConfig::default_plane();
    ControllerConfig {
        rate_hz: scene.rate_hz as f32,
        device: base.device,
        contact,
        surface: Sphere::new(radius_m as f32),
        object_origin_m: Vec3::new(0.0, 0.0, (surface_top_z_m() - radius_m) as f32),
        limits: base.limits,
    }
}

/// Which surface a scene needs, for dispatch to the monomorphised loop.
pub fn surface_of(scene: &Scene) -> SurfaceSpec {
    scene.surface
}

/// Run `ticks` closed-loop ticks. `inject(k, &mut input)` may edit each tick's input before the
/// controller sees it; `observe(k, &input, &output, &controller, &plant)` sees every tick after the
/// plant has stepped. Returns the wall time spent inside `Controller::tick`.
pub fn simulate<M: Math, S: Surface>(
    ctrl: &mut Controller<M, S>,
    plant: &mut Plant,
    ticks: u64,
    mut inject: impl FnMut(u64, &mut TickInput),
    mut observe: impl FnMut(u64, &TickInput, &TickOutput, &Controller<M, S>, &Plant),
) -> Duration {
    let dt = 1.0 / ctrl.config().rate_hz as f64;
    let mut in_controller = Duration::ZERO;
    for k in 0..ticks {
        let mut input = TickInput {
            counts: plant.counts(),
            ..TickInput::default()
        };
        inject(k, &mut input);
        let t0 = Instant::now();
        let out = ctrl.tick(&input);
        in_controller += t0.elapsed();
        plant.step_with_enable(out.duties, out.enable, dt);
        observe(k, &input, &out, ctrl, plant);
    }
    in_controller
}
