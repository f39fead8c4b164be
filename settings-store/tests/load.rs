//! Load at boot: absent, corrupt, unknown-version and migrated stores, and what may arm.

use softfinger_store::flash_model::{G474Flash, PAGE_SIZE};
use softfinger_store::record::{encode, encode_version, MAX_RECORD_LEN};
use softfinger_store::schema_v1::{CalibrationV1, SettingsV1, NOMINAL_MOTOR, VERSION as V1};
use softfinger_store::{Calibration, LoadStatus, MotorConstants, SaveError, Settings, Store};

const REGION: u32 = (4 * PAGE_SIZE) as u32;

fn calibrated() -> Settings {
    let mut s = Settings::default();
    s.identity.serial = 42;
    s.calibration = Some(Calibration {
        homing_offset_counts: [1, 2, 3],
        wrist_zero_counts: [4, 5, 6],
        encoder_direction: [1; 6],
        motors: [MotorConstants {
            torque_constant_nm_per_a: 0.03,
            resistance_ohm: 1.1,
        }; 3],
    });
    s
}

#[test]
fn an_erased_store_is_absent_gives_defaults_and_does_not_arm() {
    let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
    let l = s.load_blocking();
    assert_eq!(l.status, LoadStatus::Absent);
    assert_eq!(l.settings, Settings::default());
    assert!(!l.may_arm());
}

#[test]
fn saved_settings_read_back_and_arm_only_with_a_calibration() {
    let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
    s.save_blocking(&Settings::default(), false).unwrap();
    let l = s.load_blocking();
    assert_eq!(l.status, LoadStatus::Read);
    assert!(!l.may_arm(), "read, but no calibration in it");
    s.save_blocking(&calibrated(), false).unwrap();
    let mut s = Store::new(s.into_flash(), 0..REGION).unwrap();
    let l = s.load_blocking();
    assert_eq!((l.status, &l.settings), (LoadStatus::Read, &calibrated()));
    assert!(l.may_arm());
}

#[test]
fn saves_are_refused_while_armed_and_out_of_range_naming_the_key() {
    let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
    assert_eq!(s.save_blocking(&calibrated(), true), Err(SaveError::Armed));
    assert_eq!(s.erase_blocking(true), Err(SaveError::Armed));
    let mut bad = calibrated();
    bad.presets[0].friction = 2.5;
    match s.save_blocking(&bad, false) {
        Err(SaveError::Invalid(e)) => assert_eq!(e.key, "presets.0.friction"),
        other => panic!("{other:?}"),
    }
    let mut f = s.into_flash();
    assert_eq!(f.ops(), 0, "nothing written by a refused save");
    f.power_on();
}

#[test]
fn an_unknown_version_gives_defaults_and_a_flag() {
    let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
    s.save_blocking(&calibrated(), false).unwrap();
    let mut rec = [0u8; MAX_RECORD_LEN];
    let n = encode_version(7, &calibrated(), &mut rec).unwrap();
    embassy_block(s.save_raw_record(&rec[..n]));
    let l = s.load_blocking();
    assert_eq!(l.status, LoadStatus::UnknownVersion(7));
    assert_eq!(l.settings, Settings::default());
    assert!(!l.may_arm());
}

#[test]
fn a_record_with_a_bad_crc_is_corrupt() {
    let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
    let mut rec = [0u8; MAX_RECORD_LEN];
    let n = encode(&calibrated(), &mut rec).unwrap();
    rec[n - 1] ^= 0x40; // our CRC, inside an item whose own CRC is good
    embassy_block(s.save_raw_record(&rec[..n]));
    let l = s.load_blocking();
    assert_eq!(l.status, LoadStatus::Corrupt);
    assert!(!l.may_arm());
}

#[test]
fn garbage_flash_never_panics_and_gives_defaults() {
    // Every page filled with a pattern the storage layer did not write.
    for seed in 0u8..16 {
        let image: Vec<u8> = (0..4 * PAGE_SIZE)
            .map(|i| (i as u8).wrapping_mul(31).wrapping_add(seed))
            .collect();
        let mut s = Store::new(G474Flash::from_image(&image), 0..REGION).unwrap();
        let l = s.load_blocking();
        assert!(!l.status.from_store(), "seed {seed}: {:?}", l.status);
        assert_eq!(l.settings, Settings::default());
    }
}

#[test]
fn a_schema_1_store_migrates_and_the_next_save_writes_schema_2() {
    let v1 = SettingsV1 {
        identity: calibrated().identity,
        calibration: Some(CalibrationV1 {
            homing_offset_counts: [9, 8, 7],
            wrist_zero_counts: [6, 5, 4],
            encoder_direction: [-1; 6],
        }),
        presets: calibrated().presets,
        stream: calibrated().stream,
    };
    let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
    let mut rec = [0u8; MAX_RECORD_LEN];
    let n = encode_version(V1, &v1, &mut rec).unwrap();
    embassy_block(s.save_raw_record(&rec[..n]));
    let l = s.load_blocking();
    assert_eq!(l.status, LoadStatus::Migrated { from: 1 });
    assert!(l.may_arm(), "a migrated calibration was read");
    assert_eq!(l.settings, v1.clone().migrate());
    assert_eq!(
        l.settings.calibration.as_ref().unwrap().motors,
        [NOMINAL_MOTOR; 3]
    );
    s.save_blocking(&l.settings, false).unwrap();
    assert_eq!(s.load_blocking().status, LoadStatus::Read);
}

