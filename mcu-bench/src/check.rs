//! A small on-target test harness: each check prints a line only when it fails, and
//! [`Checker::finish`] prints `<N> passed, <M> failed` as the last line and exits with the matching
//! semihosting status.

use cortex_m_semihosting::hprintln;

/// Counts passed and failed checks.
#[derive(Default)]
pub struct Checker {
    passed: u32,
    failed: u32,
}

impl Checker {
    pub fn new() -> Checker {
        Checker::default()
    }

    /// `cond` must hold.
    pub fn ok(&mut self, name: &str, cond: bool) {
        if cond {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!("FAIL {}", name);
        }
    }

    /// `|got - expected| <= tol`, and `got` finite.
    pub fn close(&mut self, name: &str, got: f32, expected: f32, tol: f32) {
        // Written so that a NaN `got` fails (every comparison with NaN is false).
        if got.is_finite() && (got - expected).abs() <= tol {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!(
                "FAIL {}: got {}, expected {} ± {} (off by {})",
                name,
                got,
                expected,
                tol,
                got - expected
            );
        }
    }

    /// Every element of `got` within `tol` of `expected`.
    pub fn close_all(&mut self, name: &str, got: &[f32], expected: &[f32], tol: f32) {
        let good = got.len() == expected.len()
            && got
                .iter()
                .zip(expected)
                .all(|(g, e)| g.is_finite() && (g - e).abs() <= tol);
        if good {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!(
                "FAIL {}: got {:?}, expected {:?} ± {}",
                name,
                got,
                expected,
                tol
            );
        }
    }

    /// Print the summary line and end the emulation: success only if nothing failed.
    pub fn finish(&self) -> ! {
        hprintln!("{} passed, {} failed", self.passed, self.failed);
        crate::exit::exit(self.failed == 0 && self.passed > 0)
    }
}
