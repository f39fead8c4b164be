//! The full contact step: one orientation and probe sample in; contact points, force to render,
//! spin torque and contact state out. Composes [`Rolling`], [`SpinSpring`], the state machine and the
//! proxy coupling of section 3.2.
//!
//! Proxy coupling (section 3.2): in rolling, a spring-damper connects the fingertip centre implied by
//! rolling (the *anchor*: contact point + ρ·n) and the measured probe (fingertip centre), so rolling
//! the wrist drags the finger along the surface as a real fingertip would. In sliding the spring
//! slips: the anchor is dragged by the probe and kept within μ_k·f_N/K_t of it, so the rendered
//! tangential force sits on the kinetic friction cone, opposing the slide (a god-object friction
//! proxy). Normally the surface pushes back with a unilateral spring-damper on the penetration.
//! Why a proxy rather than velocity-based Coulomb friction: docs/design.md#friction-proxy.
//!
//! All vectors are in the object frame (`O`): for the plane z is the normal.

use crate::contact::decompose::Angles;
use crate::contact::limit_surface::{patch_radius, project};
use crate::contact::params::{ContactParams, Material};
use crate::contact::parts::{Full, Parts};
use crate::contact::rolling::{RollStep, Rolling};
use crate::contact::spin::{fast_test_applies, torsion_limit, SpinSpring};
use crate::contact::state::{
    next_state_derived, ContactState, Derived, Reason, StateInputs, StateParams,
};
use crate::contact::surface::Surface;
use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;
use crate::validate::{Checked, ParamError};
use core::marker::PhantomData;

/// Shortest accepted step, s (1 MHz): 1/dt and the finite differences stay finite.
pub const MIN_DT_S: f32 = 1.0e-6;
/// Longest accepted step, s (1 Hz).
pub const MAX_DT_S: f32 = 1.0;

/// Largest accepted distance of the probe from the object frame's origin (Euclidean norm), m: a
/// haptic workspace is well under 1 m; beyond this the sample is corrupt, and products with
/// stiffnesses and rates would overflow f32.
pub const MAX_PROBE_M: f32 = 100.0;
/// Largest accepted probe speed (Euclidean norm), m/s.
pub const MAX_PROBE_SPEED_M_S: f32 = 100.0;

/// One sample of the fingertip.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ContactInput {
    /// Fingertip orientation, fingertip frame → object frame (normalised by the step).
    pub q: Quat,
    /// Probe = fingertip centre, object frame, m.
    pub probe_m: Vec3,
    /// Probe velocity, object frame, m/s.
    pub probe_vel: Vec3,
}

/// What one contact step produced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ContactOutput {
    /// Force to render on the probe (the user's finger), object frame, N. |F| ≤ max_force_n.
    pub force_n: Vec3,
    /// Spin torque about the normal τn = k_z·φ_el, N·m (eq. 1, saturated at the torsional limit).
    pub tau_n_nm: f32,
    /// Accumulated spin about the normal since the contact began, rad.
    pub spin_rad: f32,
    /// Contact state after the step.
    pub state: ContactState,
    /// Why (transition or kept).
    pub reason: Reason,
    /// Contact point on the object, object frame, m.
    pub object_point_m: Vec3,
    /// Decomposed increment of this step (contact frame), rad.
    pub angles: Angles,
    /// Flags raised this step.
    pub flags: Flags,
}

/// The contact model with its state. `M`: math backend; `S`: object surface; `P`: the parts of the
/// model it runs ([`crate::contact::parts`]; the whole model unless named).
#[derive(Clone, Copy, Debug)]
pub struct ContactModel<M: Math, S: Surface, P: Parts = Full> {
    params: ContactParams,
    state_params: StateParams,
    /// What the state machine derives from `state_params` (fixed: the material does not change it).
    state_derived: Derived,
    /// Rolling kinematics (contact points, previous orientation).
    pub(crate) rolling: Rolling<S>,
    /// Torsion spring of the soft finger.
    pub(crate) spin: SpinSpring,
    state: ContactState,
    time_in_state_s: f32,
    dt_s: f32,
    /// 1/dt_s, Hz (precomputed: a division per tick is 14 cycles on the M4F).
    inv_dt: f32,
    prev_vel: Vec3,
    prev_anchor: Vec3,
    /// The normal force (N) at which `patch` was last evaluated (see [`ContactModel::patch_at`]).
    patch_key_n: f32,
    /// (patch radius a in m, static torsion limit τ_max in N·m) at `patch_key_n`.
    patch: (f32, f32),
    /// [`fast_test_applies`] for k_z and the τ_max of `patch` (evaluated with it).
    spin_fast_ok: bool,
    _m: PhantomData<(M, P)>,
}

