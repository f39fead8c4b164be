//! The control tick, board-independent: read the hardware -> [`Pipeline::tick_outputs`] -> write
//! the hardware, then [`Pipeline::tick_telemetry`], operator commands, the host link's stream and
//! the tick's own cost. Called by the board's
//! tick interrupt, which runs at the highest priority and owns a [`ControlLoop`] through
//! `isr_cell::IsrCell`.
//!
//! The tick shares nothing with tasks except through atomics ([`STATUS`], [`LINK_ACTIVITY`]) and
//! lock-free SPSC queues (commands in; outcomes, telemetry and summaries out), so it never waits
//! for a task, and a task never delays it (see `critical_section_basepri`).
//!
//! With a host link the pipeline renders the application's local model (`config::TickEnvironment`); the
//! link reports every valid frame it receives through [`note_link_activity`], which the tick
//! passes on to the pipeline's communication watchdog at its next boundary.

use core::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering};

use heapless::spsc::{Consumer, Producer};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::pipeline::liveness::{ThreadWatch, THREAD_STALE_S};
use softfinger_core::control::pipeline::{
    CheckedCommand, CommandError, CommandKey, Mode, Pipeline, PipelineOutput, PipelineRecord,
    RawInput, TimingSummary,
};
use softfinger_core::Fast;

use softfinger_protocol::RenderedTick;

use crate::board::{CommandSource, ControlHw};
use crate::stream::{StreamPoint, StreamSink, StreamTap};

/// The pipeline the tick runs: the tick's fast math, the configuration's scene (the application's
/// local model with a host link, the fixed plane without).
pub type TickPipeline = Pipeline<Fast, crate::config::TickEnvironment>;

/// Set by a host link for every valid frame it receives; taken (cleared) by the tick, which then
/// feeds the pipeline's communication watchdog. A flag, not a counter: the watchdog needs to know
/// only that something arrived since the last tick.
pub static LINK_ACTIVITY: AtomicBool = AtomicBool::new(false);

/// A valid frame arrived on a host link (any task; never waits).
pub fn note_link_activity() {
    LINK_ACTIVITY.store(true, Ordering::Relaxed);
}

/// Set by a host link's transport when the link is lost (USB bus reset, suspend, DTR dropped,
/// writes the host does not take for the transport's stated time); taken by the tick, which then
/// applies `Pipeline::link_lost` (a host-armed device fades to zero within 20 ms and latches
/// `COMM_TIMEOUT` until re-armed).
pub static LINK_LOST: AtomicBool = AtomicBool::new(false);

/// The host link was lost (any task; never waits).
pub fn note_link_lost() {
    LINK_LOST.store(true, Ordering::Relaxed);
}

/// Bumped by a thread-mode task (the logger, every `config::LOGGER_POLL_MS`): the tick feeds the
/// independent watchdog only while it moves (softfinger-core's `liveness::ThreadWatch`), so a
/// hung executor or task stops the outputs (`THREAD_STALLED`) and the watchdog resets the MCU.
pub static THREAD_HEARTBEAT: AtomicU32 = AtomicU32::new(0);

/// Thread mode is alive (call from a task's loop; never waits).
pub fn thread_heartbeat() {
    THREAD_HEARTBEAT.fetch_add(1, Ordering::Relaxed);
}

/// What the tick applied, by its key (a command is 92 bytes, and a copy of it costs the tick about
/// 90 instructions), except an operator's contact parameters (a button preset, rare), whole: the
/// host link learns the parameters in force from them.
#[derive(Clone, Copy, Debug)]
pub enum Applied {
    /// From the operator.
    Operator(CommandKey),
    /// The operator's contact parameters.
    OperatorParams(ContactParams),
    /// From a host application.
    Link(CommandKey),
}

