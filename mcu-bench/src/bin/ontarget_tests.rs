#![no_std]
#![no_main]
use cortex_m_rt::entry;
use softfinger_mcu_bench::check::Checker;
use softfinger_mcu_bench::install_fault_handler;
install_fault_handler!();
#[entry]
fn main() -> ! {
    let mut c = Checker::new();
    c.ok("x", true);
    c.finish()
}