impl<M: Math, S: Surface> ContactModel<M, S, Full> {
    /// The whole model touching nothing yet, at orientation `q0`, stepped every `dt_s` seconds
    /// ([`MIN_DT_S`] to [`MAX_DT_S`]). [`ContactModel::with_parts`] for a reduced model.
    pub fn new(params: ContactParams, surface: S, q0: Quat, dt_s: f32) -> Result<Self, ParamError> {
        Self::with_parts(params, surface, q0, dt_s)
    }
}

impl<M: Math, S: Surface, P: Parts> ContactModel<M, S, P> {
    /// A model of the parts `P` touching nothing yet, at orientation `q0`, stepped every `dt_s`
    /// seconds ([`MIN_DT_S`] to [`MAX_DT_S`]).
    pub fn with_parts(
        params: ContactParams,
        surface: S,
        q0: Quat,
        dt_s: f32,
    ) -> Result<Self, ParamError> {
        Self::with_checked_parts(&params.checked()?, surface, q0, dt_s)
    }

    /// [`Self::with_parts`] with parameters already checked: only the step period is.
    pub fn with_checked_parts(
        params: &Checked<ContactParams>,
        surface: S,
        q0: Quat,
        dt_s: f32,
    ) -> Result<Self, ParamError> {
        crate::validate::positive("dt_s", dt_s)?;
        if !(MIN_DT_S..=MAX_DT_S).contains(&dt_s) {
            return Err(ParamError::OutOfRange("dt_s"));
        }
        let params = **params;
        let (q0, _) = q0.normalized_checked::<M>();
        let state_params = params.state_params();
        Ok(ContactModel {
            params,
            state_params,
            state_derived: Derived::of(&state_params),
            rolling: Rolling::new(surface, params.fingertip_radius_m, q0, params.method),
            spin: SpinSpring::default(),
            state: ContactState::Broken,
            // Broken "since long ago": the first touch is not held back by the re-contact dwell.
            time_in_state_s: 1.0e6,
            dt_s,
            inv_dt: 1.0 / dt_s,
            prev_vel: Vec3::ZERO,
            prev_anchor: Vec3::ZERO,
            // Both functions give 0 at f_N = 0.
            patch_key_n: 0.0,
            patch: (0.0, 0.0),
            spin_fast_ok: fast_test_applies(params.spin_stiffness, 0.0),
            _m: PhantomData,
        })
    }

    /// Take the material `m` without a restart: the contact state, its points and the torsion
    /// spring's twist carry on, and the next step uses the new material (a blend calls this every
    /// tick of its ramp). `m` must pass [`ContactParams::validate_material`] (a blend between two
    /// that do does).
    pub(crate) fn take_material(&mut self, m: &Material) {
        let p = &mut self.params;
        p.normal_stiffness = m.normal_stiffness;
        p.normal_damping = m.normal_damping;
        p.mu_s = m.mu_s;
        p.mu_k = m.mu_k;
        p.spin_stiffness = m.spin_stiffness;
        // What the state machine reads of the material (`ContactParams::state_params`).
        self.state_params.mu_s = m.mu_s;
        self.state_params.mu_k = m.mu_k;
        // The patch's torsion limit depends on μ_s and its fast test on k_z: evaluate both again
        // at the next step (NaN never equals the key).
        self.patch_key_n = f32::NAN;
    }

    /// Current contact state.
    pub fn state(&self) -> ContactState {
        self.state
    }

