//! Validated parameters of the contact model. Invalid values are rejected with a typed error that
//! names the field; nothing is clamped silently.

use crate::contact::decompose::Method;
use crate::contact::state::{StateParams, Tolerances};
/// The shared parameter error, kept at its old path.
pub use crate::validate::ParamError;
use crate::validate::{at_most, non_negative, positive, Checked};

/// The material of a contact: what a local model carries and what can change without restarting
/// the contact ([`ContactParams::validate_material`] checks it). SI units, as in [`ContactParams`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Material {
    /// Normal stiffness, N/m.
    pub normal_stiffness: f32,
    /// Normal damping, N·s/m.
    pub normal_damping: f32,
    /// Static friction coefficient.
    pub mu_s: f32,
    /// Kinetic friction coefficient (≤ μ_s).
    pub mu_k: f32,
    /// Spin stiffness k_z, N·m/rad.
    pub spin_stiffness: f32,
}

impl Material {
    /// `self` moved by `k` (0..=1) towards `to`, field by field. Each field stays between its two
    /// ends, so in range, and μ_k ≤ μ_s at both ends holds in between (kept exactly by a min).
    pub fn lerp(&self, to: &Material, k: f32) -> Material {
        let l = |a: f32, b: f32| a + (b - a) * k;
        let mu_s = l(self.mu_s, to.mu_s);
        Material {
            normal_stiffness: l(self.normal_stiffness, to.normal_stiffness),
            normal_damping: l(self.normal_damping, to.normal_damping),
            mu_s,
            mu_k: l(self.mu_k, to.mu_k).min(mu_s),
            spin_stiffness: l(self.spin_stiffness, to.spin_stiffness),
        }
    }
}

/// How new contact parameters took effect in a contact stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamsChange {
    /// The contact restarted (broken, its history forgotten): the caller ramps the force in again.
    Restarted,
    /// Only the material changed: it blends in and the contact carries on.
    Blended,
}

/// Everything the contact model needs. SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ContactParams {
    /// Decomposition method for the rolling increments.
    pub method: Method,
    /// Fingertip sphere radius R₁, m (paper: 10 mm).
    pub fingertip_radius_m: f32,
    /// Normal (penetration) stiffness of the virtual surface, N/m.
    pub normal_stiffness: f32,
    /// Normal damping, N·s/m.
    pub normal_damping: f32,
    /// Tangential spring between the rolled position and the probe (section 3.2), N/m.
    pub tangential_stiffness: f32,
    /// Tangential damper of that coupling, N·s/m.
    pub tangential_damping: f32,
    /// μ_s: static friction coefficient.
    pub mu_s: f32,
    /// μ_k: kinetic friction coefficient (0 < μ_k ≤ μ_s).
    pub mu_k: f32,
    /// k_z: spin stiffness of eq. (1), N·m/rad.
    pub spin_stiffness: f32,
    /// a_ref: radius of the contact patch at the normal force `patch_ref_force_n`, m. The patch
    /// radius is a = a_ref·(f_N/f_ref)^γ ([`crate::contact::limit_surface::patch_radius`]) and sets the
    /// torsional limit τ_max = (3π/16)·μ·f_N·a.
    pub patch_radius_m: f32,
    /// f_ref: the normal force at which the patch radius is `patch_radius_m`, N (> 0).
    pub patch_ref_force_n: f32,
    /// γ: exponent of the patch radius's power law in [0, 1] (Hertz 1/3; human fingertips about
    /// 0.2-0.3, Xydas and Kao 1999; 0: a fixed patch).
    pub patch_exponent: f32,
    /// k_τ: twist stiffness of the rolling→sliding threshold, N·m·s/rad.
    pub k_tau: f32,
    /// Largest force the model may ask for, N (the device's limit; also enforced after it).
    pub max_force_n: f32,
    /// The state machine's tolerances.
    pub tolerances: Tolerances,
}

