//! The STM32G474 board's control-path register accesses, one for one, on RAM words: the same
//! loads, stores and read-modify-writes as `board::stm32g474::Stm32Control` (see that file), so
//! the instruction count matches; QEMU's RAM and the STM32's peripherals differ in wait states,
//! not in instructions.

use core::sync::atomic::{AtomicU32, Ordering::Relaxed};

use softfinger_app::board::{BridgeCommands, ControlHw, RawSample};

/// Fake registers, by role.
pub static TIM6_CNT: AtomicU32 = AtomicU32::new(0);
static TIM6_SR: AtomicU32 = AtomicU32::new(0);
/// The six encoder counters (the measurement script moves them).
pub static ENC_CNT: [AtomicU32; 6] = [const { AtomicU32::new(0) }; 6];
/// GPIOB_IDR: bit 12 is nFAULT (high: no fault).
pub static GPIOB_IDR: AtomicU32 = AtomicU32::new(1 << 12);
/// GPIOB_BSRR: the last value written. `write_bridges` writes nSLEEP high last when waking, and
/// the phase pins (never bit 0) last otherwise, so the last value tells nSLEEP's level.
static GPIOB_BSRR: AtomicU32 = AtomicU32::new(0);
/// TIM1_SR: bit 7 is BIF (break since last cleared).
pub static TIM1_SR: AtomicU32 = AtomicU32::new(0);
static TIM1_BDTR: AtomicU32 = AtomicU32::new(0);
static TIM1_CCR: [AtomicU32; 3] = [const { AtomicU32::new(0) }; 3];
static IWDG_KR: AtomicU32 = AtomicU32::new(0);

const MOE: u32 = 1 << 15;
const N_FAULT_PIN: u32 = 12;
const N_SLEEP_PIN: u32 = 0;
const PHASE_PINS: [u32; 3] = [10, 4, 5];

pub struct FakeStm32;

impl ControlHw for FakeStm32 {
    #[inline(always)]
    fn tick_period_counts(&self) -> u32 {
        17_000
    }
    #[inline(always)]
    fn tick_timer_count(&self) -> u32 {
        TIM6_CNT.load(Relaxed) & 0xFFFF
    }
    #[inline(always)]
    fn ack_tick(&mut self) {
        TIM6_SR.store(0, Relaxed);
    }
    #[inline(always)]
    fn tick_event_pending(&self) -> bool {
        TIM6_SR.load(Relaxed) & 1 != 0
    }
    #[inline(always)]
    fn read_inputs(&mut self) -> RawSample {
        let counts = core::array::from_fn(|i| ENC_CNT[i].load(Relaxed) as u16);
        let n_fault_low = GPIOB_IDR.load(Relaxed) & (1 << N_FAULT_PIN) == 0;
        let broke = TIM1_SR.load(Relaxed) & (1 << 7) != 0;
        if broke {
            TIM1_SR.store(!(1 << 7), Relaxed);
        }
        RawSample {
            counts,
            driver_fault: n_fault_low || broke,
        }
    }
    #[inline(always)]
    fn write_bridges(&mut self, cmd: &BridgeCommands) {
        if !cmd.pwm_enable {
            TIM1_BDTR.store(TIM1_BDTR.load(Relaxed) & !MOE, Relaxed);
        }
        if !cmd.driver_awake {
            GPIOB_BSRR.store(1 << (16 + N_SLEEP_PIN), Relaxed);
        }
        let mut bsrr = 0u32;
        for (pin, forward) in PHASE_PINS.into_iter().zip(cmd.phase_forward) {
            bsrr |= 1 << if forward { pin } else { pin + 16 };
        }
        GPIOB_BSRR.store(bsrr, Relaxed);
        for (ccr, compare) in TIM1_CCR.iter().zip(cmd.compare) {
            ccr.store(u32::from(compare), Relaxed);
        }
        if cmd.pwm_enable {
            TIM1_BDTR.store(TIM1_BDTR.load(Relaxed) | MOE, Relaxed);
        }
        if cmd.driver_awake {
            GPIOB_BSRR.store(1 << N_SLEEP_PIN, Relaxed);
        }
    }
    #[inline(always)]
    fn pet_watchdog(&mut self) {
        IWDG_KR.store(0xAAAA, Relaxed);
    }
}

/// The bridge outputs as last written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outputs {
    /// TIM1 main output enable.
    pub moe: bool,
    /// nSLEEP high (drivers awake).
    pub awake: bool,
    /// The three compare values.
    pub compare: [u32; 3],
}

/// Read back the fake registers.
pub fn outputs() -> Outputs {
    Outputs {
        moe: TIM1_BDTR.load(Relaxed) & MOE != 0,
        awake: GPIOB_BSRR.load(Relaxed) == 1 << N_SLEEP_PIN,
        compare: core::array::from_fn(|i| TIM1_CCR[i].load(Relaxed)),
    }
}
