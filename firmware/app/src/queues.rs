//! The queues between the control tick and the low-priority tasks: five statics, created once at
//! start-up and split into the tick's ends and the tasks' ends (the same on every board).

use heapless::spsc::{Consumer, Producer, Queue};
use softfinger_core::control::pipeline::{CheckedCommand, PipelineRecord, TimingSummary};

use crate::config;
use crate::stream::StreamSink;
use crate::tick::{CommandOutcome, TickQueues};

/// The tick's ends of the queues, all but the state stream's (the board's to choose).
pub struct TickEnds {
    commands: Consumer<'static, CheckedCommand>,
    link_commands: Consumer<'static, CheckedCommand>,
    outcomes: Producer<'static, CommandOutcome>,
    records: Producer<'static, PipelineRecord>,
    summaries: Producer<'static, TimingSummary>,
}

impl TickEnds {
    /// The tick's queues, its stream going to `stream`.
    pub fn with_stream<K: StreamSink>(self, stream: K) -> TickQueues<K> {
        TickQueues {
            commands: self.commands,
            link_commands: self.link_commands,
            outcomes: self.outcomes,
            records: self.records,
            summaries: self.summaries,
            stream,
        }
    }
}

/// The tasks' ends of the queues.
pub struct TaskEnds {
    /// Commands to the tick from the operator (the button), checked where they were given
    /// (`Command::check`).
    pub commands: Producer<'static, CheckedCommand>,
    /// Commands to the tick from the host link, checked where they arrived (`Command::check`;
    /// `Pipeline::link_apply`'s rules apply).
    pub link_commands: Producer<'static, CheckedCommand>,
    /// The tick's outcome of each command (the supervisor).
    pub outcomes: Consumer<'static, CommandOutcome>,
    /// Decimated telemetry records (the logger).
    pub records: Consumer<'static, PipelineRecord>,
    /// Once-a-second timing summaries (the logger).
    pub summaries: Consumer<'static, TimingSummary>,
}

/// The queues, created and split; `None` on a second call (each is a `cortex_m::singleton!`).
pub fn take() -> Option<(TickEnds, TaskEnds)> {
    let commands =
        cortex_m::singleton!(: Queue<CheckedCommand, {config::COMMAND_QUEUE_LEN}> = Queue::new())?;
    let link_commands =
        cortex_m::singleton!(: Queue<CheckedCommand, {config::COMMAND_QUEUE_LEN}> = Queue::new())?;
    let outcomes =
        cortex_m::singleton!(: Queue<CommandOutcome, {config::COMMAND_QUEUE_LEN}> = Queue::new())?;
    let records = cortex_m::singleton!(: Queue<PipelineRecord, {config::TELEMETRY_QUEUE_LEN}> = Queue::new())?;
    let summaries =
        cortex_m::singleton!(: Queue<TimingSummary, {config::SUMMARY_QUEUE_LEN}> = Queue::new())?;
    let (command_tx, command_rx) = commands.split();
    let (link_command_tx, link_command_rx) = link_commands.split();
    let (outcome_tx, outcome_rx) = outcomes.split();
    let (record_tx, record_rx) = records.split();
    let (summary_tx, summary_rx) = summaries.split();
    let tick = TickEnds {
        commands: command_rx,
        link_commands: link_command_rx,
        outcomes: outcome_tx,
        records: record_tx,
        summaries: summary_tx,
    };
    let tasks = TaskEnds {
        commands: command_tx,
        link_commands: link_command_tx,
        outcomes: outcome_rx,
        records: record_rx,
        summaries: summary_rx,
    };
    Some((tick, tasks))
}
