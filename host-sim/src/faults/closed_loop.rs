//! The fault campaign's view of the closed loop ([`crate::closed_loop::simulate`], one tick at a
//! time): before each tick an `act` hook may change the controller or the plant (parameter
//! changes, the hand letting go), and an `inject` hook may corrupt what the controller sees
//! (counts, fault inputs); each tick is recorded with the force the motors actually exert.
//!
//! Per tick k (period dt = 1/rate), as on the MCU:
//!
//! ```text
//! act(k, &mut controller, &mut plant)
//! input = TickInput { counts: plant.counts(), .. }; inject(k, &mut input)   // sampled at t_k
//! out = controller.tick(&input)
//! plant.step_with_enable(out.duties, out.enable, dt) // acts during tick k+1 (one-tick delay)
//! ```

use crate::plant::{HandScript, Plant, PlantParams, TouchScript};
use nalgebra::{Matrix3, Vector3};
use softfinger_core::contact_state::ContactState;
use softfinger_core::controller::{Controller, ControllerConfig, TickInput, TickOutput};
use softfinger_core::device::DeviceParams;
use softfinger_core::surface::Plane;
use softfinger_core::{Fast, Flags, Libm, Vec3};

/// The controller the campaign runs: the MCU's fast kernels on the plane scene.
pub type Ctrl = Controller<Fast, Plane>;

/// The controller configuration matching a touch script: the plane z = `surface_z_m` of the base
/// frame, the script's fingertip radius, everything else the defaults.
pub fn scene_config(touch: &TouchScript) -> ControllerConfig<Plane> {
    let mut c = ControllerConfig::default_plane();
    c.object_origin_m = Vec3::new(0.0, 0.0, touch.surface_z_m as f32);
    c.contact.fingertip_radius_m = touch.fingertip_radius_m as f32;
    c
}

/// What one tick did, as the campaign's judges see it.
#[derive(Clone, Copy, Debug)]
pub struct TickRecord {
    /// Tick index from the start of the run.
    pub k: u64,
    /// The input the controller actually received (after injection).
    pub input: TickInput,
    /// The controller's output.
    pub out: TickOutput,
    /// |force| the controller rendered, N.
    pub rendered_n: f64,
    /// |force| the motors exert on the handle after this tick's plant step, N (see
    /// [`motor_force_n`]).
    pub plant_n: f64,
    /// Any non-finite number in the controller's output.
    pub nan: bool,
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

/// Plant and controller in one loop.
#[derive(Debug)]
pub struct ClosedLoop {
    pub plant: Plant,
    pub ctrl: Ctrl,
    pub device: DeviceParams,
    pub dt_s: f64,
    pub k: u64,
}

impl ClosedLoop {
    /// The default device and plant with `script`, controlled with `config`.
    pub fn new(
        config: ControllerConfig<Plane>,
        plant_params: PlantParams,
        script: HandScript,
    ) -> Result<ClosedLoop, String> {
        let device = config.device;
        let plant = Plant::new(device, plant_params, script).map_err(|e| format!("{e:?}"))?;
        let ctrl = Ctrl::new(config).map_err(|e| format!("{e}"))?;
        Ok(ClosedLoop {
            plant,
            ctrl,
            device,
            dt_s: 1.0 / config.rate_hz as f64,
            k: 0,
        })
    }

    /// Simulated time of the next tick, s.
    pub fn time_s(&self) -> f64 {
        self.k as f64 * self.dt_s
    }

    /// One tick: `act` on the controller or plant, then the tick with `inject` on its input.
    pub fn tick(
        &mut self,
        act: &mut dyn FnMut(u64, &mut Ctrl, &mut Plant),
        inject: &mut dyn FnMut(u64, &mut TickInput),
    ) -> TickRecord {
        let k = self.k;
        act(k, &mut self.ctrl, &mut self.plant);
        let device = self.device;
        let mut rec = None;
        crate::closed_loop::simulate(
            &mut self.ctrl,
            &mut self.plant,
            1,
            |_, input| inject(k, input),
            |_, input, out, _, plant| {
                let f = out.force_n;
                let nan = !(f.is_finite()
                    && out.probe_m.is_finite()
                    && out.tau_n_nm.is_finite()
                    && out.duties.iter().all(|d| d.is_finite()));
                rec = Some(TickRecord {
                    k,
                    input: *input,
                    out: *out,
                    rendered_n: norm([f.x as f64, f.y as f64, f.z as f64]),
                    plant_n: motor_force_n(&device, plant).map_or(0.0, norm),
                    nan,
                });
            },
        );
        self.k += 1;
        rec.expect("simulate ran one tick")
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
    pub fn max_plant_n(&self) -> f64 {
        self.records.iter().map(|r| r.plant_n).fold(0.0, f64::max)
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
            let safe = !r.out.enable && r.out.duties == [0.0; 3];
            match (safe, from) {
                (true, None) => from = Some(r.k),
                (false, _) => from = None,
                _ => {}
            }
        }
        from
    }
    /// Ticks in which a latching fault was raised.
    pub fn latched_ticks(&self) -> usize {
        self.records.iter().filter(|r| !r.out.enable).count()
    }
    /// The contact state of each tick.
    pub fn states(&self) -> impl Iterator<Item = ContactState> + '_ {
        self.records.iter().map(|r| r.out.state)
    }
}
