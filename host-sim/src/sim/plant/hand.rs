//! The user's hand: a scripted reference motion and the grasp impedance that couples it to the
//! handle.
//!
//! The hand is a mass moving rigidly with the handle (added to the effector's translating mass
//! by the dynamics) and a spring-damper between the handle and a reference point the user's arm
//! moves along a script: F_hand = k·(x_ref − p) + b·(ẋ_ref − ṗ), the force the hand applies to
//! the handle. The wrist joints are passive and follow the hand's orientation exactly, so the
//! wrist angles are the script's.
//!
//! A script is a start [`Waypoint`] and a list of [`Segment`]s, each moving to its end waypoint
//! over its duration along a minimum-jerk profile s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ (zero velocity and
//! acceleration at both ends, so the reference force has no steps). Before 0 the script holds
//! the start; after the last segment it holds the end in [`Phase::Hold`].

/// What the hand is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Phase {
    Approach,
    Press,
    Roll,
    Twist,
    Slide,
    /// Slide and twist at once (the hand pushes sideways while it turns about the normal).
    SlideTwist,
    LiftOff,
    Hold,
}

impl Phase {
    /// Lower-case name for logs and chart legends.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Approach => "approach",
            Phase::Press => "press",
            Phase::Roll => "roll",
            Phase::Twist => "twist",
            Phase::Slide => "slide",
            Phase::SlideTwist => "slide-twist",
            Phase::LiftOff => "lift-off",
            Phase::Hold => "hold",
        }
    }
}

/// A pose of the hand's reference: position of the handle centre (frame `B`, m) and the three
/// wrist joint angles (rad, convention of `softfinger_core::device`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoint {
    pub position_m: [f64; 3],
    pub wrist_rad: [f64; 3],
}

/// Move to `end` over `duration_s`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub phase: Phase,
    pub duration_s: f64,
    pub end: Waypoint,
}

/// The hand's reference at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandRef {
    pub position_m: [f64; 3],
    pub velocity_m_s: [f64; 3],
    pub wrist_rad: [f64; 3],
    pub phase: Phase,
}

/// A rejected script.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ScriptError {
    /// A waypoint coordinate is not finite (index of the segment; `None` for the start).
    #[error("a coordinate of {} is not finite", waypoint_name(*.0))]
    NonFiniteWaypoint(Option<usize>),
    /// A segment's duration is not finite and positive.
    #[error("the duration of segment {0} is not finite and positive")]
    BadDuration(usize),
}

/// "the start" or "the end of segment i", for [`ScriptError`]'s message.
fn waypoint_name(segment: Option<usize>) -> String {
    match segment {
        None => "the start".to_string(),
        Some(i) => format!("the end of segment {i}"),
    }
}

/// A scripted hand motion.
#[derive(Clone, Debug, PartialEq)]
pub struct HandScript {
    start: Waypoint,
    segments: Vec<Segment>,
}

/// Minimum-jerk profile and its derivative: s(τ) = 10τ³ − 15τ⁴ + 6τ⁵, s'(τ) = 30τ²(1 − τ)².
fn min_jerk(tau: f64) -> (f64, f64) {
    let t = tau.clamp(0.0, 1.0);
    let s = t * t * t * (10.0 + t * (-15.0 + 6.0 * t));
    let ds = 30.0 * t * t * (1.0 - t) * (1.0 - t);
    (s, ds)
}

fn lerp3(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * s)
}

impl HandScript {
    /// A script that starts (and, until segments are added, stays) at `start`.
    pub fn new(start: Waypoint) -> HandScript {
        HandScript {
            start,
            segments: Vec::new(),
        }
    }

    /// Hold one position with the wrist at zero, forever.
    pub fn hold(position_m: [f64; 3]) -> HandScript {
        HandScript::new(Waypoint {
            position_m,
            wrist_rad: [0.0; 3],
        })
    }

    /// Append a segment.
    pub fn then(mut self, phase: Phase, duration_s: f64, end: Waypoint) -> HandScript {
        self.segments.push(Segment {
            phase,
            duration_s,
            end,
        });
        self
    }

    /// The segments.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Total duration of the segments, s.
    pub fn duration_s(&self) -> f64 {
        self.segments.iter().map(|s| s.duration_s).sum()
    }

