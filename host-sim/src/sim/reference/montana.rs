//! Montana's contact equations for a sphere ("finger", f) rolling without slipping on a fixed body ("object",
//! o): a plane or a sphere. Montana, "The kinematics of contact and grasp", IJRR 1988; MLS §5.2.
//!
//! # Conventions
//! - Object frame O: fixed. Finger body frame F; `R` maps F coordinates to O coordinates.
//! - Each surface has a chart and Gauss frame ([`Surface`]); `C_f(α_f)` (columns `x_f, y_f, z_f`, in F) and
//!   `C_o(α_o)` (in O), with `z` the outward normal.
//! - Contact coordinates `η = (α_f, α_o, ψ)`, stored as [`State`] `= [α_f1, α_f2, α_o1, α_o2, ψ]`.
//!   `ψ` is the angle of contact: in the object's contact frame the finger's contact frame has axes
//!   `x_f = (cos ψ, −sin ψ, 0)`, `y_f = (−sin ψ, −cos ψ, 0)`, `z_f = (0, 0, −1)`, i.e.
//!   `R·C_f = C_o·R_ψ3` with `R_ψ3 = [[cψ, −sψ, 0], [−sψ, −cψ, 0], [0, 0, −1]]` (ψ = 0: `x_f = x_o`, normals
//!   opposite).
//! - Input `ω = (ω_x, ω_y, ω_z)`: the angular velocity of F relative to O, in the finger's contact frame
//!   `L_f` (the frame fixed to F that coincides with `C_f` at the current contact). From the finger's body
//!   angular velocity `ω_b` (`Rᵀ Ṙ = [ω_b]×`) it is `ω = C_fᵀ ω_b`; from the same angular velocity in O,
//!   `ω_O = R ω_b`, it is `ω = (C_o R_ψ3)ᵀ ω_O`.
//!
//! # Equations (rolling: the contact's relative linear velocity is zero)
//! With `R_ψ = [[cψ, −sψ], [−sψ, −cψ]]` and `K̃_o = R_ψ K_o R_ψ`:
//! ```text
//! α̇_f = M_f⁻¹ (K_f + K̃_o)⁻¹ [−ω_y, ω_x]ᵀ
//! α̇_o = M_o⁻¹ R_ψ (K_f + K̃_o)⁻¹ [−ω_y, ω_x]ᵀ
//! ψ̇   = ω_z + T_f M_f α̇_f + T_o M_o α̇_o
//! ```
//! (Montana's contact equations as in MLS §5.2, with the sliding velocities `v_x = v_y = 0`.) Derivation, in the object's contact frame: differentiating
//! `R z_f = −z_o` gives `R_ψ([ω_y, −ω_x]ᵀ + K_f M_f α̇_f) = −K_o M_o α̇_o`; differentiating the contact point
//! `p + R c_f = c_o` with zero slip gives `R_ψ M_f α̇_f = M_o α̇_o`; eliminating `α̇_o` yields the first two
//! lines. Differentiating `R C_f = C_o R_ψ3` and taking the (y, x) element gives the third, because
//! `y·ẋ = T M α̇` on each surface and `Ṙ_ψ3 R_ψ3ᵀ = [(0, 0, −ψ̇)]×`.
//!
//! # The object surfaces ([`Surface`])
//! The finger is a sphere of radius `ρ`: `K_f = I/ρ`, `M_f = diag(ρ cos v_f, ρ)`, `T_f = [tan v_f/ρ, 0]`.
//! With `R_ψ² = I`, the relative curvature `K_f + K̃_o` is:
//! - plane: `I/ρ`;
//! - sphere of radius `R` (outside): `(1/ρ + 1/R) I`;
//! - bowl of radius `R` (inside a sphere, normal towards its centre, `K_o = −I/R`): `(1/ρ − 1/R) I`,
//!   invertible for `ρ ≠ R` (a fingertip smaller than the bowl: `ρ < R`; the integration fails with a
//!   non-finite rate at `ρ = R`);
//! - cylinder of radius `R` (axis `x_O`, `K_o = diag(0, 1/R)` in its chart): `I/ρ + R_ψ diag(0, 1/R) R_ψ
//!   = I/ρ + (1/R)[[s², sc], [sc, c²]]` with `(s, c) = (sin ψ, cos ψ)`: the curvature a rolling contact
//!   sees depends on the direction it rolls in, through the angle of contact `ψ` (rolling along the axis
//!   sees `1/ρ`, around it `1/ρ + 1/R`). Always positive definite.
//!
//! Singularities: the sphere and bowl charts at their poles (handled by re-centring, see
//! [`Contact::rechart`]); the cylinder chart has none; the finger chart at its poles (re-centred).
//!
//! For a finger sphere of radius `r` on a plane (chart of [`Surface::Sphere`]: `u` longitude, `v` latitude):
//! `u̇_f = −ω_y / cos v_f`, `v̇_f = ω_x`, `(ẋ, ẏ) = r R_ψ [−ω_y, ω_x]ᵀ = r·(ω_O,y, −ω_O,x)`,
//! `ψ̇ = ω_z − tan v_f · ω_y`.

