//! The grasped object run away from the devices: the application steps the body at its own rate
//! (100 Hz–1 kHz) and each device renders the body's surface as its local model at the control
//! rate. This is the seam between the two: where each device sits in the world, the body's pose
//! as each device's model pose, and each device's rendered contact as a wrench on the body.
//!
//! Frames: the **world** frame of the body; each device's **base** frame
//! ([`crate::device::delta`]) placed in the world by its [`DeviceMount`]: `p_W = o + R·p_B`.
//!
//! A device reports (its state sample) the force it renders on the fingertip `F` (base frame, N),
//! the spin torque τn about the contact normal (the moment on the fingertip is −τn·n, see
//! [`crate::contact::spin`]), the contact point on the object `c` and the fingertip centre `p`
//! (base frame, m). The body takes the reaction, as [`crate::grasp::fingertip_contact`] does:
//!
//! ```text
//! on the body:  −F_W,   τ = (c_W − x) × (−F_W) + τn·n_W    (about the centre of mass)
//! n_W = R·(p − c)/|p − c|                                   (the body's outward normal at c)
//! ```
//!
//! Or the application runs its own copy of the two contacts ([`crate::grasp::Grasp`]) on the
//! devices' fingertips ([`DeviceMount::fingertip`]): the same model on both sides, the object's
//! fast contact modes then inside the application's loop rather than across the link.
//!
//! The normal comes from the sample itself: a fingertip sphere touching a convex surface has its
//! centre on the surface normal through the contact point, so no shape is needed here.

use crate::control::local_model::ModelPose;
use crate::flags::Flags;
use crate::grasp::body::BodyState;
use crate::grasp::fingertip_contact::{Fingertip, Wrench};
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// Where one device's base frame is in the world: `p_W = origin_m + orientation·p_B`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceMount {
    /// The base frame's origin, world frame, m.
    pub origin_m: Vec3,
    /// Unit quaternion mapping base-frame vectors to the world frame.
    pub orientation: Quat,
}

/// One device's rendered contact as its state sample carries it. Base frame, SI units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DeviceContact {
    /// Force rendered on the fingertip, N.
    pub force_n: Vec3,
    /// Spin torque τn about the contact normal, N·m (moment on the fingertip −τn·n).
    pub spin_torque_nm: f32,
    /// Contact point on the object, m.
    pub contact_point_m: Vec3,
    /// Fingertip centre, m.
    pub probe_m: Vec3,
    /// Fingertip velocity, m/s.
    pub probe_vel_m_s: Vec3,
}

impl DeviceMount {
    /// A base-frame point in the world.
    pub fn point_to_world(&self, p_base: Vec3) -> Vec3 {
        self.origin_m + self.orientation.rotate(p_base)
    }

    /// A base-frame vector in the world.
    pub fn vector_to_world(&self, v_base: Vec3) -> Vec3 {
        self.orientation.rotate(v_base)
    }

    /// A world point in the base frame.
    pub fn point_to_base(&self, p_world: Vec3) -> Vec3 {
        self.orientation.conjugate().rotate(p_world - self.origin_m)
    }

    /// A world vector in the base frame.
    pub fn vector_to_base(&self, v_world: Vec3) -> Vec3 {
        self.orientation.conjugate().rotate(v_world)
    }

    /// This device's fingertip in the world, for the application's own copy of the contacts
    /// ([`crate::grasp::Grasp`] fed with the devices' fingertips): centre and velocity from the
    /// sample, orientation the base frame's (the state sample carries no wrist angles; a pinch
    /// holds the fingertip's orientation).
    pub fn fingertip(&self, c: &DeviceContact) -> Fingertip {
        Fingertip {
            pos_m: self.point_to_world(c.probe_m),
            vel_m_s: self.vector_to_world(c.probe_vel_m_s),
            q: self.orientation,
        }
    }

    /// The body's pose as this device's local-model pose: the body's object frame in the base frame.
    pub fn model_pose(&self, body: &BodyState) -> ModelPose {
        let q_c = self.orientation.conjugate();
        ModelPose {
            position_m: self.point_to_base(body.pos_m),
            orientation: q_c * body.q,
        }
    }

