//! Requests waiting for the tick: a command goes through the tick's command queue and its outcome
//! comes back through the outcome queue, in order, by its key (`CommandKey`: the tick does not
//! copy the command back). The link keeps the sequence numbers and commands it queued, oldest
//! first, and answers each when the tick reports that command's outcome.
//!
//! The tick's outcome queue also carries commands from elsewhere (the operator's button on the
//! STM32, the plant's operator on the emulated board): those answer nothing.

use heapless::Deque;
use softfinger_core::control::pipeline::{Command, CommandError, CommandKey};
use softfinger_protocol::AckResult;

/// Commands the link may have in flight (the tick's command queue holds as many).
pub const MAX_PENDING: usize = 4;

/// Sequence numbers of queued commands, oldest first.
#[derive(Debug, Default)]
pub struct PendingAcks {
    waiting: Deque<(u16, Command), MAX_PENDING>,
}

impl PendingAcks {
    /// None waiting.
    pub const fn new() -> Self {
        PendingAcks {
            waiting: Deque::new(),
        }
    }

    /// Room for one more (else the request is answered `Busy` and not queued).
    pub fn has_room(&self) -> bool {
        !self.waiting.is_full()
    }

    /// Remember that `command` of request `seq` was queued. False (nothing remembered) when full.
    pub fn push(&mut self, seq: u16, command: Command) -> bool {
        self.waiting.push_back((seq, command)).is_ok()
    }

    /// The tick applied (or refused) the link's command of key `key`: the request it answers
    /// (its sequence number and command), with its result, if it is the oldest waiting one.
    pub fn resolve(
        &mut self,
        key: CommandKey,
        result: Result<(), CommandError>,
    ) -> Option<(u16, Command, AckResult)> {
        match self.waiting.front() {
            Some((_, c)) if c.key() == key => {
                let (seq, command) = self.waiting.pop_front()?;
                Some((seq, command, AckResult::from(result)))
            }
            _ => None,
        }
    }

    /// Requests waiting.
    pub fn len(&self) -> usize {
        self.waiting.len()
    }

    /// None waiting.
    pub fn is_empty(&self) -> bool {
        self.waiting.is_empty()
    }
}