    /// Reject non-finite waypoints and non-positive or non-finite durations.
    pub fn validate(&self) -> Result<(), ScriptError> {
        let finite = |w: &Waypoint| {
            w.position_m
                .iter()
                .chain(&w.wrist_rad)
                .all(|v| v.is_finite())
        };
        if !finite(&self.start) {
            return Err(ScriptError::NonFiniteWaypoint(None));
        }
        for (i, s) in self.segments.iter().enumerate() {
            if !finite(&s.end) {
                return Err(ScriptError::NonFiniteWaypoint(Some(i)));
            }
            if !(s.duration_s.is_finite() && s.duration_s > 0.0) {
                return Err(ScriptError::BadDuration(i));
            }
        }
        Ok(())
    }

    /// The reference at time `t_s` (s from the start of the script).
    pub fn sample(&self, t_s: f64) -> HandRef {
        let mut from = self.start;
        let mut t0 = 0.0;
        if t_s > 0.0 {
            for seg in &self.segments {
                let t1 = t0 + seg.duration_s;
                if t_s < t1 {
                    let (s, ds) = min_jerk((t_s - t0) / seg.duration_s);
                    let rate = ds / seg.duration_s;
                    return HandRef {
                        position_m: lerp3(from.position_m, seg.end.position_m, s),
                        velocity_m_s: [0, 1, 2]
                            .map(|k| (seg.end.position_m[k] - from.position_m[k]) * rate),
                        wrist_rad: lerp3(from.wrist_rad, seg.end.wrist_rad, s),
                        phase: seg.phase,
                    };
                }
                from = seg.end;
                t0 = t1;
            }
        }
        HandRef {
            position_m: from.position_m,
            velocity_m_s: [0.0; 3],
            wrist_rad: from.wrist_rad,
            phase: if t_s > 0.0 || self.segments.is_empty() {
                Phase::Hold
            } else {
                self.segments[0].phase
            },
        }
    }
}

/// Parameters of the standard touch-roll-twist-slide script. The virtual surface is the plane
/// z = `surface_z_m` of frame `B` with its normal along +z; the handle centre is the fingertip
/// sphere's centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TouchScript {
    /// Where the fingertip first touches, (x, y) in `B`, m.
    pub contact_xy_m: [f64; 2],
    /// Height of the surface plane, m.
    pub surface_z_m: f64,
    /// Fingertip sphere radius, m (the paper's fingertip is ~10 mm).
    pub fingertip_radius_m: f64,
    /// Start height of the fingertip's lowest point above the surface, m.
    pub clearance_m: f64,
    /// How far the hand's reference goes below the touching position, m.
    pub press_depth_m: f64,
    /// Rolling angle about the y axis of `B`, rad.
    pub roll_rad: f64,
    /// Twist about the surface normal, rad.
    pub twist_rad: f64,
    /// Tangential slide along the heading, m.
    pub slide_m: f64,
    /// Direction of the roll and the slide in the base xy plane, rad from +x towards +y. The wrist's
    /// joint 0 (about the base z axis) turns to it during the approach, in free space.
    pub heading_rad: f64,
    /// Twist while sliding: one slide-twist phase (1 s) instead of a twist (1 s) then a slide (1 s).
    pub twist_while_sliding: bool,
}

impl Default for TouchScript {
    /// Touch at the centre of the Omega-like design workspace (fingertip centre at
    /// (0, 0, −0.165) m on contact), 10 mm fingertip, 20 mm clearance, 10 mm press (~3 N through
    /// the 300 N/m grasp against a rigid surface), 0.3 rad roll,
    /// 0.5 rad twist, 20 mm slide.
    fn default() -> TouchScript {
        TouchScript {
            contact_xy_m: [0.0, 0.0],
            surface_z_m: -0.165 - 0.010,
            fingertip_radius_m: 0.010,
            clearance_m: 0.020,
            press_depth_m: 0.010,
            roll_rad: 0.3,
            twist_rad: 0.5,
            slide_m: 0.020,
            heading_rad: 0.0,
            twist_while_sliding: false,
        }
    }
}

impl TouchScript {
    /// Approach (0.5 s), press (0.3 s), roll (1 s), twist (1 s), slide (1 s), lift off (0.5 s); with
    /// `twist_while_sliding`, twist and slide are one 1 s phase (3.3 s in all).
    ///
    /// With the heading h = 0: roll turns wrist joint 1 (about y, joint 0 being at zero then) by
    /// `roll_rad` and moves the reference by ρ·roll_rad along +x, the centre's travel for a sphere
    /// rolling without slipping (contact displacement ρ·(w_y, −w_x) for a rotation vector w). Twist
    /// turns joint 0, which is about the base z axis, the surface normal, through the fingertip
    /// centre, so the position holds. Slide moves along +x at constant orientation. Lift off
    /// rises back to the clearance height. Any other heading turns joint 0 to h during the
    /// approach; the wrist is Rz(a₀)·Ry(a₁)·Rx(a₂), so joint 1 then rolls about
    /// (−sin h, cos h, 0) and everything moves along (cos h, sin h, 0) instead of +x.
    pub fn script(&self) -> HandScript {
        self.script_with_durations(1.0, 1.0)
    }