use nalgebra::{Matrix2, Matrix3, Rotation3, Unit, Vector2, Vector3};

use super::surface::Surface;

/// Contact coordinates `[α_f1, α_f2, α_o1, α_o2, ψ]` (units of the charts; ψ in rad).
pub type State = [f64; 5];

/// The relative angular velocity of the finger with respect to the object (rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AngularVelocity {
    /// In the finger's body frame F.
    FingerBody(Vector3<f64>),
    /// In the object frame O.
    Object(Vector3<f64>),
}

/// A finger sphere in rolling contact with an object surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Finger surface: always a [`Surface::Sphere`].
    pub finger: Surface,
    /// Object surface (plane, sphere, bowl or cylinder), fixed in O.
    pub object: Surface,
}

fn alpha_f(s: &State) -> [f64; 2] {
    [s[0], s[1]]
}

fn alpha_o(s: &State) -> [f64; 2] {
    [s[2], s[3]]
}

/// `R_ψ` (2×2, symmetric, its own inverse).
fn r_psi(psi: f64) -> Matrix2<f64> {
    let (s, c) = psi.sin_cos();
    Matrix2::new(c, -s, -s, -c)
}

/// `R_ψ3` (3×3 rotation: finger contact frame → object contact frame).
fn r_psi3(psi: f64) -> Matrix3<f64> {
    let (s, c) = psi.sin_cos();
    Matrix3::new(c, -s, 0.0, -s, -c, 0.0, 0.0, 0.0, -1.0)
}

impl Contact {
    /// A finger sphere of radius `finger_radius` (m) touching `object` at its chart point `alpha_o`, with
    /// orientation `r0` (F → O). The finger chart is centred on the contact (α_f = (0, 0)).
    pub fn start(
        finger_radius: f64,
        object: Surface,
        alpha_o: [f64; 2],
        r0: &Rotation3<f64>,
    ) -> (Self, State) {
        let n_o = object.frame(alpha_o).column(2).into_owned();
        let d = Unit::new_normalize(-(r0.inverse() * n_o));
        let finger = Surface::sphere_centred(finger_radius, &d, &Vector3::x());
        let contact = Contact { finger, object };
        let psi = contact.psi_from(r0, [0.0, 0.0], alpha_o);
        (contact, [0.0, 0.0, alpha_o[0], alpha_o[1], psi])
    }

    /// The angle of contact for orientation `r` (F → O) with contacts at `af`, `ao` in the current charts.
    fn psi_from(&self, r: &Rotation3<f64>, af: [f64; 2], ao: [f64; 2]) -> f64 {
        let x_f = r * self.finger.frame(af).column(0).into_owned();
        let c_o = self.object.frame(ao);
        let (x_o, y_o) = (c_o.column(0), c_o.column(1));
        (-x_f.dot(&y_o)).atan2(x_f.dot(&x_o))
    }

    /// The finger's orientation `R = C_o R_ψ3 C_fᵀ` (F → O) encoded by the contact coordinates.
    pub fn orientation(&self, s: &State) -> Rotation3<f64> {
        let m = self.object.frame(alpha_o(s))
            * r_psi3(s[4])
            * self.finger.frame(alpha_f(s)).transpose();
        Rotation3::from_matrix_unchecked(m)
    }

    /// Contact point on the object (m, frame O).
    pub fn object_point(&self, s: &State) -> Vector3<f64> {
        self.object.point(alpha_o(s))
    }

    /// Contact point on the finger (m, frame F, origin at the sphere's centre).
    pub fn finger_point(&self, s: &State) -> Vector3<f64> {
        self.finger.point(alpha_f(s))
    }

