//! The fault campaign's view of the closed loop ([`crate::sim::closed_loop::step`], one tick at a
//! time): before each tick an `act` hook may command the pipeline or change the plant (operator
//! commands, parameter changes, the hand letting go), and an `inject` hook may corrupt what the
//! pipeline reads (raw counts, the nFAULT line, the tick timing); each tick is recorded with the
//! force the motors actually exert.
//!
//! Per tick k (period dt = 1/rate), as on the MCU:
//!
//! ```text
//! act(k, &mut pipeline, &mut plant)
//! raw = RawInput { counts: plant.raw_counts(), .. }; inject(k, &mut raw)   // sampled at t_k
//! out = pipeline.tick(&raw)
//! plant.step_bridges(&out.bridges, &timing)   // compares act from the next PWM boundary
//! ```

use crate::sim::closed_loop::{prepare, Prepared, SetupError};
use crate::sim::plant::{HandScript, Plant, PlantParams, TouchScript};
use nalgebra::{Matrix3, Vector3};
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::surface::Plane;
use softfinger_core::control::pipeline::{
    BoardTiming, Mode, Pipeline, PipelineConfig, PipelineOutput, RawInput,
};
use softfinger_core::device::DeviceParams;
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Fast, Flags, Libm, Vec3};

/// The pipeline the campaign runs: the MCU's fast kernels on the plane scene.
pub type Pipe = Pipeline<Fast, Plane>;

/// The pipeline configuration matching a touch script: the Omega-like device on the STM32G474
/// at 10 kHz, the plane z = `surface_z_m` of the base frame, the script's fingertip radius,
/// everything else the defaults.
pub fn scene_config(touch: &TouchScript) -> PipelineConfig<Plane> {
    let mut c = PipelineConfig::plane(
        OMEGA_LIKE,
        BoardTiming::STM32G474_10KHZ,
        touch.surface_z_m as f32,
    );
    c.contact.fingertip_radius_m = touch.fingertip_radius_m as f32;
    c
}

/// What one tick did, as the campaign's judges see it.
#[derive(Clone, Copy, Debug)]
pub struct TickRecord {
    /// Tick index from the start of the run.
    pub k: u64,
    /// The raw input the pipeline actually received (after injection).
    pub raw: RawInput,
    /// The pipeline's output.
    pub out: PipelineOutput,
    /// |force| the controller rendered, N.
    pub rendered_n: f64,
    /// |force| the motors exert on the handle after this tick's plant step, N (see
    /// [`motor_force_n`]).
    pub plant_n: f64,
    /// Any non-finite number in the pipeline's output.
    pub nan: bool,
    /// The motor counts of the plant's true arm angles (device zero), after the step.
    pub true_counts: [i32; 3],
    /// Wrong-direction drive of all bridges so far, s (plant truth).
    pub wrong_direction_s: f64,
    /// Phase reversals so far (plant truth).
    pub reversals: u64,
    /// Largest |arm torque| of the three motors after this tick's step, N·m (plant currents).
    pub arm_torque_nm: f64,
}

/// The force the three motors exert at the effector, frame B, N: τ = ratio·k_t·i per arm and
/// F = J⁻ᵀ·τ (virtual work: τ = Jᵀ·F with ṗ = J·θ̇). The Jacobian is the core's, at the plant's
/// true arm angles and effector position. `None` where J is singular.
pub fn motor_force_n(device: &DeviceParams, plant: &Plant) -> Option<[f64; 3]> {
    let t = plant.truth();
    let angles = t.arm_angles_rad.map(|a| a as f32);
    let p = t.effector_position_m;
    let (j, f) = device
        .delta
        .jacobian::<Libm>(angles, Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32));
    if !f.is_empty() {
        return None;
    }
    let jm = Matrix3::from_fn(|r, c| j[r][c] as f64);
    let k = device.motor.capstan_ratio as f64 * device.motor.torque_constant_nm_per_a as f64;
    let tau = Vector3::from_iterator(t.motor_currents_a.iter().map(|i| k * i));
    let f = jm.transpose().try_inverse()? * tau;
    Some([f.x, f.y, f.z])
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Plant and pipeline in one loop.
#[derive(Debug)]
pub struct ClosedLoop {
    pub plant: Plant,
    pub pipe: Pipe,
    pub device: DeviceParams,
    pub dt_s: f64,
    pub k: u64,
    /// The operator's session before tick 0 (None: the loop starts at power-up).
    pub prepared: Option<Prepared>,
    /// Arm torque per motor ampere, N·m/A (capstan ratio × k_t).
    torque_per_amp: f64,
}

