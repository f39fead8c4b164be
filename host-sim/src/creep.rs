//! `host-sim creep`: does a fingertip at rest stay at rest? The scenarios of issue 12, part 1, for
//! every method and backend on the plane:
//!
//! - `identical`: the rolling model fed one orientation sample (a tilted, twisted fingertip, not the
//!   identity) for `--seconds` at `--rate-hz`: how far the contact point and the spin moved;
//! - `dither`: the sample alternates between two orientations one wrist-encoder count apart (about
//!   the normal and about a tangent axis): how far the contact point and the spin are from where
//!   they were after an even number of samples (the same orientation);
//! - `held`: the contact step with the probe pressed 1 mm and held still, orientation constant,
//!   for `--held-ticks` ticks: how far the anchor walked and the rendered tangential force;
//! - `closed-loop`: the controller against the plant, a hand pressing 1 mm and holding still for
//!   `--hold-s` simulated seconds with the wrist tilted and one wrist count dithering every tick:
//!   the largest rendered tangential force after the press has settled, against the force of one
//!   motor-encoder count of displacement (tangential stiffness × effector displacement of one count);
//! - the same hold through the encoders ([`crate::hold_quantisation`], exact method, every
//!   backend), with and without the passivity stage, still and with the hand drifting 0.65 µm/s:
//!   the instantaneous tangential force (max, its elastic part, p99, median), the mean over the
//!   first and last windows
//!   and its change, the count changes and the anchor's walk.

use crate::backend::{dispatch, Backend};
use crate::closed_loop::{self, SetupError};
use crate::hold_quantisation::{self, HoldSetup};
use crate::plant::{HandScript, Phase, Plant, PlantParams, Waypoint};
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::spin::SpinSpring;
use softfinger_core::contact::surface::{Plane, Surface};
use softfinger_core::contact::{ContactInput, ContactModel};
use softfinger_core::control::pipeline::{BoardTiming, Pipeline, PipelineConfig};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::device::DeviceParams;
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Libm, Math, Quat, Vec3};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Simulated time of the replay scenarios, s.
    #[arg(long, default_value_t = 10.0)]
    pub seconds: f64,
    /// Sampling rate of the replay scenarios, Hz.
    #[arg(long, default_value_t = 10_000.0)]
    pub rate_hz: f64,
    /// Ticks of the held contact step (10^6 = 100 s at 10 kHz).
    #[arg(long, default_value_t = 1_000_000)]
    pub held_ticks: u64,
    /// Simulated hold of the closed-loop scenario, s (0 skips it).
    #[arg(long, default_value_t = 60.0)]
    pub hold_s: f64,
}

/// A tilted and twisted fingertip orientation (wrist angles 0.3, −0.2, 0.1 rad): its products with
/// its own conjugate round, unlike the identity's.
pub fn rest_orientation() -> Quat {
    DeviceParams::wrist_orientation::<Libm>([0.3, -0.2, 0.1])
}

/// One wrist-encoder count, rad.
pub fn wrist_count_rad() -> f32 {
    DeviceParams::OMEGA_LIKE.wrist_rad_per_count()
}

/// How far a rolling model moved: contact point on the plane (m) and spin (rad).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drift {
    pub point_m: f64,
    pub spin_rad: f64,
}

fn drift(r: &Rolling<Plane>, spin: &SpinSpring, p0: Vec3, s0: f32) -> Drift {
    let d = r.surface().contact_point() - p0;
    Drift {
        point_m: ((d.x as f64).powi(2) + (d.y as f64).powi(2)).sqrt(),
        spin_rad: (spin.accumulated_rad as f64 - s0 as f64).abs(),
    }
}

/// Feed `samples` cyclically for `n` steps; report the largest drift seen at the steps where the
/// sample equals the first one (every `samples.len()` steps).
pub fn replay_cycle<M: Math>(method: Method, samples: &[Quat], n: u64) -> Drift {
    let params = ContactParams::DEFAULT;
    let mut r = Rolling::new(Plane::default(), 0.01, samples[0], method);
    let mut spin = SpinSpring::default();
    let (p0, s0) = (r.surface().contact_point(), spin.accumulated_rad);
    let mut worst = Drift::default();
    for k in 1..=n {
        let q = samples[(k % samples.len() as u64) as usize];
        let step = r.step::<M>(q);
        spin.update(step.angles.phi, params.spin_stiffness, 1.0);
        if k % samples.len() as u64 == 0 {
            let d = drift(&r, &spin, p0, s0);
            worst.point_m = worst.point_m.max(d.point_m);
            worst.spin_rad = worst.spin_rad.max(d.spin_rad);
        }
    }
    worst
}

