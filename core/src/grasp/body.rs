//! A free rigid body: mass, principal inertia, pose and velocity, stepped by semi-implicit
//! (symplectic) Euler at the control rate.
//!
//! Frames (the crate's frames table, [`crate`]): the world frame `W` (gravity along −z in the
//! grasp scenes) and the body's object frame `O` (origin at the centre of mass, axes along the
//! principal axes of inertia). The orientation `q` maps object-frame vectors to world vectors,
//! `v_W = q·v_O·q*`.
//!
//! Equations (SI units):
//!
//! ```text
//! m·v̇  = F_W − c_v·v                         (linear velocity v in W, force F_W in W)
//! I·ω̇  = τ_O − ω × (I·ω) − c_ω·ω              (ω in O, I = diag(I_x, I_y, I_z), τ_O = qᵀ·τ_W)
//! ẋ    = v,   q̇ = ½·q ⊗ (0, ω)
//! ```
//!
//! Integrator (semi-implicit Euler, step h): v ← v + h·v̇(v), ω ← ω + h·ω̇(ω), then x ← x + h·v and
//! q ← normalise(q ⊗ exp(h·ω)) with the new velocities (the exponential map: exact for constant ω
//! over the step). Its error against a fine-step f64 RK4 of the same equations is measured in
//! host-sim's `grasp_integrator` test.

use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// Why a body was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyError {
    /// The named field is NaN, ±inf, zero or negative where it must be > 0, or negative where it
    /// must be ≥ 0.
    NotPositive(&'static str),
    /// The principal moments break the triangle inequality (I_x + I_y ≥ I_z and permutations): no
    /// rigid body has them.
    InertiaNotPhysical,
}

impl core::fmt::Display for BodyError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BodyError::NotPositive(name) => write!(f, "{name} must be finite and > 0 (>= 0 for damping)"),
            BodyError::InertiaNotPhysical => write!(
                f,
                "principal inertia breaks the triangle inequality (I_x + I_y >= I_z and permutations)"
            ),
        }
    }
}

/// A body's fixed properties.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyParams {
    /// Mass m, kg (> 0).
    pub mass_kg: f32,
    /// Principal moments of inertia (I_x, I_y, I_z) about the centre of mass, object frame, kg·m²
    /// (each > 0).
    pub inertia_kg_m2: Vec3,
    /// c_v: viscous damping of the linear velocity (the air, the table's drag), N·s/m (≥ 0).
    pub linear_damping: f32,
    /// c_ω: viscous damping of the angular velocity, N·m·s/rad (≥ 0).
    pub angular_damping: f32,
}

impl BodyParams {
    /// A solid sphere of mass `mass_kg` and radius `radius_m`: I = (2/5)·m·R² about every axis.
    pub fn solid_sphere(mass_kg: f32, radius_m: f32) -> BodyParams {
        let i = 0.4 * mass_kg * radius_m * radius_m;
        BodyParams {
            mass_kg,
            inertia_kg_m2: Vec3::new(i, i, i),
            linear_damping: 0.0,
            angular_damping: 0.0,
        }
    }

    /// A solid cylinder of mass `mass_kg`, radius `radius_m` and length `length_m` with its axis
    /// along body x: I_x = m·R²/2, I_y = I_z = m·(3R² + L²)/12.
    pub fn solid_cylinder_x(mass_kg: f32, radius_m: f32, length_m: f32) -> BodyParams {
        let r2 = radius_m * radius_m;
        let ix = 0.5 * mass_kg * r2;
        let iy = mass_kg * (3.0 * r2 + length_m * length_m) / 12.0;
        BodyParams {
            mass_kg,
            inertia_kg_m2: Vec3::new(ix, iy, iy),
            linear_damping: 0.0,
            angular_damping: 0.0,
        }
    }

    /// Check every field; the first bad one is named.
    pub fn validate(&self) -> Result<(), BodyError> {
        let pos = |name, v: f32| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(BodyError::NotPositive(name))
            }
        };
        let non_neg = |name, v: f32| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(BodyError::NotPositive(name))
            }
        };
        pos("mass_kg", self.mass_kg)?;
        let i = self.inertia_kg_m2;
        pos("inertia_kg_m2.x", i.x)?;
        pos("inertia_kg_m2.y", i.y)?;
        pos("inertia_kg_m2.z", i.z)?;
        // A relative slack of 1e-5 for moments computed in f32 (a thin rod or disc sits on the edge).
        let tri = |a: f32, b: f32, c: f32| a + b >= c * (1.0 - 1.0e-5);
        if !(tri(i.x, i.y, i.z) && tri(i.y, i.z, i.x) && tri(i.z, i.x, i.y)) {
            return Err(BodyError::InertiaNotPhysical);
        }
        non_neg("linear_damping", self.linear_damping)?;
        non_neg("angular_damping", self.angular_damping)?;
        Ok(())
    }
}

