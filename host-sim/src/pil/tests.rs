//! Tests of the PIL host's checks: the tick-by-tick comparison, the plant's view of a fault, the
//! budget and the `--check` verdict, each just inside and just outside its threshold.

use super::faults::Fault;
use super::reference::RefTick;
use super::report::{self, FaultReport, OutputReport, Summary};
use super::session::{instructions_to_timer_counts, Trace};
use softfinger_core::contact::state::ContactState;
use softfinger_core::control::pipeline::output_timing::OutputTiming;
use softfinger_core::control::pipeline::{BoardTiming, BridgeCommands, Mode};
use std::collections::BTreeMap;

fn on(compare: u16) -> BridgeCommands {
    BridgeCommands {
        phase_forward: [true, false, true],
        compare: [compare, 10, 0],
        pwm_enable: true,
        driver_awake: true,
    }
}

fn reference(b: &[BridgeCommands]) -> Vec<RefTick> {
    b.iter()
        .map(|&bridges| RefTick {
            bridges,
            state: ContactState::Broken,
            mode: Mode::Armed,
        })
        .collect()
}

fn trace(per_tick: &[BridgeCommands]) -> Trace {
    // Period 0 (before the first tick) is off; tick k's commands end period k+1.
    let mut pins = vec![BridgeCommands::OFF];
    pins.extend_from_slice(per_tick);
    Trace {
        pins,
        ..Trace::default()
    }
}

#[test]
fn comparison_counts_identical_ticks_and_the_largest_duty_difference() {
    let board = [on(100), on(100), on(108), on(100)];
    let refs = reference(&[on(100), on(100), on(100), on(100)]);
    let (compared, identical, diff, first) =
        report::compare(&trace(&board), &refs, u64::MAX, 8500.0);
    assert_eq!((compared, identical, first), (4, 3, Some(2)));
    assert_eq!(diff, 8.0 / 8500.0);
    // A limit stops the comparison before the difference.
    let (compared, identical, _, first) = report::compare(&trace(&board), &refs, 2, 8500.0);
    assert_eq!((compared, identical, first), (2, 2, None));
    // A phase flip with the bridges off is no duty difference, but not identical either.
    let off_a = BridgeCommands::OFF;
    let off_b = BridgeCommands {
        phase_forward: [false; 3],
        ..BridgeCommands::OFF
    };
    let (_, identical, diff, _) =
        report::compare(&trace(&[off_a]), &reference(&[off_b]), 9, 8500.0);
    assert_eq!((identical, diff), (0, 0.0));
}

#[test]
fn fault_view_finds_when_the_bridges_went_off_and_whether_they_stayed_off() {
    let t = trace(&[
        on(5),
        on(5),
        on(5),
        BridgeCommands::OFF,
        BridgeCommands::OFF,
    ]);
    let r = report::observe_fault(&t, Fault::Hang, Some(1));
    assert_eq!(r.outputs_off_at_tick, Some(3));
    assert_eq!(r.outputs_off_after_ticks, Some(2));
    assert_eq!(r.periods_driven_after_off, 0);
    let t = trace(&[on(5), BridgeCommands::OFF, on(5)]);
    let r = report::observe_fault(&t, Fault::Panic, Some(1));
    assert_eq!(
        (r.outputs_off_after_ticks, r.periods_driven_after_off),
        (Some(0), 1)
    );
    // Faults that must not turn the bridges off report nothing about them.
    let r = report::observe_fault(&t, Fault::LogStall, Some(1));
    assert_eq!(r.outputs_off_at_tick, None);
}

fn summary(max_tick: u32, latency: u32) -> Summary {
    Summary {
        scene: "s".into(),
        rate_hz: 10_000,
        icount_shift: 3,
        instructions_per_second: 125_000_000,
        period_instructions: 12_500,
        ticks: 10,
        overruns: 0,
        max_tick_instructions: max_tick,
        max_start_latency_instructions: latency,
        scene_start_tick: Some(1),
        scene_start_tick_in_process: Some(1),
        compared_ticks: 10,
        identical_ticks: 10,
        max_duty_diff: 0.0,
        first_difference_tick: None,
        board_late_writes: 0,
        defmt_frames: 1,
        defmt_drops: 0,
        defmt_malformed: 0,
        telemetry_records: 1,
        telemetry_drops: 0,
        watchdog_resets: 0,
        contact_state_s: BTreeMap::new(),
        contact_state_s_in_process: BTreeMap::new(),
        output: OutputReport::of(&timed_trace(&[3_000]), &BoardTiming::STM32G474_10KHZ),
        fault: FaultReport {
            name: Fault::None,
            at_tick: None,
            outputs_off_at_tick: None,
            outputs_off_after_ticks: None,
            periods_driven_after_off: 0,
            handled: true,
        },
    }
}