    /// Position of the finger's centre in O (m): `c_o(α_o) − R c_f(α_f)`.
    pub fn finger_centre(&self, s: &State) -> Vector3<f64> {
        self.object_point(s) - self.orientation(s) * self.finger_point(s)
    }

    /// The input expressed in the finger's contact frame `L_f`.
    pub fn omega_contact(&self, s: &State, w: &AngularVelocity) -> Vector3<f64> {
        match w {
            AngularVelocity::FingerBody(wb) => self.finger.frame(alpha_f(s)).transpose() * wb,
            AngularVelocity::Object(wo) => {
                (self.object.frame(alpha_o(s)) * r_psi3(s[4])).transpose() * wo
            }
        }
    }

    /// Montana's equations: `η̇` for input `w` (in `L_f`, rad/s). Non-finite if the relative curvature
    /// `K_f + K̃_o` or a metric is singular (never for a sphere on a plane or on a sphere, away from the
    /// chart poles).
    pub fn rates(&self, s: &State, w: &Vector3<f64>) -> State {
        let (af, ao, psi) = (alpha_f(s), alpha_o(s), s[4]);
        let rp = r_psi(psi);
        let k_rel = self.finger.curvature(af) + rp * self.object.curvature(ao) * rp;
        let nan2 = Vector2::repeat(f64::NAN);
        // q = (K_f + K̃_o)⁻¹ [−ω_y, ω_x]ᵀ = M_f α̇_f (the contact's velocity on the finger, in L_f, m/s).
        let q = k_rel
            .try_inverse()
            .map_or(nan2, |k| k * Vector2::new(-w.y, w.x));
        let q_o = rp * q; // M_o α̇_o
        let daf = self.finger.metric(af).try_inverse().map_or(nan2, |m| m * q);
        let dao = self
            .object
            .metric(ao)
            .try_inverse()
            .map_or(nan2, |m| m * q_o);
        let dpsi = w.z + (self.finger.torsion(af) * q)[0] + (self.object.torsion(ao) * q_o)[0];
        [daf.x, daf.y, dao.x, dao.y, dpsi]
    }

    /// Contact-point velocities `(on the finger in F, on the object in O)` (m/s) for input `w`.
    pub fn contact_velocities(
        &self,
        s: &State,
        w: &AngularVelocity,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let wc = self.omega_contact(s, w);
        let d = self.rates(s, &wc);
        let (af, ao) = (alpha_f(s), alpha_o(s));
        let mf = self.finger.metric(af) * Vector2::new(d[0], d[1]);
        let mo = self.object.metric(ao) * Vector2::new(d[2], d[3]);
        (
            self.finger.frame(af) * Vector3::new(mf.x, mf.y, 0.0),
            self.object.frame(ao) * Vector3::new(mo.x, mo.y, 0.0),
        )
    }

    /// Re-centres the sphere charts on the current contact, with the chart's east along the contact's
    /// direction of motion under `w` (so the contact then moves along the chart's equator, away from the
    /// poles). Rewrites `s` for the new charts; the physical configuration (orientation, contact points) is
    /// unchanged. A bowl object is re-centred the same way; a plane or cylinder object keeps its chart
    /// (it has no singularity).
    pub fn rechart(&mut self, s: &mut State, w: &AngularVelocity) {
        let r = self.orientation(s);
        let p_f = self.finger_point(s);
        let p_o = self.object_point(s);
        let (v_f, v_o) = self.contact_velocities(s, w);
        if let Surface::Sphere { radius, .. } = self.finger {
            self.finger = Surface::sphere_centred(radius, &Unit::new_normalize(p_f), &v_f);
        }
        match self.object {
            Surface::Sphere { radius, .. } => {
                self.object = Surface::sphere_centred(radius, &Unit::new_normalize(p_o), &v_o);
            }
            Surface::Bowl { radius, .. } => {
                self.object = Surface::bowl_centred(radius, &Unit::new_normalize(p_o), &v_o);
            }
            Surface::Plane | Surface::Cylinder { .. } => {}
        }
        let af = self.finger.coords(&p_f);
        let ao = self.object.coords(&p_o);
        let psi = self.psi_from(&r, af, ao);
        *s = [af[0], af[1], ao[0], ao[1], psi];
    }

