//! Forwarding the tick's records and command outcomes, after the logger and the supervisor have
//! used them, to the host link when the firmware has one (feature `usb`): a queue end, or nothing.
//! A full queue drops the item (the link then misses one state sample or one acknowledgement);
//! the logger and the supervisor never wait.

use heapless::spsc::Producer;

/// Somewhere to forward a copy of `T`.
pub trait Tap<T> {
    /// Forward `item`; never waits.
    fn forward(&mut self, item: &T);
}

impl<T: Copy> Tap<T> for Producer<'static, T> {
    fn forward(&mut self, item: &T) {
        let _ = self.enqueue(*item);
    }
}