/// The held contact step: anchor walk (m) and final tangential force (N).
pub fn held_contact<M: Math>(method: Method, ticks: u64) -> (f64, f64) {
    let params = ContactParams {
        method,
        ..ContactParams::DEFAULT
    };
    let q = rest_orientation();
    let Ok(mut model) = ContactModel::<M, Plane>::new(params, Plane::default(), q, 1e-4) else {
        return (f64::NAN, f64::NAN);
    };
    let input = ContactInput {
        q,
        probe_m: Vec3::new(0.0, 0.0, params.fingertip_radius_m - 0.001),
        probe_vel: Vec3::ZERO,
    };
    for _ in 0..10 {
        let _ = model.contact_step(&input);
    }
    let p0 = model.rolling().surface().contact_point();
    let mut f_t = 0.0f64;
    for _ in 0..ticks {
        let out = model.contact_step(&input);
        f_t = ((out.force_n.x as f64).powi(2) + (out.force_n.y as f64).powi(2)).sqrt();
    }
    let d = model.rolling().surface().contact_point() - p0;
    (((d.x as f64).powi(2) + (d.y as f64).powi(2)).sqrt(), f_t)
}

/// The force of one encoder count of displacement: tangential stiffness times the largest effector
/// displacement one motor count makes at the workspace centre (column norms of J·rad_per_count), N.
pub fn one_count_force_n(params: &ContactParams) -> f64 {
    let dev = DeviceParams::OMEGA_LIKE;
    let g = DeltaGeometry::OMEGA_LIKE;
    let (angles, _) = g.inverse::<Libm>(DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M);
    let (j, _) = g.jacobian::<Libm>(angles, DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M);
    let count = dev.arm_rad_per_motor_count() as f64;
    let col = |c: usize| (0..3).map(|r| (j[r][c] as f64).powi(2)).sum::<f64>().sqrt();
    params.tangential_stiffness as f64 * count * (0..3).map(col).fold(0.0, f64::max)
}

/// What the closed-loop hold measured, N.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HoldForces {
    /// Largest rendered tangential force after 1 s of hold, wrist still.
    pub still_max_n: f64,
    /// Wrist still: the largest change of the rendered tangential force (vector) from its value
    /// after 1 s of hold.
    pub still_growth_n: f64,
    /// With one wrist count dithering every tick: the largest tangential force averaged over each
    /// pair of ticks (the dither's damping force alternates sign tick by tick and cancels).
    pub dither_pair_max_n: f64,
    /// Wrist still: tangential stiffness × the largest walk of the rolling anchor (contact point)
    /// from where it was after 1 s of hold: the part of the rendered force that creep would make.
    pub still_anchor_walk_n: f64,
    /// The same with the wrist dithering.
    pub dither_anchor_walk_n: f64,
    /// The force of one encoder count of displacement.
    pub one_count_n: f64,
}

/// Closed loop: press 1 mm with the wrist at [`rest_orientation`]'s angles and hold `hold_s`, once
/// still and once with one wrist count dithering every tick.
pub fn closed_loop_hold<M: Math>(method: Method, hold_s: f64) -> Result<HoldForces, SetupError> {
    let contact = ContactParams {
        method,
        ..ContactParams::DEFAULT
    };
    let (still, still_walk, growth) = hold_run::<M>(contact, hold_s, false)?;
    let (dither, dither_walk, _) = hold_run::<M>(contact, hold_s, true)?;
    let k_t = contact.tangential_stiffness as f64;
    Ok(HoldForces {
        still_max_n: still,
        still_growth_n: growth,
        dither_pair_max_n: dither,
        still_anchor_walk_n: k_t * still_walk,
        dither_anchor_walk_n: k_t * dither_walk,
        one_count_n: one_count_force_n(&contact),
    })
}

