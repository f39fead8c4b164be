//! A small on-target test harness: each check prints a line only when it fails, and
//! [`Checker::finish`] prints `<N> passed, <M> failed` as the last line and exits with the matching
//! semihosting status.
//!
//! Golden values: between [`Checker::golden_begin`] and [`Checker::golden_end`], every value a
//! `close*` check receives is also compared bit for bit with the next entry of a table of f32 bit
//! patterns (one more check per `close*` call). The backends are deterministic f32 code, so the
//! same build gives the same bits on every run; the tables are written by
//! `scripts/mcu-bench --record-golden`, which builds with the `record-golden` feature: the
//! comparisons are then replaced by `GOLDEN|...` lines carrying each value's bits and its error
//! against the closed form.

use cortex_m_semihosting::hprintln;

/// Counts passed and failed checks.
#[derive(Default)]
pub struct Checker {
    passed: u32,
    failed: u32,
    group: &'static str,
    /// The golden table in use, and the index of its next entry.
    golden: Option<&'static [u32]>,
    golden_at: usize,
}

impl Checker {
    pub fn new() -> Checker {
        Checker::default()
    }

    /// Name of the current group of checks (e.g. the math backend), printed with each failure.
    pub fn group(&mut self, group: &'static str) {
        self.group = group;
    }

    /// From here on, compare every `close*` value bit for bit with `table`, in order.
    pub fn golden_begin(&mut self, table: &'static [u32]) {
        self.golden = Some(table);
        self.golden_at = 0;
    }

    /// Stop comparing with the golden table; one check that every entry was used (a check removed
    /// or added since the table was recorded fails here or at the first shifted value).
    pub fn golden_end(&mut self) {
        if let Some(table) = self.golden.take() {
            if !cfg!(feature = "record-golden") {
                let used = self.golden_at == table.len();
                self.ok("golden table: every entry compared", used);
            }
        }
    }

    /// The bit-for-bit comparison of `got` with the next golden entries, if a table is in use;
    /// `err` is the value's distance from the closed form (printed when recording).
    fn golden(&mut self, name: &str, got: &[f32], err: f32) {
        let Some(table) = self.golden else {
            return;
        };
        let at = self.golden_at;
        self.golden_at += got.len();
        if cfg!(feature = "record-golden") {
            for g in got {
                hprintln!(
                    "GOLDEN|{}|{}|{:#010x}|{:e}",
                    self.group,
                    name,
                    g.to_bits(),
                    err
                );
            }
            return;
        }
        let want = table.get(at..at + got.len());
        let same = want.is_some_and(|w| got.iter().zip(w).all(|(g, w)| g.to_bits() == *w));
        if same {
            self.passed += 1;
        } else {
            self.failed += 1;
            hprintln!(
                "FAIL [{}] {}: not the golden bits (entries from {}): got {:?}, golden bits {:x?}",
                self.group,
                name,
                at,
                got,
                want
            );
        }
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
        let dist = |e: &[f32]| {
            got.iter()
                .zip(e)
                .map(|(g, e)| (g - e).abs())
                .fold(0.0f32, f32::max)
        };
        self.golden(name, got, dist(expected).min(dist(alternative)));
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
        self.golden(name, &[got], (got - expected).abs());
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
        let err = got
            .iter()
            .zip(expected)
            .map(|(g, e)| (g - e).abs())
            .fold(0.0f32, f32::max);
        self.golden(name, got, err);
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
