//! Does the passivity stage change what a passive setting renders? The default scene
//! (`finger-on-plane`: touch, press, roll, twist, slide, lift) through the whole pipeline and the
//! device plant, once with the stage as built (on) and once observing only, tick by tick.

use crate::sim::closed_loop::{self, prepare, simulate};
use crate::sim::scene::{Scene, SurfaceSpec};
use softfinger_core::contact::surface::Plane;
use softfinger_core::control::controller::passivity::PassivityConfig;
use softfinger_core::control::pipeline::Pipeline;
use softfinger_core::math::Fast;

use crate::sim::closed_loop::SetupError;

/// Why the default scene could not be run.
#[derive(Debug, thiserror::Error)]
pub enum PassivitySceneError {
    /// The default scene is not on the plane.
    #[error("the default scene is expected on the plane")]
    NotPlane,
    /// The closed loop could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
}

/// The comparison's figures.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SceneDifference {
    pub ticks: u64,
    /// Largest |F_on − F_off| over the run (rendered force vectors), N.
    pub max_force_difference_n: f64,
    /// Largest |F| of the run, N (for scale).
    pub max_force_n: f64,
    /// Largest observed energy into the user, J (≤ 0: the rendering stayed passive).
    pub max_observed_energy_j: f64,
    /// Smallest observed energy, J (negative: the observer saw the user push energy in).
    pub min_observed_energy_j: f64,
    /// Ticks in which the stage (on) added damping.
    pub damped_ticks: u64,
}

/// One run: rendered forces per tick, (largest, smallest) observed energy, damped ticks.
struct Run {
    forces: Vec<[f32; 3]>,
    energy_range_j: (f64, f64),
    damped_ticks: u64,
}

/// One run of the default scene.
fn run(enabled: bool) -> Result<Run, PassivitySceneError> {
    let scene = Scene::default_scene();
    if scene.surface != SurfaceSpec::Plane {
        return Err(PassivitySceneError::NotPlane);
    }
    let contact = closed_loop::contact_params(&scene).map_err(SetupError::from)?;
    let config = closed_loop::plane_config(&scene, contact).map_err(SetupError::from)?;
    let mut pipe: Pipeline<Fast, Plane> = Pipeline::new(config).map_err(SetupError::from)?;
    let base = *pipe.controller().passivity().config();
    pipe.set_passivity(PassivityConfig { enabled, ..base })
        .map_err(SetupError::Passivity)?;
    let mut plant = closed_loop::plant(&scene, &contact).map_err(SetupError::from)?;
    prepare(&mut pipe, &mut plant).map_err(SetupError::from)?;
    let ticks = (scene.duration_s * scene.rate_hz).round() as u64;
    let mut forces = Vec::with_capacity(ticks as usize);
    let (mut max_e, mut min_e, mut damped) = (f64::MIN, f64::MAX, 0u64);
    simulate(
        &mut pipe,
        &mut plant,
        ticks,
        |_, _| {},
        |_, _, out, pipe, _| {
            forces.push(out.control.force_n.to_array());
            let e = f64::from(pipe.controller().passivity().energy_j());
            max_e = max_e.max(e);
            min_e = min_e.min(e);
            if enabled && e > 0.0 {
                damped += 1;
            }
        },
    );
    Ok(Run {
        forces,
        energy_range_j: (max_e, min_e),
        damped_ticks: damped,
    })
}

/// Run the default scene with the stage on and observing only, and compare.
pub fn compare() -> Result<SceneDifference, PassivitySceneError> {
    let Run {
        forces: on,
        energy_range_j: (max_e, min_e),
        damped_ticks: damped,
    } = run(true)?;
    let off = run(false)?.forces;
    let norm = |v: [f32; 3]| v.iter().map(|c| f64::from(*c).powi(2)).sum::<f64>().sqrt();
    let diff = on
        .iter()
        .zip(&off)
        .map(|(a, b)| norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]))
        .fold(0.0, f64::max);
    Ok(SceneDifference {
        ticks: on.len() as u64,
        max_force_difference_n: diff,
        max_force_n: on.iter().map(|f| norm(*f)).fold(0.0, f64::max),
        max_observed_energy_j: max_e,
        min_observed_energy_j: min_e,
        damped_ticks: damped,
    })
}