/// (largest tangential force, N; largest anchor walk, m; largest change of the force, N) of one
/// hold.
fn hold_run<M: Math>(
    contact: ContactParams,
    hold_s: f64,
    dither: bool,
) -> Result<(f64, f64, f64), SetupError> {
    let (mut ctrl, mut plant) = hold_scene::<M>(contact, hold_s, 0.0)?;
    let rate = f64::from(ctrl.config().timing.control_hz);
    let ticks = ((APPROACH_S + 0.5 + hold_s) * rate) as u64;
    // Approach, press (0.5 s) and the arming ramp (within them) settle before the hold is judged.
    let settle = ((APPROACH_S + 1.5) * rate) as u64;
    let mut worst = 0.0f64;
    let mut prev = [0.0f64; 2];
    let mut anchor0: Option<Vec3> = None;
    let mut walk = 0.0f64;
    let mut f0: Option<[f64; 2]> = None;
    let mut growth = 0.0f64;
    closed_loop::simulate(
        &mut ctrl,
        &mut plant,
        ticks,
        |k, input| {
            if dither {
                input.counts[4] = input.counts[4].wrapping_add((k & 1) as u16)
            }
        },
        |k, _, out, ctrl, _| {
            let a = anchor_point(ctrl);
            if k >= settle {
                let a0 = *anchor0.get_or_insert(a);
                walk = walk.max((a - a0).norm::<Libm>() as f64);
            }
            let f = [out.control.force_n.x as f64, out.control.force_n.y as f64];
            let g = if dither {
                [(f[0] + prev[0]) / 2.0, (f[1] + prev[1]) / 2.0]
            } else {
                f
            };
            prev = f;
            if k >= settle && (!dither || k % 2 == 1) {
                worst = worst.max((g[0] * g[0] + g[1] * g[1]).sqrt());
                let a = *f0.get_or_insert(g);
                growth = growth.max(((g[0] - a[0]).powi(2) + (g[1] - a[1]).powi(2)).sqrt());
            }
        },
    );
    Ok((worst, walk, growth))
}

/// The rolled contact point on the plane (object frame, m): where the held finger's anchor sits.
pub fn anchor_point<M: Math>(ctrl: &Pipeline<M, Plane>) -> Vec3 {
    ctrl.controller()
        .contact()
        .rolling()
        .surface()
        .contact_point()
}

/// Clearance of the fingertip above the plane where the hold scene arms, m: the device refuses
/// `Arm` with the probe inside the surface (at the old 2 mm it was refused, `InsideSurface`); the
/// default touch script's 20 mm, from which the default scene arms.
pub const ARM_CLEARANCE_M: f64 = 0.020;
/// The hold scene's approach from [`ARM_CLEARANCE_M`] to 2 mm above the plane (where it armed
/// before the device refused `Arm` inside the surface), s: the press starts this long after `Arm`.
pub const APPROACH_S: f64 = 0.5;

/// The closed-loop hold scene: the plant with a hand that arms with the fingertip
/// [`ARM_CLEARANCE_M`] above the plane, approaches to 2 mm above it in [`APPROACH_S`], presses 1 mm
/// at the workspace centre in 0.5 s with the wrist at [`rest_orientation`]'s angles, then holds for
/// `hold_s`, its reference
/// moving along base `x` at `drift_m_per_s` (0: still; a test hook standing for a slow walk of the
/// probe relative to the anchor), and the pipeline homed, the hand grasped and armed.
pub fn hold_scene<M: Math>(
    contact: ContactParams,
    hold_s: f64,
    drift_m_per_s: f64,
) -> Result<(Pipeline<M, Plane>, Plant), SetupError> {
    let top = closed_loop::surface_top_z_m();
    let c = DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M;
    let wrist = [0.3, -0.2, 0.1];
    let armed_at = [c.x as f64, c.y as f64, top + 0.01 + ARM_CLEARANCE_M];
    let above = [c.x as f64, c.y as f64, top + 0.012];
    let pressed = [c.x as f64, c.y as f64, top + 0.01 - 0.001];
    let held_end = [pressed[0] + drift_m_per_s * hold_s, pressed[1], pressed[2]];
    let script = HandScript::new(Waypoint {
        position_m: armed_at,
        wrist_rad: wrist,
    })
    .then(
        Phase::Approach,
        APPROACH_S,
        Waypoint {
            position_m: above,
            wrist_rad: wrist,
        },
    )
    .then(
        Phase::Press,
        0.5,
        Waypoint {
            position_m: pressed,
            wrist_rad: wrist,
        },
    )
    .then(
        Phase::Hold,
        hold_s,
        Waypoint {
            position_m: held_end,
            wrist_rad: wrist,
        },
    );
    let mut plant = Plant::new(OMEGA_LIKE.params, PlantParams::OMEGA_LIKE, script)?;
    let config = PipelineConfig {
        device: OMEGA_LIKE,
        timing: BoardTiming::STM32G474_10KHZ,
        contact,
        surface: Plane::default(),
        object_origin_m: Vec3::new(0.0, 0.0, top as f32),
        log_rate_hz: softfinger_core::control::telemetry::DEFAULT_LOG_RATE_HZ,
    };
    let mut ctrl: Pipeline<M, Plane> = Pipeline::new(config)?;
    // The operator's session first (home, grasp, arm); the script starts when armed.
    closed_loop::prepare(&mut ctrl, &mut plant)?;
    Ok((ctrl, plant))
}

