//! A power cut at every write and every erase of an update, on the G474 flash model: the
//! transfer into the DFU slot, the marking, the bootloader's swap at the reset, the trial boot's
//! confirmation; and of a rollback (an image failing its self-test, swapped back at the next
//! reset). After each cut the device is powered on and reset until it runs a confirmed image:
//! that image is the old or the new one, byte for byte, never neither (bricked), and the settings
//! store beside the slots still loads the settings saved before the update.
//! `cargo test -p softfinger-update --test power_cut -- --nocapture` prints the counts.

mod common;
use common::*;

use softfinger_store::flash_model::{G474Flash, OpKind, Tear};
use softfinger_store::{LoadStatus, Settings, Store};
use softfinger_update::boot::{active_trailer, boot_state, confirm, run_bootloader};
use softfinger_update::package::FLAG_SIMULATE_SELF_TEST_FAILURE;
use softfinger_update::{BootState, SelfTest, Slots, UpdateError};

/// The device's self-test as the virtual device runs it: passes unless the image says it fails.
fn self_test(slots: &Slots<'_, G474Flash>) -> SelfTest {
    let ok = active_trailer(slots).is_some_and(|t| t.flags & FLAG_SIMULATE_SELF_TEST_FAILURE == 0);
    SelfTest {
        clock: true,
        encoders: true,
        tick: ok,
        store: true,
    }
}

/// Power on and reset: the bootloader, then the image's self-test and confirm.
fn boot(slots: &Slots<'_, G474Flash>) -> Result<BootState, UpdateError> {
    run_bootloader(slots)?;
    let st = boot_state(slots)?;
    confirm(slots, &self_test(slots))?;
    Ok(st)
}

/// The update from the running image: transfer, then a reset (swap and trial boot), then (a
/// failing image) a second reset (the rollback).
fn update(slots: &Slots<'_, G474Flash>, new: &[u8]) -> Result<(), UpdateError> {
    transfer(slots, new)?;
    boot(slots)?;
    boot(slots)?;
    Ok(())
}

fn settings() -> Settings {
    let mut s = Settings::default();
    s.identity.serial = 4242;
    s
}

/// The device before the update: `old` in the active slot, the settings saved.
fn prepared(old: &[u8]) -> Vec<u8> {
    let f = device_with(old);
    let mut flash = f.into_inner().into_inner();
    let mut store = Store::new(flash, layout().store).unwrap();
    store.save_blocking(&settings(), false).unwrap();
    flash = store.into_flash();
    flash.bytes().to_vec()
}

fn settings_survive(f: Flash) {
    let flash = f.into_inner().into_inner();
    let mut store = Store::new(G474Flash::from_image(flash.bytes()), layout().store).unwrap();
    let l = store.load_blocking();
    assert_eq!((l.status, l.settings), (LoadStatus::Read, settings()));
}

#[derive(Default, Debug)]
struct Tally {
    cuts: u32,
    writes: u32,
    erases: u32,
    old: u32,
    new: u32,
}

/// Cut at every operation of `update(old -> new)`; `expect_new`: the update succeeds uncut.
fn campaign(old: &[u8], new: &[u8], expect_new: bool) -> (Tally, u64) {
    let image = prepared(old);
    let clean = flash_from(&image);
    let start = clean.lock(|c| c.borrow().ops());
    update(&Slots::new(&clean, layout()), new).unwrap();
    let ops = clean.lock(|c| c.borrow().ops()) - start;
    let want = if expect_new { new } else { old };
    assert_eq!(
        active(&Slots::new(&clean, layout()), want.len()),
        want,
        "the uncut update"
    );
    let mut t = Tally::default();
    for k in 0..ops {
        for tear in [Tear::Before, Tear::Torn] {
            let f = flash_from(&image);
            f.lock(|c| {
                let mut c = c.borrow_mut();
                let at = c.ops() + k;
                c.cut_at(at, tear);
            });
            let slots = Slots::new(&f, layout());
            assert!(update(&slots, new).is_err(), "op {k}: the cut is seen");
            f.lock(|c| {
                let mut c = c.borrow_mut();
                match c.cut_hit().expect("the cut happened") {
                    OpKind::Write => t.writes += 1,
                    OpKind::Erase => t.erases += 1,
                }
                c.power_on();
            });
            t.cuts += 1;
            // Power on; reset until a confirmed image runs (at most: finish a swap, roll back).
            let mut resets = 0;
            loop {
                let st = boot(&slots).unwrap_or_else(|e| panic!("op {k} {tear:?}: boot {e:?}"));
                resets += 1;
                if boot_state(&slots).unwrap() != BootState::Trial || resets > 3 {
                    let _ = st;
                    break;
                }
            }
            assert_ne!(
                boot_state(&slots).unwrap(),
                BootState::Trial,
                "op {k} {tear:?}: still on trial"
            );
            let got_old = active(&slots, old.len()) == old;
            let got_new = active(&slots, new.len()) == new;
            assert!(
                got_old || got_new,
                "op {k} {tear:?}: bricked (neither image in the active slot)"
            );
            if got_new {
                assert!(expect_new, "op {k} {tear:?}: a failing image stayed");
                t.new += 1;
            } else {
                t.old += 1;
            }
            // The device updates again from here.
            let redo = Slots::new(&f, layout());
            update(&redo, new)
                .unwrap_or_else(|e| panic!("op {k} {tear:?}: update after the cut {e:?}"));
            assert_eq!(
                active(&redo, want.len()),
                want,
                "op {k} {tear:?}: the update after the cut"
            );
            settings_survive(f);
        }
    }
    (t, ops)
}

#[test]
fn a_cut_at_every_write_and_erase_of_an_update_leaves_old_or_new() {
    let old = image(1, 9000, "1.0.0", false);
    let new = image(2, 13000, "2.0.0", false);
    let (t, ops) = campaign(&old, &new, true);
    println!(
        "power cuts during an update ({ops} writes and erases: transfer, mark, swap, confirm): {} cuts \
         ({} in writes, {} in erases), old image {} times, new {} times, bricked 0, settings lost 0",
        t.cuts, t.writes, t.erases, t.old, t.new
    );
    assert!(t.old > 0 && t.new > 0 && t.erases > 0);
}

#[test]
fn a_cut_at_every_write_and_erase_of_a_rollback_leaves_the_old_image() {
    let old = image(1, 9000, "1.0.0", false);
    let bad = image(3, 13000, "2.0.0-bad", true);
    let (t, ops) = campaign(&old, &bad, false);
    println!(
        "power cuts during a rolled-back update ({ops} writes and erases): {} cuts ({} in writes, {} in erases), \
         old image {} times, bricked 0, settings lost 0",
        t.cuts, t.writes, t.erases, t.old
    );
    assert_eq!(t.new, 0);
}
