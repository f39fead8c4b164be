//! Kinematics of the device's three active axes: a rotary (Clavel) delta mechanism, the same
//! architecture as the translational stage of the Force Dimension Omega.6.
//!
//! # Frame and conventions
//!
//! - **Base frame `B`** (the crate's frames table, [`crate`]): origin at the centre of the base (the circle through the three motor
//!   axes); z is the mechanism's axis of symmetry and points from the effector towards the base,
//!   so the effector works below the base at negative z. x points from the base centre towards
//!   motor 0. Which way `B` points in the room depends on how the device is mounted; gravity is not
//!   assumed here.
//! - **Motor `i`** (i = 0, 1, 2) sits at azimuth φᵢ = 120°·i about z. Its unit radial vector is
//!   r̂ᵢ = (cos φᵢ, sin φᵢ, 0); its axis is tangent to the base circle, at bᵢ = R_b·r̂ᵢ.
//! - **Arm angle θᵢ** (rad): 0 when the upper arm points horizontally outwards (along r̂ᵢ);
//!   positive turns the arm downwards (towards −z). The arm's unit direction is
//!   uᵢ(θ) = cos θ·r̂ᵢ − sin θ·ẑ and the elbow is at bᵢ + L_a·uᵢ(θᵢ).
//! - **Effector**: its centre p (m, frame `B`) is the point the kinematics return. The parallelogram
//!   forearms keep the effector platform parallel to the base; forearm i ends at p + eᵢ with
//!   eᵢ = R_e·r̂ᵢ.
//! - **Constraint** of chain i: gᵢ(p, θᵢ) = |p + eᵢ − bᵢ − L_a·uᵢ(θᵢ)|² − L_b² = 0. Only the
//!   difference R_b − R_e enters: p lies on a sphere of radius L_b around
//!   cᵢ = bᵢ − eᵢ + L_a·uᵢ(θᵢ) = (R_b − R_e + L_a cos θᵢ)·r̂ᵢ − L_a sin θᵢ·ẑ.
//! - **Torques** are arm-side: the torque (N·m) each motor must apply to its upper arm, after the
//!   capstan reduction, positive in the direction of increasing θ. The capstan ratio and the
//!   motor constants live in [`crate::device`].
//!
//! Units: m, rad, N, N·m.
//!
//! # Singularities and bad input
//!
//! Every function returns a finite, defined value. Non-finite input gives zero output and
//! [`Flags::NON_FINITE_INPUT`]; a configuration the mechanism cannot assemble (the three spheres
//! do not meet, or their centres are collinear) or where the forearms are close to coplanar
//! gives zero output and [`Flags::KINEMATICS_SINGULAR`]. Zero torque is the safe output for a
//! haptic device; a zero position is never inside the working volume, so a caller that ignores
//! the flag still cannot mistake it for a valid reading near the user.
//!
//! All square roots go through the backend `M`; an inaccurate `sqrt` (micromath's ~5 %) shows up
//! one-for-one in the position, so the kinematics want `Libm` or `Fast`.

use crate::flags::{all_finite, Flags};
use crate::math::vec3::Vec3;
use crate::math::Math;

/// cos φᵢ of the motor azimuths 0°, 120°, 240°.
const AZIMUTH_COS: [f32; 3] = [1.0, -0.5, -0.5];
/// sin φᵢ of the motor azimuths 0°, 120°, 240° (√3/2 rounded to f32).
const AZIMUTH_SIN: [f32; 3] = [0.0, 0.866_025_4, -0.866_025_4];

/// Sphere centres closer to collinear than this (sin² of the triangle's angle, |a×b|²/(|a|²|b|²))
/// are treated as singular. 1e-4 is sin ≈ 0.01; below it the circumcentre's f32 error would grow
/// past ~1e-3 relative. In the working volume of [`DeltaGeometry::OMEGA_LIKE`] the centres form a
/// near-equilateral triangle (sin² ≈ 0.75).
const COLLINEAR_SIN2_MIN: f32 = 1.0e-4;