impl ContactParams {
    /// Defaults for a human fingertip on a rigid surface rendered by an Omega.6-class device:
    /// 10 mm fingertip (the paper's), 2 N/mm surface (the Omega.6 renders up to 14.5 N/mm),
    /// μ_s = 0.8 / μ_k = 0.6 (skin on smooth surfaces is reported between 0.5 and 1.0), a 5 mm patch,
    /// k_z = 0.01 N·m/rad, 12 N force limit (the Omega.6's continuous force).
    pub const DEFAULT: ContactParams = ContactParams {
        method: Method::Exact,
        fingertip_radius_m: 0.01,
        normal_stiffness: 2000.0,
        normal_damping: 2.0,
        tangential_stiffness: 1000.0,
        tangential_damping: 1.0,
        mu_s: 0.8,
        mu_k: 0.6,
        spin_stiffness: 0.01,
        patch_radius_m: 0.005,
        // 2 N: the default scenes' press (1 mm at 2 N/mm), where the patch is a_ref = 5 mm.
        patch_ref_force_n: 2.0,
        patch_exponent: 1.0 / 3.0,
        k_tau: 4.0,
        max_force_n: 12.0,
        tolerances: Tolerances::DEFAULT,
    };

    /// Largest accepted value of each field (see [`Self::validate`]): far beyond any device or
    /// scene (a 1 m fingertip, 10⁷ N/m, 10 kN), and small enough that products of fields with
    /// workspace-sized lengths, speeds and rates stay far from f32 overflow.
    pub const MAX: ContactParams = ContactParams {
        method: Method::Exact,
        fingertip_radius_m: 1.0,
        normal_stiffness: 1.0e7,
        normal_damping: 1.0e5,
        tangential_stiffness: 1.0e7,
        tangential_damping: 1.0e5,
        mu_s: 100.0,
        mu_k: 100.0,
        spin_stiffness: 1.0e3,
        patch_radius_m: 1.0,
        patch_ref_force_n: 1.0e4,
        patch_exponent: 1.0,
        k_tau: 1.0e6,
        max_force_n: 1.0e4,
        tolerances: Tolerances::MAX,
    };

    /// Smallest accepted fingertip radius, m (0.1 mm): 1/ρ stays finite and meaningful.
    pub const MIN_FINGERTIP_RADIUS_M: f32 = 1.0e-4;

    /// Smallest accepted force limit, N (1 mN): the limit is applied by a rescale F·(max/|F|),
    /// which must not fall into the subnormal range, where it would lose its precision.
    pub const MIN_MAX_FORCE_N: f32 = 1.0e-3;

    /// Check every field; the first bad one is reported. Each field must be finite, within its
    /// sign constraint and at most its value in [`Self::MAX`].
    pub fn validate(&self) -> Result<(), ParamError> {
        let m = &Self::MAX;
        positive("fingertip_radius_m", self.fingertip_radius_m)?;
        if self.fingertip_radius_m < Self::MIN_FINGERTIP_RADIUS_M {
            return Err(ParamError::OutOfRange("fingertip_radius_m"));
        }
        at_most(
            "fingertip_radius_m",
            self.fingertip_radius_m,
            m.fingertip_radius_m,
        )?;
        self.validate_material()?;
        non_negative("tangential_stiffness", self.tangential_stiffness)?;
        at_most(
            "tangential_stiffness",
            self.tangential_stiffness,
            m.tangential_stiffness,
        )?;
        non_negative("tangential_damping", self.tangential_damping)?;
        at_most(
            "tangential_damping",
            self.tangential_damping,
            m.tangential_damping,
        )?;
        non_negative("patch_radius_m", self.patch_radius_m)?;
        at_most("patch_radius_m", self.patch_radius_m, m.patch_radius_m)?;
        positive("patch_ref_force_n", self.patch_ref_force_n)?;
        at_most(
            "patch_ref_force_n",
            self.patch_ref_force_n,
            m.patch_ref_force_n,
        )?;
        non_negative("patch_exponent", self.patch_exponent)?;
        at_most("patch_exponent", self.patch_exponent, m.patch_exponent)?;
        positive("k_tau", self.k_tau)?;
        at_most("k_tau", self.k_tau, m.k_tau)?;
        positive("max_force_n", self.max_force_n)?;
        if self.max_force_n < Self::MIN_MAX_FORCE_N {
            return Err(ParamError::OutOfRange("max_force_n"));
        }
        at_most("max_force_n", self.max_force_n, m.max_force_n)?;
        self.tolerances.validate()
    }

