//! The delta linkage in f64: the plant's own kinematics, independent of the controller's f32 code.
//!
//! Same frame and conventions as `softfinger_core::device::delta` (base frame `B`, z from the effector
//! towards the base, motor i at azimuth 120°·i, θ = 0 arm horizontal outwards, positive down),
//! re-derived here in f64 because the dynamics need more than the controller does (forearm
//! vectors, the velocity-product acceleration) and because a plant that shared the controller's
//! kinematics could not catch a mistake in them. `tests` cross-check the two.

use softfinger_core::device::delta::DeltaGeometry;

pub use super::linalg::{M3, V3};

/// Forearm-volume floor |det J_x|/L_b³ below which the plant treats the linkage as jammed. Far
/// below the controller's guard (0.05): the plant must keep working wherever the real linkage
/// can go, and the mechanical stops keep it above 0.11 (see `PlantParams::OMEGA_LIKE`).
const MIN_VOLUME: f64 = 1.0e-6;

/// Link lengths in f64, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mechanism {
    /// R_b − R_e, m.
    r: f64,
    /// Upper arm L_a, m.
    la: f64,
    /// Forearm L_b, m.
    lb: f64,
}

/// Everything the dynamics need at one configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    /// Effector centre, frame `B`, m.
    pub p: V3,
    /// Forearm vectors sᵢ = p − cᵢ, m.
    pub s: [V3; 3],
    /// Arm unit directions uᵢ(θᵢ).
    pub u: [V3; 3],
    /// Arm direction derivatives duᵢ/dθ.
    pub du: [V3; 3],
    /// Jacobian ṗ = J·θ̇, m/rad.
    pub j: M3,
    /// J_x⁻¹ (rows of J_x are sᵢᵀ).
    pub jx_inv: M3,
    /// Forearm volume |det J_x|/L_b³.
    pub volume: f64,
}

fn radial(i: usize) -> V3 {
    let phi = 2.0 * std::f64::consts::PI / 3.0 * i as f64;
    V3::new(phi.cos(), phi.sin(), 0.0)
}

impl Mechanism {
    pub fn new(g: &DeltaGeometry) -> Mechanism {
        Mechanism {
            r: g.base_radius_m as f64 - g.effector_radius_m as f64,
            la: g.upper_arm_m as f64,
            lb: g.forearm_m as f64,
        }
    }

    /// Upper arm length L_a, m.
    pub fn upper_arm_m(&self) -> f64 {
        self.la
    }

    /// Arm direction uᵢ(θ) = cos θ·r̂ᵢ − sin θ·ẑ and its derivative −sin θ·r̂ᵢ − cos θ·ẑ.
    fn arm(i: usize, theta: f64) -> (V3, V3) {
        let (s, c) = theta.sin_cos();
        let r = radial(i);
        let z = V3::new(0.0, 0.0, 1.0);
        (r * c - z * s, -r * s - z * c)
    }

    /// Sphere centre cᵢ = (R_b − R_e)·r̂ᵢ + L_a·uᵢ(θ).
    fn centre(&self, i: usize, theta: f64) -> V3 {
        radial(i) * self.r + Self::arm(i, theta).0 * self.la
    }

    /// Forward kinematics (closed form: circumcentre of the sphere centres plus the offset along
    /// their normal, lower branch). None where the linkage cannot be assembled.
    pub fn forward(&self, theta: [f64; 3]) -> Option<V3> {
        let c = [0, 1, 2].map(|i| self.centre(i, theta[i]));
        let a = c[1] - c[0];
        let b = c[2] - c[0];
        let n = a.cross(b);
        let n2 = n.norm_squared();
        if n2 <= 1e-12 * a.norm_squared() * b.norm_squared() {
            return None;
        }
        let p0 = (b.cross(n) * a.norm_squared() + n.cross(a) * b.norm_squared()) * (0.5 / n2);
        let h2 = self.lb * self.lb - p0.norm_squared();
        if h2 < 0.0 {
            return None;
        }
        let step = (h2 / n2).sqrt();
        let sign = if n.z() > 0.0 { -1.0 } else { 1.0 };
        Some(c[0] + p0 + n * (sign * step))
    }

