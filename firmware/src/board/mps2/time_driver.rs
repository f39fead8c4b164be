//! embassy-time driver of the emulated board: APB timer 1 interrupts at 1 kHz (one embassy tick,
//! feature `tick-hz-1_000`), below the control tick's priority; each interrupt advances the clock,
//! wakes the expired timers, and lets the log reader drain the defmt ring.

use core::cell::{Cell, RefCell};
use core::task::Waker;

use critical_section::Mutex;
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;

use super::cmsdk::{ApbTimer, PCLK_HZ, TIME_BASE_TIMER};
use super::defmt_sink;

/// The embassy tick rate, Hz (must match the `tick-hz-*` feature).
pub const TICK_HZ: u32 = 1_000;

struct TickDriver {
    now: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: TickDriver = TickDriver {
    now: Mutex::new(Cell::new(0)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

impl Driver for TickDriver {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.now.borrow(cs).get())
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            let now = self.now.borrow(cs).get();
            let mut q = self.queue.borrow_ref_mut(cs);
            if q.schedule_wake(at, waker) {
                // Wakes whatever is already due; the rest waits for the next 1 kHz interrupt.
                let _ = q.next_expiration(now);
            }
        });
    }
}

/// The timer, configured for [`TICK_HZ`] (started by [`start`]).
const TIMER: ApbTimer = TIME_BASE_TIMER;

/// Start the 1 kHz interrupt.
pub fn start() {
    TIMER.configure(PCLK_HZ / TICK_HZ);
    TIMER.start();
}

/// The 1 kHz interrupt: one embassy tick, then the log reader.
#[allow(unsafe_code)] // `no_mangle`: the vector table (vectors.rs) names it
#[no_mangle]
extern "C" fn TIMER1() {
    TIMER.clear();
    critical_section::with(|cs| {
        let now = DRIVER.now.borrow(cs).get() + 1;
        DRIVER.now.borrow(cs).set(now);
        let _ = DRIVER.queue.borrow_ref_mut(cs).next_expiration(now);
    });
    defmt_sink::drain();
}
