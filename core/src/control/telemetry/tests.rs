use super::*;
extern crate std;
use std::vec::Vec;

fn selected_ticks(d: &mut Decimator, n: u32) -> impl Iterator<Item = u32> + '_ {
    (1..=n).filter(move |_| d.tick())
}

#[test]
fn decimator_default_rates_log_every_hundredth_tick() {
    // 10 kHz control, 100 Hz log: period 100, ticks 100, 200, ... selected.
    let mut d = Decimator::new(10_000, DEFAULT_LOG_RATE_HZ);
    assert_eq!(d.period(), 100);
    let sel: Vec<u32> = selected_ticks(&mut d, 1000).collect();
    assert_eq!(sel, [100, 200, 300, 400, 500, 600, 700, 800, 900, 1000]);
}

#[test]
fn decimator_count_over_one_second_matches_the_log_rate() {
    for (tick, log) in [
        (10_000, 100),
        (20_000, 100),
        (10_000, 1),
        (20_000, 250),
        (12_000, 7),
    ] {
        let mut d = Decimator::new(tick, log);
        let n = selected_ticks(&mut d, tick).count() as u32;
        // Period = round(tick/log); over `tick` ticks that selects floor(tick / period).
        let period = (tick + log / 2) / log;
        assert_eq!(n, tick / period, "{tick} Hz / {log} Hz");
    }
}

#[test]
fn decimator_rounds_to_the_nearest_period() {
    assert_eq!(Decimator::new(10_000, 300).period(), 33); // 33.33 -> 33
    assert_eq!(Decimator::new(10_000, 600).period(), 17); // 16.67 -> 17
}

#[test]
fn decimator_edge_rates() {
    let mut every = Decimator::new(100, 1_000);
    assert_eq!(every.period(), 1);
    assert!((0..10).all(|_| every.tick()));
    let mut off = Decimator::new(10_000, 0);
    assert!((0..100_000).all(|_| !off.tick()));
    let mut off = Decimator::new(0, 100);
    assert!(!off.tick());
}

#[test]
fn drop_counter_counts_only_failures_and_reports_each_once() {
    let mut c = DropCounter::new();
    for ok in [true, false, false, true, false] {
        c.note(ok);
    }
    assert_eq!(c.total(), 3);
    assert_eq!(c.unreported(), 3, "peeking does not reset");
    assert_eq!(c.take_unreported(), 3);
    assert_eq!(c.take_unreported(), 0);
    c.note(false);
    assert_eq!(c.take_unreported(), 1);
    assert_eq!(c.total(), 4);
}

#[test]
fn offer_reports_each_drop_exactly_once_in_the_next_queued_record() {
    // A queue of capacity 2 that a consumer drains only at chosen moments; each queued item
    // carries the drop count handed to it. Every drop must be reported exactly once.
    let mut queue: Vec<u32> = Vec::new();
    let mut reported: Vec<u32> = Vec::new();
    let mut c = DropCounter::new();
    let mut offered = 0u32;
    for round in 0..50u32 {
        // Offer 1 + round % 5 records, then drain: rounds with 3 or more offers overflow.
        for _ in 0..(1 + round % 5) {
            offered += 1;
            c.offer(|dropped_before| {
                if queue.len() < 2 {
                    queue.push(dropped_before);
                    true
                } else {
                    false
                }
            });
        }
        reported.append(&mut queue);
    }
    let queued = reported.len() as u32;
    assert_eq!(offered - queued, c.total(), "every failed offer is a drop");
    // Drops after the last queued record are still pending, not lost.
    let total_reported: u32 = reported.iter().sum();
    assert_eq!(total_reported + c.unreported(), c.total());
    assert!(c.total() > 0, "the scenario must overflow");
}

#[test]
fn drop_counter_saturates() {
    let mut c = DropCounter {
        total: u32::MAX - 1,
        unreported: u32::MAX - 1,
    };
    c.note(false);
    c.note(false);
    assert_eq!(c.total(), u32::MAX);
    assert_eq!(c.take_unreported(), u32::MAX);
}