    /// The parameters in force.
    pub fn params(&self) -> &ContactParams {
        &self.params
    }

    /// The step period, s.
    pub fn dt_s(&self) -> f32 {
        self.dt_s
    }

    /// The rolling kinematics: the surface with its contact point, the fingertip's contact point,
    /// the previous orientation sample.
    #[must_use]
    pub fn rolling(&self) -> &Rolling<S> {
        &self.rolling
    }

    /// The torsion spring: elastic twist and accumulated spin, rad.
    #[must_use]
    pub fn spin(&self) -> &SpinSpring {
        &self.spin
    }

    /// (patch radius a in m, static torsion limit τ_max in N·m) at the normal force `f_n` (N): a
    /// pure function of `f_n` and the fixed parameters, evaluated again only when `f_n` changes
    /// (a held contact keeps its force bit for bit, and the power law is the dearest term of the
    /// step). NaN never equals the key, so it is always evaluated.
    #[inline]
    fn patch_at(&mut self, f_n: f32) -> (f32, f32) {
        if f_n != self.patch_key_n {
            let p = &self.params;
            let a = patch_radius(f_n, p.patch_radius_m, p.patch_ref_force_n, p.patch_exponent);
            self.patch = (a, torsion_limit(p.mu_s, f_n, a));
            self.spin_fast_ok = fast_test_applies(p.spin_stiffness, self.patch.1);
            self.patch_key_n = f_n;
        }
        self.patch
    }

    /// The fingertip centre implied by rolling: contact point + ρ·n (object frame).
    #[inline]
    fn anchor(&self) -> Vec3 {
        let s = &self.rolling.surface;
        s.contact_point() + s.along_normal(self.params.fingertip_radius_m)
    }

    /// Move the contact under the probe; rolling restarts from the orientation of this step's
    /// sample (already the rolling state's `q_prev`).
    fn restart_at(&mut self, probe: Vec3) {
        self.rolling.surface.place_under::<M>(probe);
        self.prev_anchor = self.anchor();
    }

    /// The sliding state's force and torque: the kinetic limit surface. The anchor spring and the
    /// torsion spring slip together to the closest point of the ellipse (slip along its normal),
    /// and the sliding proxy is left where the slip put it. Returns (force N, τn N·m, whether the
    /// spring slipped: its own limit held it, or the projection took a non-zero torque). Out of
    /// line: the common path is rolling.
    #[cold]
    #[inline(never)]
    fn slide(&mut self, probe: Vec3, dphi: f32, f_n: f32, patch: f32) -> (Vec3, f32, bool) {
        let p = self.params;
        let (k_t, k_z) = (p.tangential_stiffness, p.spin_stiffness);
        let surface = self.rolling.surface;
        let tau_max_k = torsion_limit(p.mu_k, f_n, patch);
        let (tau, sat) = if P::SPIN {
            self.spin.update(dphi, k_z, tau_max_k)
        } else {
            (0.0, false)
        };
        let (_, e_t) = surface.split(self.anchor() - probe);
        let d = e_t.norm::<M>();
        let (sf, st) = if P::LIMIT_SURFACE {
            project(d * k_t, tau, p.mu_k * f_n, tau_max_k, k_t, k_z)
        } else {
            // The friction cone alone (the torque met its own limit in `update`).
            let (f, f_max) = (d * k_t, p.mu_k * f_n);
            (if f > f_max { f_max / f } else { 1.0 }, 1.0)
        };
        let e_t = e_t * sf;
        let (tau, slipped) = if st < 1.0 && tau != 0.0 {
            self.spin.slip_to(self.spin.elastic_rad * st);
            (k_z * self.spin.elastic_rad, true)
        } else {
            (tau, sat)
        };
        self.restart_at(probe + e_t);
        (surface.along_normal(f_n) + e_t * k_t, tau, slipped)
    }

    fn output(&self, flags: Flags) -> ContactOutput {
        ContactOutput {
            state: self.state,
            reason: Reason::Kept,
            object_point_m: self.rolling.surface.contact_point(),
            spin_rad: self.spin.accumulated_rad,
            flags,
            ..ContactOutput::default()
        }
    }

