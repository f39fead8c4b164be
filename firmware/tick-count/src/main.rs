//! Instructions per control tick of the firmware's app: `src/tick.rs` (read -> `Pipeline::tick`
//! -> write, telemetry, commands, accounting) and the `TIM6_DAC` handler's body, with the STM32
//! board's register accesses reproduced one for one on RAM words (`fake_hw`), on QEMU mps2-an386
//! (Cortex-M4F) with `-icount shift=0`.
//!
//! `cargo run --release` (from this directory) prints one `TICK <phase> <instructions>` line per
//! operating phase, the mean over `N` ticks, and checks the bridge outputs the app wrote in each
//! phase (asleep and off before homing, off when disarmed, driving only when homing or armed, off
//! and asleep at once on nFAULT or a break flag, nFAULT ignored while asleep); it exits with
//! failure if a check fails. The script drives the device through the
//! real command sequence: power-up (Unhomed), Home, homing drive with the arms moving down, the stall at
//! the far stops, the arms moved up the mechanism's range to the reference stops and stalled
//! there, the arms moved to the park angle, Disarmed, Arm (the force ramping in), then the arms
//! moved down until the probe touches the plane, Armed in contact, then pressed on and stroked
//! sideways back and forth until it slides (the dearest contact path), Armed sliding. Between
//! contact and sliding, still pressing: the application session of `scripts/pil --app-session`
//! (`softfinger_app::scripted_app`, 2 s, every tick timed alone), then a host link's local model
//! on every tick (a new pose; a new pose and material) and new contact parameters on every tick,
//! each checked in thread mode as the link task checks it; a model's tick must cost at most 1.2x
//! the ordinary tick measured the same way, or the run fails.
//!
//! Not included (no instructions, or not the app's): exception entry/exit (hardware stacking, 12
//! cycles each way on the M4), wait states.
#![no_std]
#![no_main]

mod fake_hw;

use core::hint::black_box;
use core::sync::atomic::AtomicU32;
use core::sync::atomic::Ordering::Relaxed;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use heapless::spsc::{Consumer, Producer, Queue};
use softfinger_core::contact::state::ContactState;
use softfinger_core::control::local_model::{LocalModelSpec, ModelPose};
use softfinger_core::control::pipeline::{
    CheckedCommand, Command, Mode, PipelineRecord, TimingSummary,
};
use softfinger_core::Vec3;

use softfinger_app::{config, stream, tick};

use fake_hw::{outputs, FakeStm32, Outputs, ENC_CNT, GPIOB_IDR, TIM1_SR, TIM6_CNT};
use softfinger_app::isr_cell::IsrCell;
use softfinger_app::tick::{published_mode, CommandOutcome, ControlLoop, TickQueues, STATUS};

/// Ticks per measurement.
const N: u32 = 1000;
/// Instructions per SysTick count: 25 MHz SysTick, 1 ns per instruction under `-icount shift=0`.
const INSTRUCTIONS_PER_COUNT: u32 = 40;

/// The tick's state stream: as the firmware with the host link's fastest stream (every
/// `STREAM_DIVISOR`-th tick streamed, into a queue drained between measurements).
type StreamTx = Producer<'static, stream::StreamPoint>;

/// The host link's smallest stream divisor at the control rate (its fastest stream, 2 kHz), so a
/// fifth of the measured ticks at 10 kHz are streamed.
const STREAM_DIVISOR: u16 = stream::min_stream_divisor(config::CONTROL_RATE_HZ);

/// Stream points queued between two drains: more than one measurement's (`N / STREAM_DIVISOR`),
/// so every streamed tick queues its point.
const STREAM_QUEUE_LEN: usize = 512;

static CONTROL: IsrCell<ControlLoop<FakeStm32, StreamTx>> = IsrCell::new();

/// No log output: the tick never logs; softfinger-core's `Format` impls need a logger to link.
#[defmt::global_logger]
struct NoLog;
// SAFETY: every method does nothing, which is a valid logger.
unsafe impl defmt::Logger for NoLog {
    fn acquire() {}
    unsafe fn flush() {}
    unsafe fn release() {}
    unsafe fn write(_: &[u8]) {}
}
defmt::timestamp!("{=u8}", 0);

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    hprintln!("panic");
    exit(false)
}

