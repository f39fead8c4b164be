//! One TCP connection of the virtual device: a reader thread that decodes frames and hands
//! messages to the device loop, and a writer thread that sends what the device queued.
//!
//! A bad frame is counted (per kind, over all connections) and answered with
//! [`DeviceMsg::FrameError`]; the connection goes on. The outgoing queue is bounded: a client
//! that stops reading loses state samples (counted), never stalls the device loop. State samples
//! may fill only [`OUT_QUEUE_STATES`] of it, so replies always find room.

use softfinger_protocol::{
    encode_frame, DeviceMsg, FrameDecoder, FrameErrorKind, HostMsg, LinkCounters, MAX_FRAME_LEN,
    PROTOCOL_VERSION,
};
use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering::Relaxed};
use std::sync::mpsc::{sync_channel, Receiver, Sender, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread;

/// State samples a connection may have queued for sending before new ones are dropped (0.5 s of
/// a 1 kHz stream, 51 ms of a 10 kHz one).
pub const OUT_QUEUE_STATES: usize = 512;
/// Room kept for replies and frame-error answers on top of the samples.
pub const OUT_QUEUE_REPLIES: usize = 512;

/// Link counters over all connections, shared by the threads.
#[derive(Debug, Default)]
pub struct LinkStats {
    rx_frames: AtomicU32,
    rx_cobs: AtomicU32,
    rx_crc: AtomicU32,
    rx_version: AtomicU32,
    rx_decode: AtomicU32,
    rx_oversized: AtomicU32,
    tx_frames: AtomicU32,
    tx_dropped: AtomicU32,
    connections: AtomicU32,
}

impl LinkStats {
    /// The counters now.
    pub fn snapshot(&self) -> LinkCounters {
        let g = |a: &AtomicU32| a.load(Relaxed);
        let (cobs, crc, version, decode, oversized) = (
            g(&self.rx_cobs),
            g(&self.rx_crc),
            g(&self.rx_version),
            g(&self.rx_decode),
            g(&self.rx_oversized),
        );
        LinkCounters {
            rx_frames: g(&self.rx_frames),
            rx_errors: cobs + crc + version + decode + oversized,
            rx_cobs: cobs,
            rx_crc: crc,
            rx_version: version,
            rx_decode: decode,
            rx_oversized: oversized,
            tx_frames: g(&self.tx_frames),
            tx_dropped: g(&self.tx_dropped),
            connections: g(&self.connections).min(u16::MAX as u32) as u16,
        }
    }

    fn count_error(&self, kind: FrameErrorKind) {
        let c = match kind {
            FrameErrorKind::Cobs => &self.rx_cobs,
            FrameErrorKind::Crc => &self.rx_crc,
            FrameErrorKind::Version => &self.rx_version,
            FrameErrorKind::Decode => &self.rx_decode,
            FrameErrorKind::Oversized => &self.rx_oversized,
        };
        c.fetch_add(1, Relaxed);
    }
}

/// What the connections tell the device loop.
#[derive(Debug)]
pub enum Event {
    /// A client connected; send to it through `out`.
    Connected { id: u32, out: Outbox },
    /// A client sent a valid message.
    Message { id: u32, msg: HostMsg },
    /// A client went away.
    Disconnected { id: u32 },
}

/// The sending side of one connection's bounded queue.
#[derive(Clone, Debug)]
pub struct Outbox {
    tx: SyncSender<Outgoing>,
    /// State samples queued and not yet written.
    queued_states: Arc<AtomicUsize>,
    stats: Arc<LinkStats>,
}

impl Outbox {
    /// Queue `msg`; false (and counted as dropped) when the queue is full or the client gone.
    pub fn send(&self, msg: &DeviceMsg) -> bool {
        let is_state = matches!(msg, DeviceMsg::State(_));
        if is_state && self.queued_states.load(Relaxed) >= OUT_QUEUE_STATES {
            self.stats.tx_dropped.fetch_add(1, Relaxed);
            return false;
        }
        let mut buf = [0u8; MAX_FRAME_LEN];
        let Ok(n) = encode_frame(msg, &mut buf) else {
            self.stats.tx_dropped.fetch_add(1, Relaxed);
            return false;
        };
        let item = Outgoing {
            frame: buf[..n].to_vec(),
            is_state,
        };
        // Counted before it is queued: the writer may take it (and count it out) at once.
        if is_state {
            self.queued_states.fetch_add(1, Relaxed);
        }
        match self.tx.try_send(item) {
            Ok(()) => {
                self.stats.tx_frames.fetch_add(1, Relaxed);
                true
            }
            Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => {
                if is_state {
                    self.queued_states.fetch_sub(1, Relaxed);
                }
                self.stats.tx_dropped.fetch_add(1, Relaxed);
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
pub fn serve_connection(stream: TcpStream, id: u32, events: Sender<Event>, stats: Arc<LinkStats>) {
    let _ = stream.set_nodelay(true);
    let Ok(write_half) = stream.try_clone() else {
        return;
    };
    let (tx, rx) = sync_channel(OUT_QUEUE_STATES + OUT_QUEUE_REPLIES);
    let queued_states = Arc::new(AtomicUsize::new(0));
    let out = Outbox {
        tx,
        queued_states: queued_states.clone(),
        stats: stats.clone(),
    };
    stats.connections.fetch_add(1, Relaxed);
    let writer = thread::spawn(move || write_loop(write_half, rx, &queued_states));
    if events
        .send(Event::Connected {
            id,
            out: out.clone(),
        })
        .is_ok()
    {
        read_loop(&stream, id, &events, &stats, &out);
    }
    let _ = events.send(Event::Disconnected { id });
    drop(out);
    let _ = stream.shutdown(Shutdown::Both);
    let _ = writer.join();
    stats.connections.fetch_sub(1, Relaxed);
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

fn read_loop(
    mut stream: &TcpStream,
    id: u32,
    events: &Sender<Event>,
    stats: &LinkStats,
    out: &Outbox,
) {
    let mut decoder = FrameDecoder::new();
    let mut buf = [0u8; 4096];
    loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        for &b in &buf[..n] {
            match decoder.push::<HostMsg>(b) {
                None => {}
                Some(Ok(msg)) => {
                    stats.rx_frames.fetch_add(1, Relaxed);
                    if events.send(Event::Message { id, msg }).is_err() {
                        return;
                    }
                }
                Some(Err(e)) => {
                    stats.count_error(e.kind);
                    out.send(&DeviceMsg::FrameError {
                        kind: e.kind,
                        device_version: PROTOCOL_VERSION,
                    });
                }
            }
        }
    }
}