    /// [`Self::script`] with the roll and twist phases lasting `roll_s` and `twist_s` seconds (the
    /// fault campaign uses a 10× faster twist).
    pub fn script_with_durations(&self, roll_s: f64, twist_s: f64) -> HandScript {
        let [cx, cy] = self.contact_xy_m;
        let touch_z = self.surface_z_m + self.fingertip_radius_m;
        let above = touch_z + self.clearance_m;
        let pressed = touch_z - self.press_depth_m;
        let h = self.heading_rad;
        let (sin_h, cos_h) = h.sin_cos();
        // Distance travelled along the heading from the first contact.
        let rolled_d = self.fingertip_radius_m * self.roll_rad;
        let slid_d = rolled_d + self.slide_m;
        let w = |d: f64, z: f64, wrist: [f64; 3]| Waypoint {
            position_m: [cx + d * cos_h, cy + d * sin_h, z],
            wrist_rad: wrist,
        };
        let headed = [h, 0.0, 0.0];
        let rolled = [h, self.roll_rad, 0.0];
        let twisted = [h + self.twist_rad, self.roll_rad, 0.0];
        let script = HandScript::new(w(0.0, above, [0.0; 3]))
            .then(Phase::Approach, 0.5, w(0.0, touch_z, headed))
            .then(Phase::Press, 0.3, w(0.0, pressed, headed))
            .then(Phase::Roll, roll_s, w(rolled_d, pressed, rolled));
        let script = if self.twist_while_sliding {
            script.then(Phase::SlideTwist, 1.0, w(slid_d, pressed, twisted))
        } else {
            script
                .then(Phase::Twist, twist_s, w(rolled_d, pressed, twisted))
                .then(Phase::Slide, 1.0, w(slid_d, pressed, twisted))
        };
        script.then(Phase::LiftOff, 0.5, w(slid_d, above, twisted))
    }
}