/// The body of `TIM6_DAC` (board/stm32g474.rs), with the fake tick timer.
#[inline(never)]
fn isr() {
    // The thread mode's heartbeat (the board's logger task beats it every 5 ms): without it the
    // tick would stop the outputs (THREAD_STALLED) after 50 ms.
    tick::thread_heartbeat();
    let entry = TIM6_CNT.load(Relaxed) & 0xFFFF;
    // SAFETY: only this function calls `get_mut`, and it never re-enters itself.
    match unsafe { CONTROL.get_mut() } {
        Some(control) => control.run(entry),
        None => TIM6_CNT.store(0, Relaxed),
    }
}

struct Queues {
    /// The operator's end: commands checked where they are given, as the button task checks them.
    commands: Producer<'static, CheckedCommand>,
    /// The host link's end: commands checked where they arrive, as the link task checks them.
    link: Producer<'static, CheckedCommand>,
    outcomes: Consumer<'static, CommandOutcome>,
    records: Consumer<'static, PipelineRecord>,
    summaries: Consumer<'static, TimingSummary>,
    stream: Consumer<'static, stream::StreamPoint>,
    last_record: PipelineRecord,
}

impl Queues {
    /// Empty the output queues (outside the measured loops), keeping the latest record.
    fn drain(&mut self) {
        while self.outcomes.dequeue().is_some() {}
        while self.summaries.dequeue().is_some() {}
        while let Some(r) = self.records.dequeue() {
            self.last_record = r;
        }
        while self.stream.dequeue().is_some() {}
    }
}

fn now() -> u32 {
    SYST::get_current()
}

/// Instructions per iteration of `step(ENC_CNT)` + `isr`, minus the same loop with
/// `step(SCRATCH)` and no `isr` (the same work on counters no tick reads).
fn measure(step: &mut impl FnMut(&[AtomicU32; 6])) -> u32 {
    let t0 = now();
    // `isr` beats the thread mode's heartbeat first (the logger's, on the board): not the tick's
    // cost, so the loop without the tick beats it too.
    for _ in 0..N {
        step(black_box(&ENC_CNT));
        isr();
    }
    let t1 = now();
    for _ in 0..N {
        step(black_box(&SCRATCH));
        tick::thread_heartbeat();
        black_box(());
    }
    let t2 = now();
    let with = t0.wrapping_sub(t1) & 0x00FF_FFFF;
    let without = t1.wrapping_sub(t2) & 0x00FF_FFFF;
    with.saturating_sub(without) * INSTRUCTIONS_PER_COUNT / N
}

fn report(phase: &str, instructions: u32) {
    hprintln!("TICK {} {}", phase, instructions);
}

fn fail(what: &str) -> ! {
    hprintln!("FAILED: {}", what);
    exit(false)
}

/// Run ticks (unmeasured) until `mode` is published, at most `limit` ticks, moving the motors by
/// `step` counts per tick.
fn run_until(q: &mut Queues, mode: Mode, step: i32, limit: u32) {
    for _ in 0..limit {
        move_motors(step);
        isr();
        q.drain();
        if published_mode() == mode {
            return;
        }
    }
    fail("mode not reached");
}

static SCRATCH: [AtomicU32; 6] = [const { AtomicU32::new(0) }; 6];

fn move_motors(step: i32) {
    move_motors_of(&ENC_CNT, step);
}

fn move_motors_of(counters: &[AtomicU32; 6], step: i32) {
    for c in &counters[..3] {
        c.store(c.load(Relaxed).wrapping_add(step as u32), Relaxed);
    }
}