    /// Check the material alone (normal stiffness and damping, μ_s, μ_k, spin stiffness: what a
    /// local model carries), as [`Self::validate`] does.
    pub fn validate_material(&self) -> Result<(), ParamError> {
        let m = &Self::MAX;
        non_negative("normal_stiffness", self.normal_stiffness)?;
        at_most(
            "normal_stiffness",
            self.normal_stiffness,
            m.normal_stiffness,
        )?;
        non_negative("normal_damping", self.normal_damping)?;
        at_most("normal_damping", self.normal_damping, m.normal_damping)?;
        positive("mu_s", self.mu_s)?;
        at_most("mu_s", self.mu_s, m.mu_s)?;
        positive("mu_k", self.mu_k)?;
        if self.mu_k > self.mu_s {
            return Err(ParamError::KineticAboveStatic);
        }
        non_negative("spin_stiffness", self.spin_stiffness)?;
        at_most("spin_stiffness", self.spin_stiffness, m.spin_stiffness)?;
        Ok(())
    }

    /// `self` after [`Self::validate`] passed, as [`Checked`] parameters.
    pub fn checked(self) -> Result<Checked<ContactParams>, ParamError> {
        self.validate()?;
        Ok(Checked::assume_checked(self))
    }

    /// The material of these parameters.
    pub fn material(&self) -> Material {
        Material {
            normal_stiffness: self.normal_stiffness,
            normal_damping: self.normal_damping,
            mu_s: self.mu_s,
            mu_k: self.mu_k,
            spin_stiffness: self.spin_stiffness,
        }
    }

    /// `self` with the material `m`.
    pub fn with_material(&self, m: &Material) -> ContactParams {
        ContactParams {
            normal_stiffness: m.normal_stiffness,
            normal_damping: m.normal_damping,
            mu_s: m.mu_s,
            mu_k: m.mu_k,
            spin_stiffness: m.spin_stiffness,
            ..*self
        }
    }

    /// Take `other`'s material in place: with [`Self::same_but_material`] true, `self` then equals
    /// `other` (==) without a copy of the whole parameters.
    #[inline(always)]
    pub fn take_material_of(&mut self, other: &ContactParams) {
        self.normal_stiffness = other.normal_stiffness;
        self.normal_damping = other.normal_damping;
        self.mu_s = other.mu_s;
        self.mu_k = other.mu_k;
        self.spin_stiffness = other.spin_stiffness;
    }

    /// `self` with the material of `other` (see [`Self::validate_material`]).
    pub fn with_material_of(&self, other: &ContactParams) -> ContactParams {
        self.with_material(&other.material())
    }

    /// True when `self` and `other` differ at most in their material: a contact can then carry
    /// on from one to the other (same fingertip, coupling, patch, limits and tolerances).
    ///
    /// Compared field by field where both lie (a tick that applies new parameters asks this, and
    /// a copy of either side costs it about 110 instructions); the destructuring is exhaustive,
    /// so a new field must be named here as material or not.
    #[inline(always)]
    pub fn same_but_material(&self, other: &ContactParams) -> bool {
        let ContactParams {
            method,
            fingertip_radius_m,
            normal_stiffness: _,
            normal_damping: _,
            tangential_stiffness,
            tangential_damping,
            mu_s: _,
            mu_k: _,
            spin_stiffness: _,
            patch_radius_m,
            patch_ref_force_n,
            patch_exponent,
            k_tau,
            max_force_n,
            tolerances,
        } = self;
        *method == other.method
            && *fingertip_radius_m == other.fingertip_radius_m
            && *tangential_stiffness == other.tangential_stiffness
            && *tangential_damping == other.tangential_damping
            && *patch_radius_m == other.patch_radius_m
            && *patch_ref_force_n == other.patch_ref_force_n
            && *patch_exponent == other.patch_exponent
            && *k_tau == other.k_tau
            && *max_force_n == other.max_force_n
            && tolerances.same(&other.tolerances)
    }

