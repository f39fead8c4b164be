use super::*;

fn at(h: f64, f: f64) -> Sample {
    Sample {
        t_s: 0.0,
        z_m: 0.0,
        probe_height_m: h,
        force_z_n: f,
        force_n: f.abs(),
        energy_j: 0.0,
    }
}

/// Heights that round to the same 0.1 µm are one level (1.09 and 1.12 µm: one bin rounded, two
/// truncated); levels come lowest first with their tick counts, mean force and first height;
/// heights 0.2 µm apart stay apart.
#[test]
fn levels_group_equal_heights() {
    let s = [
        at(-7.58e-6, 2.0),
        at(15.01e-6, 0.0),
        at(-7.58e-6 + 0.01e-6, 4.0),
        at(-7.38e-6, 1.0),
        at(1.09e-6, 0.5),
        at(1.12e-6, 0.5),
    ];
    let l = levels(&s);
    assert_eq!(l.len(), 4, "{l:?}");
    assert!((l[0].height_m + 7.58e-6).abs() < 1e-12);
    assert_eq!(l[0].ticks, 2);
    assert!((l[0].mean_force_z_n - 3.0).abs() < 1e-12);
    assert!((l[1].height_m + 7.38e-6).abs() < 1e-12 && l[1].ticks == 1);
    assert!((l[2].height_m - 1.09e-6).abs() < 1e-12 && l[2].ticks == 2);
    assert!((l[3].height_m - 15.01e-6).abs() < 1e-12 && l[3].mean_force_z_n == 0.0);
    assert!(levels(&[]).is_empty());
}

/// The 3x wall with the passivity stage, in closed loop with the device plant at 10 kHz and the
/// firmware timing, stays within the encoder quantisation's floor (`encoder_cell::verdict`).
/// Measured: largest late peak to peak 4.23 µm, force standard deviation 0.92 N; bounds 3x those
/// (12.7 µm, 2.8 N), both inside the floor (one 22.6 µm cell, K·cell/2 = 4.06 N). With the wall
/// transparent through the contact's re-contact dwell (before the fix) it cycled at 31.4 µm and
/// 2.10 N. K is 3 × 119 708 N/m, the largest passive wall measured at this rate and timing
/// (`device_plant[0].kmax_firmware_timing` of `host-sim stability --json`).
#[test]
fn the_3x_wall_with_the_stage_stays_within_the_encoder_floor_on_the_device_plant() {
    let l = DeviceLoop::omega_like(10_000.0, 0.247, true);
    let k = 3.0 * 119_708.0;
    let (env, cycle) = envelope(&l, k).unwrap();
    let cell = encoder_cell::normal_cell_m(&DeviceParams::OMEGA_LIKE).unwrap();
    let v = encoder_cell::verdict(&env, cycle.force_z_std_n, k, cell).unwrap();
    assert!(v.bounded, "{v:?}");
    assert!(v.late_amp_max_m < 12.7e-6, "{v:?}");
    assert!(v.force_z_std_n < 2.8, "{v:?}");
}
