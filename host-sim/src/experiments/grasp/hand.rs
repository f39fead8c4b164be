//! A simulated hand driving one fingertip: it squeezes with a set grip force along the grasp axis
//! and holds the fingertip on a path (the lift) across it with a stiff spring and damper; the
//! fingertip is a point mass that also receives the contact's reaction, so the wrench on the
//! fingertip and the wrench on the object are equal and opposite. The hand holds the fingertip's
//! orientation fixed (a pinch: the fingertips do not turn); the contact's moment on the fingertip
//! is taken by the hand.
//!
//! Units SI, world frame (z up).

use nalgebra::Vector3;
use softfinger_core::grasp::Fingertip;
use softfinger_core::{Quat, Vec3};

/// Mass of the fingertip and the hand's distal phalanx that moves with it, kg.
pub const FINGERTIP_MASS_KG: f64 = 0.02;
/// Stiffness of the hand's hold across the grasp axis, N/m.
pub const HOLD_STIFFNESS: f64 = 20000.0;
/// Damping of that hold, N·s/m.
pub const HOLD_DAMPING: f64 = 40.0;
/// Damping of the squeeze along the grasp axis (the arm's own), N·s/m.
pub const SQUEEZE_DAMPING: f64 = 5.0;

/// One hand and its fingertip.
#[derive(Clone, Copy, Debug)]
pub struct Hand {
    /// Unit direction of the squeeze (from the fingertip towards the object), world.
    pub axis: Vector3<f64>,
    /// The grip force the hand pushes with, N.
    pub grip_n: f64,
    /// Where the hand holds the fingertip at lift 0 (across the axis; the axial coordinate is free).
    pub home: Vector3<f64>,
    /// Fingertip centre, m.
    pub pos: Vector3<f64>,
    /// Fingertip velocity, m/s.
    pub vel: Vector3<f64>,
}

impl Hand {
    /// A hand at rest with its fingertip at `pos`, squeezing along `axis` (unit) with `grip_n`.
    pub fn new(pos: Vector3<f64>, axis: Vector3<f64>, grip_n: f64) -> Hand {
        Hand {
            axis,
            grip_n,
            home: pos,
            pos,
            vel: Vector3::zeros(),
        }
    }

    /// The fingertip as the core's grasp takes it.
    pub fn fingertip(&self) -> Fingertip {
        Fingertip {
            pos_m: v32(self.pos),
            vel_m_s: v32(self.vel),
            q: Quat::IDENTITY,
        }
    }

    /// One semi-implicit Euler step of `dt` s: the hand's force (grip along the axis, the hold
    /// towards `home + lift` across it) plus `contact_n` (the contact's force on the fingertip).
    /// `open`: the hand lets go (no grip, it pulls the fingertip back 10 mm along the axis).
    pub fn step(
        &mut self,
        lift: Vector3<f64>,
        lift_vel: Vector3<f64>,
        contact_n: Vec3,
        open: bool,
        dt: f64,
    ) {
        let u = self.axis;
        let across = |v: Vector3<f64>| v - u * u.dot(&v);
        let target = self.home + lift;
        let hold =
            across(target - self.pos) * HOLD_STIFFNESS + across(lift_vel - self.vel) * HOLD_DAMPING;
        let squeeze = if open {
            // Back 10 mm from home along the axis, stiffly.
            let back = self.home - u * 0.01;
            u * (u.dot(&(back - self.pos)) * HOLD_STIFFNESS)
        } else {
            u * self.grip_n
        };
        let damp = -u * (u.dot(&self.vel) * SQUEEZE_DAMPING);
        let f = hold + squeeze + damp + v64(contact_n);
        self.vel += f * (dt / FINGERTIP_MASS_KG);
        self.pos += self.vel * dt;
    }
}

/// f64 → core f32 vector.
pub fn v32(v: Vector3<f64>) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Core f32 → f64 vector.
pub fn v64(v: Vec3) -> Vector3<f64> {
    Vector3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}
