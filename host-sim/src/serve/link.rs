//! One TCP connection of the virtual device: a reader thread that hands the bytes it receives to
//! the device loop, and a writer thread that sends what the device queued.
//!
//! The device loop decodes them with the connection's `softfinger_protocol::DeviceEndpoint`: a bad
//! frame is counted there (per kind) and answered with `DeviceMsg::FrameError`; the connection
//! goes on. The outgoing queue is bounded: a client that stops reading loses state samples
//! (counted by the endpoint), never stalls the device loop. State samples may fill only
//! [`OUT_QUEUE_STATES`] of it, so replies always find room.

use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::mpsc::{sync_channel, Receiver, Sender, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread;

/// State samples a connection may have queued for sending before new ones are dropped (0.5 s of
/// a 1 kHz stream, 51 ms of a 10 kHz one).
pub const OUT_QUEUE_STATES: usize = 512;
/// Room kept for replies and frame-error answers on top of the samples.
pub const OUT_QUEUE_REPLIES: usize = 512;

/// What the connections tell the device loop.
#[derive(Debug)]
pub enum Event {
    /// A client connected; send to it through `out`.
    Connected { id: u32, out: Outbox },
    /// A client sent these bytes (any number of frames, or parts of them).
    Bytes { id: u32, bytes: Vec<u8> },
    /// A client went away.
    Disconnected { id: u32 },
}

/// The sending side of one connection's bounded queue.
#[derive(Clone, Debug)]
pub struct Outbox {
    tx: SyncSender<Outgoing>,
    /// State samples queued and not yet written.
    queued_states: Arc<AtomicUsize>,
}

impl Outbox {
    /// Queue one encoded frame (`is_state`: a state sample, which may fill only
    /// [`OUT_QUEUE_STATES`] of the queue); false when the queue is full or the client gone. The
    /// endpoint that encoded it counts it sent or dropped.
    pub fn push(&self, frame: &[u8], is_state: bool) -> bool {
        if is_state && self.queued_states.load(Relaxed) >= OUT_QUEUE_STATES {
            return false;
        }
        let item = Outgoing {
            frame: frame.to_vec(),
            is_state,
        };
        // Counted before it is queued: the writer may take it (and count it out) at once.
        if is_state {
            self.queued_states.fetch_add(1, Relaxed);
        }
        match self.tx.try_send(item) {
            Ok(()) => true,
            Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => {
                if is_state {
                    self.queued_states.fetch_sub(1, Relaxed);
                }
                false
            }
        }
    }
}

/// One frame waiting to be written.
#[derive(Debug)]
struct Outgoing {
    frame: Vec<u8>,
    is_state: bool,
}

/// Serve one accepted connection: spawns its writer, then reads until the client goes away.
pub fn serve_connection(stream: TcpStream, id: u32, events: Sender<Event>) {
    let _ = stream.set_nodelay(true);
    let Ok(write_half) = stream.try_clone() else {
        return;
    };
    let (tx, rx) = sync_channel(OUT_QUEUE_STATES + OUT_QUEUE_REPLIES);
    let queued_states = Arc::new(AtomicUsize::new(0));
    let out = Outbox {
        tx,
        queued_states: queued_states.clone(),
    };
    let writer = thread::spawn(move || write_loop(write_half, rx, &queued_states));
    if events.send(Event::Connected { id, out }).is_ok() {
        read_loop(&stream, id, &events);
    }
    let _ = events.send(Event::Disconnected { id });
    let _ = stream.shutdown(Shutdown::Both);
    let _ = writer.join();
}

fn write_loop(mut stream: TcpStream, rx: Receiver<Outgoing>, queued_states: &AtomicUsize) {
    while let Ok(item) = rx.recv() {
        if item.is_state {
            queued_states.fetch_sub(1, Relaxed);
        }
        if stream.write_all(&item.frame).is_err() {
            break;
        }
    }
    let _ = stream.shutdown(Shutdown::Both);
}

fn read_loop(mut stream: &TcpStream, id: u32, events: &Sender<Event>) {
    let mut buf = [0u8; 4096];
    loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        let bytes = buf[..n].to_vec();
        if events.send(Event::Bytes { id, bytes }).is_err() {
            return;
        }
    }
}
