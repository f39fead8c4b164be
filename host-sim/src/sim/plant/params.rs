//! Values only the plant model needs: inertias, masses, friction, inductance, mechanical stops,
//! gravity, the user's hand impedance and the integration sub-step count. Everything the
//! controller must also know lives in `softfinger_core::device::DeviceParams`.

/// Plant-only parameters (SI units; "arm side" means referred to the arm axis, after the
/// capstan reduction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantParams {
    /// Motor winding inductance, H.
    pub motor_inductance_h: f64,
    /// Motor rotor plus capstan drive pulley inertia on the motor shaft, kg·m² (reflected to
    /// the arm by ratio²).
    pub rotor_inertia_kg_m2: f64,
    /// Inertia about the motor axis of the arm, its capstan sector and the elbow's share of the
    /// forearms, kg·m².
    pub arm_inertia_kg_m2: f64,
    /// First mass moment Σ m·r of the same parts along the arm direction uᵢ, kg·m (gravity
    /// torque = this × g·duᵢ/dθ). Negative if the sector over-balances the arm.
    pub arm_mass_moment_kg_m: f64,
    /// Translating mass of the effector: platform, wrist gimbal, handle and the effector's share
    /// of the forearms, kg.
    pub effector_mass_kg: f64,
    /// Coulomb friction of each drive train, arm side, N·m.
    pub coulomb_friction_nm: f64,
    /// Viscous friction of each drive train, arm side, N·m·s/rad.
    pub viscous_friction_nm_s_per_rad: f64,
    /// Velocity scale ω_s of the tanh-smoothed Coulomb term, rad/s.
    pub friction_smoothing_rad_s: f64,
    /// Mechanical stops of every arm, [min, max], rad.
    pub arm_limits_rad: [f64; 2],
    /// Stop contact stiffness, N·m/rad.
    pub stop_stiffness_nm_per_rad: f64,
    /// Stop contact damping (only while in contact, never pulling), N·m·s/rad.
    pub stop_damping_nm_s_per_rad: f64,
    /// Gravitational acceleration in the base frame `B`, m/s².
    pub gravity_m_s2: [f64; 3],
    /// Mass of the user's hand, moving rigidly with the handle, kg. Its weight is carried by the
    /// user, not the device.
    pub hand_mass_kg: f64,
    /// Grasp stiffness between the hand's scripted reference and the handle, N/m.
    pub hand_stiffness_n_per_m: f64,
    /// Grasp damping, N·s/m.
    pub hand_damping_n_s_per_m: f64,
    /// Integration sub-steps per control tick.
    pub substeps: u32,
}

