//! The contact state machine: rolling, sliding, broken (paper section 3.2, after Yin, Sugimoto and
//! Hosoe, 2005), written as robust f32 predicates.
//!
//! The paper's five conditions use exact equalities (f_N = 0, a_N = 0, μ²f_N² − f_T² = 0, v_T = 0).
//! Here each equality is a tolerance band (`*_tol`/`*_eps` in [`Tolerances`]) and the friction cone
//! has a hysteresis margin, so a force sitting on the cone boundary does not chatter:
//!
//! | from | to | condition (all must hold) |
//! | --- | --- | --- |
//! | any contact | broken | f_N ≤ ε_f and (a_N > ε_a or gap > ε_gap) — the paper's "f_N = 0, a_N > 0"; the gap test is ours, so a probe lifted off at constant speed also breaks contact |
//! | broken | rolling | f_N > f_make (contact made; the paper gives no rule for it). f_make > ε_f is a hysteresis band: encoder quantisation makes the penetration of a grazing probe flicker around zero, and without the band the state chatters broken ↔ rolling ↔ sliding; and at least t_broken since the break (a probe lifted off fast re-crosses zero penetration for single ticks). The dwell holds back the *state* only: a probe pressed beyond f_make during it gets the normal spring (docs/design.md#the-wall-stays-solid-through-the-re-contact-dwell) |
//! | rolling | sliding | |a_N| ≤ tol_a, (\|f_T\|/(μ_s·f_N))² + (τn/τ_max)² > (1 + h)² (the limit surface; the friction cone when τn = 0), relative tangential motion (\|a_T\| > ε_a or \|v_T\| > v_stick), and the haptic rule: f_T·d_roll ≥ 0 (the user's tangential force agrees with the rolling displacement d_roll) or no rolling this step |
//! | rolling | sliding | the twist threshold: Δθ > Δθ_max = f_N·μ_s/(k_τ·r), with Δθ the tilt rate δξ/T (see below) |
//! | sliding | rolling | |a_N| ≤ tol_a, \|f_T\| ≤ μ_k·f_N, \|v_T\| ≤ v_stick, and at least t_slide in sliding (a dwell: at the onset of a slide the probe has not picked up speed yet) |
//! | otherwise | unchanged | rolling kept inside the cone; sliding kept while moving or pushed |
//!
//! All vectors are in the object frame with their normal component removed (tangential). f_T is
//! the tangential force the **user applies to the fingertip** (minus the force rendered). Δθ is a
//! tilt rate (rad/s) and k_τ is in N·m·s/rad. Why a slip speed also leaves rolling, the haptic rule
//! and the threshold as a rate: docs/design.md#state-machine.

use crate::math::vec3::Vec3;
use crate::validate::{at_most, non_negative, ParamError};

/// The contact state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ContactState {
    /// No contact: no friction, no rolling, no spin torque, and no force unless the probe presses
    /// beyond the make force f_make while the re-contact dwell t_broken still holds the state:
    /// then the unilateral normal spring alone, so the wall stays solid.
    #[default]
    Broken,
    /// Rolling without slip: the contact point moves by rolling.
    Rolling,
    /// Sliding: the contact point follows the probe, kinetic friction opposes the motion.
    Sliding,
}

impl ContactState {
    /// Name used in files and logs.
    pub const fn name(self) -> &'static str {
        match self {
            ContactState::Broken => "broken",
            ContactState::Rolling => "rolling",
            ContactState::Sliding => "sliding",
        }
    }
}

/// Why the state is what it is after a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Reason {
    /// No transition.
    #[default]
    Kept,
    /// Broken → rolling: the probe pressed on the surface.
    MadeContact,
    /// Rolling/sliding → broken: no normal force and the surfaces separate.
    Separated,
    /// Rolling → sliding: the user's tangential force left the static friction cone.
    ConeExceeded,
    /// Rolling → sliding: the tilt rate exceeded the twist threshold Δθ_max.
    TwistExceeded,
    /// Sliding → rolling: the probe stopped inside the kinetic friction cone.
    Stuck,
}

