//! The run's summary: the board's own figures, the comparison with the in-process reference, the
//! defmt log, the contact states, and what the plant saw of an injected fault.

use super::faults::Fault;
use super::reference::RefTick;
use super::session::Trace;
use super::wire::{enabled, signed_compare};
use serde::Serialize;
use softfinger_core::control::pipeline::output_timing::{OutputTiming, CCM_CYCLES_PER_INSTRUCTION};
use softfinger_core::control::pipeline::BoardTiming;
use std::collections::BTreeMap;

/// Keys of the board's end-of-run figures (`Report` messages), in the board's order.
pub const REPORT_KEYS: [&str; 6] = [
    "ticks",
    "overruns",
    "max_start_latency_instructions",
    "max_tick_instructions",
    "defmt_frames",
    "defmt_drops",
];

/// Everything `host-sim pil` reports; the JSON of `--json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub scene: String,
    pub rate_hz: u32,
    /// Virtual time per guest instruction is 2^shift ns.
    pub icount_shift: u32,
    pub instructions_per_second: u64,
    pub period_instructions: u64,
    /// Control ticks the board ran (its own count, all boots).
    pub ticks: u32,
    pub overruns: u32,
    /// Whole interrupt, hardware layer included: first instruction to the last timer read.
    pub max_tick_instructions: u32,
    /// Timer event to the interrupt's first timer read.
    pub max_start_latency_instructions: u32,
    /// The tick the scene started at (homed and armed), on the board and in-process.
    pub scene_start_tick: Option<u64>,
    pub scene_start_tick_in_process: Option<u64>,
    /// Ticks compared with the in-process run, and how many wrote identical bridge commands.
    pub compared_ticks: u64,
    pub identical_ticks: u64,
    /// Largest |duty difference| (signed compare / full scale) over the compared ticks.
    pub max_duty_diff: f64,
    pub first_difference_tick: Option<u64>,
    /// Ticks whose pipeline was told that the previous tick's writes ended after its first PWM
    /// period, in emulated time (`instructions_per_second`; the in-process run is told the same):
    /// such a tick holds a direction reversal one tick longer. On the STM32 see `output`.
    pub board_late_writes: usize,
    pub defmt_frames: u32,
    pub defmt_drops: u32,
    pub defmt_malformed: usize,
    pub telemetry_records: usize,
    /// Records the tick could not queue (the decoded records' `dropped_before`, summed).
    pub telemetry_drops: u64,
    pub watchdog_resets: usize,
    /// Seconds in each contact state, from the board's decoded telemetry records.
    pub contact_state_s: BTreeMap<String, f64>,
    /// Seconds in each contact state in the in-process run (every tick).
    pub contact_state_s_in_process: BTreeMap<String, f64>,
    pub output: OutputReport,
    pub fault: FaultReport,
}

/// Sample-to-output delay per tick, measured: encoder sample (the `Sense` message) to the PWM
/// period boundary after the compare write (the `Drive` message) that loads it, both from the
/// board's instruction count at `cycles_per_instruction` (see `session`).
#[derive(Clone, Debug, Serialize)]
pub struct OutputReport {
    pub pwm_hz: u32,
    pub pwm_periods_per_tick: u32,
    /// Cycles per instruction of the tick's code in CCM SRAM (170 MHz timer clock).
    pub cycles_per_instruction: f32,
    /// Ticks measured (sample and write in the same period).
    pub ticks: usize,
    /// Latest sample and compare write after the tick event, instructions.
    pub max_sample_instructions: u64,
    pub max_write_instructions: u64,
    /// Cycles per instruction at which the latest write would miss the first PWM period.
    pub cpi_margin: f64,
    /// Sample-to-output delay over the measured ticks, µs and fraction of the tick.
    pub min_delay_us: f64,
    pub max_delay_us: f64,
    pub min_delay_ticks: f64,
    pub max_delay_ticks: f64,
    /// The delay the in-process run and `host-sim stability` assume (`OutputTiming::planned`).
    pub planned_delay_ticks: f64,
    /// Ticks whose compare loaded later than the planned boundary.
    pub late_ticks: usize,
}