    /// The state machine's view of these parameters.
    pub fn state_params(&self) -> StateParams {
        StateParams {
            mu_s: self.mu_s,
            mu_k: self.mu_k,
            k_tau: self.k_tau,
            radius_m: self.fingertip_radius_m,
            roll_eps_m: 1e-9,
            tol: self.tolerances,
        }
    }
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only the five material fields count as material: each of them changed alone keeps
    /// `same_but_material`, any other field changed alone breaks it.
    #[test]
    fn same_but_material_names_exactly_the_material() {
        let d = ContactParams::DEFAULT;
        let material: [fn(&mut ContactParams); 5] = [
            |p| p.normal_stiffness *= 0.5,
            |p| p.normal_damping += 1.0,
            |p| p.mu_s += 0.1,
            |p| p.mu_k *= 0.5,
            |p| p.spin_stiffness *= 2.0,
        ];
        for change in material {
            let mut p = d;
            change(&mut p);
            assert_ne!(p, d);
            assert!(p.same_but_material(&d) && d.same_but_material(&p), "{p:?}");
            assert_eq!(d.with_material_of(&p), p);
            let mut taken = d;
            taken.take_material_of(&p);
            assert_eq!(taken, p);
        }
        // Every other field, the tolerances one by one included.
        let other: [fn(&mut ContactParams); 18] = [
            |p| p.method = Method::Rpy,
            |p| p.fingertip_radius_m *= 1.5,
            |p| p.tangential_stiffness *= 0.5,
            |p| p.tangential_damping += 1.0,
            |p| p.patch_radius_m *= 0.5,
            |p| p.patch_ref_force_n *= 2.0,
            |p| p.patch_exponent = 0.5,
            |p| p.max_force_n = 30.0,
            |p| p.k_tau *= 0.5,
            |p| p.tolerances.force_eps_n *= 2.0,
            |p| p.tolerances.accel_eps *= 2.0,
            |p| p.tolerances.normal_accel_tol *= 2.0,
            |p| p.tolerances.gap_eps_m *= 2.0,
            |p| p.tolerances.stick_speed *= 2.0,
            |p| p.tolerances.hysteresis *= 0.5,
            |p| p.tolerances.make_force_n *= 2.0,
            |p| p.tolerances.min_slide_s *= 2.0,
            |p| p.tolerances.min_broken_s *= 2.0,
        ];
        for change in other {
            let mut p = d;
            change(&mut p);
            assert_ne!(p, d);
            assert!(
                !p.same_but_material(&d) && !d.same_but_material(&p),
                "{p:?}"
            );
            assert_eq!(
                p.tolerances.same(&d.tolerances),
                p.tolerances == d.tolerances
            );
        }
    }

    /// A blend's material stays valid on every step: each field between its ends, μ_k ≤ μ_s
    /// even where μ_k's end is μ_s's (0.5 → 0.6 and 0.5 → 0.6 in a different order).
    #[test]
    fn a_material_blend_stays_valid() {
        let a = Material {
            mu_s: 0.5,
            mu_k: 0.5,
            ..ContactParams::DEFAULT.material()
        };
        let b = Material {
            normal_stiffness: 1.0,
            mu_s: 0.9,
            mu_k: 0.9,
            ..a
        };
        for i in 0..=100 {
            let k = i as f32 / 100.0;
            let m = a.lerp(&b, k);
            let p = ContactParams::DEFAULT.with_material(&m);
            assert_eq!(p.validate_material(), Ok(()), "{k}: {m:?}");
            assert!(m.mu_k <= m.mu_s);
            assert!(m.normal_stiffness <= a.normal_stiffness && m.normal_stiffness >= 1.0);
        }
        assert_eq!(a.lerp(&b, 0.0), a);
        assert_eq!(a.lerp(&b, 1.0), b);
    }