    /// Inverse kinematics, elbows outwards. None out of reach.
    pub fn inverse(&self, p: V3) -> Option<[f64; 3]> {
        let mut theta = [0.0; 3];
        for (i, t) in theta.iter_mut().enumerate() {
            let r = radial(i);
            let q = p - r * self.r;
            let qx = q.dot(r);
            let qz = q.z();
            let k = (q.norm_squared() + self.la * self.la - self.lb * self.lb) / (2.0 * self.la);
            let rho = qx.hypot(qz);
            if rho == 0.0 || k.abs() > rho {
                return None;
            }
            *t = -qz.atan2(qx) - (k / rho).acos();
        }
        Some(theta)
    }

    /// Kinematics at `theta`: position, forearm vectors and jacobian. None where the linkage
    /// cannot be assembled or the forearms are coplanar.
    pub fn kinematics(&self, theta: [f64; 3]) -> Option<Kinematics> {
        let p = self.forward(theta)?;
        let arms = [0, 1, 2].map(|i| Self::arm(i, theta[i]));
        let u = arms.map(|a| a.0);
        let du = arms.map(|a| a.1);
        let s = [0, 1, 2].map(|i| p - self.centre(i, theta[i]));
        let jx = M3::from_rows(s);
        let volume = jx.determinant().abs() / self.lb.powi(3);
        if volume < MIN_VOLUME {
            return None;
        }
        let jx_inv = jx.inverse()?;
        // J_x·ṗ = diag(dᵢ)·θ̇ with dᵢ = L_a·sᵢ·duᵢ (from d/dt |sᵢ|² = 0): column i of J is
        // dᵢ times column i of J_x⁻¹.
        let j = M3::from_columns([0, 1, 2].map(|i| jx_inv.column(i) * (self.la * s[i].dot(du[i]))));
        Some(Kinematics {
            p,
            s,
            u,
            du,
            j,
            jx_inv,
            volume,
        })
    }
}

impl Kinematics {
    /// Effector velocity ṗ = J·θ̇, m/s.
    pub fn velocity(&self, omega: [f64; 3]) -> V3 {
        self.j.mul_vec(V3::from(omega))
    }

    /// Generalised (arm-side) torques of a force applied at the effector: Jᵀ·F, N·m.
    pub fn joint_torques(&self, force: V3) -> [f64; 3] {
        self.j.transpose().mul_vec(force).into()
    }

