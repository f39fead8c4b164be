//! A small on-target test harness: each check prints a line only when it fails, and
//! [`Checker::finish`] prints `<N> passed, <M> failed` as the last line and exits with the matching
//! semihosting status.

use cortex_m_semihosting::hprintln;

/// Counts passed and failed checks.
#[derive(Default)]
pub struct Checker {
    passed: u32,
    failed: u32,
    group: &'static str,
}

impl Checker {
    pub fn new() -> Checker {
        Checker::default()
    }

    /// Name of the current group of checks (e.g. the math backend), printed with each failure.
    pub fn group(&mut self, group: &'static str) {
        self.group = group;
    }

    /// `cond` must hold.
    pub fn ok(&mut self, name: &str, cond: bool) {
        if cond {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!("FAIL [{}] {}", self.group, name);
        }
    }

    /// `cond` must hold for the input `x`, which is printed on failure.
    pub fn ok_at(&mut self, name: &str, x: f32, cond: bool) {
        if cond {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!("FAIL [{}] {} (at x = {:e})", self.group, name, x);
        }
    }

    /// Every element of `got` within `tol` of `expected`, or of `alternative` (for results defined
    /// only up to an equivalence, e.g. a rotation vector of angle π).
    pub fn close_all_either(
        &mut self,
        name: &str,
        got: &[f32],
        expected: &[f32],
        alternative: &[f32],
        tol: f32,
    ) {
        let within = |e: &[f32]| {
            got.len() == e.len()
                && got
                    .iter()
                    .zip(e)
                    .all(|(g, e)| g.is_finite() && (g - e).abs() <= tol)
        };
        if within(expected) || within(alternative) {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!(
                "FAIL [{}] {}: got {:?}, expected {:?} or {:?} ± {}",
                self.group,
                name,
                got,
                expected,
                alternative,
                tol
            );
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
                "FAIL [{}] {}: got {}, expected {} ± {} (off by {})",
                self.group,
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
                "FAIL [{}] {}: got {:?}, expected {:?} ± {}",
                self.group,
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
