//! Pipeline tests: modes, homing against a simple arm model, faults, bridges, telemetry.

use super::*;
use crate::devices::OMEGA_LIKE;
use crate::Libm;

fn pipeline() -> Pipeline<Libm> {
    let cfg = PipelineConfig::plane(OMEGA_LIKE, BoardTiming::STM32G474_10KHZ, 0.0);
    match Pipeline::new(cfg) {
        Ok(p) => p,
        Err(e) => panic!("{e:?}"),
    }
}

#[test]
fn power_up_is_unhomed_asleep_and_refuses_to_arm() {
    let mut p = pipeline();
    for _ in 0..100 {
        let out = p.tick(&RawInput::default());
        assert_eq!(out.mode, Mode::Unhomed);
        assert_eq!(out.bridges, BridgeCommands::OFF);
        assert_eq!(out.control.force_n, crate::Vec3::ZERO);
    }
    assert_eq!(p.command(Command::Arm), Err(CommandError::NotHomed));
    assert_eq!(p.mode(), Mode::Unhomed);
}
