//! The bytes waiting for the transport: a fixed ring that takes whole frames or nothing, so a
//! host that stops reading loses frames (the endpoint counts them) and never stalls anyone.

use heapless::Deque;

/// Bytes of frames waiting to be sent.
#[derive(Debug, Default)]
pub struct TxRing<const N: usize> {
    bytes: Deque<u8, N>,
}

impl<const N: usize> TxRing<N> {
    /// Empty.
    pub const fn new() -> Self {
        TxRing {
            bytes: Deque::new(),
        }
    }

    /// Queue a whole frame; false (nothing queued) when it does not fit.
    pub fn push_frame(&mut self, frame: &[u8]) -> bool {
        if N - self.bytes.len() < frame.len() {
            return false;
        }
        for &b in frame {
            // Cannot fail: the room was checked above.
            let _ = self.bytes.push_back(b);
        }
        true
    }

    /// The next byte to send, left in the ring.
    pub fn peek(&self) -> Option<u8> {
        self.bytes.front().copied()
    }

    /// The next byte to send.
    pub fn pop(&mut self) -> Option<u8> {
        self.bytes.pop_front()
    }

    /// Up to `out.len()` bytes to send, returns how many.
    pub fn pop_into(&mut self, out: &mut [u8]) -> usize {
        let mut n = 0;
        for slot in out.iter_mut() {
            match self.bytes.pop_front() {
                Some(b) => *slot = b,
                None => break,
            }
            n += 1;
        }
        n
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.bytes.len()
    }

    /// Nothing waiting.
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }
}
