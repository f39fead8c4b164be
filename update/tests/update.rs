//! Updates on the flash model: refused ones leave the running image untouched; a good one is
//! swapped in at a reset and confirmed by its self-test; one failing it rolls back; a transfer
//! resumes after a disconnect.

mod common;
use common::*;

use softfinger_update::boot::{active_trailer, boot_state, confirm, run_bootloader};
use softfinger_update::keys::DEV_PUBLIC_KEY;
use softfinger_update::package::sign;
use softfinger_update::session::chunk_crc;
use softfinger_update::{BootState, SelfTest, Slots, Status, UpdateError, UpdateSession};

const PASS: SelfTest = SelfTest {
    clock: true,
    encoders: true,
    tick: true,
    store: true,
};

#[test]
fn a_good_update_swaps_at_reset_and_is_confirmed_by_its_self_test() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 12000, "2.0.0", false);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    assert_eq!(active_trailer(&slots).unwrap().version(), "1.0.0");
    transfer(&slots, &new).unwrap();
    assert_eq!(
        active(&slots, old.len()),
        old,
        "nothing swapped before the reset"
    );
    run_bootloader(&slots).unwrap();
    assert_eq!(boot_state(&slots).unwrap(), BootState::Trial);
    assert_eq!(active(&slots, new.len()), new);
    assert_eq!(active_trailer(&slots).unwrap().version(), "2.0.0");
    assert!(confirm(&slots, &PASS).unwrap());
    assert_eq!(boot_state(&slots).unwrap(), BootState::Normal);
    run_bootloader(&slots).unwrap();
    assert_eq!(active(&slots, new.len()), new, "a confirmed image stays");
}

#[test]
fn an_image_failing_its_self_test_rolls_back_at_the_next_reset() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(3, 9000, "2.0.0-bad", true);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    transfer(&slots, &new).unwrap();
    run_bootloader(&slots).unwrap();
    let failed = SelfTest {
        tick: false,
        ..PASS
    };
    assert!(!confirm(&slots, &failed).unwrap());
    // A further update is refused while the trial image is unconfirmed.
    let sig = sign(&new, &seed());
    assert_eq!(
        UpdateSession::new().begin(&slots, new.len() as u32, &sig, false),
        Err(UpdateError::TrialNotConfirmed)
    );
    run_bootloader(&slots).unwrap();
    assert_eq!(boot_state(&slots).unwrap(), BootState::RolledBack);
    assert_eq!(active(&slots, old.len()), old);
    assert_eq!(active_trailer(&slots).unwrap().version(), "1.0.0");
    // And after a rollback a new update is accepted.
    transfer(&slots, &image(4, 5000, "2.0.1", false)).unwrap();
}

#[test]
fn a_wrong_signature_is_refused_and_the_image_untouched() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 9000, "2.0.0", false);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    let mut sig = sign(&new, &seed());
    sig[0] ^= 1;
    let mut s = UpdateSession::new();
    s.begin(&slots, new.len() as u32, &sig, false).unwrap();
    send(&mut s, &slots, &new, 0).unwrap();
    assert_eq!(
        s.finish(&slots, &DEV_PUBLIC_KEY, false),
        Err(UpdateError::BadSignature)
    );
    // Signed with another key.
    let other = sign(&new, &[7u8; 32]);
    let mut s = UpdateSession::new();
    s.begin(&slots, new.len() as u32, &other, false).unwrap();
    send(&mut s, &slots, &new, 0).unwrap();
    assert_eq!(
        s.finish(&slots, &DEV_PUBLIC_KEY, false),
        Err(UpdateError::BadSignature)
    );
    run_bootloader(&slots).unwrap();
    assert_eq!(boot_state(&slots).unwrap(), BootState::Normal);
    assert_eq!(active(&slots, old.len()), old);
}

#[test]
fn a_truncated_image_is_refused() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 9000, "2.0.0", false);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    let sig = sign(&new, &seed());
    let mut s = UpdateSession::new();
    s.begin(&slots, new.len() as u32, &sig, false).unwrap();
    send(&mut s, &slots, &new[..4096], 0).unwrap();
    assert_eq!(
        s.finish(&slots, &DEV_PUBLIC_KEY, false),
        Err(UpdateError::Truncated {
            received: 4096,
            len: new.len() as u32
        })
    );
    run_bootloader(&slots).unwrap();
    assert_eq!(active(&slots, old.len()), old);
}

