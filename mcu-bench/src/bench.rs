//! The benchmark harness: instructions per call of a closure, measured with SysTick under QEMU.
//!
//! Method: call the closure [`N`] times between two SysTick reads, subtract the counts of the same
//! loop with an empty body (measured once, at start-up), convert counts to instructions
//! ([`INSTRUCTIONS_PER_COUNT`]) and divide by N, rounding to the nearest instruction. The resolution
//! is 40 / N = 0.04 instructions per call; under `-icount shift=0` the figure is the same on every
//! run.
//!
//! Inputs go through [`core::hint::black_box`] inside the closure and the result goes through it in
//! the loop, so nothing is hoisted out of the loop or optimised away. The figure therefore includes
//! loading the inputs and storing the result (about one instruction per scalar), which a real caller
//! also pays unless the call is fused into surrounding code.
//!
//! Adding a benchmark is one line, see [`bench!`](crate::bench!).

use crate::counter::{Counter, INSTRUCTIONS_PER_COUNT, MAX_INTERVAL_COUNTS};
use core::hint::black_box;
use cortex_m_semihosting::hprintln;

/// Calls per measurement.
pub const N: u32 = 1000;

/// Runs benchmarks and prints one `BENCH` line per result.
pub struct Bencher {
    counter: Counter,
    baseline_counts: u32,
    ok: bool,
}

impl Bencher {
    /// Start the harness and measure the empty-loop baseline.
    pub fn new(counter: Counter) -> Bencher {
        let mut b = Bencher {
            counter,
            baseline_counts: 0,
            ok: true,
        };
        b.baseline_counts = b.counts(N, &mut || ());
        hprintln!(
            "INFO empty loop: {} SysTick counts for {} iterations ({} instructions per iteration)",
            b.baseline_counts,
            N,
            (b.baseline_counts * INSTRUCTIONS_PER_COUNT) as f32 / N as f32
        );
        b
    }

    /// True when every measurement and sanity check so far succeeded.
    pub fn ok(&self) -> bool {
        self.ok
    }

    /// Mark the run failed (a benchmark's precondition did not hold); the caller prints why.
    pub fn fail(&mut self) {
        self.ok = false;
    }

    /// SysTick counts for `n` calls of `f`, loop overhead included. Never inlined, so every closure
    /// gets its own copy of the loop with the closure body inlined into it.
    #[inline(never)]
    fn counts<R, F: FnMut() -> R>(&self, n: u32, f: &mut F) -> u32 {
        let n = black_box(n);
        let start = self.counter.now();
        for _ in 0..n {
            black_box(f());
        }
        let end = self.counter.now();
        Counter::elapsed(start, end)
    }

    /// Instructions per call of `f`, or `None` (with an `ERROR` line) if N calls would overflow the
    /// counter.
    pub fn measure<R, F: FnMut() -> R>(&mut self, name: &str, mut f: F) -> Option<u32> {
        // One call first: N of them must fit in the counter's unambiguous range.
        let one = self.counts(1, &mut f);
        if (one as u64 + 1) * N as u64 > MAX_INTERVAL_COUNTS as u64 {
            hprintln!(
                "ERROR {}: one call takes {} counts, too long for N = {}",
                name,
                one,
                N
            );
            self.ok = false;
            return None;
        }
        let counts = self.counts(N, &mut f);
        let net = counts.saturating_sub(self.baseline_counts) as u64;
        let per_call = (net * INSTRUCTIONS_PER_COUNT as u64 + N as u64 / 2) / N as u64;
        Some(per_call as u32)
    }

    /// Measure `f` and print `BENCH <name> <backend> <instructions per call>`.
    pub fn run<R, F: FnMut() -> R>(&mut self, name: &str, backend: &str, f: F) {
        if let Some(instr) = self.measure(name, f) {
            hprintln!("BENCH {} {} {}", name, backend, instr);
        }
    }

    /// Measure `f`, whose exact instruction count is `expected`, and print
    /// `SANITY <name> <expected> <measured>`; a mismatch marks the run failed.
    pub fn sanity<R, F: FnMut() -> R>(&mut self, name: &str, expected: u32, f: F) {
        if let Some(instr) = self.measure(name, f) {
            hprintln!("SANITY {} {} {}", name, expected, instr);
            if instr != expected {
                hprintln!(
                    "ERROR sanity check {}: expected {}, measured {}",
                    name,
                    expected,
                    instr
                );
                self.ok = false;
            }
        }
    }
}

/// One benchmark per line:
///
/// ```ignore
/// // the same expression for each backend; `M` names the backend inside the closure
/// bench!(b, "sin", for M in [Libm, Micromath, Fast], || M::sin(bb(1.0f32)));
/// // one backend
/// bench!(b, "sqrt", Fast, || Fast::sqrt(bb(2.5f32)));
/// // backend-independent code (reported with backend "-")
/// bench!(b, "state_machine", _, || step(bb(x)));
/// ```
#[macro_export]
macro_rules! bench {
    ($b:expr, $name:expr, for $m:ident in [$($backend:ident),+ $(,)?], $f:expr) => {
        $({
            #[allow(dead_code)]
            type $m = $backend;
            $b.run($name, <$m as $crate::__Math>::NAME, $f);
        })+
    };
    ($b:expr, $name:expr, _, $f:expr) => {
        $b.run($name, "-", $f)
    };
    ($b:expr, $name:expr, $backend:ident, $f:expr) => {
        $b.run($name, <$backend as $crate::__Math>::NAME, $f)
    };
}