/// A body's pose and velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// Centre of mass, world frame, m.
    pub pos_m: Vec3,
    /// Velocity of the centre of mass, world frame, m/s.
    pub vel_m_s: Vec3,
    /// Orientation, body → world (unit).
    pub q: Quat,
    /// Angular velocity, object frame, rad/s.
    pub omega_body: Vec3,
}

impl Default for BodyState {
    fn default() -> BodyState {
        BodyState {
            pos_m: Vec3::ZERO,
            vel_m_s: Vec3::ZERO,
            q: Quat::IDENTITY,
            omega_body: Vec3::ZERO,
        }
    }
}

impl BodyState {
    /// Angular velocity in the world frame, rad/s.
    pub fn omega_world(&self) -> Vec3 {
        self.q.rotate(self.omega_body)
    }

    /// Velocity of the body point at world position `p_m` (m), world frame, m/s.
    pub fn point_velocity(&self, p_m: Vec3) -> Vec3 {
        self.vel_m_s + self.omega_world().cross(p_m - self.pos_m)
    }

    fn is_finite(&self) -> bool {
        self.pos_m.is_finite()
            && self.vel_m_s.is_finite()
            && self.q.is_finite()
            && self.omega_body.is_finite()
    }
}

/// A rigid body with its state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBody {
    params: BodyParams,
    inv_mass: f32,
    inv_inertia: Vec3,
    /// The current pose and velocity.
    pub state: BodyState,
}

impl RigidBody {
    /// A body with validated `params` at `state` (its quaternion normalised).
    pub fn new(params: BodyParams, state: BodyState) -> Result<RigidBody, BodyError> {
        params.validate()?;
        let i = params.inertia_kg_m2;
        let mut state = state;
        if !state.is_finite() {
            return Err(BodyError::NotPositive("initial state (non-finite)"));
        }
        let (q, f) = state.q.normalized_checked::<crate::math::Libm>();
        if f.intersects(Flags::ZERO_AXIS | Flags::NON_FINITE_INPUT) {
            return Err(BodyError::NotPositive("initial orientation norm"));
        }
        state.q = q;
        Ok(RigidBody {
            params,
            inv_mass: 1.0 / params.mass_kg,
            inv_inertia: Vec3::new(1.0 / i.x, 1.0 / i.y, 1.0 / i.z),
            state,
        })
    }

    /// The body's fixed properties.
    pub fn params(&self) -> &BodyParams {
        &self.params
    }

