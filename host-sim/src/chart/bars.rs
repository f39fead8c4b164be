//! Grouped bar charts on a log y axis, in the style of [`super::style`].

use super::style::{
    draw_side_legend, drawing_err, fmt_num, render_svg, split_for_legend, Area, Entry, Key, FONT,
};
use crate::error::ChartError;
use plotters::prelude::*;
use std::path::Path;

/// A grouped bar chart on a log y axis: `groups` (one colour and label each) × `categories`;
/// `values[g][c]`. Zero values draw no bar but a "0" at the floor. Every bar is annotated.
#[derive(Clone, Debug)]
pub struct BarChart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub categories: &'a [String],
    pub groups: &'a [(String, RGBColor)],
    pub values: &'a [Vec<f64>],
    /// The y axis, (min > 0, max).
    pub y_range: (f64, f64),
}

impl BarChart<'_> {
    /// Renders the chart and writes it atomically to `path`.
    pub fn write(&self, path: &Path) -> Result<(), ChartError> {
        render_svg(path, (1200, 560), |root| self.draw(root))
    }

    fn draw(&self, root: &Area) -> Result<(), ChartError> {
        let BarChart {
            title,
            x_label,
            y_label,
            categories,
            groups,
            values,
            y_range,
        } = *self;
        let e = drawing_err;
        let nc = categories.len() as f64;
        // The legend beside the bars, off the data.
        let entries: Vec<Entry> = groups
            .iter()
            .map(|(label, color)| Entry {
                label: label.clone(),
                key: Key::Fill(*color),
            })
            .collect();
        let root = &root.titled(title, (FONT, 20)).map_err(e)?;
        let (root, legend) = split_for_legend(root, &entries, 12);
        if let Some(l) = &legend {
            draw_side_legend(&l.margin(10, 0, 0, 0), &entries, 12)?;
        }
        let root = &root;
        let mut chart = ChartBuilder::on(root)
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(78)
            .build_cartesian_2d(0.0..nc, (y_range.0..y_range.1).log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .x_desc(x_label)
            .y_desc(y_label)
            .y_label_formatter(&|v| fmt_num(*v))
            .label_style((FONT, 13))
            .axis_desc_style((FONT, 15))
            .draw()
            .map_err(e)?;
        let ng = groups.len().max(1) as f64;
        let bw = 0.8 / ng;
        for (g, (label, color)) in groups.iter().enumerate() {
            let c = *color;
            let bars: Vec<_> = values[g]
                .iter()
                .enumerate()
                .filter(|(_, &v)| v > y_range.0)
                .map(|(i, &v)| {
                    let x0 = i as f64 + 0.1 + bw * g as f64;
                    Rectangle::new([(x0, y_range.0), (x0 + bw * 0.92, v)], c.filled())
                })
                .collect();
            chart
                .draw_series(bars)
                .map_err(e)?
                .label(label.as_str())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
            let texts: Vec<_> = values[g]
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    let x0 = i as f64 + 0.1 + bw * (g as f64 + 0.1);
                    let y = if v > y_range.0 {
                        v * 1.15
                    } else {
                        y_range.0 * 1.3
                    };
                    let t = if v >= 10.0 {
                        format!("{v:.0}")
                    } else {
                        fmt_num(v)
                    };
                    Text::new(t, (x0, y), (FONT, 10).into_font())
                })
                .collect();
            chart.draw_series(texts).map_err(e)?;
        }
        // Category labels under the axis, centred on each group of bars.
        for (i, c) in categories.iter().enumerate() {
            let px = chart.backend_coord(&(i as f64 + 0.5, y_range.0));
            root.draw(&Text::new(
                c.as_str(),
                (px.0 - 4 * c.len() as i32, px.1 + 8),
                (FONT, 13).into_font(),
            ))
            .map_err(e)?;
        }
        Ok(())
    }
}