impl OutputReport {
    /// The figures of `trace` on `timing`.
    pub fn of(trace: &Trace, timing: &BoardTiming) -> OutputReport {
        let planned = OutputTiming::planned(timing);
        let us = |counts: u32| f64::from(counts) * 1e6 / f64::from(timing.timer_clock_hz.max(1));
        let delays = trace.output.iter().map(|t| t.delay_counts());
        let (min, max) = (delays.clone().min().unwrap_or(0), delays.max().unwrap_or(0));
        let tick = f64::from(timing.tick_period_counts().max(1));
        OutputReport {
            pwm_hz: timing.pwm_hz,
            pwm_periods_per_tick: timing.pwm_periods_per_tick(),
            cycles_per_instruction: CCM_CYCLES_PER_INSTRUCTION,
            ticks: trace.output.len(),
            max_sample_instructions: trace.max_sample_instructions,
            max_write_instructions: trace.max_write_instructions,
            cpi_margin: f64::from(timing.pwm_period_counts())
                / trace.max_write_instructions.max(1) as f64,
            min_delay_us: us(min),
            max_delay_us: us(max),
            min_delay_ticks: f64::from(min) / tick,
            max_delay_ticks: f64::from(max) / tick,
            planned_delay_ticks: f64::from(planned.delay_ticks()),
            late_ticks: trace
                .output
                .iter()
                .filter(|t| t.effect_counts > planned.effect_counts)
                .count(),
        }
    }

    /// `--check`'s failure: no tick measured, or a compare loaded later than planned.
    pub fn failure(&self) -> Option<String> {
        (self.ticks == 0 || self.late_ticks > 0).then(|| {
            format!(
                "{} of {} ticks' compares loaded after the planned PWM boundary",
                self.late_ticks, self.ticks
            )
        })
    }

    fn print(&self) {
        println!(
            "  sample to output ({} ticks, {} Hz PWM, {} periods per tick, {} cycles/instr in CCM): \
             {:.2}..{:.2} µs = {:.3}..{:.3} of a tick (planned {:.3}); latest write {} instr \
             (first PWM period held up to {:.2} cycles/instr), {} late",
            self.ticks,
            self.pwm_hz,
            self.pwm_periods_per_tick,
            self.cycles_per_instruction,
            self.min_delay_us,
            self.max_delay_us,
            self.min_delay_ticks,
            self.max_delay_ticks,
            self.planned_delay_ticks,
            self.max_write_instructions,
            self.cpi_margin,
            self.late_ticks
        );
    }
}

/// What the plant saw of the injected fault.
#[derive(Clone, Debug, Serialize)]
pub struct FaultReport {
    pub name: Fault,
    pub at_tick: Option<u64>,
    /// First tick at or after the fault whose period ended with the bridges off.
    pub outputs_off_at_tick: Option<u64>,
    /// Ticks from the fault to outputs off.
    pub outputs_off_after_ticks: Option<u64>,
    /// Periods after `outputs_off_at_tick` with the bridges on.
    pub periods_driven_after_off: u64,
    /// The fault was handled as required (see `judge`).
    pub handled: bool,
}

/// Compare the board's outputs, period by period, with the reference's, over `limit` ticks.
/// Tick k's outputs are the ones held at the end of period k+1; `full_scale` is the PWM period in
/// compare counts.
pub fn compare(
    trace: &Trace,
    reference: &[RefTick],
    limit: u64,
    full_scale: f64,
) -> (u64, u64, f64, Option<u64>) {
    let (mut compared, mut identical, mut max_diff, mut first) = (0, 0, 0.0f64, None);
    for (k, r) in reference.iter().enumerate().take(limit as usize) {
        let Some(p) = trace.pins.get(k + 1) else {
            break;
        };
        compared += 1;
        if *p == r.bridges {
            identical += 1;
        } else {
            first.get_or_insert(k as u64);
            let (a, b) = (signed_compare(p), signed_compare(&r.bridges));
            for i in 0..3 {
                max_diff = max_diff.max((a[i] - b[i]).abs() as f64 / full_scale);
            }
        }
    }
    (compared, identical, max_diff, first)
}

