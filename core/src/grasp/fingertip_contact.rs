//! One fingertip touching the free body: the existing soft-finger contact model run in the body's
//! frame, its force and spin torque turned into equal and opposite world-frame wrenches on the body
//! and on the fingertip.
//!
//! The contact model ([`ContactModel`]) sees the body as its fixed object: each tick the
//! fingertip's centre, velocity and orientation are expressed relative to the body,
//!
//! ```text
//! probe     = qᵀ·(p_tip − x)                       (object frame, m)
//! probe_vel = qᵀ·(v_tip − v − ω_W × (p_tip − x))   (object frame, m/s)
//! q_rel     = q* ⊗ q_tip                           (fingertip → body)
//! ```
//!
//! so the normal spring and damper, the friction proxy, the limit surface coupling twist and slide,
//! the rolling of the contact point on both surfaces and the state machine are those of the
//! one-fingertip rendering, unchanged. Its force `F` (object frame, on the fingertip) and spin torque
//! τn (about the outward normal n; the moment on the fingertip is −τn·n, see
//! [`crate::contact::spin`]) give, with c the contact point (world):
//!
//! ```text
//! on the fingertip: F_W = q·F,   τ = (c − p_tip) × F_W − τn·n_W   (about the fingertip centre)
//! on the body:     −F_W,         τ = (c − x) × (−F_W) + τn·n_W     (about the centre of mass)
//! ```

use crate::contact::limit_surface::patch_radius;
use crate::contact::spin::torsion_limit;
use crate::contact::{
    ContactInput, ContactModel, ContactOutput, ContactParams, Full, Parts, Surface,
};
use crate::grasp::body::BodyState;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// A force and a moment, world frame (N, N·m); the moment about the point the context names.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Wrench {
    /// Force, N.
    pub force_n: Vec3,
    /// Moment, N·m.
    pub torque_nm: Vec3,
}

/// A fingertip sample, world frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fingertip {
    /// Fingertip centre, m.
    pub pos_m: Vec3,
    /// Velocity of the centre, m/s.
    pub vel_m_s: Vec3,
    /// Orientation, fingertip → world.
    pub q: Quat,
}

/// What one contact did in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactReport {
    /// False when no fingertip was given for this contact (its model is held broken).
    pub active: bool,
    /// The contact model's own output (the body's object frame).
    pub output: ContactOutput,
    /// Wrench on the body, moment about its centre of mass.
    pub on_body: Wrench,
    /// Wrench on the fingertip, moment about the fingertip centre (equal and opposite force).
    pub on_fingertip: Wrench,
    /// Contact point on the body, world frame, m.
    pub point_w: Vec3,
    /// Outward unit normal of the body at the contact, world frame.
    pub normal_w: Vec3,
    /// Normal force f_N ≥ 0, N.
    pub normal_force_n: f32,
    /// Tangential force |f_t|, N.
    pub tangential_force_n: f32,
    /// The static tangential limit μ_s·f_N at this tick's normal force, N.
    pub f_max_n: f32,
    /// The static torsional limit τ_max(f_N) at this tick's normal force, N·m.
    pub tau_max_nm: f32,
}

/// One fingertip's contact with the body. `P`: the parts of the contact model it runs
/// ([`crate::contact::parts`]; the whole model unless named), so a grasp that leaves a part out
/// does not pay for it.
#[derive(Clone, Copy, Debug)]
pub struct FingertipContact<M: Math, S: Surface, P: Parts = Full> {
    model: ContactModel<M, S, P>,
}

impl<M: Math, S: Surface> FingertipContact<M, S, Full> {
    /// A contact of the whole model with `params` on `surface` (the body's object frame), stepped
    /// every `dt_s`. [`FingertipContact::with_parts`] for a reduced model.
    pub fn new(
        params: ContactParams,
        surface: S,
        dt_s: f32,
    ) -> Result<Self, crate::contact::ParamError> {
        Self::with_parts(params, surface, dt_s)
    }
}

impl<M: Math, S: Surface, P: Parts> FingertipContact<M, S, P> {
    /// A contact of the model of parts `P` with `params` on `surface` (the body's object frame), stepped every
    /// `dt_s`.
    pub fn with_parts(
        params: ContactParams,
        surface: S,
        dt_s: f32,
    ) -> Result<Self, crate::contact::ParamError> {
        Ok(FingertipContact {
            model: ContactModel::with_parts(params, surface, Quat::IDENTITY, dt_s)?,
        })
    }

    /// The contact model.
    pub fn model(&self) -> &ContactModel<M, S, P> {
        &self.model
    }

    /// The static limits (μ_s·f_N in N, τ_max in N·m) at the normal force `f_n` (N), as the model
    /// computes them: τ_max = (3π/16)·μ_s·f_N·a(f_N), a the patch radius's power law.
    pub fn limits_at(&self, f_n: f32) -> (f32, f32) {
        let p = self.model.params();
        let a = patch_radius(f_n, p.patch_radius_m, p.patch_ref_force_n, p.patch_exponent);
        (p.mu_s * f_n.max(0.0), torsion_limit(p.mu_s, f_n, a))
    }

    /// One tick of the contact between `tip` and the body in `body` (its state before the tick).
    /// `None`: no fingertip; the model is stepped with its probe far out along the normal, so it
    /// breaks and renders nothing (no force holds a body a fingertip has left). A point contact (no
    /// torsion) is the model with spin stiffness k_z = 0: its spin torque is then exactly zero.
    pub fn step(&mut self, body: &BodyState, tip: Option<&Fingertip>) -> ContactReport {
        let q_c = body.q.conjugate();
        let input = match tip {
            Some(t) => {
                let r_w = t.pos_m - body.pos_m;
                ContactInput {
                    q: q_c * t.q,
                    probe_m: q_c.rotate(r_w),
                    probe_vel: q_c.rotate(t.vel_m_s - body.point_velocity(t.pos_m)),
                }
            }
            None => {
                let s = self.model.rolling().surface();
                let r = self.model.params().fingertip_radius_m;
                ContactInput {
                    q: self.model.rolling().q_prev(),
                    probe_m: s.contact_point() + s.normal() * (r + 1.0),
                    probe_vel: Vec3::ZERO,
                }
            }
        };
        let out = self.model.contact_step(&input);
        let surface = self.model.rolling().surface();
        let normal_w = body.q.rotate(surface.normal());
        let point_w = body.pos_m + body.q.rotate(out.object_point_m);
        let f_w = body.q.rotate(out.force_n);
        let tau = out.tau_n_nm;
        let f_normal = f_w.dot(normal_w);
        let f_t = f_w - normal_w * f_normal;
        let normal_force_n = f_normal.max(0.0);
        let (f_max_n, tau_max_nm) = self.limits_at(normal_force_n);
        let tip_centre = tip.map_or(point_w, |t| t.pos_m);
        ContactReport {
            active: tip.is_some(),
            output: out,
            on_body: Wrench {
                force_n: -f_w,
                torque_nm: (point_w - body.pos_m).cross(-f_w) + normal_w * tau,
            },
            on_fingertip: Wrench {
                force_n: f_w,
                torque_nm: (point_w - tip_centre).cross(f_w) - normal_w * tau,
            },
            point_w,
            normal_w,
            normal_force_n,
            tangential_force_n: f_t.norm::<M>(),
            f_max_n,
            tau_max_nm,
        }
    }
}