/// Sphere-centre triangles with |(c₁−c₀)×(c₂−c₀)| (twice the area) below this fraction of L_b²
/// are treated as singular: the centres have (nearly) merged, the mechanism gains a degree of
/// freedom and the circumcentre is set by rounding. In the working volume of `OMEGA_LIKE` the
/// ratio is above 0.5.
const MIN_TRIANGLE_AREA_RATIO: f32 = 1.0e-3;

/// Smallest accepted forearm volume |s₀·(s₁×s₂)|/L_b³ (the three forearm directions' triple
/// product). Below it the forearms are close to coplanar and the force map blows up: with this
/// guard |τᵢ| ≤ L_a·|F|/0.05 = 20·L_a·|F|. The working volume of `OMEGA_LIKE` stays above 0.6.
pub const MIN_FOREARM_VOLUME: f32 = 0.05;

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

/// The linkage at one configuration: the effector position and the velocity terms of the
/// Jacobian (see [`DeltaGeometry::pose`]). `det == 0` marks a pose without valid torques.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeltaPose {
    /// Effector centre, frame `B`, m.
    pub effector_m: Vec3,
    /// Forearm vectors sᵢ = p − cᵢ, m.
    forearms: [Vec3; 3],
    /// dᵢ = L_a·sᵢ·duᵢ/dθ, m².
    d: [f32; 3],
    /// det J_x = s₀·(s₁×s₂), m³ (0: no valid torques).
    det: f32,
}

impl DeltaPose {
    /// A pose with no valid position or torques.
    pub const INVALID: DeltaPose = DeltaPose {
        effector_m: Vec3::ZERO,
        forearms: [Vec3::ZERO; 3],
        d: [0.0; 3],
        det: 0.0,
    };
}

/// The jacobian ṗ = J·θ̇ (m/rad), row-major: `j[row][col]`, row = Cartesian axis x, y, z of `B`,
/// column = motor.
pub type Jacobian = [[f32; 3]; 3];

impl DeltaGeometry {
    /// R_b − R_e: the only combination of the two radii the kinematics depend on, m.
    #[inline]
    fn radius_offset(&self) -> f32 {
        self.base_radius_m - self.effector_radius_m
    }

    /// Sphere centre cᵢ (see the module doc) and the arm's derivative direction
    /// duᵢ/dθ = −sin θ·r̂ᵢ − cos θ·ẑ, for arm `i` at angle with (sin, cos) = `sc`.
    #[inline]
    fn chain(&self, cos_phi: f32, sin_phi: f32, sc: (f32, f32)) -> (Vec3, Vec3) {
        let (s, c) = sc;
        let rho = self.radius_offset() + self.upper_arm_m * c;
        let centre = Vec3::new(rho * cos_phi, rho * sin_phi, -self.upper_arm_m * s);
        let du = Vec3::new(-s * cos_phi, -s * sin_phi, -c);
        (centre, du)
    }

    /// Sphere centres and arm derivative directions of all three chains.
    fn chains<M: Math>(&self, angles_rad: [f32; 3]) -> ([Vec3; 3], [Vec3; 3]) {
        let mut centres = [Vec3::ZERO; 3];
        let mut dus = [Vec3::ZERO; 3];
        for (((centre, du), &theta), (&cp, &sp)) in centres
            .iter_mut()
            .zip(dus.iter_mut())
            .zip(angles_rad.iter())
            .zip(AZIMUTH_COS.iter().zip(AZIMUTH_SIN.iter()))
        {
            (*centre, *du) = self.chain(cp, sp, M::sin_cos(theta));
        }
        (centres, dus)
    }

    /// Forward kinematics: motor angles (rad) to the effector centre in the device base frame (m).
    ///
    /// Closed-form intersection of the three spheres |p − cᵢ| = L_b: the circumcentre p₀ of the
    /// triangle c₀c₁c₂ lies on the line where they meet, which runs along n = (c₁−c₀)×(c₂−c₀);
    /// p = p₀ ∓ h·n̂ with h² = L_b² − |p₀ − c₀|², taking the solution with the smaller z (the
    /// effector below the elbows).
    ///
    /// Non-finite angles: `(Vec3::ZERO, NON_FINITE_INPUT)`. Spheres that do not meet (h² < 0) or
    /// centres that are collinear: `(Vec3::ZERO, KINEMATICS_SINGULAR)`.
    #[must_use]
    pub fn forward<M: Math>(&self, angles_rad: [f32; 3]) -> (Vec3, Flags) {
        if !all_finite(&angles_rad) {
            return (Vec3::ZERO, Flags::NON_FINITE_INPUT);
        }
        let (centres, _) = self.chains::<M>(angles_rad);
        self.forward_from_centres::<M>(centres)
    }

