//! Hand a value to one interrupt handler without a lock.
//!
//! The control interrupt must never wait for a lock held by a task (a task's critical section does
//! not mask it, see `critical_section_basepri`), so its state is handed over once, before the
//! interrupt is unmasked, and afterwards only that handler touches it. Tasks exchange data with it
//! through atomics and lock-free SPSC queues only.

use core::cell::UnsafeCell;
use core::mem::MaybeUninit;
use core::sync::atomic::{AtomicU8, Ordering};

const EMPTY: u8 = 0;
const WRITING: u8 = 1;
const READY: u8 = 2;

/// A write-once slot read by exactly one interrupt handler.
pub struct IsrCell<T> {
    state: AtomicU8,
    value: UnsafeCell<MaybeUninit<T>>,
}

// SAFETY: the value is written once, by `install`, before `READY` is published with Release
// ordering; afterwards only the one handler that calls `get_mut` (Acquire) touches it. `T: Send`
// because the value moves from thread mode to the interrupt.
unsafe impl<T: Send> Sync for IsrCell<T> {}

impl<T> IsrCell<T> {
    /// An empty slot.
    pub const fn new() -> Self {
        IsrCell {
            state: AtomicU8::new(EMPTY),
            value: UnsafeCell::new(MaybeUninit::uninit()),
        }
    }

    /// Store the value (once). Call before the handler's interrupt is unmasked. A second call
    /// hands the value back.
    pub fn install(&self, value: T) -> Result<(), T> {
        if self
            .state
            .compare_exchange(EMPTY, WRITING, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
        {
            return Err(value);
        }
        // SAFETY: the EMPTY -> WRITING exchange above succeeds once, so this is the only writer,
        // and no reader dereferences the slot before it sees READY.
        unsafe { (*self.value.get()).write(value) };
        self.state.store(READY, Ordering::Release);
        Ok(())
    }

    /// The value, once installed.
    ///
    /// # Safety
    ///
    /// Only one interrupt handler may call this, and it must not hold the reference past its
    /// return nor re-enter itself (a Cortex-M handler never preempts itself).
    #[inline(always)]
    #[allow(clippy::mut_from_ref)] // exclusivity is the caller's contract, stated above
    pub unsafe fn get_mut(&self) -> Option<&mut T> {
        if self.state.load(Ordering::Acquire) == READY {
            // SAFETY: READY means fully written; the caller is the only user from now on.
            Some(unsafe { (*self.value.get()).assume_init_mut() })
        } else {
            None
        }
    }
}
