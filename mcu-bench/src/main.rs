//! `mcu-bench`: instructions per call of softfinger-core's kernels on an emulated Cortex-M4F.
//!
//! Runs on QEMU `mps2-an386` with `-icount shift=0` (see `.cargo/config.toml`); prints one
//! `BENCH <name> <backend> <instructions>` line per result through semihosting and exits with
//! failure if a sanity check or a measurement fails. `scripts/mcu-bench` builds, runs and parses it.
//!
//! To add a benchmark, add one `bench!` line below (see [`softfinger_mcu_bench::bench!`]).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use softfinger_core::decompose::{decompose, Method};
use softfinger_core::rolling::Rolling;
use softfinger_core::surface::{Plane, Sphere};
use softfinger_core::{Fast, Libm, Math, Micromath, Quat, Rot3, Vec3};
use softfinger_mcu_bench::bench::Bencher;
use softfinger_mcu_bench::counter::Counter;
use softfinger_mcu_bench::{bb, bench, exit::exit, install_fault_handler};

install_fault_handler!();

#[entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        exit(false)
    };
    let mut b = Bencher::new(Counter::new(peripherals.SYST));

    sanity_checks(&mut b);
    math_kernels(&mut b);
    rotations(&mut b);
    pipeline(&mut b);

    exit(b.ok())
}

// The instruction sequences are written out, not `.rept`: LLVM sizes inline assembly by its lines
// when it places literal pools, and a `.rept` line would be sized as one instruction.
macro_rules! x5 {
    ($i:expr) => {
        concat!($i, "\n", $i, "\n", $i, "\n", $i, "\n", $i, "\n")
    };
}
macro_rules! x10 {
    ($i:expr) => {
        concat!(x5!($i), x5!($i))
    };
}
macro_rules! x100 {
    ($i:expr) => {
        x10!(x10!($i))
    };
}

/// Sequences of known length: the method must report exactly their instruction count. The FP one
/// also proves the FPU is enabled (with CP10/CP11 off, VADD raises a usage fault → HardFault → the
/// handler reports it and exits with failure).
fn sanity_checks(b: &mut Bencher) {
    b.sanity("nop_x100", 100, || {
        // SAFETY: NOPs only; no memory, stack or flags touched.
        unsafe { core::arch::asm!(x100!("nop"), options(nomem, nostack, preserves_flags)) }
    });
    b.sanity("vadd_f32_x50", 50, || {
        // SAFETY: touches only s0, which is declared clobbered.
        unsafe {
            core::arch::asm!(
                x10!(x5!("vadd.f32 s0, s0, s0")),
                out("s0") _,
                options(nomem, nostack, preserves_flags)
            )
        }
    });
}

/// The scalar kernels of each math backend, at a mid-range input (1 rad: away from each backend's
/// small-argument fast path; libm's sinf/cosf reduce 1 rad against π/2 in f64).
fn math_kernels(b: &mut Bencher) {
    bench!(b, "sin", for M in [Libm, Micromath, Fast], || M::sin(bb(1.0f32)));
    bench!(b, "cos", for M in [Libm, Micromath, Fast], || M::cos(bb(1.0f32)));
    bench!(b, "sin_cos", for M in [Libm, Micromath, Fast], || M::sin_cos(bb(1.0f32)));
    bench!(b, "atan2", for M in [Libm, Micromath, Fast], || M::atan2(bb(0.3f32), bb(-0.8f32)));
    bench!(b, "sqrt", for M in [Libm, Micromath, Fast], || M::sqrt(bb(2.5f32)));
}

/// Rodrigues (eq. 4) and the quaternion log map.
fn rotations(b: &mut Bencher) {
    // A unit axis (1, 2, 3)/√14 and 1 rad; the axis is re-normalised inside (one sqrt).
    let axis = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);
    bench!(b, "rot3_from_axis_angle", for M in [Libm, Micromath, Fast], || {
        Rot3::from_axis_angle::<M>(bb(axis), bb(1.0f32))
    });
    // The same rotation as a unit quaternion (cos 0.5, axis · sin 0.5).
    let q = Quat::new(0.877_582_56, 0.128_129_8, 0.256_259_6, 0.384_389_4);
    bench!(b, "quat_to_rotation_vector", for M in [Libm, Micromath, Fast], || {
        bb(q).to_rotation_vector::<M>()
    });
}

/// The paper scene's rotation increment per 10 ms step: δψ = 0.03 rad about x, δθ = 0.02 rad about y,
/// δφ = 0.05 rad about z (the contact normal), as a rotation vector (x, y, z).
const SCENE_STEP: Vec3 = Vec3::new(0.03, 0.02, 0.05);

/// The contact pipeline, stage by stage.
fn pipeline(b: &mut Bencher) {
    let (dq, _) = Quat::from_rotation_vector::<Libm>(SCENE_STEP);
    bench!(b, "decompose_paper", for M in [Libm, Micromath, Fast], || {
        decompose::<M>(Method::PaperVerbatim, bb(dq))
    });
    bench!(b, "decompose_rpy", for M in [Libm, Micromath, Fast], || {
        decompose::<M>(Method::Rpy, bb(dq))
    });
    bench!(b, "decompose_exact", for M in [Libm, Micromath, Fast], || {
        decompose::<M>(Method::Exact, bb(dq))
    });

    // Rolling update (Algorithm 1): one orientation sample in, the contact points move. The samples
    // alternate between q0 and q0·dq, so every step rolls by the scene increment, forwards then back
    // (the alternation costs about two instructions per call).
    let q0 = Quat::new(0.877_582_56, 0.128_129_8, 0.256_259_6, 0.384_389_4);
    let samples = [q0 * dq, q0];
    macro_rules! rolling {
        ($name:literal, $surface:expr, $method:expr) => {
            bench!(b, $name, for M in [Libm, Micromath, Fast], {
                let mut r = Rolling::new($surface, 0.01, q0, $method);
                let mut k = 0;
                move || {
                    let q = samples[k];
                    k ^= 1;
                    r.step::<M>(bb(q))
                }
            });
        };
    }
    rolling!(
        "rolling_plane_paper",
        Plane::default(),
        Method::PaperVerbatim
    );
    rolling!("rolling_plane_rpy", Plane::default(), Method::Rpy);
    rolling!("rolling_plane_exact", Plane::default(), Method::Exact);
    rolling!("rolling_sphere_exact", Sphere::new(0.05), Method::Exact);

    // PENDING until they have real bodies on main (then one `bench!` line each):
    // - `state_machine`: the contact state machine's update
    // - `contact_step`: orientation sample in; contact point, spin torque and state out. Target
    //   <= 400 instructions with the best backend that keeps the error <= 0.001 mm (budget.json).
    // - `control_tick`: `Controller::<M>::tick`, six encoder counts in, three duties out. Target
    //   <= 2000 instructions (budget.json).
}