    /// [`Self::model_pose`] of the body as it will be `lead_s` seconds on, at its present linear
    /// and angular velocity: the application sends this to hide the delay between its step and the
    /// device rendering it (the link latency, half a model period of sample-and-hold, half the
    /// device's blend). `lead_s` = 0 is the pose itself; a non-finite or negative lead is taken as 0.
    pub fn model_pose_ahead<M: Math>(&self, body: &BodyState, lead_s: f32) -> ModelPose {
        let lead = if lead_s.is_finite() && lead_s > 0.0 {
            lead_s
        } else {
            0.0
        };
        let (dq, _) = Quat::from_rotation_vector::<M>(body.omega_body * lead);
        let ahead = BodyState {
            pos_m: body.pos_m + body.vel_m_s * lead,
            q: body.q * dq,
            ..*body
        };
        self.model_pose(&ahead)
    }

    /// The wrench this device's contact puts on the body (world frame, moment about the centre of
    /// mass): the reaction of what the device renders on the fingertip. A non-finite sample gives
    /// zero and [`Flags::NON_FINITE_INPUT`]; a contact point on the fingertip centre (no normal
    /// to put the spin torque on) drops the spin torque with [`Flags::ZERO_AXIS`].
    pub fn wrench_on_body<M: Math>(&self, c: &DeviceContact, body: &BodyState) -> (Wrench, Flags) {
        let finite = c.force_n.is_finite()
            && c.spin_torque_nm.is_finite()
            && c.contact_point_m.is_finite()
            && c.probe_m.is_finite();
        if !finite {
            return (Wrench::default(), Flags::NON_FINITE_INPUT);
        }
        let f_w = self.vector_to_world(c.force_n);
        let point_w = self.point_to_world(c.contact_point_m);
        let out = self.vector_to_world(c.probe_m - c.contact_point_m);
        let len = out.norm::<M>();
        let mut flags = Flags::NONE;
        let spin = if len > 1.0e-9 {
            out * (c.spin_torque_nm / len)
        } else {
            if c.spin_torque_nm != 0.0 {
                flags |= Flags::ZERO_AXIS;
            }
            Vec3::ZERO
        };
        let wrench = Wrench {
            force_n: -f_w,
            torque_nm: (point_w - body.pos_m).cross(-f_w) + spin,
        };
        (wrench, flags)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    fn mount() -> DeviceMount {
        DeviceMount {
            origin_m: Vec3::new(-0.12, 0.01, 0.02),
            orientation: Quat::from_axis_angle::<Libm>(Vec3::new(0.48, 0.8, -0.36), 1.1),
        }
    }

    fn body() -> BodyState {
        BodyState {
            pos_m: Vec3::new(0.01, -0.02, 0.03),
            q: Quat::from_axis_angle::<Libm>(Vec3::new(0.8, 0.6, 0.0), 0.4),
            ..BodyState::default()
        }
    }

    #[test]
    fn model_pose_maps_body_points_to_the_same_world_points() {
        let (m, b) = (mount(), body());
        let pose = m.model_pose(&b);
        let p_body = Vec3::new(0.03, 0.0, -0.01);
        let via_device = m.point_to_world(pose.point_to_base(p_body));
        let direct = b.pos_m + b.q.rotate(p_body);
        // f32 rounding of two rotations and translations of ~0.1 m: measured 1.8e-8 m; bound 3×.
        let e = (via_device - direct).norm::<Libm>();
        std::println!("pose round trip error {e:e} m");
        assert!(e < 5.0e-8, "{e}");
    }

    #[test]
    fn the_pose_ahead_is_the_pose_moved_on_at_the_body_velocity() {
        let (m, mut b) = (mount(), body());
        b.vel_m_s = Vec3::new(0.02, 0.0, -0.01);
        b.omega_body = Vec3::new(0.0, 0.0, 2.0);
        assert_eq!(m.model_pose_ahead::<Libm>(&b, 0.0), m.model_pose(&b));
        assert_eq!(m.model_pose_ahead::<Libm>(&b, f32::NAN), m.model_pose(&b));
        assert_eq!(m.model_pose_ahead::<Libm>(&b, -1.0), m.model_pose(&b));
        let ahead = m.model_pose_ahead::<Libm>(&b, 0.005);
        let moved = m.point_to_world(ahead.position_m) - b.pos_m;
        // 5 ms at 22.4 mm/s: 0.112 mm; f32 rounding measured below 1e-8 m.
        assert!(
            (moved - b.vel_m_s * 0.005).norm::<Libm>() < 3.0e-8,
            "{moved:?}"
        );
        // The body turned 10 mrad about its own z.
        let turn = (m.model_pose(&b).orientation.conjugate() * ahead.orientation)
            .to_rotation_vector::<Libm>();
        assert!(
            (turn.z - 0.01).abs() < 1.0e-6 && turn.x.abs() < 1.0e-6,
            "{turn:?}"
        );
    }

    #[test]
    fn the_body_takes_the_reaction_of_the_rendered_wrench() {
        let (m, b) = (mount(), body());
        // A fingertip pressing on the body's surface along the outward normal n (world) at c.
        let n_w = Vec3::new(0.0, 0.6, 0.8);
        let c_w = b.pos_m + n_w * 0.03;
        let p_w = c_w + n_w * 0.01;
        let f_w = n_w * 3.0 + Vec3::new(0.5, 0.0, 0.0);
        let tau = 0.004;
        let sample = DeviceContact {
            force_n: m.vector_to_base(f_w),
            spin_torque_nm: tau,
            contact_point_m: m.point_to_base(c_w),
            probe_m: m.point_to_base(p_w),
            probe_vel_m_s: Vec3::ZERO,
        };
        let (w, flags) = m.wrench_on_body::<Libm>(&sample, &b);
        assert_eq!(flags, Flags::NONE);
        let ef = (w.force_n + f_w).norm::<Libm>();
        std::println!("force error {ef:e} N");
        // f32 rounding of the rotations of a 3 N force: measured 2.7e-7 N; bound 3×.
        assert!(ef < 8.0e-7, "{ef}");
        // About a common point (the fingertip centre) the moments on body and fingertip cancel:
        // on the fingertip (c − p) × F − τn·n; on the body, moved to p, w.τ + (x − p) × w.F.
        let on_tip = (c_w - p_w).cross(f_w) - n_w * tau;
        let on_body_at_p = w.torque_nm + (b.pos_m - p_w).cross(w.force_n);
        // f32 rounding: measured 1.2e-8 N·m; bound 3×.
        let em = (on_tip + on_body_at_p).norm::<Libm>();
        std::println!("moment error {em:e} N·m");
        assert!(em < 3.6e-8, "{em}");
    }

    #[test]
    fn bad_samples_give_zero_and_a_flag() {
        let (m, b) = (mount(), body());
        let bad = DeviceContact {
            force_n: Vec3::new(f32::NAN, 0.0, 0.0),
            ..DeviceContact::default()
        };
        let (w, f) = m.wrench_on_body::<Libm>(&bad, &b);
        assert_eq!(w, Wrench::default());
        assert!(f.contains(Flags::NON_FINITE_INPUT));
        // A contact point on the fingertip centre: no normal for the spin torque.
        let degenerate = DeviceContact {
            force_n: Vec3::new(1.0, 0.0, 0.0),
            spin_torque_nm: 0.01,
            ..DeviceContact::default()
        };
        let (w, f) = m.wrench_on_body::<Libm>(&degenerate, &b);
        assert!(f.contains(Flags::ZERO_AXIS));
        assert!(w.torque_nm.is_finite());
        // The same with no spin torque raises nothing.
        let quiet = DeviceContact {
            spin_torque_nm: 0.0,
            ..degenerate
        };
        assert_eq!(m.wrench_on_body::<Libm>(&quiet, &b).1, Flags::NONE);
    }
}