    /// One contact step. Never panics; any non-finite input gives zero force with
    /// [`Flags::NON_FINITE_INPUT`], a probe farther than [`MAX_PROBE_M`] or faster than
    /// [`MAX_PROBE_SPEED_M_S`] (Euclidean norm) zero force with [`Flags::OUT_OF_RANGE`]; both
    /// leave the state unchanged.
    pub fn contact_step(&mut self, input: &ContactInput) -> ContactOutput {
        // One comparison per vector on the common path: |p|² ≤ max² is false for NaN and ±inf as
        // well as for a probe too far or too fast, and the flag is told apart only then.
        let p_ok = input.probe_m.norm_squared() <= MAX_PROBE_M * MAX_PROBE_M;
        let v_ok = input.probe_vel.norm_squared() <= MAX_PROBE_SPEED_M_S * MAX_PROBE_SPEED_M_S;
        if !(p_ok && v_ok) {
            let finite =
                input.probe_m.is_finite() && input.probe_vel.is_finite() && input.q.is_finite();
            return self.output(if finite {
                Flags::OUT_OF_RANGE
            } else {
                Flags::NON_FINITE_INPUT
            });
        }
        let probe = input.probe_m;

        // 1. Rolling kinematics.
        let roll = self.roll(input);
        // A non-finite or zero quaternion: `roll` left every state untouched.
        if roll
            .flags
            .intersects(Flags::NON_FINITE_INPUT | Flags::ZERO_AXIS)
        {
            return self.output(roll.flags);
        }
        let mut flags = roll.flags;

        // 2.–3. Normal force, rolling coupling and the state machine's inputs.
        let sensed = self.sense(probe, input.probe_vel, &roll);

        // 4. State transition and entry actions.
        let (state, reason) = self.transition(&sensed.inputs, probe);

        // 5. Force and spin torque for the new state.
        let p = self.params;
        let k_z = p.spin_stiffness;
        let s = &sensed;
        let dphi = roll.angles.phi;
        let (force, tau_n_nm, saturated) = match state {
            // Pressed beyond the make force (by the spring alone: K·penetration, so velocity
            // noise on a hovering probe does not count) but held broken by the re-contact dwell:
            // the normal force without friction, rolling or spin. The dwell holds back the state,
            // never the wall. Within the make band nothing, as before contact is made.
            ContactState::Broken
                if p.normal_stiffness * -s.inputs.gap_m > p.tolerances.make_force_n =>
            {
                (s.normal * s.f_n, 0.0, false)
            }
            ContactState::Broken => (Vec3::ZERO, 0.0, false),
            ContactState::Rolling => {
                let placed = reason == Reason::MadeContact || reason == Reason::Stuck;
                // The anchor just placed under the probe: no tangential force.
                let (f_t, ft2) = if placed {
                    (Vec3::ZERO, 0.0)
                } else {
                    (s.f_couple, s.f_couple.norm_squared())
                };
                // The torsion spring gets what the tangential load leaves of the static limit
                // surface: τ ≤ τ_max·√(1 − (|f_t|/(μ_s·f_N))²). μ_s as the state machine read
                // it (the same value, `take_material` sets both), so its cone is reused.
                let f_max = self.state_params.mu_s * s.f_n;
                let (tau, sat) = if !P::SPIN {
                    (0.0, false)
                } else if !P::LIMIT_SURFACE {
                    self.spin.update(dphi, k_z, s.tau_max_s)
                } else {
                    self.spin.update_within_prechecked::<M>(
                        dphi,
                        k_z,
                        s.tau_max_s,
                        ft2,
                        f_max * f_max,
                        self.spin_fast_ok,
                    )
                };
                let force = self
                    .rolling
                    .surface
                    .normal_plus_tangential(s.normal, s.f_n, f_t);
                (force, tau, sat)
            }
            ContactState::Sliding => self.slide(probe, dphi, s.f_n, s.patch),
        };
        if saturated && sensed.f_n > p.tolerances.force_eps_n {
            flags |= Flags::SPIN_SATURATED;
        }

        // 6. Limits and the last NaN guard.
        let (force, tau_n_nm) = guard_output::<M>(force, tau_n_nm, p.max_force_n, &mut flags);
        ContactOutput {
            force_n: force,
            tau_n_nm,
            spin_rad: self.spin.accumulated_rad,
            state,
            reason,
            object_point_m: self.rolling.surface.contact_point(),
            angles: roll.angles,
            flags,
        }
    }