fn command(q: &mut Queues, c: Command) {
    let Ok(c) = c.check() else {
        fail("an operator command was refused by its check")
    };
    if q.commands.enqueue(c).is_err() {
        fail("command queue full");
    }
}

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        fail("peripherals")
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();

    let Ok(pipeline) = tick::TickPipeline::new(config::pipeline_config()) else {
        fail("pipeline configuration")
    };
    let (Some(cq), Some(lq), Some(oq), Some(rq), Some(sq)) = (
        cortex_m::singleton!(: Queue<CheckedCommand, {config::COMMAND_QUEUE_LEN}> = Queue::new()),
        cortex_m::singleton!(: Queue<CheckedCommand, {config::COMMAND_QUEUE_LEN}> = Queue::new()),
        cortex_m::singleton!(: Queue<CommandOutcome, {config::COMMAND_QUEUE_LEN}> = Queue::new()),
        cortex_m::singleton!(: Queue<PipelineRecord, {config::TELEMETRY_QUEUE_LEN}> = Queue::new()),
        cortex_m::singleton!(: Queue<TimingSummary, {config::SUMMARY_QUEUE_LEN}> = Queue::new()),
    ) else {
        fail("queues")
    };
    let (ctx, crx) = cq.split();
    // The host link's queue: the model updates' phases (the operator's commands drive the rest).
    let (ltx, lrx) = lq.split();
    let (otx, orx) = oq.split();
    let (rtx, rrx) = rq.split();
    let (stx, srx) = sq.split();
    let Some(pq) =
        cortex_m::singleton!(: Queue<stream::StreamPoint, STREAM_QUEUE_LEN> = Queue::new())
    else {
        fail("queues")
    };
    let (ptx, prx) = pq.split();
    stream::set_divisor(STREAM_DIVISOR);
    let tick_queues = TickQueues {
        commands: crx,
        link_commands: lrx,
        outcomes: otx,
        records: rtx,
        summaries: stx,
        stream: ptx,
    };
    if CONTROL
        .install(ControlLoop::new(FakeStm32, pipeline, tick_queues))
        .is_err()
    {
        fail("install");
    }
    let mut q = Queues {
        commands: ctx,
        link: ltx,
        outcomes: orx,
        records: rrx,
        summaries: srx,
        stream: prx,
        last_record: PipelineRecord::default(),
    };
    run_phases(&mut q);
    exit(true)
}

/// The measured sequence: each phase reached through the real commands, measured, and its bridge
/// outputs checked.
fn run_phases(q: &mut Queues) {
    // A plausible entry latency on the fake tick timer.
    TIM6_CNT.store(40, Relaxed);
    for c in &ENC_CNT {
        c.store(30_000, Relaxed);
    }
    isr();
    q.drain();
    report("unhomed", measure(&mut |_| {}));
    expect(Mode::Unhomed, OFF, "unhomed: asleep, outputs off");
    // nFAULT asserted while the drivers sleep must not latch.
    nfault(true);
    ticks(q, 100);
    nfault(false);
    expect(Mode::Unhomed, OFF, "nFAULT while asleep: ignored");
    check(
        STATUS.latched.load(Relaxed) == 0,
        "nFAULT while asleep latched a fault",
    );

    command(q, Command::Home);
    run_until(q, Mode::Homing, 0, 2);
    // The nSLEEP edge and the drivers' 2 ms wake time (nFAULT masked, no drive), then the arms
    // move down toward their far stops.
    ticks(q, WAKE_TICKS);
    let o = outputs();
    check(
        o.moe && o.awake && o.compare != [0; 3],
        "homing: driving after the wake",
    );
    report("homing_moving", measure(&mut |c| move_motors_of(c, 3)));
    let o = outputs();
    check(o.moe && o.awake && o.compare != [0; 3], "homing: driving");
    stops(q);
    park(q);
    run_until(q, Mode::Disarmed, 0, 20_000);
    report("disarmed", measure(&mut |_| {}));
    expect(Mode::Disarmed, AWAKE_OFF, "disarmed: awake, outputs off");

    command(q, Command::Arm);
    run_until(q, Mode::Armed, 0, 2);
    report("armed_ramping_free", measure(&mut |_| {}));
    lower_until_contact(q);
    report("armed_contact", measure(&mut |_| {}));
    let o = outputs();
    check(
        o.moe && o.awake && o.compare != [0; 3],
        "armed in contact: driving",
    );
    q.drain();
    print_record("in contact", &q.last_record);
    app_session(q);
    model_updates(q);
    slide(q);
    report(
        "armed_sliding",
        measure(&mut |c| move_sideways_of(c, SLIDE_STEP)),
    );
    q.drain();
    check(
        q.last_record.state == ContactState::Sliding,
        "armed sliding: not sliding at the end of the phase",
    );
    print_record("sliding", &q.last_record);
    fault_checks(q);
}