#[test]
fn check_fails_just_above_the_budget_and_on_any_difference_or_overrun() {
    let dir = std::env::temp_dir().join(format!("pil-budget-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let budget = dir.join("b.json");
    std::fs::write(
        &budget,
        r#"{"tolerance_percent": 10, "baseline": {"10000": {"max_tick_instructions": 1000, "max_start_latency_instructions": 10}}}"#,
    )
    .unwrap();
    // 10 % over 1000 is the limit: 1100 passes, 1105 (the next 5-instruction step) fails.
    assert!(super::check(&summary(1100, 11), Some(&budget)).is_ok());
    let e = super::check(&summary(1105, 11), Some(&budget))
        .unwrap_err()
        .to_string();
    assert!(e.contains("max_tick_instructions 1105"), "{e}");
    let e = super::check(&summary(1000, 12), Some(&budget))
        .unwrap_err()
        .to_string();
    assert!(e.contains("max_start_latency_instructions"), "{e}");
    // A tick longer than its period fails without a budget.
    assert!(super::check(&summary(12_500, 5), None).is_ok());
    assert!(super::check(&summary(12_505, 5), None).is_err());
    let mut s = summary(1000, 5);
    s.identical_ticks = 9;
    assert!(super::check(&s, None)
        .unwrap_err()
        .to_string()
        .contains("1 of 10 ticks differ"));
    let mut s = summary(1000, 5);
    s.overruns = 1;
    assert!(super::check(&s, None)
        .unwrap_err()
        .to_string()
        .contains("1 overruns"));
    // A rate without a baseline is an error, not a pass.
    let mut s = summary(1000, 5);
    s.rate_hz = 20_000;
    assert!(super::check(&s, Some(&budget))
        .unwrap_err()
        .to_string()
        .contains("no baseline"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A trace whose ticks sampled 50 counts after the event and wrote at `write_counts`.
fn timed_trace(write_counts: &[u32]) -> Trace {
    let b = BoardTiming::STM32G474_10KHZ;
    Trace {
        output: write_counts
            .iter()
            .map(|&w| OutputTiming::new(&b, 50, w - 50))
            .collect(),
        max_sample_instructions: 40,
        max_write_instructions: 2_000,
        ..Trace::default()
    }
}

#[test]
fn output_report_measures_the_delay_and_fails_a_late_load() {
    let b = BoardTiming::STM32G474_10KHZ;
    // 2000 instructions at 1.25 cycles: 2500 counts of the 170 MHz timer clock.
    assert_eq!(instructions_to_timer_counts(2_000), 2_500);
    assert_eq!(instructions_to_timer_counts(1), 2);
    // Writes up to 4249 counts load at the first 40 kHz boundary (4250): 4200 counts after the
    // sample, 24.71 µs, 0.247 of the 17 000-count tick.
    let r = OutputReport::of(&timed_trace(&[3_000, 4_249]), &b);
    assert_eq!((r.ticks, r.late_ticks, r.pwm_periods_per_tick), (2, 0, 4));
    // The report's quotients measured exactly these.
    assert_eq!(r.max_delay_us, 4_200.0 / 170.0, "{r:?}");
    assert_eq!(r.max_delay_ticks, 4_200.0 / 17_000.0);
    assert_eq!(r.min_delay_us, r.max_delay_us);
    assert_eq!(r.cpi_margin, 4_250.0 / 2_000.0);
    assert!(r.failure().is_none());
    // At 4250 the write misses that boundary: late, and --check fails.
    let r = OutputReport::of(&timed_trace(&[3_000, 4_250]), &b);
    assert_eq!(r.late_ticks, 1);
    assert_eq!(r.max_delay_ticks, 8_450.0 / 17_000.0);
    let mut s = summary(1000, 5);
    assert!(super::check(&s, None).is_ok());
    s.output = r;
    let e = super::check(&s, None).unwrap_err().to_string();
    assert!(e.contains("1 of 2 ticks' compares"), "{e}");
    // No measured tick fails too.
    assert!(OutputReport::of(&Trace::default(), &b).failure().is_some());
}

/// The reference's initial local model is the plane the scene runs render (same top, same
/// material), so the PIL's default scene keeps its meaning with the firmware's local model.
#[test]
fn the_firmware_configs_initial_model_is_the_scenes_plane() {
    use crate::sim::closed_loop;
    use crate::sim::scene::Scene;
    use softfinger_core::control::local_model::ModelKind;
    let scene = Scene::load("finger-on-plane").unwrap();
    let contact = closed_loop::contact_params(&scene).unwrap();
    let plane = closed_loop::plane_config(&scene, contact).unwrap();
    let lm = super::reference::firmware_config(plane.timing, contact);
    let m = lm.surface.initial;
    assert_eq!(m.kind, ModelKind::Plane);
    assert_eq!(m.pose.position_m, plane.object_origin_m);
    assert_eq!(m.contact_params(&contact), contact);
    assert_eq!(m.max_age_s, 0.0);
    assert_eq!(lm.surface.watchdog_timeout_s, 0.0);
    assert_eq!(lm.object_origin_m, softfinger_core::Vec3::ZERO);
}

/// The firmware compiles the contact model the default scene names (issue: model no more than a
/// scene needs): the reference's parts are that model's, so a scene file naming another model
/// fails here until the firmware's `TickEnvironment` follows it.
#[test]
fn the_firmware_runs_the_model_the_default_scene_names() {
    use crate::sim::closed_loop;
    use crate::sim::scene::Scene;
    use softfinger_core::contact::Parts;
    use softfinger_core::control::local_model::LocalModelEnvironment;
    fn parts_name<P: Parts>(_: &LocalModelEnvironment<P>) -> &'static str {
        P::NAME
    }
    let scene = Scene::load("finger-on-plane").unwrap();
    let contact = closed_loop::contact_params(&scene).unwrap();
    let plane = closed_loop::plane_config(&scene, contact).unwrap();
    let lm = super::reference::firmware_config(plane.timing, contact);
    assert_eq!(parts_name(&lm.surface), scene.model().unwrap().name());
}

/// The board's late writes are counted from what its pipeline was told: a write ending one count
/// before the first PWM period's end is on time, one ending on it (or an overrun) is late.
#[test]
fn late_writes_are_counted_from_the_first_pwm_period_on() {
    let pwm = 4_250;
    let trace = Trace {
        prev_write_done: vec![0, pwm - 1, pwm, u32::MAX, 3_000],
        ..Trace::default()
    };
    assert_eq!(trace.late_writes_seen(pwm), 2);
    assert_eq!(trace.late_writes_seen(pwm + 1), 1);
}

/// The in-process reference gets the board's timing input: told that every write ended on the
/// first PWM period's last count it runs exactly as told nothing; told that every write ended one
/// count later (late, not an overrun), it holds each direction reversal one more tick and its
/// bridge commands differ (or, holding them every tick, it never finishes homing).
#[test]
fn the_reference_is_told_the_boards_write_times() {
    use super::session::Settings;
    use crate::sim::closed_loop;
    use crate::sim::scene::Scene;
    let scene = Scene::load("finger-on-plane").unwrap();
    let contact = closed_loop::contact_params(&scene).unwrap();
    let rate_hz: u32 = 2_000;
    let scene = Scene {
        rate_hz: f64::from(rate_hz),
        ..scene
    };
    let plane = closed_loop::plane_config(&scene, contact).unwrap();
    let plant = closed_loop::plant(&scene, &contact).unwrap();
    let s = Settings {
        timing: plane.timing,
        scene_ticks: u64::from(rate_hz),
        fault: Fault::None,
        fault_offset: 0,
        app_session: false,
    };
    let pwm = plane.timing.pwm_period_counts();
    let run = |told: u32| {
        let told = vec![told; 20_000];
        super::reference::run(
            &plant,
            super::reference::firmware_config(plane.timing, contact),
            &s,
            &told,
        )
        .map(|r| r.ticks.iter().map(|t| t.bridges).collect::<Vec<_>>())
    };
    let untold = super::reference::run(
        &plant,
        super::reference::firmware_config(plane.timing, contact),
        &s,
        &[],
    )
    .unwrap();
    let untold: Vec<_> = untold.ticks.iter().map(|t| t.bridges).collect();
    assert_eq!(run(pwm - 1).unwrap(), untold);
    assert!(run(pwm).map_or(true, |late| late != untold));
}