/// What the state machine looks at each step (object frame, tangential parts only).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateInputs {
    /// f_N: normal force pressing the surfaces together, N (≥ 0).
    pub normal_force_n: f32,
    /// Gap between the surfaces, m (> 0: apart; ≤ 0: touching or overlapping).
    pub gap_m: f32,
    /// a_N: relative normal acceleration, m/s² (> 0: separating).
    pub normal_accel: f32,
    /// f_T: tangential force the user applies to the fingertip, N.
    pub tangential_force_n: Vec3,
    /// a_T: relative tangential acceleration, m/s².
    pub tangential_accel: Vec3,
    /// v_T: relative tangential velocity, m/s: in rolling, of the probe against the fingertip centre
    /// implied by rolling (slip); in sliding, of the probe against the object.
    pub tangential_velocity: Vec3,
    /// d_roll: the contact point's rolling displacement this step, m.
    pub roll_disp_m: Vec3,
    /// Δθ²: the square of the tilt rate δξ/T, rad²/s² (squared so no square root is needed).
    pub tilt_rate_sq: f32,
    /// Time spent in the current state, s.
    pub time_in_state_s: f32,
    /// τn: the spin torque the contact would carry this step (trial, before any slip), N·m.
    pub spin_torque_nm: f32,
    /// τ_max: the static torsional limit (3π/16)·μ_s·f_N·a, N·m. Zero: no twist in the budget.
    pub torsion_limit_nm: f32,
}

/// The state machine's tolerances: what counts as zero, apart, still, and how long a state is kept.
/// One struct, held by [`crate::contact::ContactParams`] (validated there) and read by
/// [`next_state`] through [`StateParams`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tolerances {
    /// ε_f: a normal force at or below this is "zero", N.
    pub force_eps_n: f32,
    /// ε_a: an acceleration above this is "non-zero", m/s².
    pub accel_eps: f32,
    /// tol_a: |a_N| at or below this counts as "a_N = 0", m/s².
    pub normal_accel_tol: f32,
    /// ε_gap: a gap above this means the surfaces are apart, m.
    pub gap_eps_m: f32,
    /// v_stick: a tangential speed at or below this is "v_T = 0", m/s.
    pub stick_speed: f32,
    /// h: hysteresis margin on the static cone, fraction in [0, 1).
    pub hysteresis: f32,
    /// f_make: the normal force that makes contact from broken, N (≥ ε_f).
    pub make_force_n: f32,
    /// t_slide: least time in sliding before sticking again, s.
    pub min_slide_s: f32,
    /// t_broken: least time in broken before contact can be made again, s.
    pub min_broken_s: f32,
}

impl Tolerances {
    /// `self == other`, field by field and always inline (the derived `eq` may be left out of
    /// line, where the firmware's tick cannot call it: it runs from RAM only). Exhaustive, so a
    /// new field must be compared here.
    #[inline(always)]
    pub fn same(&self, other: &Tolerances) -> bool {
        let Tolerances {
            force_eps_n,
            accel_eps,
            normal_accel_tol,
            gap_eps_m,
            stick_speed,
            hysteresis,
            make_force_n,
            min_slide_s,
            min_broken_s,
        } = self;
        *force_eps_n == other.force_eps_n
            && *accel_eps == other.accel_eps
            && *normal_accel_tol == other.normal_accel_tol
            && *gap_eps_m == other.gap_eps_m
            && *stick_speed == other.stick_speed
            && *hysteresis == other.hysteresis
            && *make_force_n == other.make_force_n
            && *min_slide_s == other.min_slide_s
            && *min_broken_s == other.min_broken_s
    }

    /// The defaults of [`crate::contact::ContactParams::DEFAULT`].
    pub const DEFAULT: Tolerances = Tolerances {
        force_eps_n: 0.01,
        accel_eps: 0.05,
        normal_accel_tol: 50.0,
        gap_eps_m: 1e-4,
        stick_speed: 0.002,
        hysteresis: 0.05,
        // 0.05 N is 25 µm of penetration at 2 N/mm: about two counts of the default encoders'
        // quantisation at the effector (~13 µm), the noise a grazing probe sees.
        make_force_n: 0.05,
        min_slide_s: 0.02,
        min_broken_s: 0.002,
    };