/// The force the hand applies to the handle, N: k·(x_ref − p) + b·(ẋ_ref − ṗ).
pub fn grasp_force(
    stiffness: f64,
    damping: f64,
    reference: &HandRef,
    p: [f64; 3],
    v: [f64; 3],
) -> [f64; 3] {
    [0, 1, 2].map(|k| {
        stiffness * (reference.position_m[k] - p[k]) + damping * (reference.velocity_m_s[k] - v[k])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_touch_script_visits_its_waypoints_in_order() {
        let t = TouchScript::default();
        let s = t.script();
        assert_eq!(s.validate(), Ok(()));
        // The waypoints below measured exact (sums and the minimum-jerk polynomial at its ends,
        // no transcendental functions): asserted equal.
        assert_eq!(s.duration_s(), 4.3);
        let start = s.sample(0.0);
        assert_eq!(start.position_m, [0.0, 0.0, -0.165 + 0.020]);
        assert_eq!(start.phase, Phase::Approach);
        // End of approach: fingertip centre one radius above the surface.
        let touch = s.sample(0.5);
        assert_eq!(touch.position_m[2], -0.165);
        assert_eq!(touch.phase, Phase::Press);
        // End of roll: x advanced by ρ·roll = 3 mm, wrist joint 1 at the roll angle.
        let rolled = s.sample(1.8);
        assert_eq!(rolled.position_m[0], 0.003);
        assert_eq!(rolled.wrist_rad[1], 0.3);
        assert_eq!(rolled.phase, Phase::Twist);
        // After the end: held, zero velocity.
        let end = s.sample(10.0);
        assert_eq!(end.phase, Phase::Hold);
        assert_eq!(end.velocity_m_s, [0.0; 3]);
        assert_eq!(end.position_m[0], 0.023);
        assert_eq!(end.wrist_rad, [0.5, 0.3, 0.0]);
    }

    #[test]
    fn heading_and_twist_while_sliding_turn_the_script() {
        let t = TouchScript {
            heading_rad: std::f64::consts::FRAC_PI_2,
            twist_while_sliding: true,
            ..TouchScript::default()
        };
        let s = t.script();
        assert_eq!(s.validate(), Ok(()));
        // Measured exact but for x after the roll (below): asserted equal.
        assert_eq!(s.duration_s(), 3.3);
        // Joint 0 at the heading on contact, still at the start's x, y.
        let touch = s.sample(0.5);
        assert_eq!(touch.wrist_rad, [std::f64::consts::FRAC_PI_2, 0.0, 0.0]);
        assert_eq!([touch.position_m[0], touch.position_m[1]], [0.0, 0.0]);
        // Rolled 3 mm along +y (cos 90° rounds to 6e-17, so x moves by 0.003·6e-17 = 1.8e-19 m:
        // measured 1.84e-19 m; bound 3×).
        let rolled = s.sample(1.8);
        assert!(rolled.position_m[0].abs() < 5.5e-19);
        assert_eq!(rolled.position_m[1], 0.003);
        // Half-way through the slide-twist, moving and turning at once.
        let mid = s.sample(2.3);
        assert_eq!(mid.phase, Phase::SlideTwist);
        assert!(mid.velocity_m_s[1] > 0.0 && mid.wrist_rad[0] > std::f64::consts::FRAC_PI_2);
        let end = s.sample(10.0);
        assert_eq!(end.position_m[1], 0.023);
        assert_eq!(end.wrist_rad[0], std::f64::consts::FRAC_PI_2 + 0.5);
    }

    #[test]
    fn reference_velocity_is_the_derivative_of_position_and_continuous() {
        let s = TouchScript::default().script();
        let h = 1e-6;
        let mut t = 0.001;
        while t < s.duration_s() {
            let a = s.sample(t - h);
            let b = s.sample(t + h);
            let mid = s.sample(t);
            for k in 0..3 {
                let fd = (b.position_m[k] - a.position_m[k]) / (2.0 * h);
                // Central difference error h²·|x'''|/6 with |x'''| ≤ 60·Δ/T³ ≈ 60·0.02/0.125
                // ≈ 10 m/s³: ~2e-12 m/s; rounding 1e-17/1e-6 = 1e-11 m/s. Measured 2.2e-11 m/s at
                // worst over the samples; bound 3×.
                assert!(
                    (fd - mid.velocity_m_s[k]).abs() < 6.5e-11,
                    "t {t}: {fd} vs {mid:?}"
                );
            }
            t += 0.0137;
        }
        // Minimum jerk: zero velocity at every segment boundary (measured exactly 0).
        for b in [0.5, 0.8, 1.8, 2.8, 3.8, 4.3] {
            assert_eq!(s.sample(b).velocity_m_s, [0.0; 3]);
        }
    }

    #[test]
    fn peak_minimum_jerk_speed_is_fifteen_eighths_of_the_mean() {
        // Closed form: max s'(τ) = 30·(1/2)²·(1/2)² = 1.875 at τ = 1/2.
        let s = HandScript::hold([0.0; 3]).then(
            Phase::Slide,
            2.0,
            Waypoint {
                position_m: [0.1, 0.0, 0.0],
                wrist_rad: [0.0; 3],
            },
        );
        // Measured exact.
        let v = s.sample(1.0).velocity_m_s[0];
        assert_eq!(v, 1.875 * 0.1 / 2.0);
    }

    #[test]
    fn bad_scripts_are_rejected() {
        let w = Waypoint {
            position_m: [0.0; 3],
            wrist_rad: [0.0; 3],
        };
        let s = HandScript::new(w).then(Phase::Press, 0.0, w);
        assert_eq!(s.validate(), Err(ScriptError::BadDuration(0)));
        let bad = Waypoint {
            position_m: [f64::NAN, 0.0, 0.0],
            ..w
        };
        let s = HandScript::new(w).then(Phase::Press, 1.0, bad);
        assert_eq!(s.validate(), Err(ScriptError::NonFiniteWaypoint(Some(0))));
        assert_eq!(
            HandScript::new(bad).validate(),
            Err(ScriptError::NonFiniteWaypoint(None))
        );
    }

    #[test]
    fn grasp_force_pulls_towards_the_reference() {
        let r = HandRef {
            position_m: [0.0, 0.0, -0.1],
            velocity_m_s: [0.1, 0.0, 0.0],
            wrist_rad: [0.0; 3],
            phase: Phase::Hold,
        };
        let f = grasp_force(300.0, 13.1, &r, [0.0, 0.01, -0.1], [0.0, 0.0, 0.2]);
        // k·Δx: −3 N along y; b·Δv: +1.31 N along x, −2.62 N along z (measured exact).
        assert_eq!(f, [1.31, -3.0, -2.62]);
    }
}
