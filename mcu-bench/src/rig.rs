//! A control pipeline of the default plane scene, homed and armed through its raw inputs alone
//! (no plant on the target): the counters follow a scripted homing (the arms travel 500 counts
//! down to their far stops, stay there for the stall time, travel the mechanism's range up to the
//! reference stops, stay again, then move to the park angle), as a real device would make them. Shared by the `pipeline_tick` benchmark and the on-target pipeline tests.

use softfinger_core::contact::surface::Plane;
use softfinger_core::control::pipeline::{
    BoardTiming, Command, Mode, Pipeline, PipelineConfig, PipelineOutput, RawInput,
};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Libm, Math, Vec3};

/// Homed motor count at the Omega-like stops: −40° at 4096·12 counts per arm turn.
pub const STOP_COUNT: i32 = -5461;

/// The plane scene: 10 mm below the workspace centre, so the 10 mm fingertip touches it with its
/// centre there; the STM32G474 timing at 10 kHz.
pub fn config() -> PipelineConfig<Plane> {
    let z = DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.z - 0.010;
    PipelineConfig::plane(OMEGA_LIKE, BoardTiming::STM32G474_10KHZ, z)
}

/// Homed motor counts that put the probe `depth_m` into the plane at the workspace centre, wrist
/// at `wrist`; `None` if unreachable.
pub fn pressing_counts(depth_m: f32, wrist: [i32; 3]) -> Option<[i32; 6]> {
    let c = config();
    let p = c.object_origin_m + Vec3::new(0.0, 0.0, c.contact.fingertip_radius_m - depth_m);
    c.device.params.counts_at::<Libm>(p, wrist)
}

/// A pipeline and the map from homed motor counts to raw counter values.
pub struct Rig<M: Math> {
    pub pipe: Pipeline<M, Plane>,
    /// raw motor counter = homed count + shift (mod 2¹⁶).
    pub shift: i32,
}

impl<M: Math> Rig<M> {
    /// Power-up (unhomed); `None` if the configuration is rejected.
    pub fn powered() -> Option<Rig<M>> {
        Some(Rig {
            pipe: Pipeline::new(config()).ok()?,
            shift: 0,
        })
    }

    /// The raw input for homed counts (motors) and wrist counts.
    pub fn raw(&self, homed: [i32; 6]) -> RawInput {
        RawInput {
            counts: core::array::from_fn(|i| {
                let s = if i < 3 { self.shift } else { 0 };
                homed[i].wrapping_add(s) as u16
            }),
            ..RawInput::default()
        }
    }

    /// One tick at homed counts.
    pub fn tick(&mut self, homed: [i32; 6]) -> PipelineOutput {
        let raw = self.raw(homed);
        self.pipe.tick(&raw)
    }

    /// Home by the scripted counter motion from raw reading 0 (the power-up reading); true when the
    /// pipeline reached `Disarmed`.
    pub fn home(&mut self) -> bool {
        let mut raw = 0i32;
        let feed = |p: &mut Pipeline<M, Plane>, raw: i32| {
            p.tick(&RawInput {
                counts: [raw as u16, raw as u16, raw as u16, 0, 0, 0],
                ..RawInput::default()
            })
        };
        feed(&mut self.pipe, raw);
        if self.pipe.command(Command::Home).is_err() {
            return false;
        }
        for _ in 0..21 {
            feed(&mut self.pipe, raw); // the nSLEEP edge and the drivers' 2 ms wake time
        }
        // Down 500 counts to the far stops, still for the stall time, then up the mechanism's
        // 145° (19 797 counts) to the reference stops, still again: homing checks the range.
        for _ in 0..500 {
            raw += 1;
            feed(&mut self.pipe, raw);
        }
        for _ in 0..1001 {
            feed(&mut self.pipe, raw);
        }
        for _ in 0..19_797 {
            raw -= 1;
            feed(&mut self.pipe, raw);
        }
        for _ in 0..1001 {
            feed(&mut self.pipe, raw);
        }
        self.shift = raw - STOP_COUNT;
        while raw < self.shift {
            raw = (raw + 2).min(self.shift);
            feed(&mut self.pipe, raw);
        }
        for _ in 0..1000 {
            if feed(&mut self.pipe, raw).mode == Mode::Disarmed {
                break;
            }
        }
        // One disarmed tick looks at the contact (Arm is refused until one has).
        feed(&mut self.pipe, raw);
        self.pipe.mode() == Mode::Disarmed
    }

    /// Move the motors from `from` to `to` at most `step` counts per tick (wrist at 0).
    pub fn move_to(&mut self, from: [i32; 3], to: [i32; 3], step: i32) -> Option<PipelineOutput> {
        let mut c = from;
        let mut out = None;
        while c != to || out.is_none() {
            for i in 0..3 {
                c[i] += (to[i] - c[i]).clamp(-step, step);
            }
            out = Some(self.tick([c[0], c[1], c[2], 0, 0, 0]));
        }
        out
    }

    /// Powered, homed, armed, moved to `depth_m` in the plane and past the 0.5 s arming ramp.
    pub fn pressing(depth_m: f32) -> Option<(Rig<M>, [i32; 6])> {
        let mut rig = Rig::powered()?;
        if !rig.home() || rig.pipe.command(Command::Arm).is_err() {
            return None;
        }
        let above = pressing_counts(-0.005, [0; 3])?;
        let press = pressing_counts(depth_m, [0; 3])?;
        rig.move_to([0; 3], [above[0], above[1], above[2]], 20)?;
        for _ in 0..5_000 {
            rig.tick(above);
        }
        rig.move_to(
            [above[0], above[1], above[2]],
            [press[0], press[1], press[2]],
            20,
        )?;
        Some((rig, press))
    }
}