    /// The velocity-product part of the effector acceleration: p̈ = J·θ̈ + a_b, m/s².
    ///
    /// Differentiating |sᵢ|² = L_b² twice (ṡᵢ = ṗ − L_a·duᵢ·θ̇ᵢ, d²uᵢ/dθ² = −uᵢ) gives
    /// sᵢ·p̈ = dᵢ·θ̈ᵢ + cᵢ with cᵢ = −L_a·(sᵢ·uᵢ)·θ̇ᵢ² − |ṡᵢ|², so a_b = J_x⁻¹·c.
    pub fn bias_acceleration(&self, la: f64, omega: [f64; 3]) -> V3 {
        let pdot = self.velocity(omega);
        let c = V3([0, 1, 2].map(|i| {
            let sdot = pdot - self.du[i] * (la * omega[i]);
            -la * self.s[i].dot(self.u[i]) * omega[i] * omega[i] - sdot.norm_squared()
        }));
        self.jx_inv.mul_vec(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_core::math::vec3::Vec3;
    use softfinger_core::math::Libm;

    const G: DeltaGeometry = DeltaGeometry::OMEGA_LIKE;

    fn grid() -> impl Iterator<Item = [f64; 3]> {
        let a = |k: i32| -0.5 + 0.25 * k as f64;
        (0..8).flat_map(move |i| (0..8).flat_map(move |j| (0..8).map(move |k| [a(i), a(j), a(k)])))
    }

    #[test]
    fn f64_kinematics_agree_with_the_controllers_f32_kinematics() {
        let m = Mechanism::new(&G);
        for theta in grid() {
            let Some(kin) = m.kinematics(theta) else {
                continue;
            };
            if kin.volume < 0.1 {
                continue;
            }
            let t32 = theta.map(|x| x as f32);
            let (p32, flags) = G.forward::<Libm>(t32);
            assert!(flags.is_empty());
            // The core's forward is good to < 0.1 µm against an f64 Newton reference (its own
            // tests), plus the f32 rounding of θ (6e-8 rad × 0.3 m/rad): measured 9.7e-8 m at worst
            // over the grid; bound 3×.
            let err = (kin.p - V3::new(p32.x as f64, p32.y as f64, p32.z as f64)).norm();
            assert!(err < 2.9e-7, "{theta:?}: {err}");
            let f = V3::new(2.0, -3.0, 5.0);
            let (tau32, _) = G.joint_torques::<Libm>(
                t32,
                p32,
                Vec3::new(f.x() as f32, f.y() as f32, f.z() as f32),
            );
            let tau = kin.joint_torques(f);
            for k in 0..3 {
                // |F| = 6.2 N, |τ| < 1 N·m; f32 relative error ~1e-6 (core tests), plus the
                // position rounding above: measured 3.5e-7 N·m at worst; bound 3×.
                assert!(
                    (tau[k] - tau32[k] as f64).abs() < 1.05e-6,
                    "{theta:?}: {tau:?} {tau32:?}"
                );
            }
        }
    }

    #[test]
    fn jacobian_and_bias_acceleration_match_finite_differences_of_forward() {
        let m = Mechanism::new(&G);
        let theta0 = [0.3, 0.6, 0.9];
        let omega = [1.5, -2.0, 0.7];
        let theta_at = |t: f64| [0, 1, 2].map(|i| theta0[i] + omega[i] * t);
        let kin = m.kinematics(theta0).unwrap();
        // Along the path θ(t) = θ₀ + ω·t (θ̈ = 0): ṗ = J·ω and p̈ = a_b. Central differences with
        // h = 1e-4 s: truncation h²·|p⁽³⁾|/6 ~ 1e-8·(~10 m/s³) ≈ 1e-7; rounding 1e-16/h² = 1e-8.
        // Measured 9.4e-10 m/s (velocity) and 7.5e-9 m/s² (acceleration); bounds 3×.
        let h = 1e-4;
        let p_plus = m.forward(theta_at(h)).unwrap();
        let p_minus = m.forward(theta_at(-h)).unwrap();
        let vel_fd = (p_plus - p_minus) * (0.5 / h);
        let acc_fd = (p_plus - kin.p * 2.0 + p_minus) * (1.0 / (h * h));
        assert!((kin.velocity(omega) - vel_fd).norm() < 2.8e-9, "{vel_fd:?}");
        let acc = kin.bias_acceleration(m.upper_arm_m(), omega);
        // |a_b| ~ 0.4 m/s² here (measured 0.36).
        assert!((acc - acc_fd).norm() < 2.2e-8, "{acc:?} vs {acc_fd:?}");
        assert!(acc.norm() > 0.1, "the check must not be vacuous: {acc:?}");
    }

    #[test]
    fn the_linkage_assembles_everywhere_between_the_arm_stops() {
        // PlantParams::OMEGA_LIKE puts the stops at −40° and 105°: the whole box of arm angles
        // between them must assemble, with forearm volume above the controller's 0.05 guard.
        let m = Mechanism::new(&G);
        let deg = std::f64::consts::PI / 180.0;
        let a = |k: i32| (-40.0 + 145.0 * k as f64 / 12.0) * deg;
        let mut worst = f64::MAX;
        for i in 0..=12 {
            for j in 0..=12 {
                for k in 0..=12 {
                    let kin = m.kinematics([a(i), a(j), a(k)]).expect("assembles");
                    worst = worst.min(kin.volume);
                }
            }
        }
        // Measured 0.112 on this 13³ grid.
        assert!(worst > 0.11, "{worst}");
    }

    #[test]
    fn inverse_inverts_forward() {
        let m = Mechanism::new(&G);
        for theta in grid() {
            if let Some(p) = m.forward(theta) {
                let back = m.inverse(p).unwrap();
                // Measured 3.6e-14 rad at worst over the grid; bound 3×.
                for k in 0..3 {
                    assert!((back[k] - theta[k]).abs() < 1.1e-13, "{theta:?} {back:?}");
                }
            }
        }
    }
}