#[test]
fn tick_stats_mean_max_and_overruns() {
    let mut s = TickStats::new(1000);
    let costs = [400, 600, 1001, 1200, 500, 2000, 300];
    let over: [bool; 7] = costs.map(|c| s.record(c, false));
    assert_eq!(over, [false, false, true, true, false, true, false]);
    let sum: u32 = costs.iter().sum();
    let summary = s.take_summary(5);
    assert_eq!(
        summary,
        TickSummary {
            ticks: 7,
            mean_cycles: sum / 7, // 6001 / 7 = 857
            max_cycles: 2000,
            overruns: 3,
            longest_overrun_streak: 2,
            dropped_total: 5,
        }
    );
}

#[test]
fn tick_stats_late_flag_counts_as_overrun_within_budget() {
    let mut s = TickStats::new(1000);
    assert!(s.record(10, true));
    assert_eq!(s.streak(), 1);
    assert!(!s.record(10, false));
    assert_eq!(s.streak(), 0);
}

#[test]
fn tick_stats_exactly_the_budget_is_not_an_overrun() {
    let mut s = TickStats::new(1000);
    assert!(!s.record(1000, false));
}

#[test]
fn tick_stats_window_resets_but_streak_carries_over() {
    let mut s = TickStats::new(10);
    s.record(20, false);
    s.record(20, false);
    let first = s.take_summary(0);
    assert_eq!(first.longest_overrun_streak, 2);
    assert_eq!(s.ticks(), 0);
    assert_eq!(s.streak(), 2);
    s.record(20, false);
    assert_eq!(s.streak(), 3);
    let second = s.take_summary(0);
    assert_eq!(second.ticks, 1);
    assert_eq!(second.overruns, 1);
    assert_eq!(second.max_cycles, 20);
    assert_eq!(
        second.longest_overrun_streak, 3,
        "the open streak spans both windows"
    );
}

#[test]
fn tick_stats_empty_window_has_zero_mean() {
    let mut s = TickStats::new(10);
    assert_eq!(s.take_summary(0).mean_cycles, 0);
}

#[test]
fn tick_stats_mean_is_exact_for_a_full_second_of_large_costs() {
    // 20 000 ticks of 4 000 000 000 cycles overflow u32 sums; the u64 accumulator must not.
    let mut s = TickStats::new(u32::MAX);
    for _ in 0..20_000 {
        s.record(4_000_000_000, false);
    }
    assert_eq!(s.take_summary(0).mean_cycles, 4_000_000_000);
}

#[test]
fn record_takes_written_outputs_not_controller_outputs() {
    let input = TickInput {
        counts: [1, 2, 3, 4, 5, 6],
        driver_fault: false,
        overrun: false,
    };
    let output = TickOutput {
        duties: [0.9, -0.9, 0.5],
        enable: true,
        flags: Flags::NONE,
        probe_m: Vec3::new(0.0, 0.0, 0.1),
        force_n: Vec3::new(1.0, 2.0, 3.0),
        tau_n_nm: 0.01,
        state: ContactState::Sliding,
    };
    let r = TelemetryRecord::new(
        7,
        &input,
        &output,
        ([0.0; 3], false, Flags::DRIVER_FAULT),
        1234,
    );
    assert_eq!(r.counts, input.counts);
    assert_eq!(r.force_n, output.force_n);
    assert_eq!(r.probe_m, output.probe_m);
    assert_eq!(r.tau_n_nm, 0.01);
    assert_eq!(r.state, ContactState::Sliding);
    assert_eq!(r.duties, [0.0; 3]);
    assert!(!r.enable);
    assert_eq!(r.flags, Flags::DRIVER_FAULT);
    assert_eq!((r.tick, r.cycles, r.dropped_before), (7, 1234, 0));
}