    #[test]
    fn defaults_are_valid() {
        assert_eq!(ContactParams::DEFAULT.validate(), Ok(()));
    }

    #[test]
    fn each_bad_field_is_named() {
        let d = ContactParams::DEFAULT;
        let cases: [(ContactParams, ParamError); 9] = [
            (
                ContactParams {
                    fingertip_radius_m: 0.0,
                    ..d
                },
                ParamError::NotPositive("fingertip_radius_m"),
            ),
            (
                ContactParams {
                    fingertip_radius_m: f32::NAN,
                    ..d
                },
                ParamError::NotFinite("fingertip_radius_m"),
            ),
            (
                ContactParams {
                    normal_stiffness: -1.0,
                    ..d
                },
                ParamError::Negative("normal_stiffness"),
            ),
            (
                ContactParams {
                    mu_s: f32::INFINITY,
                    ..d
                },
                ParamError::NotFinite("mu_s"),
            ),
            (
                ContactParams { mu_k: 0.0, ..d },
                ParamError::NotPositive("mu_k"),
            ),
            (
                ContactParams { mu_k: 0.9, ..d },
                ParamError::KineticAboveStatic,
            ),
            (
                ContactParams { k_tau: 0.0, ..d },
                ParamError::NotPositive("k_tau"),
            ),
            (
                ContactParams {
                    tolerances: Tolerances {
                        hysteresis: 1.0,
                        ..d.tolerances
                    },
                    ..d
                },
                ParamError::OutOfRange("hysteresis"),
            ),
            (
                ContactParams {
                    max_force_n: -3.0,
                    ..d
                },
                ParamError::NotPositive("max_force_n"),
            ),
        ];
        for (p, e) in cases {
            assert_eq!(p.validate(), Err(e));
        }
    }

    /// The patch law's parameters: exponent in [0, 1], reference force > 0 (both ends and just
    /// beyond them).
    #[test]
    fn patch_law_parameters_are_checked_at_their_ends() {
        let d = ContactParams::DEFAULT;
        let with = |g: f32, f: f32| ContactParams {
            patch_exponent: g,
            patch_ref_force_n: f,
            ..d
        };
        assert_eq!(with(0.0, 2.0).validate(), Ok(()));
        assert_eq!(with(1.0, 2.0).validate(), Ok(()));
        assert_eq!(
            with(-1e-6, 2.0).validate(),
            Err(ParamError::Negative("patch_exponent"))
        );
        assert_eq!(
            with(1.000_001, 2.0).validate(),
            Err(ParamError::OutOfRange("patch_exponent"))
        );
        assert_eq!(
            with(0.3, 0.0).validate(),
            Err(ParamError::NotPositive("patch_ref_force_n"))
        );
        assert_eq!(with(0.3, 1e-6).validate(), Ok(()));
        assert_eq!(
            with(0.3, f32::NAN).validate(),
            Err(ParamError::NotFinite("patch_ref_force_n"))
        );
    }

    /// The message names the field, and a device error is shown by its message (not `Debug`).
    #[test]
    fn display_names_the_field() {
        use std::string::ToString;
        let bad = ContactParams {
            fingertip_radius_m: 0.0,
            ..ContactParams::DEFAULT
        };
        let e: &dyn core::error::Error = &bad.validate().unwrap_err();
        assert_eq!(e.to_string(), "fingertip_radius_m must be > 0");
        assert_eq!(
            ParamError::OutOfRange("mu_s").to_string(),
            "mu_s is out of range"
        );
        let device = ParamError::Device(crate::device::DeviceParamError::NotPositive(
            crate::device::DeviceParamField::CapstanRatio,
        ));
        assert_eq!(
            device.to_string(),
            "device parameters: motor.capstan_ratio must be > 0"
        );
    }
}