fn embassy_block<T>(f: impl core::future::Future<Output = Result<(), T>>) {
    assert!(embassy_futures::block_on(f).is_ok());
}

mod boot {
    //! The firmware's boot-time load (`softfinger_store::boot`): each status, its device-info
    //! flags and the arm gate.
    use super::*;
    use softfinger_store::boot::*;
    use softfinger_store::load_at_boot_blocking;

    fn flash_with(settings: Option<&Settings>) -> G474Flash {
        let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
        if let Some(x) = settings {
            s.save_blocking(x, false).unwrap();
        }
        s.into_flash()
    }

    #[test]
    fn a_calibrated_store_reads_with_no_flag_and_may_arm() {
        let mut f = flash_with(Some(&calibrated()));
        let b = load_at_boot_blocking(&mut f, 0..REGION);
        assert_eq!(b.status(), LoadStatus::Read);
        assert_eq!(b.settings(), &calibrated());
        assert_eq!(b.flags(), 0);
        assert!(b.may_arm());
        assert_eq!(b.arm_refusal(), None);
        assert_eq!(b.notice(), "settings: read from the store");
    }

    #[test]
    fn read_without_a_calibration_does_not_arm_and_says_why() {
        let mut f = flash_with(Some(&Settings::default()));
        let b = load_at_boot_blocking(&mut f, 0..REGION);
        assert_eq!(b.status(), LoadStatus::Read);
        assert_eq!(b.flags(), FLAG_NO_CALIBRATION);
        assert!(b.arm_refusal().unwrap().contains("no calibration"));
    }

    #[test]
    fn an_erased_store_gives_defaults_flagged_absent() {
        let mut f = flash_with(None);
        let b = load_at_boot_blocking(&mut f, 0..REGION);
        assert_eq!(b.status(), LoadStatus::Absent);
        assert_eq!(b.settings(), &Settings::default());
        assert_eq!(b.flags(), FLAG_DEFAULTS | FLAG_ABSENT | FLAG_NO_CALIBRATION);
        assert!(b.arm_refusal().unwrap().contains("could not be read"));
        assert!(b.notice().contains("defaults"));
    }

    #[test]
    fn a_corrupt_record_gives_defaults_flagged_corrupt() {
        let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
        let mut rec = [0u8; MAX_RECORD_LEN];
        let n = encode(&calibrated(), &mut rec).unwrap();
        rec[n - 1] ^= 1; // the record's CRC
        embassy_block(s.save_raw_record(&rec[..n]));
        let mut f = s.into_flash();
        let b = load_at_boot_blocking(&mut f, 0..REGION);
        assert_eq!(b.status(), LoadStatus::Corrupt);
        assert_eq!(
            b.flags(),
            FLAG_DEFAULTS | FLAG_CORRUPT | FLAG_NO_CALIBRATION
        );
        assert!(!b.may_arm());
    }

    #[test]
    fn an_unknown_version_gives_defaults_flagged_unknown() {
        let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
        let mut rec = [0u8; MAX_RECORD_LEN];
        let n = encode_version(99, &calibrated(), &mut rec).unwrap();
        embassy_block(s.save_raw_record(&rec[..n]));
        let mut f = s.into_flash();
        let b = load_at_boot_blocking(&mut f, 0..REGION);
        assert_eq!(b.status(), LoadStatus::UnknownVersion(99));
        assert_eq!(
            b.flags(),
            FLAG_DEFAULTS | FLAG_UNKNOWN_VERSION | FLAG_NO_CALIBRATION
        );
        assert!(b.notice().contains("newer firmware"));
    }

    #[test]
    fn a_schema_1_record_is_migrated_flagged_and_may_arm() {
        let mut s = Store::new(G474Flash::new(4), 0..REGION).unwrap();
        let v1 = SettingsV1 {
            calibration: Some(CalibrationV1 {
                homing_offset_counts: [1, 2, 3],
                wrist_zero_counts: [4, 5, 6],
                encoder_direction: [1; 6],
            }),
            identity: Settings::default().identity,
            presets: Settings::default().presets,
            stream: Settings::default().stream,
        };
        let mut rec = [0u8; MAX_RECORD_LEN];
        let n = encode_version(V1, &v1, &mut rec).unwrap();
        embassy_block(s.save_raw_record(&rec[..n]));
        let mut f = s.into_flash();
        let b = load_at_boot_blocking(&mut f, 0..REGION);
        assert_eq!(b.status(), LoadStatus::Migrated { from: V1 });
        assert_eq!(b.flags(), FLAG_MIGRATED);
        assert!(b.may_arm());
        let cal = b.settings().calibration.as_ref().unwrap();
        assert_eq!(cal.motors[0], NOMINAL_MOTOR);
    }

    #[test]
    fn a_region_the_map_cannot_use_gives_defaults_flagged_flash_error() {
        let mut f = flash_with(Some(&calibrated()));
        // One page (the map needs two) and a range not on page boundaries.
        for region in [0..PAGE_SIZE as u32, 100..REGION] {
            let b = load_at_boot_blocking(&mut f, region);
            assert_eq!(b.status(), LoadStatus::FlashError);
            assert_eq!(b.settings(), &Settings::default());
            assert_eq!(
                b.flags(),
                FLAG_DEFAULTS | FLAG_FLASH_ERROR | FLAG_NO_CALIBRATION
            );
            assert!(!b.may_arm());
        }
    }
}