#[test]
fn a_corrupted_chunk_is_refused_unwritten_and_its_resend_accepted() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 9000, "2.0.0", false);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    let sig = sign(&new, &seed());
    let mut s = UpdateSession::new();
    s.begin(&slots, new.len() as u32, &sig, false).unwrap();
    send(&mut s, &slots, &new[..1024], 0).unwrap();
    let good = &new[1024..1152];
    let mut bad = good.to_vec();
    bad[3] ^= 0x10;
    assert_eq!(
        s.chunk(&slots, 1024, &bad, chunk_crc(good), false),
        Err(UpdateError::ChunkCrc { offset: 1024 })
    );
    assert_eq!(
        s.status(),
        Status::Receiving {
            len: new.len() as u32,
            received: 1024
        }
    );
    assert_eq!(
        s.chunk(&slots, 1152, good, chunk_crc(good), false),
        Err(UpdateError::OutOfOrder { expected: 1024 })
    );
    send(&mut s, &slots, &new, 1024).unwrap();
    s.finish(&slots, &DEV_PUBLIC_KEY, false).unwrap();
    run_bootloader(&slots).unwrap();
    assert_eq!(active(&slots, new.len()), new);
}

#[test]
fn a_transfer_resumes_after_a_disconnect() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 9000, "2.0.0", false);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    let sig = sign(&new, &seed());
    let mut s = UpdateSession::new();
    s.begin(&slots, new.len() as u32, &sig, false).unwrap();
    send(&mut s, &slots, &new[..5120], 0).unwrap();
    // The link drops; the host reconnects and begins the same image again.
    assert_eq!(s.begin(&slots, new.len() as u32, &sig, false), Ok(5120));
    // A chunk whose acknowledgement was lost is acknowledged again.
    let c = &new[4992..5120];
    assert_eq!(s.chunk(&slots, 4992, c, chunk_crc(c), false), Ok(5120));
    send(&mut s, &slots, &new, 5120).unwrap();
    s.finish(&slots, &DEV_PUBLIC_KEY, false).unwrap();
    run_bootloader(&slots).unwrap();
    assert_eq!(active(&slots, new.len()), new);
}

#[test]
fn every_step_is_refused_while_armed_and_bad_lengths_named() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 9000, "2.0.0", false);
    let f = device_with(&old);
    let slots = Slots::new(&f, layout());
    let sig = sign(&new, &seed());
    let mut s = UpdateSession::new();
    assert_eq!(
        s.begin(&slots, new.len() as u32, &sig, true),
        Err(UpdateError::Armed)
    );
    let max = slots.max_image_len();
    assert_eq!(
        s.begin(&slots, max + 1, &sig, false),
        Err(UpdateError::TooLarge { len: max + 1, max })
    );
    assert!(
        s.begin(&slots, max, &sig, false).is_ok(),
        "exactly the slot fits"
    );
    assert_eq!(s.begin(&slots, 0, &sig, false), Err(UpdateError::Empty));
    s.begin(&slots, new.len() as u32, &sig, false).unwrap();
    let c = &new[..128];
    assert_eq!(
        s.chunk(&slots, 0, c, chunk_crc(c), true),
        Err(UpdateError::Armed)
    );
    let c7 = &new[..7];
    assert_eq!(
        s.chunk(&slots, 0, c7, chunk_crc(c7), false),
        Err(UpdateError::ChunkLen { offset: 0 })
    );
    let c129 = &new[..129];
    assert_eq!(
        s.chunk(&slots, 0, c129, chunk_crc(c129), false),
        Err(UpdateError::ChunkLen { offset: 0 })
    );
    send(&mut s, &slots, &new, 0).unwrap();
    assert_eq!(
        s.finish(&slots, &DEV_PUBLIC_KEY, true),
        Err(UpdateError::Armed)
    );
    s.finish(&slots, &DEV_PUBLIC_KEY, false).unwrap();
}