impl Applied {
    /// What the tick reports of `command` from `from`.
    #[inline(always)]
    pub fn of(from: CommandSource, command: &CheckedCommand) -> Applied {
        match (from, command) {
            (CommandSource::Operator, CheckedCommand::SetContactParams(p)) => {
                Applied::OperatorParams(**p)
            }
            (CommandSource::Operator, c) => Applied::Operator(c.key()),
            (CommandSource::Host, c) => Applied::Link(c.key()),
        }
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Applied {
    fn format(&self, f: defmt::Formatter) {
        match self {
            Applied::Operator(k) => defmt::write!(f, "{}", k),
            Applied::OperatorParams(p) => defmt::write!(f, "SetContactParams({})", p),
            Applied::Link(k) => defmt::write!(f, "host {}", k),
        }
    }
}

/// A command and what the pipeline made of it, for the log and the host link's acknowledgement.
#[derive(Clone, Copy, Debug)]
pub struct CommandOutcome {
    pub command: Applied,
    pub result: Result<(), CommandError>,
}

/// What the tick publishes for the tasks, one atomic per field (written by the tick only, except
/// `max_tick_counts`, which the logger resets).
pub struct TickStatus {
    /// `Mode::code()` after the last tick.
    pub mode: AtomicU8,
    /// Latched faults (`Flags` bits) after the last tick.
    pub latched: AtomicU32,
    /// Longest whole tick (timer event -> end of the tick, telemetry and commands included) since
    /// the logger last took it, timer counts.
    pub max_tick_counts: AtomicU32,
}

/// The mode published in [`TickStatus::mode`].
pub fn published_mode() -> Mode {
    match STATUS.mode.load(Ordering::Relaxed) {
        0 => Mode::Unhomed,
        1 => Mode::Homing,
        2 => Mode::Disarmed,
        3 => Mode::Armed,
        _ => Mode::Faulted,
    }
}

/// The tick's published status.
pub static STATUS: TickStatus = TickStatus {
    mode: AtomicU8::new(0),
    latched: AtomicU32::new(0),
    max_tick_counts: AtomicU32::new(0),
};

/// The queue ends the tick holds; `K`: where the host link's state stream goes
/// ([`crate::stream::NoStream`] without a link).
pub struct TickQueues<K: StreamSink> {
    /// From the operator, checked where they were given (`Pipeline::apply`).
    pub commands: Consumer<'static, CheckedCommand>,
    /// From the host link, checked where they arrived (`Pipeline::link_apply`).
    pub link_commands: Consumer<'static, CheckedCommand>,
    pub outcomes: Producer<'static, CommandOutcome>,
    pub records: Producer<'static, PipelineRecord>,
    pub summaries: Producer<'static, TimingSummary>,
    pub stream: K,
}

/// Everything one tick reads and writes.
pub struct ControlLoop<H: ControlHw, K: StreamSink> {
    hw: H,
    pipeline: TickPipeline,
    queues: TickQueues<K>,
    /// Timer counts from the previous tick's event to the end of its hardware writes
    /// (`u32::MAX`: they ended after the next event).
    prev_write_done: u32,
    stream: StreamTap,
    /// The thread mode's heartbeat as the tick sees it.
    thread: ThreadWatch,
}

impl<H: ControlHw, K: StreamSink> ControlLoop<H, K> {
    /// The loop, ready for its first tick.
    pub fn new(hw: H, pipeline: TickPipeline, queues: TickQueues<K>) -> Self {
        let rate_hz = pipeline.config().timing.control_hz as f32;
        ControlLoop {
            thread: ThreadWatch::new(THREAD_STALE_S, rate_hz),
            hw,
            pipeline,
            queues,
            prev_write_done: 0,
            stream: StreamTap::default(),
        }
    }

    /// The hardware, for the board's start-up code.
    pub fn hw_mut(&mut self) -> &mut H {
        &mut self.hw
    }

    /// One control tick. `entry_count` is the tick timer's count read as the interrupt's first
    /// action: the start latency, in timer counts. Never blocks, never panics.
    #[inline(always)]
    pub fn run(&mut self, entry_count: u32) {
        // Sample first: the sample-to-output delay runs from here to the PWM period boundary
        // after the compare writes below (`softfinger_core::control::pipeline::output_timing`).
        let sample = self.hw.read_inputs();
        self.hw.ack_tick();
        let raw = RawInput {
            counts: sample.counts,
            driver_fault: sample.driver_fault,
            start_latency_counts: entry_count,
            prev_write_done_counts: self.prev_write_done,
        };
        // Thread mode hung: this tick's outputs already go to zero torque (THREAD_STALLED), and
        // the watchdog is no longer fed below.
        let thread_alive = self.thread.tick(THREAD_HEARTBEAT.load(Ordering::Relaxed));
        if !thread_alive {
            self.pipeline.thread_stalled();
        }
        let mut out = self.pipeline.tick_outputs(&raw);
        // The compares right after the pipeline's outputs, before anything else (its telemetry
        // included): written within the tick's first PWM period, they act from its second.
        self.hw.write_bridges(&out.bridges);
        // Count first, then the flag: an event between the two reads reports "late", never a
        // wrapped small count.
        let done = self.hw.tick_timer_count();
        self.prev_write_done = if self.hw.tick_event_pending() {
            u32::MAX
        } else {
            done
        };
        self.hw.prev_write_done(self.prev_write_done);
        if thread_alive {
            self.hw.pet_watchdog();
        }
        self.pipeline.tick_telemetry(&mut out, &raw);

        STATUS.mode.store(out.mode.code(), Ordering::Relaxed);
        STATUS.latched.store(out.latched.0, Ordering::Relaxed);
        if let Some(record) = out.telemetry {
            let queued = self.queues.records.enqueue(record).is_ok();
            self.pipeline.telemetry_sent(queued);
        }
        if let Some(summary) = out.summary {
            // A lost summary (logger stalled for seconds) is not worth more than its absence.
            let _ = self.queues.summaries.enqueue(summary);
        }
        self.serve_commands();
        if K::ENABLED {
            self.stream_out(&out);
        }
        self.account();
    }

    /// On a streamed tick, what the pipeline rendered, for the host link.
    fn stream_out(&mut self, out: &PipelineOutput) {
        if !self.stream.due() {
            return;
        }
        let mut point = StreamPoint {
            rendered: RenderedTick::of(&self.pipeline, out),
            ..StreamPoint::default()
        };
        self.stream.stamp(&mut point);
        // A full queue loses the point; the link counts the gap.
        let _ = self.queues.stream.push(point);
    }

    /// Feed the communication watchdog if a link saw a valid frame, then apply the commands
    /// waiting: the operator's queue, the board's sampled command, the host link's queue (at the
    /// tick boundary: they act from the next tick).
    fn serve_commands(&mut self) {
        // Load, then clear only if set: the tick preempts every task, so no store of a task can
        // fall between the two (and the common case, nothing new, writes nothing).
        if LINK_ACTIVITY.load(Ordering::Relaxed) {
            LINK_ACTIVITY.store(false, Ordering::Relaxed);
            self.pipeline.note_link_activity();
        }
        if LINK_LOST.load(Ordering::Relaxed) {
            LINK_LOST.store(false, Ordering::Relaxed);
            self.pipeline.link_lost();
        }
        // Each applied where it waits, by reference, then dropped: a command is 92 bytes, and
        // every copy of it costs about 90 instructions.
        let (pipeline, outcomes) = (&mut self.pipeline, &mut self.queues.outcomes);
        while let Some(command) = self.queues.commands.peek() {
            apply_and_report(pipeline, outcomes, CommandSource::Operator, command);
            let _ = self.queues.commands.dequeue();
        }
        if let Some((from, command)) = self.hw.sampled_command() {
            apply_and_report(pipeline, outcomes, from, command);
            self.hw.sampled_command_done();
        }
        while let Some(command) = self.queues.link_commands.peek() {
            apply_and_report(pipeline, outcomes, CommandSource::Host, command);
            let _ = self.queues.link_commands.dequeue();
        }
    }

    /// The whole tick's cost, from the timer event to here.
    fn account(&mut self) {
        let now = self.hw.tick_timer_count();
        let overrun = self.hw.tick_event_pending();
        let end = if overrun {
            now + self.hw.tick_period_counts()
        } else {
            now
        };
        STATUS.max_tick_counts.fetch_max(end, Ordering::Relaxed);
        if K::ENABLED {
            self.stream.account(end, overrun);
        }
    }
}

/// Apply `command` by `from`'s rules (`Pipeline::apply` for the operator, `Pipeline::link_apply`
/// for a host) and queue its outcome for the log and the link.
#[inline(always)]
fn apply_and_report(
    pipeline: &mut TickPipeline,
    outcomes: &mut Producer<'static, CommandOutcome>,
    from: CommandSource,
    command: &CheckedCommand,
) {
    let result = match from {
        CommandSource::Operator => pipeline.apply(command),
        CommandSource::Host => pipeline.link_apply(command),
    };
    // Outcomes are for the log only; a full queue loses the report, not the command.
    let _ = outcomes.enqueue(CommandOutcome {
        command: Applied::of(from, command),
        result,
    });
}
