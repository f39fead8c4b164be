//! Delta (parallel) mechanism kinematics of the device's 3 active axes. STUB: signatures fixed, bodies pending.

use crate::flags::Flags;
use crate::math::Math;
use crate::vec3::Vec3;

/// Geometry of a rotary delta mechanism (Clavel type), metres.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeltaGeometry {
    /// Distance from the base centre to each motor axis, m.
    pub base_radius_m: f32,
    /// Distance from the effector centre to each forearm joint, m.
    pub effector_radius_m: f32,
    /// Motor-driven upper arm length, m.
    pub upper_arm_m: f32,
    /// Parallelogram forearm length, m.
    pub forearm_m: f32,
}

impl DeltaGeometry {
    /// Forward kinematics: motor angles (rad) to the effector centre in the device base frame (m).
    pub fn forward<M: Math>(&self, _angles_rad: [f32; 3]) -> (Vec3, Flags) {
        (Vec3::ZERO, Flags::KINEMATICS_SINGULAR)
    }
    /// Jacobian transpose: motor torques (N·m) that render `force_n` (N, base frame) at the effector.
    pub fn joint_torques<M: Math>(
        &self,
        _angles_rad: [f32; 3],
        _effector_m: Vec3,
        _force_n: Vec3,
    ) -> ([f32; 3], Flags) {
        ([0.0; 3], Flags::KINEMATICS_SINGULAR)
    }
}
