//! The link task: moves bytes between a transport and a [`LinkSession`], the tick's command
//! outcomes and stream points into it, its commands into the tick's queue. Runs at the lowest
//! priority, polls, never waits for the tick and never makes the tick wait.

use embassy_time::Timer;
use heapless::spsc::Consumer;

use super::session::{CommandSink, LinkSession};
use crate::persist::Persistence;
use crate::stream::{self, StreamPoint};
use crate::tick::CommandOutcome;

/// A byte-at-a-time transport that never blocks (a UART's holding registers).
pub trait ByteTransport {
    /// The next received byte, if one is there.
    fn read_byte(&mut self) -> Option<u8>;
    /// Send `byte` if the transmitter takes it now (false: try again later).
    fn write_byte(&mut self, byte: u8) -> bool;
}

/// Bytes taken from the transport per poll, at most (the rest wait in the transport).
const RX_PER_POLL: usize = 512;

/// The queue ends the link task holds (the command queue's end is separate: the link may share
/// it with the operator).
pub struct LinkQueues {
    /// The tick's command outcomes.
    pub outcomes: Consumer<'static, CommandOutcome>,
    /// The tick's stream points.
    pub stream: Consumer<'static, StreamPoint>,
}

impl LinkQueues {
    /// Hand the tick's outcomes and stream points to `session`, and its stream divisor to the
    /// tick.
    pub fn forward_news<const TX: usize, S: Persistence>(
        &mut self,
        session: &mut LinkSession<TX, S>,
    ) {
        stream::set_divisor(session.stream_divisor());
        while let Some(o) = self.outcomes.dequeue() {
            session.outcome(&o.command, o.result);
        }
        while let Some(p) = self.stream.dequeue() {
            session.stream(&p);
        }
    }
}

/// One poll: receive, then the tick's news, then send what fits.
pub fn poll<const TX: usize, S: Persistence>(
    transport: &mut impl ByteTransport,
    session: &mut LinkSession<TX, S>,
    commands: &mut impl CommandSink,
    q: &mut LinkQueues,
) {
    for _ in 0..RX_PER_POLL {
        let Some(b) = transport.read_byte() else {
            break;
        };
        if session.receive(b, commands) {
            crate::tick::note_link_activity();
        }
    }
    q.forward_news(session);
    let tx = session.tx();
    while let Some(b) = tx.peek() {
        if !transport.write_byte(b) {
            break;
        }
        let _ = tx.pop();
    }
}

/// Poll every `period_us` forever.
pub async fn run<const TX: usize, S: Persistence>(
    mut transport: impl ByteTransport,
    mut session: LinkSession<TX, S>,
    mut commands: impl CommandSink,
    mut q: LinkQueues,
    period_us: u64,
) -> ! {
    loop {
        poll(&mut transport, &mut session, &mut commands, &mut q);
        Timer::after_micros(period_us).await;
    }
}