impl ClosedLoop {
    /// Power-up: the plant with `script` (hand holding the handle), the pipeline unhomed; tick 0
    /// is the first tick after power-up.
    pub fn powered(
        config: PipelineConfig<Plane>,
        plant_params: PlantParams,
        script: HandScript,
    ) -> Result<ClosedLoop, SetupError> {
        let device = config.device.params;
        let plant = Plant::new(device, plant_params, script)?;
        let pipe = Pipe::new(config)?;
        Ok(ClosedLoop {
            plant,
            pipe,
            device,
            dt_s: 1.0 / f64::from(config.timing.control_hz),
            k: 0,
            prepared: None,
            torque_per_amp: f64::from(device.motor.capstan_ratio)
                * f64::from(device.motor.torque_constant_nm_per_a),
        })
    }

    /// Power-up and the operator's session ([`prepare`]): tick 0 is the first armed tick, with the
    /// script at its start.
    pub fn new(
        config: PipelineConfig<Plane>,
        plant_params: PlantParams,
        script: HandScript,
    ) -> Result<ClosedLoop, SetupError> {
        let mut lp = ClosedLoop::powered(config, plant_params, script)?;
        lp.prepared = Some(prepare(&mut lp.pipe, &mut lp.plant)?);
        Ok(lp)
    }

    /// Simulated time of the next tick since tick 0, s.
    pub fn time_s(&self) -> f64 {
        self.k as f64 * self.dt_s
    }

    /// One tick: `act` on the pipeline or plant, then the tick with `inject` on its raw input.
    pub fn tick(
        &mut self,
        act: &mut dyn FnMut(u64, &mut Pipe, &mut Plant),
        inject: &mut dyn FnMut(u64, &mut RawInput),
    ) -> TickRecord {
        let k = self.k;
        act(k, &mut self.pipe, &mut self.plant);
        let (raw, out, _) =
            crate::sim::closed_loop::step(&mut self.pipe, &mut self.plant, |r| inject(k, r));
        let c = out.control;
        let f = c.force_n;
        let nan = !(f.is_finite()
            && c.probe_m.is_finite()
            && c.tau_n_nm.is_finite()
            && c.duties.iter().all(|d| d.is_finite()));
        let truth = self.plant.truth();
        let true_counts = self.plant.counts();
        self.k += 1;
        TickRecord {
            k,
            raw,
            out,
            rendered_n: norm([f.x as f64, f.y as f64, f.z as f64]),
            plant_n: motor_force_n(&self.device, &self.plant).map_or(0.0, norm),
            nan,
            true_counts: [true_counts[0], true_counts[1], true_counts[2]],
            wrong_direction_s: truth.wrong_direction_s.iter().sum(),
            reversals: truth.reversals,
            arm_torque_nm: truth
                .motor_currents_a
                .iter()
                .map(|i| (i * self.torque_per_amp).abs())
                .fold(0.0, f64::max),
        }
    }
}

/// A run's records and its summary figures.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    pub records: Vec<TickRecord>,
}

impl Trace {
    pub fn max_rendered_n(&self) -> f64 {
        self.records
            .iter()
            .map(|r| r.rendered_n)
            .fold(0.0, f64::max)
    }
    /// Largest force the motors exert on the handle, N, outside homing (homing drives the arms
    /// against their stops, where the linkage is near a dead centre and the stops, not the
    /// handle, take the load; its torque is checked by [`Self::max_homing_torque_nm`]).
    pub fn max_plant_n(&self) -> f64 {
        self.records
            .iter()
            .filter(|r| r.out.mode != Mode::Homing)
            .map(|r| r.plant_n)
            .fold(0.0, f64::max)
    }
    /// Largest arm torque of the motors during homing, N·m.
    pub fn max_homing_torque_nm(&self) -> f64 {
        self.records
            .iter()
            .filter(|r| r.out.mode == Mode::Homing)
            .map(|r| r.arm_torque_nm)
            .fold(0.0, f64::max)
    }
    pub fn nan_outputs(&self) -> usize {
        self.records.iter().filter(|r| r.nan).count()
    }
    /// First tick at or after `from` whose output carries `flag`.
    pub fn first_flag(&self, flag: Flags, from: u64) -> Option<u64> {
        self.records
            .iter()
            .find(|r| r.k >= from && r.out.flags.contains(flag))
            .map(|r| r.k)
    }
    /// First tick from which the output stays at zero torque (disabled, zero duties) to the end.
    pub fn safe_from(&self) -> Option<u64> {
        let mut from = None;
        for r in &self.records {
            let b = &r.out.bridges;
            let safe = !b.pwm_enable && b.compare == [0; 3];
            match (safe, from) {
                (true, None) => from = Some(r.k),
                (false, _) => from = None,
                _ => {}
            }
        }
        from
    }
    /// Ticks with a latched fault.
    pub fn latched_ticks(&self) -> usize {
        self.records
            .iter()
            .filter(|r| !r.out.latched.is_empty())
            .count()
    }
    /// The contact state of each tick.
    pub fn states(&self) -> impl Iterator<Item = ContactState> + '_ {
        self.records.iter().map(|r| r.out.control.state)
    }
}
