//! The wire format pinned: every message of the round-trip lists, and one of each mode, contact
//! state and surface, encodes to the very bytes recorded here (frames of protocol version 1,
//! recorded before the wire types were shared with the core). A change of layout, field order or
//! variant order fails here. The one change since: the device info's two trailing fields
//! (`settings_flags`, `reset_cause`), appended, so the frame's earlier bytes are as before.

use super::*;

/// Every mode, contact state and surface shape once, and a contact-parameters answer.
fn every_variant_msgs() -> Vec<DeviceMsg> {
    let modes = [
        Mode::Unhomed,
        Mode::Homing,
        Mode::Disarmed,
        Mode::Armed,
        Mode::Faulted,
    ];
    let contacts = [
        ContactState::Broken,
        ContactState::Rolling,
        ContactState::Sliding,
    ];
    let mut msgs: Vec<DeviceMsg> = modes
        .iter()
        .zip(contacts.iter().cycle())
        .map(|(&mode, &contact)| {
            DeviceMsg::State(StateSample {
                mode,
                contact,
                ..StateSample::default()
            })
        })
        .collect();
    msgs.push(DeviceMsg::ContactParams {
        seq: 3,
        params: contact_params(),
    });
    msgs
}

/// A model of each surface shape.
fn every_shape_msgs() -> Vec<HostMsg> {
    let shapes = [
        SurfaceShape::Plane,
        SurfaceShape::Sphere { radius_m: 0.05 },
        SurfaceShape::Bowl { radius_m: 0.2 },
        SurfaceShape::Cylinder { radius_m: 0.03 },
    ];
    shapes
        .iter()
        .zip(1u16..)
        .map(|(&shape, seq)| HostMsg::Request {
            seq,
            req: Request::SetLocalModel(LocalModel {
                shape,
                ..model(u32::from(seq))
            }),
        })
        .collect()
}

fn hex(bytes: &[u8]) -> std::string::String {
    use core::fmt::Write;
    let mut s = std::string::String::new();
    for b in bytes {
        write!(s, "{b:02x}").ok();
    }
    s
}

/// `host_msgs()` then `every_shape_msgs()`, each frame in hex, delimiter included.
const HOST_FRAMES: [&str; 19] = [
    "0201070103fc8ad09500",
    "040101010576ebc12300",
    "0901010201ecc04de500",
    "090101020218331df600",
    "09010103036c28d41700",
    "0901010404c28573b900",
    "0901010505b69eba5800",
    "0901010606dbc50d7f00",
    "0901010707afdec49e00",
    "0901010808a69b443c04401c450103204004808944010fa03f6666663f3333333f0ad7a33c0107304153e1ba7c00",
    "110101ffff0309ffffffff0f01cdcc4c3d010101090ad7233c0ad7a3bc0103803f0101010101010101010101010103fa4401011540cdcc4c3f9a99193f0ad7233cffff03019e691b00",
    "0a01010a0a0a8704ab0600",
    "0a01010b0b64cb22f67d00",
    "0501010c0c0101010101010115cdcccc3dcdcccc3dcdcc4c3e9a99993efe8d9dac00",
    "0901010d0dc105774f00",
    "06010101090101010101090ad7233c0ad7a3bc0103803f0101010101010101010101010103fa4401011540cdcc4c3f9a99193f0ad7233cffff03d611929600",
    "0b010102090201cdcc4c3d010101090ad7233c0ad7a3bc0103803f0101010101010101010101010103fa4401011540cdcc4c3f9a99193f0ad7233cffff038720801200",
    "0b010103090302cdcc4c3e010101090ad7233c0ad7a3bc0103803f0101010101010101010101010103fa4401011540cdcc4c3f9a99193f0ad7233cffff03a2ab841100",
    "0b0101040904038fc2f53c010101090ad7233c0ad7a3bc0103803f0101010101010101010101010103fa4401011540cdcc4c3f9a99193f0ad7233cffff035af3058d00",
];

/// `largest_device_msgs()` then `every_variant_msgs()`.
const DEVICE_FRAMES: [&str; 12] = [
    "250105ffffffffffffffffff01ffff7f7fffff7f7fffff7f7fffff7fffffff7fffffff7fff0103803f0103803f0103803f010480bf02010102400101024001012540ffffffff0f04ffffffff0fffffffff0fffffffff0fffffffff0fffffffff0fd1bcbcd900",
    "370102ffff03ff18c3a978c3a978c3a978c3a978c3a978c3a978c3a978c3a978103939393939393939393939393939393901ffffffff0f01284041ffff03080101010101010101ffff03ff10c3a9c3a9c3a9c3a9c3a9c3a9c3a9c3a90e245dd000",
    "3a0103ffff03ffffffff0fffffffff0fffffffff0fffffffff0fffffffff0fffffffff0fffffffff0fffffffff0fffffffff0fffff03053cf13a00",
    "0a0101070105235b85f200",
    "0201080101019390eb3900",
    "090106020185a4bd9100",
    "030105010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101052b62b42b00",
    "030105010101010101010101010101010101010101010101010101010101010101010101010101010101010201010101010101010101010101020101010101058ffec7f300",
    "03010501010101010101010101010101010101010101010101010101010101010101010101010101010101020201010101010101010101010102020101010105922dbf9e00",
    "03010501010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010101010102030101010105f1a9081f00",
    "03010501010101010101010101010101010101010101010101010101010101010101010101010101010101020101010101010101010101010102040101010105e1a202ae00",
    "08010403a69b443c04401c450103204004808944010fa03f6666663f3333333f0ad7a33c010730417dd00c0100",
];

#[test]
fn every_message_encodes_to_its_recorded_frame() {
    let host: Vec<HostMsg> = host_msgs().into_iter().chain(every_shape_msgs()).collect();
    assert_eq!(host.len(), HOST_FRAMES.len());
    for (m, want) in host.iter().zip(HOST_FRAMES) {
        assert_eq!(hex(&frame_of(m)), want, "{m:?}");
    }
    let device: Vec<DeviceMsg> = largest_device_msgs()
        .into_iter()
        .chain(every_variant_msgs())
        .collect();
    assert_eq!(device.len(), DEVICE_FRAMES.len());
    for (m, want) in device.iter().zip(DEVICE_FRAMES) {
        assert_eq!(hex(&frame_of(m)), want, "{m:?}");
    }
}