    /// Stage 1: rolling kinematics while touching; when apart only the orientation is tracked
    /// and the contact placed under the probe. A non-finite or zero quaternion leaves every
    /// state untouched (the returned flags tell).
    #[inline(always)]
    fn roll(&mut self, input: &ContactInput) -> RollStep {
        if self.state == ContactState::Broken {
            let (q, f) = input.q.normalized_checked::<M>();
            if !f.intersects(Flags::NON_FINITE_INPUT | Flags::ZERO_AXIS) {
                self.rolling.q_prev = q;
                self.rolling.surface.place_under::<M>(input.probe_m);
            }
            RollStep {
                flags: f,
                ..Default::default()
            }
        } else if P::ROLLING {
            self.rolling.step_parts::<M, true>(input.q)
        } else if P::SPIN {
            self.rolling.step_parts::<M, false>(input.q)
        } else {
            // No spin and no rolling: only the orientation is tracked (checked as the rolling
            // step checks it, so a bad sample is flagged the same).
            let (q, f) = match self.rolling.method {
                crate::contact::decompose::Method::Exact => input.q.unit_checked::<M>(),
                _ => input.q.normalized_checked::<M>(),
            };
            if !f.intersects(Flags::NON_FINITE_INPUT | Flags::ZERO_AXIS) {
                self.rolling.q_prev = q;
            }
            RollStep {
                flags: f,
                ..Default::default()
            }
        }
    }

    /// Stages 2 and 3: the normal geometry and kinematics (penetration, velocity and acceleration
    /// split along the normal, the unilateral normal force), then the rolling coupling force as
    /// it would be if rolling is kept, gathered into the state machine's inputs.
    #[inline(always)]
    fn sense(&mut self, probe: Vec3, vel: Vec3, roll: &RollStep) -> Sensed {
        let p = &self.params;
        let r = p.fingertip_radius_m;
        let inv_dt = self.inv_dt;

        // 2. Normal geometry and kinematics.
        let pen = self.rolling.surface.penetration::<M>(probe, r);
        let surface = self.rolling.surface;
        let (v_n, v_t) = surface.split(vel);
        let accel = (vel - self.prev_vel) * inv_dt;
        self.prev_vel = vel;
        let (a_n, a_t) = surface.split(accel);
        let f_n = if pen > 0.0 {
            let f = p.normal_stiffness * pen - p.normal_damping * v_n;
            if f > 0.0 {
                f
            } else {
                0.0
            }
        } else {
            0.0
        };

        // 3. The rolling coupling force (tangential), as it would be if rolling is kept.
        let anchor = self.anchor();
        let anchor_vel = (anchor - self.prev_anchor) * inv_dt;
        self.prev_anchor = anchor;
        let couple = |e: Vec3, v_rel: Vec3| {
            let f = e * p.tangential_stiffness + v_rel * p.tangential_damping;
            surface.split(f).1
        };
        let f_couple = couple(anchor - probe, anchor_vel - vel);
        // The twist threshold on the tilt rate belongs to rolling.
        let tilt2 = if P::ROLLING {
            roll.angles.theta * roll.angles.theta + roll.angles.psi * roll.angles.psi
        } else {
            0.0
        };
        // The patch grows with the normal force; its torsional limit joins the tangential one in
        // one limit surface (see `crate::contact::limit_surface`). No spin: no patch.
        let (patch, tau_max_s) = if P::SPIN {
            self.patch_at(f_n)
        } else {
            (0.0, 0.0)
        };
        let p = &self.params;
        let inputs = StateInputs {
            normal_force_n: f_n,
            gap_m: -pen,
            normal_accel: a_n,
            tangential_force_n: -f_couple,
            tangential_accel: a_t,
            tangential_velocity: if self.state == ContactState::Rolling {
                v_t - surface.split(anchor_vel).1
            } else {
                v_t
            },
            roll_disp_m: roll.object_disp_m,
            tilt_rate_sq: tilt2 * inv_dt * inv_dt,
            time_in_state_s: self.time_in_state_s,
            // Without the limit surface the state machine sees the friction cone alone.
            spin_torque_nm: if P::LIMIT_SURFACE {
                p.spin_stiffness * (self.spin.elastic_rad + roll.angles.phi)
            } else {
                0.0
            },
            torsion_limit_nm: if P::LIMIT_SURFACE { tau_max_s } else { 0.0 },
        };
        Sensed {
            inputs,
            normal: surface.normal(),
            f_n,
            f_couple,
            patch,
            tau_max_s,
        }
    }