/// The plant's view of the fault: when the bridges went off and whether they stayed off.
pub fn observe_fault(trace: &Trace, fault: Fault, at_tick: Option<u64>) -> FaultReport {
    let mut r = FaultReport {
        name: fault,
        at_tick: at_tick.filter(|_| fault != Fault::None),
        outputs_off_at_tick: None,
        outputs_off_after_ticks: None,
        periods_driven_after_off: 0,
        handled: true,
    };
    let Some(at_tick) = r.at_tick.filter(|_| fault.expects_outputs_off()) else {
        return r;
    };
    let after: Vec<_> = trace.pins.iter().skip(at_tick as usize + 1).collect();
    if let Some(i) = after.iter().position(|p| !enabled(p)) {
        r.outputs_off_at_tick = Some(at_tick + i as u64);
        r.outputs_off_after_ticks = Some(i as u64);
        r.periods_driven_after_off = after[i..].iter().filter(|p| enabled(p)).count() as u64;
    }
    r
}

/// Seconds per contact state from (state name, seconds) samples.
pub fn state_time<'a>(samples: impl Iterator<Item = (&'a str, f64)>) -> BTreeMap<String, f64> {
    let mut m = BTreeMap::new();
    for (s, dt) in samples {
        *m.entry(s.to_lowercase()).or_insert(0.0) += dt;
    }
    for v in m.values_mut() {
        *v = (*v * 1e6).round() / 1e6;
    }
    m
}

impl Summary {
    /// The human-readable summary.
    pub fn print(&self) {
        println!(
            "PIL {} at {} Hz on QEMU mps2-an386 (-icount shift={}: {} instructions/s, {} per period)",
            self.scene,
            self.rate_hz,
            self.icount_shift,
            self.instructions_per_second,
            self.period_instructions
        );
        println!(
            "  ticks {}  overruns {}  max tick {} instr  max start latency {} instr",
            self.ticks,
            self.overruns,
            self.max_tick_instructions,
            self.max_start_latency_instructions
        );
        println!(
            "  in-process comparison: {} of {} ticks identical, max duty diff {:e}{}",
            self.identical_ticks,
            self.compared_ticks,
            self.max_duty_diff,
            self.first_difference_tick
                .map_or(String::new(), |t| format!(", first difference at tick {t}"))
        );
        println!(
            "  late writes in emulated time (told to the in-process run too): {} ticks",
            self.board_late_writes
        );
        println!(
            "  defmt: {} frames, {} dropped, {} malformed; {} telemetry records ({} dropped)",
            self.defmt_frames,
            self.defmt_drops,
            self.defmt_malformed,
            self.telemetry_records,
            self.telemetry_drops
        );
        self.output.print();
        println!("  watchdog resets {}", self.watchdog_resets);
        let states: Vec<String> = self
            .contact_state_s
            .iter()
            .map(|(k, v)| format!("{k} {v:.3} s"))
            .collect();
        println!("  contact states (telemetry): {}", states.join(", "));
        if self.fault.name != Fault::None {
            println!(
                "  fault {:?} at tick {:?}: outputs off at tick {:?} ({:?} ticks later), driven {} periods after; handled: {}",
                self.fault.name,
                self.fault.at_tick.unwrap_or(0),
                self.fault.outputs_off_at_tick,
                self.fault.outputs_off_after_ticks,
                self.fault.periods_driven_after_off,
                self.fault.handled
            );
        }
    }
}
