//! Whether the grasp held: after it settles in the first [`SETTLE_S`], the object moves less than
//! [`SLIP_LIMIT_MM`] and turns less than [`ROTATION_LIMIT_RAD`] about the grasp axis relative to
//! the fingertips for the rest of the run. The elastic deflection of the contact springs while it
//! settles is not slip: displacement and turn are measured from the pose at [`SETTLE_S`].
//!
//! Relative to the fingertips: the object centre minus the fingertips' midpoint; the object's turn
//! about the grasp axis (the line through the fingertip centres, which for a pinch passes through
//! both contact points) from its orientation at [`SETTLE_S`] (the hands keep the fingertips' own
//! orientation fixed, so this is the turn relative to them).

use super::simulate::{GraspRun, Sample, SETTLE_S};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Largest displacement relative to the fingertips that still counts as held, mm.
pub const SLIP_LIMIT_MM: f64 = 0.1;
/// Largest turn about the grasp axis relative to the fingertips that still counts as held, rad.
pub const ROTATION_LIMIT_RAD: f64 = 0.01;

/// The verdict on a run.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Verdict {
    /// True when the grasp did not slip after settling (see the module doc).
    pub held: bool,
    /// Largest displacement of the object relative to the fingertips' midpoint after settling, mm.
    pub slip_mm: f64,
    /// Largest rotation of the object about the grasp axis relative to the fingertips after
    /// settling, rad.
    pub rotation_rad: f64,
    /// Whether any value of the run was non-finite (never expected: the core guards its outputs).
    pub non_finite: bool,
}

fn rel_pos(s: &Sample) -> Vector3<f64> {
    let mid = (Vector3::from(s.tips_m[0]) + Vector3::from(s.tips_m[1])) * 0.5;
    Vector3::from(s.pos_m) - mid
}

fn orientation(s: &Sample) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(s.q[0], s.q[1], s.q[2], s.q[3]))
}

/// The turn of `q` from `q0` about the unit `axis` (the twist part of the relative rotation), rad.
pub fn twist_about(q0: &UnitQuaternion<f64>, q: &UnitQuaternion<f64>, axis: &Vector3<f64>) -> f64 {
    let d = q * q0.inverse();
    let v = Vector3::new(d.i, d.j, d.k);
    2.0 * v.dot(axis).atan2(d.w)
}

/// Judge `run`.
pub fn judge(run: &GraspRun) -> Verdict {
    let s = &run.samples;
    let non_finite = s.iter().any(|x| {
        x.pos_m
            .iter()
            .chain(&x.q)
            .chain(x.f_n.iter())
            .chain(&x.tau_n)
            .any(|v| !v.is_finite())
    });
    let Some(k0) = s.iter().position(|x| x.t_s >= SETTLE_S) else {
        return Verdict {
            held: false,
            slip_mm: 0.0,
            rotation_rad: 0.0,
            non_finite,
        };
    };
    let p0 = rel_pos(&s[k0]);
    let q0 = orientation(&s[k0]);
    let (mut slip, mut rot) = (0.0_f64, 0.0_f64);
    // The turn is summed tick by tick (unwrapped: a body spun through a full turn is not back).
    let mut turn = 0.0_f64;
    let mut q_prev = q0;
    for x in &s[k0..] {
        let axis = (Vector3::from(x.tips_m[0]) - Vector3::from(x.tips_m[1]))
            .try_normalize(1e-9)
            .unwrap_or_else(Vector3::x);
        let q = orientation(x);
        turn += twist_about(&q_prev, &q, &axis);
        q_prev = q;
        slip = slip.max((rel_pos(x) - p0).norm() * 1e3);
        rot = rot.max(turn.abs());
    }
    // A NaN slip or turn fails the comparisons: never held.
    Verdict {
        held: !non_finite && slip < SLIP_LIMIT_MM && rot < ROTATION_LIMIT_RAD,
        slip_mm: slip,
        rotation_rad: rot,
        non_finite,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twist_is_the_turn_about_the_axis_only() {
        let q0 = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.7);
        let about_x = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3) * q0;
        assert!((twist_about(&q0, &about_x, &Vector3::x()) - 0.3).abs() < 1e-12);
        assert!((twist_about(&q0, &about_x, &-Vector3::x()) + 0.3).abs() < 1e-12);
        let about_y = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.3) * q0;
        assert!(twist_about(&q0, &about_y, &Vector3::x()).abs() < 1e-12);
    }
}