    /// Stage 4: the state transition and its entry actions (a new rolling contact restarts
    /// under the probe at this step's orientation; a broken one drops the spin).
    #[inline(always)]
    fn transition(&mut self, inputs: &StateInputs, probe: Vec3) -> (ContactState, Reason) {
        let (state, reason) =
            next_state_derived(self.state, inputs, &self.state_params, &self.state_derived);
        if state == self.state {
            // Saturates (f32 stops growing past 2^24 ticks of 1e-4 s), which is harmless.
            self.time_in_state_s += self.dt_s;
        } else {
            self.time_in_state_s = 0.0;
            match state {
                ContactState::Rolling => self.restart_at(probe),
                ContactState::Broken => self.spin.reset(),
                ContactState::Sliding => {}
            }
        }
        self.state = state;
        (state, reason)
    }
}

/// What stages 2 and 3 of the contact step hand on to the later stages.
#[derive(Clone, Copy)]
struct Sensed {
    /// The state machine's inputs.
    inputs: StateInputs,
    /// The surface's outward unit normal at the contact as it was before the transition (a
    /// restart moves the contact), object frame.
    normal: Vec3,
    /// Normal force, N (≥ 0).
    f_n: f32,
    /// The rolling coupling force (tangential), object frame, N.
    f_couple: Vec3,
    /// Contact patch radius at `f_n`, m.
    patch: f32,
    /// Static torsion limit at `f_n`, N·m.
    tau_max_s: f32,
}

/// The contact step's last stage: |F| ≤ `max_force_n` (N; a larger force is rescaled to 4 ulps
/// below it, so the rounding of the rescale and of any later norm cannot put it above, and
/// flagged [`Flags::OUTPUT_LIMITED`] into `flags`) and nothing non-finite out (a non-finite force or torque
/// gives zero force, a non-finite torque zero torque, [`Flags::NON_FINITE_OUTPUT`]). One
/// comparison on the common path: τ·0 is ±0 for a finite τ and NaN otherwise, so |F|² + τ·0 is
/// within the limit only when |F| is and both are finite.
#[inline(always)]
#[must_use]
fn guard_output<M: Math>(
    force: Vec3,
    tau_nm: f32,
    max_force_n: f32,
    flags: &mut Flags,
) -> (Vec3, f32) {
    let f2 = force.norm_squared();
    let (mut force, mut tau_nm) = (force, tau_nm);
    // False for NaN as well as for a force over the limit.
    let within = f2 + tau_nm * 0.0 <= max_force_n * max_force_n;
    if !within {
        if !f2.is_finite() || !tau_nm.is_finite() {
            force = Vec3::ZERO;
            *flags |= Flags::NON_FINITE_OUTPUT;
            if !tau_nm.is_finite() {
                tau_nm = 0.0;
            }
        } else {
            force = force * (max_force_n * (1.0 - 4.0 * f32::EPSILON) / M::sqrt(f2));
            *flags |= Flags::OUTPUT_LIMITED;
        }
    }
    (force, tau_nm)
}

#[cfg(test)]
mod tests;
