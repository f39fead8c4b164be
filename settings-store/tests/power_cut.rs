//! A power cut at every write and every erase of a save, on the G474 flash model: after each cut
//! the store loads the settings of before the save or the ones being saved, never the defaults
//! nor a mix; and the next save after the cut succeeds.
//!
//! The saves run long enough to fill every page of the region and wrap around it several times,
//! so cuts land in page migrations and erases as well as in item writes. The counts are printed
//! (`cargo test -p softfinger-store --test power_cut -- --nocapture`).

use softfinger_store::flash_model::{G474Flash, OpKind, Tear, PAGE_SIZE};
use softfinger_store::{Calibration, LoadStatus, MotorConstants, Settings, Store};

/// Pages in the store's region (the firmware's region; see the crate README).
const PAGES: usize = 4;
/// Saves in the run: about 20 records fit a page, so 160 saves wrap the 4 pages twice.
const SAVES: u32 = 160;

fn settings(i: u32) -> Settings {
    let mut s = Settings::default();
    s.identity.serial = 1000 + i;
    s.identity.name.push_str("bench-").unwrap();
    s.identity
        .name
        .push(char::from(b'a' + (i % 26) as u8))
        .unwrap();
    s.calibration = Some(Calibration {
        homing_offset_counts: [i as i32, -(i as i32), 7],
        wrist_zero_counts: [i as i16, 2, 3],
        encoder_direction: [1, -1, 1, 1, -1, 1],
        motors: [MotorConstants {
            torque_constant_nm_per_a: 0.03,
            resistance_ohm: 1.0 + i as f32 * 0.01,
        }; 3],
    });
    s.presets[1].stiffness_n_per_m = 1000.0 + i as f32;
    s.watchdog.timeout_ms = 100 + (i % 50) as u16;
    s
}

fn store(flash: G474Flash) -> Store<G474Flash> {
    Store::new(flash, 0..(PAGES * PAGE_SIZE) as u32).unwrap()
}

#[derive(Default, Debug)]
struct Tally {
    cuts: u32,
    in_write: u32,
    in_erase: u32,
    old: u32,
    new: u32,
}

#[test]
fn a_cut_at_every_write_and_erase_of_a_save_leaves_old_or_new() {
    let mut image = G474Flash::new(PAGES).bytes().to_vec();
    let mut t = Tally::default();
    let mut erases_in_saves = 0u64;
    for i in 0..SAVES {
        let old = if i == 0 { None } else { Some(settings(i - 1)) };
        let new = settings(i);
        // The save uncut, to count its operations.
        let mut clean = store(G474Flash::from_image(&image));
        let before = clean.load_blocking();
        assert_eq!(before.status.from_store(), old.is_some());
        let f = clean.into_flash();
        let start = f.ops();
        let erases_before: u32 = f.erases.iter().sum();
        let mut s = store(f);
        s.save_blocking(&new, false).unwrap();
        let f = s.into_flash();
        let ops = f.ops() - start;
        erases_in_saves += u64::from(f.erases.iter().sum::<u32>() - erases_before);
        for k in 0..ops {
            for tear in [Tear::Before, Tear::Torn] {
                let mut cut = store(G474Flash::from_image(&image));
                let _ = cut.load_blocking(); // the boot before the save
                let mut f = cut.into_flash();
                f.cut_at(f.ops() + k, tear);
                let mut cut = store(f);
                assert!(
                    cut.save_blocking(&new, false).is_err(),
                    "save {i}, op {k}: the cut is seen"
                );
                let mut f = cut.into_flash();
                match f.cut_hit().expect("the cut happened") {
                    OpKind::Write => t.in_write += 1,
                    OpKind::Erase => t.in_erase += 1,
                }
                t.cuts += 1;
                // Power back on: boot, load.
                let boot_hit = f.cut_hit();
                f.power_on();
                let mut boot = store(G474Flash::from_image(f.bytes()));
                let got = boot.load_blocking();
                if got.status == LoadStatus::Read && got.settings == new {
                    t.new += 1;
                } else if let Some(old) = &old {
                    assert_eq!(
                        got.status,
                        LoadStatus::Read,
                        "save {i}, op {k}, {tear:?}: {got:?}"
                    );
                    assert_eq!(
                        &got.settings, old,
                        "save {i}, op {k}, {tear:?}: neither old nor new"
                    );
                    t.old += 1;
                } else {
                    assert_eq!(
                        got.status,
                        LoadStatus::Absent,
                        "first save {i}, op {k}, {tear:?}: {got:?}"
                    );
                    t.old += 1;
                }
                // The store is usable after the cut: the save again, then a load finds it.
                boot.save_blocking(&new, false).unwrap_or_else(|e| {
                    panic!("save {i}, op {k} of {ops}, {tear:?} in {boot_hit:?}: re-save {e:?}")
                });
                assert_eq!(
                    boot.load_blocking().settings,
                    new,
                    "save {i}, op {k}, {tear:?}: re-save"
                );
            }
        }
        image = f.bytes().to_vec();
    }
    println!(
        "power cuts during {SAVES} saves on {PAGES} pages of 2 KiB: {} cuts ({} in writes, {} in erases), \
         old settings {} times, new {} times, neither 0; erases in the saves {erases_in_saves}",
        t.cuts, t.in_write, t.in_erase, t.old, t.new
    );
    assert!(
        erases_in_saves >= 2 * PAGES as u64,
        "the run wraps the region: {erases_in_saves} erases"
    );
    assert!(t.in_erase > 0 && t.in_write > 0);
    assert_eq!(t.old + t.new, t.cuts);
}