/// The backends in the order the command prints them.
const PRINT_ORDER: [Backend; 3] = [Backend::Libm, Backend::Micromath, Backend::Fast];

/// One printed row: every creep measurement of `method` on backend `M`.
fn backend_row<M: Math>(args: &Args, method: Method) -> Result<(), CreepError> {
    let n = (args.seconds * args.rate_hz) as u64;
    let q = rest_orientation();
    let c = wrist_count_rad();
    let twist = q * Quat::from_axis_angle::<Libm>(Vec3::Z, c);
    let tilt = q * Quat::from_axis_angle::<Libm>(Vec3::X, c);
    let same = replay_cycle::<M>(method, &[q], n);
    let dt = replay_cycle::<M>(method, &[q, tilt], n);
    let dz = replay_cycle::<M>(method, &[q, twist], n);
    let (walk, f_t) = held_contact::<M>(method, args.held_ticks);
    let cl = if args.hold_s > 0.0 {
        let h = closed_loop_hold::<M>(method, args.hold_s)?;
        format!(
            "still {:.3e} N (change {:.3e} N, anchor walk {:.3e} N), dither pair mean {:.3e} N (anchor walk {:.3e} N), one count {:.3e} N",
            h.still_max_n, h.still_growth_n, h.still_anchor_walk_n, h.dither_pair_max_n, h.dither_anchor_walk_n, h.one_count_n
        )
    } else {
        "skipped".to_string()
    };
    println!(
        "{:<15} {:<9} identical {:.3e} m {:.3e} rad | tilt dither {:.3e} m | twist dither {:.3e} rad | held anchor {:.3e} m f_t {:.3e} N | closed loop {}",
        method.name(),
        M::NAME,
        same.point_m,
        same.spin_rad,
        dt.point_m,
        dz.spin_rad,
        walk,
        f_t,
        cl
    );
    Ok(())
}

/// Why the creep command failed.
#[derive(Debug, thiserror::Error)]
pub enum CreepError {
    /// An option out of range (its message names it).
    #[error("{0}")]
    Option(&'static str),
    /// A closed-loop hold could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A hold measurement failed.
    #[error(transparent)]
    Hold(#[from] hold_quantisation::HoldError),
}

pub fn main(args: &Args) -> Result<(), CreepError> {
    if !(args.seconds.is_finite()
        && args.seconds > 0.0
        && args.rate_hz.is_finite()
        && args.rate_hz > 0.0)
    {
        return Err(CreepError::Option(
            "--seconds and --rate-hz must be positive numbers",
        ));
    }
    if !(args.hold_s.is_finite() && args.hold_s >= 0.0) {
        return Err(CreepError::Option("--hold-s must be a non-negative number"));
    }
    println!(
        "creep at rest: {} s at {} Hz (replay), {} held ticks, {} s closed-loop hold",
        args.seconds, args.rate_hz, args.held_ticks, args.hold_s
    );
    for m in Method::ALL {
        for b in PRINT_ORDER {
            dispatch!(b, M => backend_row::<M>(args, m))?;
        }
    }
    if args.hold_s > 2.0 {
        // The hold through the encoders (exact method, libm): with and without the passivity
        // stage, and with the hand's reference drifting 0.65 µm/s (the creep rate of issue 12).
        for (passivity, drift) in [(true, 0.0), (false, 0.0), (true, 0.65e-6), (false, 0.65e-6)] {
            let setup = HoldSetup {
                hold_s: args.hold_s,
                passivity,
                drift_m_per_s: drift,
                window_s: (args.hold_s / 6.0).min(10.0),
            };
            for b in PRINT_ORDER {
                let p = dispatch!(b, M => hold_quantisation::measure::<M>(setup))?;
                println!("{b:<9} {}", hold_quantisation::line(&setup, &p));
            }
        }
    }
    Ok(())
}