/// Print the latest telemetry record of a phase.
fn print_record(phase: &str, r: &PipelineRecord) {
    hprintln!(
        "record {}: mode {} state {} force_mn {:?} compare {:?} flags {:#x}",
        phase,
        r.mode.name(),
        r.state as u8,
        r.force_mn,
        r.compare,
        r.flags.0
    );
}

/// Faults while armed: nFAULT low, then a break flag alone (a pulse the pin read missed); each
/// gives Faulted with the drivers asleep and the outputs off at once, and clears to Disarmed.
fn fault_checks(q: &mut Queues) {
    nfault(true);
    ticks(q, 1);
    nfault(false);
    expect(Mode::Faulted, OFF, "nFAULT while armed: faulted at once");
    command(q, Command::ClearFaults);
    // Served at the end of a tick; the next tick wakes the drivers.
    ticks(q, 2);
    expect(Mode::Disarmed, AWAKE_OFF, "cleared: disarmed, never armed");

    ticks(q, WAKE_TICKS);
    // Lift the probe off the plane: Arm is refused while it is inside the surface.
    for _ in 0..200 {
        move_motors(-1);
        isr();
    }
    q.drain();
    command(q, Command::Arm);
    run_until(q, Mode::Armed, 0, 2);
    ticks(q, 100);
    TIM1_SR.store(1 << 7, Relaxed);
    ticks(q, 1);
    expect(
        Mode::Faulted,
        OFF,
        "break flag while armed: faulted at once",
    );
    check(
        TIM1_SR.load(Relaxed) & (1 << 7) == 0,
        "break flag not cleared",
    );
    hprintln!("CHECKS passed");
}

const OFF: Outputs = Outputs {
    moe: false,
    awake: false,
    compare: [0; 3],
};
const AWAKE_OFF: Outputs = Outputs {
    moe: false,
    awake: true,
    compare: [0; 3],
};

fn expect(mode: Mode, out: Outputs, what: &str) {
    check(published_mode() == mode, what);
    check(outputs() == out, what);
}

fn check(ok: bool, what: &str) {
    if !ok {
        hprintln!("outputs {:?}, mode {}", outputs(), published_mode().name());
        fail(what);
    }
}

fn nfault(asserted: bool) {
    GPIOB_IDR.store(if asserted { 0 } else { 1 << 12 }, Relaxed);
}

fn ticks(q: &mut Queues, n: u32) {
    for _ in 0..n {
        isr();
    }
    q.drain();
}

/// Ticks after `Home` (or a cleared fault) for the nSLEEP edge and the drivers' 2 ms wake time at
/// 10 kHz; the last of them drives, so every measured homing tick does.
const WAKE_TICKS: u32 = 21;

/// Hold the arms still for longer than the stall time.
fn stall(q: &mut Queues) {
    let spec = config::DEVICE.homing;
    let stall_ticks = (spec.stall_s * config::CONTROL_RATE_HZ as f32) as u32;
    ticks(q, stall_ticks + 200);
}

/// Homing's two stops: still at the far stops for the stall time, then up the mechanism's range
/// (the device's homing spec: 145°, 19 797 counts) to the reference stops, still again (homing
/// checks the measured range).
fn stops(q: &mut Queues) {
    stall(q);
    let spec = config::DEVICE.homing;
    let rad_per_count = config::DEVICE.params.arm_rad_per_motor_count();
    let mut left =
        -(((spec.stop_angle_rad - spec.far_stop_angle_rad) / rad_per_count).abs() + 0.5) as i32;
    while left != 0 {
        let step = left.clamp(-3, 3);
        move_motors(step);
        left -= step;
        isr();
    }
    q.drain();
    stall(q);
}