    /// Largest distance to a chart pole over both surfaces (`|latitude|`, rad).
    pub fn pole_proximity(&self, s: &State) -> f64 {
        self.finger
            .pole_proximity(alpha_f(s))
            .max(self.object.pole_proximity(alpha_o(s)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R_F: f64 = 0.01;
    const R_O: f64 = 0.05;

    /// A generic configuration: charts not centred on the contact, ψ arbitrary.
    fn configurations() -> Vec<(Contact, State)> {
        let finger = Surface::Sphere {
            radius: R_F,
            chart: Rotation3::from_scaled_axis(Vector3::new(0.4, 0.1, -0.9)),
        };
        let sphere_obj = Surface::Sphere {
            radius: R_O,
            chart: Rotation3::from_scaled_axis(Vector3::new(-0.2, 0.8, 0.3)),
        };
        vec![
            (
                Contact {
                    finger,
                    object: Surface::Plane,
                },
                [0.3, -0.4, 0.002, -0.001, 0.7],
            ),
            (
                Contact {
                    finger,
                    object: sphere_obj,
                },
                [-1.1, 0.5, 0.6, -0.2, -2.3],
            ),
        ]
    }

    fn omega_b() -> Vector3<f64> {
        Vector3::new(1.3, -0.6, 2.1)
    }

    fn add(s: &State, d: &State, h: f64) -> State {
        let mut o = *s;
        for i in 0..5 {
            o[i] += h * d[i];
        }
        o
    }

    #[test]
    fn rates_reproduce_the_commanded_rotation() {
        // Independent of the equations' derivation: the orientation encoded by η must evolve as
        // Ṙ = R [ω_b]×. Central difference with h = 1e-6 s (truncation ~h²·|ω|³ ≈ 1e-11, round-off
        // ~1e-16/1e-6 = 1e-10): measured 1.8e-10 per matrix element at worst (|Ṙ| ~ 2.6 1/s), the
        // difference's round-off; bound 3×: 5.3e-10.
        for (c, s) in configurations() {
            let w = AngularVelocity::FingerBody(omega_b());
            let d = c.rates(&s, &c.omega_contact(&s, &w));
            let h = 1e-6;
            let dr = (c.orientation(&add(&s, &d, h)).matrix()
                - c.orientation(&add(&s, &d, -h)).matrix())
                / (2.0 * h);
            let expected = c.orientation(&s).matrix() * omega_b().cross_matrix();
            assert!((dr - expected).abs().max() < 5.3e-10, "{:?}", c.object);
        }
    }

    #[test]
    fn rates_keep_the_contact_rolling_without_slip() {
        // The finger's centre must move as ṗ = R (ω_b × (−c_f)) ... i.e. the finger's material point at the
        // contact is at rest: ṗ + Ṙ c_f = 0 with ṗ the derivative of `finger_centre`. Same difference scheme
        // argument as above, scaled by the 1e-2 m lengths: measured 1.3e-12 m/s; bound 3×: 4e-12 m/s.
        for (c, s) in configurations() {
            let w = AngularVelocity::FingerBody(omega_b());
            let d = c.rates(&s, &c.omega_contact(&s, &w));
            let h = 1e-6;
            let dp =
                (c.finger_centre(&add(&s, &d, h)) - c.finger_centre(&add(&s, &d, -h))) / (2.0 * h);
            let r = c.orientation(&s);
            let material_point_velocity = dp + r * (omega_b().cross(&c.finger_point(&s)));
            assert!(material_point_velocity.norm() < 4e-12, "{:?}", c.object);
        }
    }

    #[test]
    fn contact_stays_on_both_surfaces_with_opposite_normals() {
        // The contact coordinates describe a touching configuration by construction; check the encoded
        // pose: the finger's contact point lands on the object's contact point and the normals oppose.
        // Measured 3.5e-18 m and 2.2e-16 (unit normals) at worst; bounds 3×.
        for (c, s) in configurations() {
            let r = c.orientation(&s);
            let p = c.finger_centre(&s) + r * c.finger_point(&s);
            assert!((p - c.object_point(&s)).norm() < 1e-17);
            let z_f = r * c.finger.frame(alpha_f(&s)).column(2).into_owned();
            let z_o = c.object.frame(alpha_o(&s)).column(2).into_owned();
            assert!((z_f + z_o).norm() < 6.7e-16);
        }
    }

    #[test]
    fn plane_contact_velocity_is_closed_form() {
        // Sphere on plane: the contact moves on the plane at r·(ω_O,y, −ω_O,x) and on the sphere (in F)
        // at −ω_b × p_f (the point (0,0,−r) of O seen from the rotating body). Both exact up to round-off:
        // measured 3.6e-18 and 9.8e-18 m/s; bounds 3×.
        let (c, s) = configurations()[0];
        let wb = omega_b();
        let wo = c.orientation(&s) * wb;
        let (v_f, v_o) = c.contact_velocities(&s, &AngularVelocity::FingerBody(wb));
        assert!((v_o - Vector3::new(R_F * wo.y, -R_F * wo.x, 0.0)).norm() < 1.1e-17);
        assert!((v_f + wb.cross(&c.finger_point(&s))).norm() < 2.9e-17);
    }

    #[test]
    fn sphere_contact_velocity_is_closed_form() {
        // Sphere (r) on sphere (R): the contact normal n (O) turns as ṅ = r/(R + r)·ω_O × n, so the object
        // contact moves at R·ṅ and the finger contact p_f = Rᵀ(−r n) at −ω_b × p_f − r Rᵀ ṅ. Measured
        // 6.5e-18 and 4.9e-18 m/s off; bounds 3×.
        let (c, s) = configurations()[1];
        let wb = omega_b();
        let r = c.orientation(&s);
        let wo = r * wb;
        let n = c.object_point(&s).normalize();
        let n_dot = R_F / (R_O + R_F) * wo.cross(&n);
        let (v_f, v_o) = c.contact_velocities(&s, &AngularVelocity::FingerBody(wb));
        assert!((v_o - R_O * n_dot).norm() < 1.9e-17);
        let expected_f = -wb.cross(&c.finger_point(&s)) - R_F * (r.inverse() * n_dot);
        assert!((v_f - expected_f).norm() < 1.5e-17);
    }

    #[test]
    fn body_and_object_inputs_agree() {
        // Measured 8.0e-16 rad/s apart at worst; bound 3×.
        for (c, s) in configurations() {
            let wb = omega_b();
            let wo = c.orientation(&s) * wb;
            let a = c.omega_contact(&s, &AngularVelocity::FingerBody(wb));
            let b = c.omega_contact(&s, &AngularVelocity::Object(wo));
            assert!((a - b).norm() < 2.4e-15);
        }
    }

    #[test]
    fn rechart_keeps_the_configuration() {
        // Round-off only; measured at worst: orientation 2.8e-16 per element, finger point 6.5e-19 m,
        // object point 1.6e-17 m, chart coordinates 4.9e-17 and 2.8e-17, velocity 1.1e-17 m/s, its
        // direction 2.8e-16. Bounds 3× each.
        for (mut c, mut s) in configurations() {
            let before = (c.orientation(&s), c.finger_point(&s), c.object_point(&s));
            let w = AngularVelocity::FingerBody(omega_b());
            let (v_f, _) = c.contact_velocities(&s, &w);
            c.rechart(&mut s, &w);
            assert!((c.orientation(&s).matrix() - before.0.matrix()).abs().max() < 8.3e-16);
            assert!((c.finger_point(&s) - before.1).norm() < 2e-18);
            assert!((c.object_point(&s) - before.2).norm() < 4.8e-17);
            // Finger contact now at the chart origin, moving due east (along the equator).
            assert!(s[0].abs() < 1.5e-16 && s[1].abs() < 8.3e-17);
            let (v_f2, _) = c.contact_velocities(&s, &w);
            assert!((v_f2 - v_f).norm() < 3.3e-17);
            let east = c.finger.frame([0.0, 0.0]).column(0).into_owned();
            assert!((v_f.normalize() - east).norm() < 8.3e-16);
        }
    }

    #[test]
    fn start_encodes_the_given_orientation() {
        let r0 = Rotation3::from_scaled_axis(Vector3::new(0.5, -1.0, 0.2));
        let (c, s) = Contact::start(R_F, Surface::Plane, [0.0, 0.0], &r0);
        // Measured 2.2e-16 per element, 2.1e-18 m and 3.9e-18 m; bounds 3×.
        assert!((c.orientation(&s).matrix() - r0.matrix()).abs().max() < 6.7e-16);
        assert!(
            (c.finger_point(&s) - r0.inverse() * Vector3::new(0.0, 0.0, -R_F)).norm() < 6.4e-18
        );
        assert!((c.finger_centre(&s) - Vector3::new(0.0, 0.0, R_F)).norm() < 1.2e-17);
    }
}
