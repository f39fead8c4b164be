//! Who moves the virtual device's handle: the scene's hand script (looped), or a client that
//! drives the hand to a target. Either way a new hand script starts from where the handle is, so
//! the handle never jumps: the plant is rebuilt at rest at the current effector position and
//! wrist angles, and the script moves from there (minimum jerk) to where it should be.

use crate::sim::plant::{HandScript, Phase, Plant, PlantError, PlantParams, Waypoint};
use softfinger_core::device::DeviceParams;

/// Reference speed of the move to a new script's start, m/s.
const MOVE_SPEED_M_S: f64 = 0.05;

/// Who drives the hand now.
#[derive(Clone, Debug, PartialEq)]
pub enum HandMode {
    /// The scene's script, replayed whenever it ends.
    Script,
    /// A client's target, held.
    Driven,
}

fn here(plant: &Plant) -> Waypoint {
    Waypoint {
        position_m: plant.effector_position_m(),
        wrist_rad: plant.wrist_angles_rad(),
    }
}

fn move_duration_s(a: &Waypoint, b: &Waypoint) -> f64 {
    let d: f64 = (0..3)
        .map(|k| (a.position_m[k] - b.position_m[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    (d / MOVE_SPEED_M_S).clamp(0.2, 2.0)
}

/// Why a new hand motion was refused.
#[derive(Debug, thiserror::Error)]
pub enum HandError {
    /// The hand's path from the handle to the script could not be built.
    #[error("hand script: {0}")]
    Script(PlantError),
    /// The target is out of the device's reach.
    #[error("hand target: {0}")]
    Target(PlantError),
    /// The target has a NaN or infinite coordinate.
    #[error("hand target is not finite")]
    NotFinite,
}

/// A plant at the current handle position whose hand moves to `script`'s start and plays it.
pub fn following(
    plant: &Plant,
    script: &HandScript,
    device: DeviceParams,
) -> Result<Plant, HandError> {
    let now = here(plant);
    let first = script.sample(0.0);
    let start = Waypoint {
        position_m: first.position_m,
        wrist_rad: first.wrist_rad,
    };
    let mut s = HandScript::new(now).then(Phase::Approach, move_duration_s(&now, &start), start);
    for seg in script.segments() {
        s = s.then(seg.phase, seg.duration_s, seg.end);
    }
    Plant::new(device, PlantParams::OMEGA_LIKE, s).map_err(HandError::Script)
}

/// A plant at the current handle position whose hand moves to `target` and holds it.
pub fn holding(plant: &Plant, target: Waypoint, device: DeviceParams) -> Result<Plant, HandError> {
    let all_finite = target
        .position_m
        .iter()
        .chain(target.wrist_rad.iter())
        .all(|v| v.is_finite());
    if !all_finite {
        return Err(HandError::NotFinite);
    }
    let now = here(plant);
    let s = HandScript::new(now).then(Phase::Approach, move_duration_s(&now, &target), target);
    let p = Plant::new(device, PlantParams::OMEGA_LIKE, s).map_err(HandError::Script)?;
    // The target itself must be reachable too (the start is, by construction).
    Plant::new(device, PlantParams::OMEGA_LIKE, HandScript::new(target))
        .map_err(HandError::Target)?;
    Ok(p)
}