    /// [`Self::forward`] from the sphere centres.
    #[must_use]
    fn forward_from_centres<M: Math>(&self, [c0, c1, c2]: [Vec3; 3]) -> (Vec3, Flags) {
        let a = c1 - c0;
        let b = c2 - c0;
        let n = a.cross(b);
        let n2 = n.norm_squared();
        let a2 = a.norm_squared();
        let b2 = b.norm_squared();
        let lb2 = self.forearm_m * self.forearm_m;
        let min_area = MIN_TRIANGLE_AREA_RATIO * lb2;
        // Comparisons with NaN (from a non-finite geometry) are false, so NaN is not `ok` either.
        let ok = n2 > COLLINEAR_SIN2_MIN * a2 * b2 && n2 > min_area * min_area;
        if !ok {
            return (Vec3::ZERO, Flags::KINEMATICS_SINGULAR);
        }
        // Circumcentre relative to c0: (|a|²·(b×n) + |b|²·(n×a)) / (2|n|²).
        let p0 = (b.cross(n) * a2 + n.cross(a) * b2) * (0.5 / n2);
        let h2 = lb2 - p0.norm_squared();
        let reachable = h2 >= 0.0; // false for NaN too
        if !reachable {
            return (Vec3::ZERO, Flags::KINEMATICS_SINGULAR);
        }
        let step = M::sqrt(h2) / M::sqrt(n2);
        let p = if n.z > 0.0 {
            c0 + p0 - n * step
        } else {
            c0 + p0 + n * step
        };
        if !p.is_finite() {
            return (Vec3::ZERO, Flags::KINEMATICS_SINGULAR);
        }
        (p, Flags::NONE)
    }

    /// Inverse kinematics: effector centre (m, frame `B`) to motor angles (rad), elbows outwards.
    ///
    /// Per chain, with q = p + eᵢ − bᵢ in the arm's axes (x along r̂ᵢ, y tangential, z along ẑ),
    /// the constraint reduces to q_x cos θ − q_z sin θ = K, K = (|q|² + L_a² − L_b²)/(2L_a), whose
    /// solution with the elbow outside the forearm (the larger radial elbow coordinate) is
    /// θ = −atan2(q_z, q_x) − acos(K/√(q_x² + q_z²)).
    ///
    /// Non-finite input: `([0; 3], NON_FINITE_INPUT)`; a point out of reach of any chain:
    /// `([0; 3], KINEMATICS_SINGULAR)`.
    #[must_use]
    pub fn inverse<M: Math>(&self, effector_m: Vec3) -> ([f32; 3], Flags) {
        if !effector_m.is_finite() {
            return ([0.0; 3], Flags::NON_FINITE_INPUT);
        }
        let la = self.upper_arm_m;
        let lb = self.forearm_m;
        let mut angles = [0.0f32; 3];
        for (theta, (&cp, &sp)) in angles
            .iter_mut()
            .zip(AZIMUTH_COS.iter().zip(AZIMUTH_SIN.iter()))
        {
            // Effector joint relative to the motor axis, in the arm's (radial, tangential, z) axes.
            let qx = cp * effector_m.x + sp * effector_m.y - self.radius_offset();
            let qy = -sp * effector_m.x + cp * effector_m.y;
            let qz = effector_m.z;
            let k = (qx * qx + qy * qy + qz * qz + la * la - lb * lb) / (2.0 * la);
            let rho2 = qx * qx + qz * qz;
            // |K| ≤ ρ ⇔ K² ≤ ρ². Comparisons with NaN are false, so NaN is not `reachable`.
            let reachable = k * k <= rho2 && rho2 > 0.0;
            if !reachable {
                return ([0.0; 3], Flags::KINEMATICS_SINGULAR);
            }
            // acos(K/ρ) = atan2(√(ρ² − K²), K), exact at both ends of the range.
            let t = -M::atan2(qz, qx) - M::atan2(M::sqrt(rho2 - k * k), k);
            if !t.is_finite() {
                return ([0.0; 3], Flags::KINEMATICS_SINGULAR);
            }
            *theta = t;
        }
        (angles, Flags::NONE)
    }

