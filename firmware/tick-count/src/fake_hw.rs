//! The STM32G474 board's control-path register accesses, one for one, on RAM words: the same
//! loads, stores and read-modify-writes as `board::stm32g474::Stm32Control` (see that file), so
//! the instruction count matches; QEMU's RAM and the STM32's peripherals differ in wait states,
//! not in instructions.

use core::sync::atomic::{AtomicU32, Ordering::Relaxed};

use crate::board::{BridgeCommands, ControlHw, RawSample};

/// Fake registers, by role.
pub static TIM6_CNT: AtomicU32 = AtomicU32::new(0);
static TIM6_SR: AtomicU32 = AtomicU32::new(0);
/// The six encoder counters (the measurement script moves them).
pub static ENC_CNT: [AtomicU32; 6] = [const { AtomicU32::new(0) }; 6];
static GPIOB_IDR: AtomicU32 = AtomicU32::new(1 << 12);
static GPIOB_BSRR: AtomicU32 = AtomicU32::new(0);
static TIM1_SR: AtomicU32 = AtomicU32::new(0);
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
