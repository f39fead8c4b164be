//! Plain-text tables for the terminal and the summary file.

/// A table: a header row and data rows of preformatted cells. The first column is left-aligned,
/// the others right-aligned.
#[derive(Clone, Debug, Default)]
pub struct Table {
    pub title: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn new(title: &str, header: &[&str]) -> Table {
        Table {
            title: title.to_string(),
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// Render with columns padded to their widest cell.
    pub fn render(&self) -> String {
        let ncol = self.header.len();
        let mut w = vec![0usize; ncol];
        for r in std::iter::once(&self.header).chain(&self.rows) {
            for (i, c) in r.iter().enumerate().take(ncol) {
                w[i] = w[i].max(c.chars().count());
            }
        }
        let line = |r: &Vec<String>| {
            let cells: Vec<String> = (0..ncol)
                .map(|i| {
                    let c = r.get(i).map_or("", String::as_str);
                    let pad = w[i].saturating_sub(c.chars().count());
                    if i == 0 {
                        format!("{c}{}", " ".repeat(pad))
                    } else {
                        format!("{}{c}", " ".repeat(pad))
                    }
                })
                .collect();
            cells.join("  ").trim_end().to_string()
        };
        let mut s = format!("{}\n", self.title);
        s += &line(&self.header);
        s.push('\n');
        s += &"-".repeat(w.iter().sum::<usize>() + 2 * ncol.saturating_sub(1));
        s.push('\n');
        for r in &self.rows {
            s += &line(r);
            s.push('\n');
        }
        s
    }
}

/// Short scientific notation: 1.23e-4.
pub fn sci(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_line_up() {
        let mut t = Table::new("T", &["name", "value"]);
        t.row(vec!["a".into(), "1".into()]);
        t.row(vec!["long".into(), "22.5".into()]);
        let s = t.render();
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines[1], "name  value");
        assert_eq!(lines[3], "a         1");
        assert_eq!(lines[4], "long   22.5");
        assert_eq!(sci(0.000123), "1.23e-4");
    }
}