    /// The pieces of the velocity relation J_x·ṗ + J_θ·θ̇ = 0, from differentiating gᵢ:
    /// forearm vectors sᵢ = p − cᵢ (rows of J_x), dᵢ = L_a·sᵢ·duᵢ/dθ (J_θ = −diag(dᵢ)) and
    /// det J_x = s₀·(s₁×s₂). `None` when the forearm volume is below [`MIN_FOREARM_VOLUME`].
    fn velocity_terms<M: Math>(
        &self,
        angles_rad: [f32; 3],
        effector_m: Vec3,
    ) -> Option<([Vec3; 3], [f32; 3], f32)> {
        let (centres, dus) = self.chains::<M>(angles_rad);
        self.velocity_terms_from(centres, dus, effector_m)
    }

    /// [`Self::velocity_terms`] from the sphere centres and arm derivative directions.
    fn velocity_terms_from(
        &self,
        centres: [Vec3; 3],
        dus: [Vec3; 3],
        effector_m: Vec3,
    ) -> Option<([Vec3; 3], [f32; 3], f32)> {
        let s = [
            effector_m - centres[0],
            effector_m - centres[1],
            effector_m - centres[2],
        ];
        let d = [
            self.upper_arm_m * s[0].dot(dus[0]),
            self.upper_arm_m * s[1].dot(dus[1]),
            self.upper_arm_m * s[2].dot(dus[2]),
        ];
        let det = s[0].dot(s[1].cross(s[2]));
        let lb = self.forearm_m;
        let volume_min = MIN_FOREARM_VOLUME * lb * lb * lb;
        // Comparisons with NaN are false, so NaN is not `conditioned`.
        let conditioned = det.abs() >= volume_min && volume_min > 0.0;
        if !conditioned {
            return None;
        }
        Some((s, d, det))
    }

    /// Jacobian J with ṗ = J·θ̇ (m/rad; see [`Jacobian`]) at a configuration whose effector
    /// position `effector_m` has already been found by [`Self::forward`].
    ///
    /// From J_x·ṗ = diag(d)·θ̇: J = J_x⁻¹·diag(d), with J_x⁻¹ by Cramer's rule (its columns are
    /// (s₁×s₂, s₂×s₀, s₀×s₁)/det J_x). Non-finite input: zeros and `NON_FINITE_INPUT`; forearm
    /// volume below [`MIN_FOREARM_VOLUME`]: zeros and `KINEMATICS_SINGULAR`.
    #[must_use]
    pub fn jacobian<M: Math>(&self, angles_rad: [f32; 3], effector_m: Vec3) -> (Jacobian, Flags) {
        if !all_finite(&angles_rad) || !effector_m.is_finite() {
            return ([[0.0; 3]; 3], Flags::NON_FINITE_INPUT);
        }
        let Some((s, d, det)) = self.velocity_terms::<M>(angles_rad, effector_m) else {
            return ([[0.0; 3]; 3], Flags::KINEMATICS_SINGULAR);
        };
        let inv_det = 1.0 / det;
        let cols = [
            s[1].cross(s[2]) * (d[0] * inv_det),
            s[2].cross(s[0]) * (d[1] * inv_det),
            s[0].cross(s[1]) * (d[2] * inv_det),
        ];
        let j = [
            [cols[0].x, cols[1].x, cols[2].x],
            [cols[0].y, cols[1].y, cols[2].y],
            [cols[0].z, cols[1].z, cols[2].z],
        ];
        if !j.iter().all(|row| all_finite(row)) {
            return ([[0.0; 3]; 3], Flags::KINEMATICS_SINGULAR);
        }
        (j, Flags::NONE)
    }

