//! `ontarget-tests`: softfinger-core's checks, run on the emulated Cortex-M4F (QEMU `mps2-an386`), so
//! f32 code generation and the single-precision FPU path are exercised on the real target ISA.
//!
//! Every expected value comes from a closed form (sin π/6 = 1/2, Rodrigues of 90° about z maps x to
//! y, ...), never from running the code under test on the host. Tolerances are derived from each
//! backend's stated kernel accuracy ([`accuracy::Accuracy`]); each check says how. Those worst-case
//! tolerances are far above what a single closed-form case measures (often 0 or an ulp), so every
//! value the math checks (kernels, rotations, decompositions, rolling) compare is also held to its
//! golden bits, recorded on the target (`golden.rs`, `scripts/mcu-bench --record-golden`; the
//! value's measured distance from its closed form is noted on each entry). The backends are
//! deterministic f32 code: the host computes the same bits (checked for the kernels and the
//! Rodrigues cases of all three backends). The contact and controller checks, outside the golden
//! groups, carry bounds about 3x their measured error.
//!
//! Output: one `FAIL ...` line per failed check, then `<N> passed, <M> failed` as the last line; the
//! semihosting exit status is failure if anything failed. Run with `scripts/mcu-bench --tests`.
#![no_std]
#![no_main]

mod accuracy;
mod contact;
mod controller;
mod creep;
mod decompose;
mod golden;
mod kernels;
mod pipeline;
mod protocol;
mod robustness;
mod rolling;
mod rotations;

use accuracy::Accuracy;
use cortex_m_rt::entry;
use softfinger_core::{Fast, Libm, Micromath};
use softfinger_mcu_bench::check::Checker;
use softfinger_mcu_bench::install_fault_handler;

install_fault_handler!();

/// All checks that are generic over the math backend.
fn backend_checks<M: Accuracy>(c: &mut Checker, accurate_kinematics: bool) {
    c.group(M::NAME);
    // The math checks' results are also held to their golden bits (`golden.rs`); the contact and
    // controller checks below are not, so that a deliberate change of the model does not have to
    // re-record them.
    c.golden_begin(M::GOLDEN);
    kernels::checks::<M>(c);
    rotations::checks::<M>(c);
    decompose::checks::<M>(c);
    rolling::checks::<M>(c);
    c.golden_end();
    robustness::checks::<M>(c);
    contact::step_checks::<M>(c);
    creep::checks::<M>(c);
    controller::checks::<M>(c, accurate_kinematics);
}

#[entry]
fn main() -> ! {
    let mut c = Checker::new();
    c.group("fpu");
    c.ok(
        "f32 arithmetic is IEEE single precision",
        f32_is_single_precision(),
    );
    c.group("contact");
    contact::checks(&mut c);
    backend_checks::<Libm>(&mut c, true);
    backend_checks::<Micromath>(&mut c, false);
    backend_checks::<Fast>(&mut c, true);
    pipeline::checks(&mut c);
    protocol::checks(&mut c);
    c.finish()
}

/// 2^24 + 1 rounds back to 2^24 in f32 (24-bit significand) but not in any wider format, and 1/3·3
/// is exactly 1 in f32 round-to-nearest. Runs FP instructions: with the FPU disabled this would fault
/// (the HardFault handler reports it) instead of returning.
fn f32_is_single_precision() -> bool {
    let big = core::hint::black_box(16_777_216.0f32);
    let one = core::hint::black_box(1.0f32);
    let three = core::hint::black_box(3.0f32);
    big + one == big && three * (one / three) == one
}
