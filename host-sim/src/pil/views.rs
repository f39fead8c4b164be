//! What host-sim makes of decoded telemetry records: a force chart (SVG), and the wrist
//! orientations as `host-sim replay` input (`t_s,qw,qx,qy,qz`), so a log taken on the device (or
//! the emulated board) is looked at and replayed on the PC.

use crate::atomic_file::AtomicFile;
use crate::chart::lines::{line_chart, Axes, Series, Style};
use crate::chart::style::{linear_range, PALETTE};
use crate::error::{ChartError, FileError};
use softfinger_core::device::DeviceParams;
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::Libm;
use std::path::Path;

/// A record's value of `column` as f64 (NaN when absent or not a number).
fn value(row: &[(String, String)], column: &str) -> f64 {
    row.iter()
        .find(|(c, _)| c == column)
        .and_then(|(_, v)| v.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Seconds of a record: its tick at `rate_hz`.
fn t_s(row: &[(String, String)], rate_hz: u32) -> f64 {
    value(row, "tick") / f64::from(rate_hz)
}

/// The rendered force (`force_mn_*`, base frame) against time, in N.
pub fn force_chart(
    path: &Path,
    rows: &[Vec<(String, String)>],
    rate_hz: u32,
) -> Result<(), ChartError> {
    let series: Vec<Series> = ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(i, axis)| Series {
            label: format!("F{axis}"),
            color: PALETTE[i],
            style: Style::Line,
            points: rows
                .iter()
                .map(|r| (t_s(r, rate_hz), value(r, &format!("force_mn_{i}")) / 1000.0))
                .collect(),
        })
        .collect();
    let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let axes = Axes {
        title: "Rendered force (telemetry)".into(),
        x_label: "t (s)".into(),
        y_label: "force (N)".into(),
        x: linear_range(xs, 1e-3, 0.0),
        y: linear_range(ys, 0.1, 0.3),
        ..Axes::default()
    };
    line_chart(path, 900, 600, &[(axes, series)])
}

/// The handle orientation of each record from its wrist counts (the device's wrist
/// kinematics), as `host-sim replay` reads it.
pub fn replay_csv(
    path: &Path,
    rows: &[Vec<(String, String)>],
    rate_hz: u32,
) -> Result<(), FileError> {
    let mut file = AtomicFile::create(path).map_err(FileError::on(path, "cannot create"))?;
    let mut w = csv::Writer::from_writer(file.writer());
    let err = |e: csv::Error| FileError::on(path, "write failed")(e);
    w.write_record(crate::experiments::replay::INPUT_HEADER)
        .map_err(err)?;
    let device = OMEGA_LIKE.params;
    for r in rows {
        let angles: [f32; 3] = std::array::from_fn(|i| {
            let counts = value(r, &format!("wrist_counts_{i}"));
            device.wrist_counts_to_angle_rad(if counts.is_finite() { counts as i32 } else { 0 })
        });
        let q = DeviceParams::wrist_orientation::<Libm>(angles);
        w.write_record([
            format!("{:.6}", t_s(r, rate_hz)),
            q.w.to_string(),
            q.x.to_string(),
            q.y.to_string(),
            q.z.to_string(),
        ])
        .map_err(err)?;
    }
    w.flush().map_err(FileError::on(path, "write failed"))?;
    drop(w);
    file.commit().map_err(FileError::on(path, "cannot publish"))
}