    /// Jacobian transpose: motor torques (N·m) that render `force_n` (N, base frame) at the effector.
    ///
    /// `force_n` is the force the effector exerts on the user's hand; the result is the arm-side
    /// torque each motor must apply (positive towards increasing θ) to hold it statically. By
    /// virtual work τ·δθ = F·δp = F·J·δθ, so τ = Jᵀ·F: with λ = J_x⁻ᵀ·F (Cramer's rule),
    /// τᵢ = dᵢ·λᵢ = dᵢ·(sⱼ×sₖ)·F / det J_x, (i, j, k) cyclic. λᵢ·sᵢ is the force carried by
    /// forearm i. `effector_m` is the position [`Self::forward`] returned for `angles_rad`.
    ///
    /// Non-finite input: zero torques and `NON_FINITE_INPUT`; forearm volume below
    /// [`MIN_FOREARM_VOLUME`]: zero torques and `KINEMATICS_SINGULAR`.
    #[must_use]
    pub fn joint_torques<M: Math>(
        &self,
        angles_rad: [f32; 3],
        effector_m: Vec3,
        force_n: Vec3,
    ) -> ([f32; 3], Flags) {
        if !all_finite(&angles_rad) || !effector_m.is_finite() || !force_n.is_finite() {
            return ([0.0; 3], Flags::NON_FINITE_INPUT);
        }
        let Some((s, d, det)) = self.velocity_terms::<M>(angles_rad, effector_m) else {
            return ([0.0; 3], Flags::KINEMATICS_SINGULAR);
        };
        Self::torques_from(s, d, det, force_n)
    }

    /// Forward kinematics and everything [`Self::torques_at`] needs, from one evaluation of the
    /// arms' sines and cosines (a control tick needs both; computing them once saves three
    /// `sin_cos`). Flags as [`Self::forward`]; a configuration whose forearm volume is below
    /// [`MIN_FOREARM_VOLUME`] has a valid position but is flagged `KINEMATICS_SINGULAR` and gives
    /// zero torques.
    #[must_use]
    pub fn pose<M: Math>(&self, angles_rad: [f32; 3]) -> (DeltaPose, Flags) {
        if !all_finite(&angles_rad) {
            return (DeltaPose::INVALID, Flags::NON_FINITE_INPUT);
        }
        let (centres, dus) = self.chains::<M>(angles_rad);
        let (p, flags) = self.forward_from_centres::<M>(centres);
        if !flags.is_empty() {
            return (DeltaPose::INVALID, flags);
        }
        match self.velocity_terms_from(centres, dus, p) {
            Some((s, d, det)) => (
                DeltaPose {
                    effector_m: p,
                    forearms: s,
                    d,
                    det,
                },
                Flags::NONE,
            ),
            None => (
                DeltaPose {
                    effector_m: p,
                    ..DeltaPose::INVALID
                },
                Flags::KINEMATICS_SINGULAR,
            ),
        }
    }

    /// Jacobian-transpose torques (as [`Self::joint_torques`]) at a pose from [`Self::pose`].
    #[must_use]
    pub fn torques_at(&self, pose: &DeltaPose, force_n: Vec3) -> ([f32; 3], Flags) {
        if !force_n.is_finite() {
            return ([0.0; 3], Flags::NON_FINITE_INPUT);
        }
        if pose.det == 0.0 {
            return ([0.0; 3], Flags::KINEMATICS_SINGULAR);
        }
        Self::torques_from(pose.forearms, pose.d, pose.det, force_n)
    }

    /// τᵢ = dᵢ·(sⱼ×sₖ)·F / det J_x, (i, j, k) cyclic.
    #[must_use]
    fn torques_from(s: [Vec3; 3], d: [f32; 3], det: f32, force_n: Vec3) -> ([f32; 3], Flags) {
        let inv_det = 1.0 / det;
        let tau = [
            d[0] * s[1].cross(s[2]).dot(force_n) * inv_det,
            d[1] * s[2].cross(s[0]).dot(force_n) * inv_det,
            d[2] * s[0].cross(s[1]).dot(force_n) * inv_det,
        ];
        if !all_finite(&tau) {
            // Only reachable with forces near f32::MAX; the overflowed torque is not meaningful.
            return ([0.0; 3], Flags::OUT_OF_RANGE);
        }
        (tau, Flags::NONE)
    }
}

#[cfg(test)]
mod tests;
