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