/// A rejected plant parameter, naming the field.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlantParamError {
    /// The named field is NaN or infinite.
    #[error("{0} is not finite")]
    NonFinite(&'static str),
    /// The named field is below zero.
    #[error("{0} must not be negative")]
    Negative(&'static str),
    /// The named field is zero or below.
    #[error("{0} must be positive")]
    NotPositive(&'static str),
    /// `arm_limits_rad[0]` must be below `arm_limits_rad[1]`.
    #[error("arm_limits_rad[0] must be below arm_limits_rad[1]")]
    ArmLimitsInverted,
}

impl PlantParams {
    /// Our plant for the Omega-like device of `DeviceParams::OMEGA_LIKE`. All values are
    /// assumptions unless a source is named:
    ///
    /// - inductance 0.24 mH and rotor inertia 10.8 g·cm² of the maxon RE 25-class motor
    ///   (catalogue values for that class), plus 0.08 g·cm² for a Ø10 × 10 mm steel drive
    ///   pulley: 1.16e-6 kg·m², 1.67e-4 kg·m² at the arm through 12²;
    /// - arm: 20 g tube over 105 mm (m·L²/3 = 7.4e-5), 30 g sector with 40 mm radius of gyration
    ///   (4.8e-5), 12 g elbow share of forearms and joints at 105 mm (1.3e-4): 2.5e-4 kg·m²; mass
    ///   moment 1.05e-3 + 1.26e-3 − 0.75e-3 (sector centroid 25 mm behind the axis) = 1.5e-3 kg·m;
    /// - effector: platform, three-encoder wrist gimbal, handle and forearm share: 0.15 kg;
    /// - friction, arm side: Coulomb 0.01 N·m (the RE 25's ~23 mA no-load current is 6.5 mN·m at
    ///   the arm, plus capstan and joints), viscous 5e-4 N·m·s/rad, smoothing 0.01 rad/s;
    /// - stops at −40° and 105°: the linkage assembles over the whole box [−40°, 105°]³ with
    ///   forearm volume ≥ 0.11 (sweep in `mechanism` tests); 100 N·m/rad, 0.3 N·m·s/rad;
    /// - gravity −9.81 m/s² along z (the base is mounted above the working volume);
    /// - hand: 0.4 kg, 300 N/m, 13.1 N·s/m (ζ = b/(2√(k·m)) = 0.6 on the hand mass alone).
    ///   These are assumptions in the range system-identification studies report for a hand or
    ///   arm holding a haptic handle (e.g. Hasser & Cutkosky, pinch grasp on a haptic knob;
    ///   Fu & Çavuşoğlu, stylus grasp on a PHANToM; one fitted trial in Sci. Rep. 5:18004 gives
    ///   M = 0.55 kg, B = 6.5 N·s/m, K = 135 N/m), not measurements of ours;
    /// - 10 sub-steps per tick (10 µs at 10 kHz: 0.09 τ_e, and ω·h < 0.005 for the stiffest
    ///   mode, the stop contact at ~460 rad/s).
    pub const OMEGA_LIKE: PlantParams = PlantParams {
        motor_inductance_h: 0.24e-3,
        rotor_inertia_kg_m2: 1.16e-6,
        arm_inertia_kg_m2: 2.5e-4,
        arm_mass_moment_kg_m: 1.5e-3,
        effector_mass_kg: 0.15,
        coulomb_friction_nm: 0.01,
        viscous_friction_nm_s_per_rad: 5e-4,
        friction_smoothing_rad_s: 0.01,
        arm_limits_rad: [-40.0 * DEG, 105.0 * DEG],
        stop_stiffness_nm_per_rad: 100.0,
        stop_damping_nm_s_per_rad: 0.3,
        gravity_m_s2: [0.0, 0.0, -9.81],
        hand_mass_kg: 0.4,
        hand_stiffness_n_per_m: 300.0,
        hand_damping_n_s_per_m: 13.1,
        substeps: 10,
    };

    /// The same plant with nobody holding the handle.
    pub fn without_hand(self) -> PlantParams {
        PlantParams {
            hand_mass_kg: 0.0,
            hand_stiffness_n_per_m: 0.0,
            hand_damping_n_s_per_m: 0.0,
            ..self
        }
    }

    /// The same plant in zero gravity.
    pub fn without_gravity(self) -> PlantParams {
        PlantParams {
            gravity_m_s2: [0.0; 3],
            ..self
        }
    }

    /// The same plant without drive-train friction.
    pub fn frictionless(self) -> PlantParams {
        PlantParams {
            coulomb_friction_nm: 0.0,
            viscous_friction_nm_s_per_rad: 0.0,
            ..self
        }
    }

    /// Check every field; the first problem is returned.
    pub fn validate(&self) -> Result<(), PlantParamError> {
        use PlantParamError as E;
        let positive = [
            (self.motor_inductance_h, "motor_inductance_h"),
            (self.rotor_inertia_kg_m2, "rotor_inertia_kg_m2"),
            (self.arm_inertia_kg_m2, "arm_inertia_kg_m2"),
            (self.friction_smoothing_rad_s, "friction_smoothing_rad_s"),
            (self.stop_stiffness_nm_per_rad, "stop_stiffness_nm_per_rad"),
        ];
        let non_negative = [
            (self.effector_mass_kg, "effector_mass_kg"),
            (self.coulomb_friction_nm, "coulomb_friction_nm"),
            (
                self.viscous_friction_nm_s_per_rad,
                "viscous_friction_nm_s_per_rad",
            ),
            (self.stop_damping_nm_s_per_rad, "stop_damping_nm_s_per_rad"),
            (self.hand_mass_kg, "hand_mass_kg"),
            (self.hand_stiffness_n_per_m, "hand_stiffness_n_per_m"),
            (self.hand_damping_n_s_per_m, "hand_damping_n_s_per_m"),
        ];
        let finite = [
            (self.arm_mass_moment_kg_m, "arm_mass_moment_kg_m"),
            (self.arm_limits_rad[0], "arm_limits_rad"),
            (self.arm_limits_rad[1], "arm_limits_rad"),
            (self.gravity_m_s2[0], "gravity_m_s2"),
            (self.gravity_m_s2[1], "gravity_m_s2"),
            (self.gravity_m_s2[2], "gravity_m_s2"),
        ];
        for (v, name) in positive.iter().chain(&non_negative).chain(&finite) {
            if !v.is_finite() {
                return Err(E::NonFinite(name));
            }
        }
        for (v, name) in positive {
            if v <= 0.0 {
                return Err(E::NotPositive(name));
            }
        }
        for (v, name) in non_negative {
            if v < 0.0 {
                return Err(E::Negative(name));
            }
        }
        if self.substeps == 0 {
            return Err(E::NotPositive("substeps"));
        }
        if self.arm_limits_rad[0] >= self.arm_limits_rad[1] {
            return Err(E::ArmLimitsInverted);
        }
        Ok(())
    }
}

const DEG: f64 = std::f64::consts::PI / 180.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn omega_like_is_valid_and_bad_fields_are_named() {
        assert_eq!(PlantParams::OMEGA_LIKE.validate(), Ok(()));
        let p = PlantParams {
            motor_inductance_h: 0.0,
            ..PlantParams::OMEGA_LIKE
        };
        assert_eq!(
            p.validate(),
            Err(PlantParamError::NotPositive("motor_inductance_h"))
        );
        let p = PlantParams {
            hand_damping_n_s_per_m: -1.0,
            ..PlantParams::OMEGA_LIKE
        };
        assert_eq!(
            p.validate(),
            Err(PlantParamError::Negative("hand_damping_n_s_per_m"))
        );
        let p = PlantParams {
            gravity_m_s2: [0.0, f64::NAN, 0.0],
            ..PlantParams::OMEGA_LIKE
        };
        assert_eq!(
            p.validate(),
            Err(PlantParamError::NonFinite("gravity_m_s2"))
        );
        let p = PlantParams {
            arm_limits_rad: [1.0, 0.5],
            ..PlantParams::OMEGA_LIKE
        };
        assert_eq!(p.validate(), Err(PlantParamError::ArmLimitsInverted));
        let p = PlantParams {
            substeps: 0,
            ..PlantParams::OMEGA_LIKE
        };
        assert_eq!(p.validate(), Err(PlantParamError::NotPositive("substeps")));
        // The hand-impedance damping ratio quoted in the doc.
        let h = PlantParams::OMEGA_LIKE;
        let zeta =
            h.hand_damping_n_s_per_m / (2.0 * (h.hand_stiffness_n_per_m * h.hand_mass_kg).sqrt());
        assert!((zeta - 0.6).abs() < 0.005, "{zeta}");
    }
}