    /// Check every field: finite, non-negative, at most its value in [`Self::MAX`], the hysteresis
    /// below 1 and f_make ≥ ε_f. The first bad field is reported by name.
    pub fn validate(&self) -> Result<(), ParamError> {
        let m = &Self::MAX;
        non_negative("force_eps_n", self.force_eps_n)?;
        at_most("force_eps_n", self.force_eps_n, m.force_eps_n)?;
        non_negative("accel_eps", self.accel_eps)?;
        at_most("accel_eps", self.accel_eps, m.accel_eps)?;
        non_negative("normal_accel_tol", self.normal_accel_tol)?;
        at_most(
            "normal_accel_tol",
            self.normal_accel_tol,
            m.normal_accel_tol,
        )?;
        non_negative("gap_eps_m", self.gap_eps_m)?;
        at_most("gap_eps_m", self.gap_eps_m, m.gap_eps_m)?;
        non_negative("stick_speed", self.stick_speed)?;
        at_most("stick_speed", self.stick_speed, m.stick_speed)?;
        non_negative("hysteresis", self.hysteresis)?;
        if self.hysteresis >= 1.0 {
            return Err(ParamError::OutOfRange("hysteresis"));
        }
        non_negative("make_force_n", self.make_force_n)?;
        at_most("make_force_n", self.make_force_n, m.make_force_n)?;
        if self.make_force_n < self.force_eps_n {
            return Err(ParamError::OutOfRange("make_force_n"));
        }
        non_negative("min_slide_s", self.min_slide_s)?;
        at_most("min_slide_s", self.min_slide_s, m.min_slide_s)?;
        non_negative("min_broken_s", self.min_broken_s)?;
        at_most("min_broken_s", self.min_broken_s, m.min_broken_s)?;
        Ok(())
    }

    /// The largest accepted values (see [`crate::contact::ContactParams::MAX`]).
    pub const MAX: Tolerances = Tolerances {
        force_eps_n: 1.0e4,
        accel_eps: 1.0e6,
        normal_accel_tol: 1.0e6,
        gap_eps_m: 1.0,
        stick_speed: 100.0,
        hysteresis: 1.0,
        make_force_n: 1.0e4,
        min_slide_s: 1.0e3,
        min_broken_s: 1.0e3,
    };
}

/// Friction, geometry and tolerances of one state-machine step (built by
/// [`crate::contact::ContactParams::state_params`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateParams {
    /// μ_s: static friction coefficient.
    pub mu_s: f32,
    /// μ_k: kinetic (sliding) friction coefficient, 0 < μ_k ≤ μ_s.
    pub mu_k: f32,
    /// k_τ: twist stiffness for the rolling→sliding threshold, N·m·s/rad.
    pub k_tau: f32,
    /// r: fingertip radius, m.
    pub radius_m: f32,
    /// A rolling displacement shorter than this is "no rolling" for the haptic rule, m.
    pub roll_eps_m: f32,
    /// What counts as zero, apart and still.
    pub tol: Tolerances,
}

/// What [`next_state`] derives from its [`StateParams`] (the fields it does not share with the
/// material, so a material change leaves it valid): computed once by the contact model rather
/// than on every step. Each is the same single operation `next_state` would do, so the answer is
/// the same bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Derived {
    /// 1 + h.
    one_plus_h: f32,
    /// k_τ·r, N·m·s.
    kr: f32,
}

impl Derived {
    /// The derived values of `p`.
    pub(crate) fn of(p: &StateParams) -> Derived {
        Derived {
            one_plus_h: 1.0 + p.tol.hysteresis,
            kr: p.k_tau * p.radius_m,
        }
    }
}

/// The state after one step, and why. Pure function: no state of its own.
#[inline(always)]
pub fn next_state(state: ContactState, i: &StateInputs, p: &StateParams) -> (ContactState, Reason) {
    next_state_derived(state, i, p, &Derived::of(p))
}