    /// One semi-implicit Euler step of `dt_s` seconds under the world-frame force `force_w` (N,
    /// through the centre of mass) and torque `torque_w` (N·m, about the centre of mass). A
    /// non-finite wrench is ignored (zero) with [`Flags::NON_FINITE_INPUT`]; a step whose result is
    /// not finite (an overflow) is undone, the body stopped where it was, and
    /// [`Flags::NON_FINITE_OUTPUT`] raised. Never panics.
    pub fn step<M: Math>(&mut self, force_w: Vec3, torque_w: Vec3, dt_s: f32) -> Flags {
        let mut flags = Flags::NONE;
        let (force_w, torque_w) = if force_w.is_finite() && torque_w.is_finite() {
            (force_w, torque_w)
        } else {
            flags |= Flags::NON_FINITE_INPUT;
            (Vec3::ZERO, Vec3::ZERO)
        };
        let p = &self.params;
        let s = self.state;
        let i = p.inertia_kg_m2;
        let vel = s.vel_m_s + (force_w - s.vel_m_s * p.linear_damping) * (dt_s * self.inv_mass);
        let w = s.omega_body;
        let tau_b = s.q.conjugate().rotate(torque_w);
        let iw = Vec3::new(i.x * w.x, i.y * w.y, i.z * w.z);
        let rhs = tau_b - w.cross(iw) - w * p.angular_damping;
        let ii = self.inv_inertia;
        let w = w + Vec3::new(rhs.x * ii.x, rhs.y * ii.y, rhs.z * ii.z) * dt_s;
        let pos = s.pos_m + vel * dt_s;
        let (dq, f) = Quat::from_rotation_vector::<M>(w * dt_s);
        let (q, fq) = (s.q * dq).normalized_checked::<M>();
        let next = BodyState {
            pos_m: pos,
            vel_m_s: vel,
            q,
            omega_body: w,
        };
        if next.is_finite() && !(f | fq).intersects(Flags::NON_FINITE_INPUT | Flags::ZERO_AXIS) {
            self.state = next;
        } else {
            self.state.vel_m_s = Vec3::ZERO;
            self.state.omega_body = Vec3::ZERO;
            flags |= Flags::NON_FINITE_OUTPUT;
        }
        flags
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    fn ball() -> RigidBody {
        RigidBody::new(BodyParams::solid_sphere(0.1, 0.03), BodyState::default()).unwrap()
    }

    #[test]
    fn free_fall_matches_the_closed_form_of_semi_implicit_euler() {
        // v_n = n·h·g, x_n = h²·g·n(n+1)/2: the integrator's own closed form, exactly.
        let mut b = ball();
        let (g, h, n) = (-9.81_f32, 1.0e-3_f32, 1000);
        for _ in 0..n {
            b.step::<Libm>(Vec3::new(0.0, 0.0, 0.1 * g), Vec3::ZERO, h);
        }
        let nf = n as f32;
        let x = h * h * g * nf * (nf + 1.0) / 2.0;
        assert!(
            (b.state.pos_m.z - x).abs() < 1.0e-4 * x.abs(),
            "{} vs {x}",
            b.state.pos_m.z
        );
        assert!((b.state.vel_m_s.z - nf * h * g).abs() < 1.0e-4);
    }

    #[test]
    fn constant_torque_spins_at_tau_over_i() {
        let mut b = ball();
        let i = b.params().inertia_kg_m2.x;
        for _ in 0..1000 {
            b.step::<Libm>(Vec3::ZERO, Vec3::new(1.0e-4, 0.0, 0.0), 1.0e-3);
        }
        let w = b.state.omega_world().x;
        assert!((w - 1.0e-4 / i).abs() < 1.0e-4 * (1.0e-4 / i), "{w}");
        // Angle = Σ h·ω_n = h²·α·n(n+1)/2.
        let angle = b.state.q.to_rotation_vector::<Libm>().x;
        let expect = 1.0e-6 * (1.0e-4 / i) * 1000.0 * 1001.0 / 2.0;
        assert!(
            (angle - expect).abs() < 1.0e-3 * expect,
            "{angle} vs {expect}"
        );
    }

    #[test]
    fn bad_parameters_are_named() {
        let mut p = BodyParams::solid_sphere(0.1, 0.03);
        p.mass_kg = 0.0;
        assert_eq!(p.validate(), Err(BodyError::NotPositive("mass_kg")));
        p.mass_kg = f32::NAN;
        assert_eq!(p.validate(), Err(BodyError::NotPositive("mass_kg")));
        let mut p = BodyParams::solid_sphere(0.1, 0.03);
        p.inertia_kg_m2.y = 0.0;
        assert_eq!(p.validate(), Err(BodyError::NotPositive("inertia_kg_m2.y")));
        p.inertia_kg_m2 = Vec3::new(1.0, 1.0, 2.01);
        assert_eq!(p.validate(), Err(BodyError::InertiaNotPhysical));
        p.inertia_kg_m2 = Vec3::new(1.0, 1.0, 1.99);
        assert_eq!(p.validate(), Ok(()));
        p.angular_damping = -1.0;
        assert_eq!(p.validate(), Err(BodyError::NotPositive("angular_damping")));
    }

    #[test]
    fn non_finite_wrench_is_ignored_and_flagged() {
        let mut b = ball();
        let before = b.state;
        let f = b.step::<Libm>(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ZERO, 1.0e-3);
        assert!(f.contains(Flags::NON_FINITE_INPUT));
        assert_eq!(b.state, before);
    }

    #[test]
    fn an_overflowing_step_is_undone_and_flagged() {
        let mut b = ball();
        let f = b.step::<Libm>(Vec3::new(f32::MAX, 0.0, 0.0), Vec3::ZERO, 1.0);
        let f2 = b.step::<Libm>(Vec3::new(f32::MAX, 0.0, 0.0), Vec3::ZERO, 1.0);
        assert!((f | f2).contains(Flags::NON_FINITE_OUTPUT));
        assert!(b.state.is_finite());
    }
}
