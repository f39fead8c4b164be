use super::*;
use crate::frame::encode_frame;
use crate::messages::DeviceMsg;
use crate::MAX_FRAME_LEN;

/// Every field of what was rendered lands in its field of the sample, vectors as their x, y, z,
/// the flags as their bits; `dropped` is left to the connection; and the frame is the one of the
/// same sample written out field by field.
#[test]
fn a_sample_carries_what_was_rendered() {
    let r = RenderedTick {
        mode: Mode::Armed,
        contact: ContactState::Sliding,
        flags: Flags::COMM_TIMEOUT,
        probe_m: Vec3::new(0.01, -0.02, -0.15),
        probe_vel_m_s: Vec3::new(0.1, 0.2, -0.3),
        force_n: Vec3::new(-0.5, 0.25, 2.0),
        spin_torque_nm: 0.004,
        contact_point_m: Vec3::new(0.011, -0.019, -0.175),
        model_seq: 7,
    };
    let stats = TickStatsWire {
        max_duration_ns: 900,
        mean_duration_ns: 450,
        overruns: 3,
    };
    let s = StateSample::rendered(42, &r, stats);
    let by_hand = StateSample {
        tick: 42,
        probe_m: [0.01, -0.02, -0.15],
        probe_vel_m_s: [0.1, 0.2, -0.3],
        force_n: [-0.5, 0.25, 2.0],
        spin_torque_nm: 0.004,
        contact: ContactState::Sliding,
        contact_point_m: [0.011, -0.019, -0.175],
        flags: Flags::COMM_TIMEOUT.0,
        mode: Mode::Armed,
        model_seq: 7,
        tick_stats: stats,
        dropped: 0,
    };
    assert_eq!(s, by_hand);
    let (mut a, mut b) = ([0u8; MAX_FRAME_LEN], [0u8; MAX_FRAME_LEN]);
    let na = encode_frame(&DeviceMsg::State(s), &mut a).unwrap();
    let nb = encode_frame(&DeviceMsg::State(by_hand), &mut b).unwrap();
    assert_eq!(a[..na], b[..nb]);
}