/// [`next_state`] with `d` = [`Derived::of`]`(p)`.
///
/// Inlined into the contact step so the inputs only its rare branches read (accelerations, slip
/// velocity, rolling displacement) are computed only when those branches run.
#[inline(always)]
pub(crate) fn next_state_derived(
    state: ContactState,
    i: &StateInputs,
    p: &StateParams,
    d: &Derived,
) -> (ContactState, Reason) {
    let f_n = i.normal_force_n;
    // Separated: no normal force and the probe leaving or away. Asked only when f_N ≤ ε, so the
    // common path (pressed) makes one comparison.
    let leaving = || i.normal_accel > p.tol.accel_eps || i.gap_m > p.tol.gap_eps_m;
    let normal_steady = || i.normal_accel.abs() <= p.tol.normal_accel_tol;
    let ft2 = i.tangential_force_n.norm_squared();
    match state {
        ContactState::Broken => {
            if f_n > p.tol.make_force_n && i.time_in_state_s >= p.tol.min_broken_s {
                (ContactState::Rolling, Reason::MadeContact)
            } else {
                (ContactState::Broken, Reason::Kept)
            }
        }
        ContactState::Rolling => {
            if f_n <= p.tol.force_eps_n {
                return if leaving() {
                    (ContactState::Broken, Reason::Separated)
                } else {
                    (ContactState::Rolling, Reason::Kept)
                };
            }
            // Predicates are evaluated lazily, cheapest and most often false first: on the
            // common path (inside the cone) only |f_T|² is computed.
            // One friction budget for slide and twist (see `crate::contact::limit_surface`): outside the
            // static ellipse (|f_T|/(μ_s·f_N))² + (τn/τ_max)² ≤ (1 + h)². With no torque this is
            // the friction cone.
            let cone = p.mu_s * f_n;
            let has_torsion = i.torsion_limit_nm > 0.0;
            let outside = if i.spin_torque_nm == 0.0 || !has_torsion {
                let c = cone * d.one_plus_h;
                ft2 > c * c
            } else {
                crate::contact::limit_surface::outside(
                    ft2,
                    i.spin_torque_nm,
                    cone,
                    i.torsion_limit_nm,
                    d.one_plus_h,
                )
            };
            if outside && normal_steady() {
                let moving = i.tangential_accel.norm_squared() > p.tol.accel_eps * p.tol.accel_eps
                    || i.tangential_velocity.norm_squared() > p.tol.stick_speed * p.tol.stick_speed;
                let agrees = i.roll_disp_m.norm_squared() <= p.roll_eps_m * p.roll_eps_m
                    || i.tangential_force_n.dot(i.roll_disp_m) >= 0.0;
                if moving && agrees {
                    return (ContactState::Sliding, Reason::ConeExceeded);
                }
            }
            // Δθ > f_N·μ_s/(k_τ·r)  ⇔  Δθ²·(k_τ·r)² > (f_N·μ_s)² (both sides ≥ 0; no division or
            // square root).
            let kr = d.kr;
            let fm = f_n * p.mu_s;
            if i.tilt_rate_sq * kr * kr > fm * fm {
                return (ContactState::Sliding, Reason::TwistExceeded);
            }
            (ContactState::Rolling, Reason::Kept)
        }
        ContactState::Sliding => {
            if f_n <= p.tol.force_eps_n && leaving() {
                return (ContactState::Broken, Reason::Separated);
            }
            let kinetic = p.mu_k * f_n;
            let stopped =
                i.tangential_velocity.norm_squared() <= p.tol.stick_speed * p.tol.stick_speed;
            let dwelt = i.time_in_state_s >= p.tol.min_slide_s;
            if f_n > p.tol.force_eps_n
                && normal_steady()
                && ft2 <= kinetic * kinetic
                && stopped
                && dwelt
            {
                return (ContactState::Rolling, Reason::Stuck);
            }
            (ContactState::Sliding, Reason::Kept)
        }
    }
}

#[cfg(test)]
mod tests;