/// Move the arms from the stop angle to the park angle (the device's homing spec), where homing
/// ends.
fn park(q: &mut Queues) {
    let spec = config::DEVICE.homing;
    let rad_per_count = config::DEVICE.params.arm_rad_per_motor_count();
    let mut left = ((spec.park_angle_rad - spec.stop_angle_rad) / rad_per_count) as i32;
    while left != 0 {
        let step = left.clamp(-3, 3);
        move_motors(step);
        left -= step;
        isr();
    }
    q.drain();
}

/// Lower the arms until the probe presses the plane (a record shows a force), still armed.
/// The sliding phase's stroke per tick (see [`move_sideways_of`]), faster than the static friction
/// holds the fingertip.
const SLIDE_STEP: i32 = 2;

/// Motor 0 by +2·`step`, motors 1 and 2 by −`step` counts each (the sum kept, so about the same
/// height): the fingertip moves along the plane.
fn move_sideways_of(counters: &[AtomicU32; 6], step: i32) {
    // Back and forth, 400 ticks each way, so the stroke stays on the plane.
    let n = STROKE.fetch_add(1, Relaxed);
    let step = if (n / 400).is_multiple_of(2) {
        step
    } else {
        -step
    };
    counters[0].store(
        counters[0].load(Relaxed).wrapping_add(2 * step as u32),
        Relaxed,
    );
    for c in &counters[1..3] {
        c.store(c.load(Relaxed).wrapping_sub(step as u32), Relaxed);
    }
}

/// Ticks stroked sideways so far (the stroke's direction flips every 400).
static STROKE: AtomicU32 = AtomicU32::new(0);

/// Press on, then stroke sideways until the contact slides (at most 2 000 ticks).
fn slide(q: &mut Queues) {
    for _ in 0..200 {
        move_motors(1);
        isr();
    }
    for _ in 0..20 {
        for _ in 0..100 {
            move_sideways_of(&ENC_CNT, SLIDE_STEP);
            isr();
        }
        q.drain();
        if q.last_record.state == ContactState::Sliding {
            return;
        }
    }
    fail("no sliding reached");
}

fn lower_until_contact(q: &mut Queues) {
    for _ in 0..3_000 {
        // 20 counts per telemetry record (one record per 100 ticks).
        for k in 0..100 {
            if k % 5 == 0 {
                move_motors(1);
            }
            isr();
        }
        q.drain();
        if q.last_record.force_mn != [0; 3] {
            check(published_mode() == Mode::Armed, "left Armed while lowering");
            return;
        }
    }
    fail("no contact reached");
}

/// End the QEMU run with the program's status.
fn exit(ok: bool) -> ! {
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}

/// Instructions of the tick alone, per tick: the SysTick read just before and just after each
/// call, less the same pair of reads around nothing; `before` runs untimed before each tick.
fn measure_each(q: &mut Queues, before: &mut impl FnMut(&mut Queues, u32)) -> u32 {
    let mut overhead = 0u32;
    for _ in 0..N {
        let t0 = now();
        black_box(());
        let t1 = now();
        overhead += t0.wrapping_sub(t1) & 0x00FF_FFFF;
    }
    let mut total = 0u32;
    for k in 0..N {
        before(q, k);
        let t0 = now();
        isr();
        let t1 = now();
        total += t0.wrapping_sub(t1) & 0x00FF_FFFF;
        if k % 64 == 63 {
            q.drain();
        }
    }
    total.saturating_sub(overhead) * INSTRUCTIONS_PER_COUNT / N
}

/// Sequence numbers of the phases' models: after the initial model's 0 and the application
/// session's (one per update, from 1).
static MODEL_SEQ: AtomicU32 = AtomicU32::new(1 << 20);

/// Print `RATIO name a/b` with three decimals.
fn ratio(name: &str, a: u32, b: u32) {
    let b = b.max(1);
    hprintln!("RATIO {} {}.{:03}", name, a / b, (a % b) * 1000 / b);
}

/// The host link's local-model updates while armed in contact, one on every tick, checked
/// where they arrive (thread mode, untimed) and applied by the tick: a new pose (the plane up
/// and down by 10 µm: the surface slews), then a new material as well (its stiffness alternating
/// with 0.8 of it: blended in the one contact model), then new contact parameters (the same
/// stiffness change through `SetContactParams`). Each is reported against the ordinary tick of
/// the same contact, measured the same way; a model's tick must cost at most 1.2x an ordinary
/// one (fails otherwise). The initial plane and parameters are restored at the end.
fn model_updates(q: &mut Queues) {
    let base = config::pipeline_config().contact;
    let plane = |n: u32, dz: f32, stiffness: f32| {
        let material = softfinger_core::contact::params::ContactParams {
            normal_stiffness: stiffness,
            ..base
        };
        let top = config::INITIAL_PLANE_TOP_M + Vec3::new(0.0, 0.0, dz);
        Command::SetLocalModel(LocalModelSpec::plane(n, ModelPose::at(top), &material))
    };
    let submit = |q: &mut Queues, c: Command| {
        let Ok(c) = c.check() else {
            fail("a phase's command was refused by its check")
        };
        if q.link.enqueue(c).is_err() {
            fail("link queue full");
        }
    };
    let ordinary = measure_each(q, &mut |_, _| {});
    report("armed_contact_each", ordinary);
    let k = base.normal_stiffness;
    let pose = measure_each(q, &mut |q, i| {
        let n = MODEL_SEQ.fetch_add(1, Relaxed);
        submit(q, plane(n, (i % 2) as f32 * 1e-5, k));
    });
    report("armed_model_pose", pose);
    let material = measure_each(q, &mut |q, i| {
        let n = MODEL_SEQ.fetch_add(1, Relaxed);
        let s = if i % 2 == 0 { 0.8 * k } else { k };
        submit(q, plane(n, (i % 2) as f32 * 1e-5, s));
    });
    report("armed_model_material", material);
    let params = measure_each(q, &mut |q, i| {
        let s = if i % 2 == 0 { 0.8 * k } else { k };
        let p = softfinger_core::contact::params::ContactParams {
            normal_stiffness: s,
            ..base
        };
        submit(q, Command::SetContactParams(p));
    });
    report("armed_contact_params", params);
    let worst = pose.max(material);
    ratio("model_update", worst, ordinary);
    ratio("contact_params", params, ordinary);
    check(
        worst * 10 <= ordinary * 12,
        "a tick applying a local model costs more than 1.2x an ordinary one",
    );
    let n = MODEL_SEQ.fetch_add(1, Relaxed);
    submit(q, Command::SetContactParams(base));
    submit(q, plane(n, 0.0, k));
    ticks(q, 100);
    check(
        published_mode() == Mode::Armed,
        "left Armed applying models",
    );
}

/// The scripted application session of `scripts/pil --app-session`
/// (`softfinger_app::scripted_app`: a local model every 1 ms, contact parameters every 100 ms)
/// for 2 s against the held probe: every tick timed alone (to the SysTick's 40 instructions);
/// the longest, the longest of the ticks that applied nothing, and the update of the longest.
fn app_session(q: &mut Queues) {
    use softfinger_app::scripted_app::ScriptedApp;
    let mut app = ScriptedApp::new(config::pipeline_config().contact);
    let period = ScriptedApp::update_period_ticks(config::CONTROL_RATE_HZ);
    let mut worst = (0u32, 0u32, false);
    let mut ordinary_worst = 0u32;
    for k in 0..20_000u32 {
        let applies = k % period == 0;
        if applies {
            let Ok(c) = app.next_command().check() else {
                fail("a session command was refused by its check")
            };
            let _ = q.link.enqueue(c);
        }
        let t0 = now();
        isr();
        let t1 = now();
        let n = (t0.wrapping_sub(t1) & 0x00FF_FFFF) * INSTRUCTIONS_PER_COUNT;
        if n > worst.0 {
            worst = (n, k, applies);
        }
        if !applies {
            ordinary_worst = ordinary_worst.max(n);
        }
        if k % 64 == 63 {
            q.drain();
        }
    }
    report("session_longest", worst.0);
    report("session_longest_applying_nothing", ordinary_worst);
    hprintln!(
        "session: the longest tick is tick {} of {} ({})",
        worst.1,
        20_000,
        if worst.2 {
            "it applied an update"
        } else {
            "it applied nothing"
        }
    );
    check(published_mode() == Mode::Armed, "left Armed in the session");
}
