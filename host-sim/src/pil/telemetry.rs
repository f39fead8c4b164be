//! defmt logs decoded on the host with the `defmt-decoder` crate against the firmware's ELF (the
//! emulated board's, or the STM32 build's with a raw RTT capture), and the telemetry records in
//! them written as CSV.
//!
//! The decoder renders each frame's message; a `PipelineRecord` renders as its derived `Format`
//! (`PipelineRecord { tick: 3, mode: Armed, state: Rolling, motor_counts: [..], .. }`), which
//! [`flatten`] turns into named columns (`tick`, `mode`, `state`, `motor_counts_0`..).

use super::PilError;
use crate::atomic_file::AtomicFile;
use crate::error::FileError;
use defmt_decoder::{DecodeError, Table};

/// One decoded frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Log level (`info`, `debug`...), if the frame has one.
    pub level: String,
    /// The rendered message.
    pub message: String,
}

/// All frames of a raw log, and how many bytes could not be decoded.
#[derive(Clone, Debug, Default)]
pub struct Log {
    pub frames: Vec<Frame>,
    pub malformed: usize,
}

/// Decode a raw defmt stream (rzCOBS frames as defmt-rtt or the emulated board write them).
pub fn decode(elf: &[u8], raw: &[u8]) -> Result<Log, PilError> {
    let table = Table::parse(elf)
        .map_err(|e| PilError::Elf(e.to_string()))?
        .ok_or(PilError::NoDefmt)?;
    let mut decoder = table.new_stream_decoder();
    decoder.received(raw);
    let mut log = Log::default();
    loop {
        match decoder.decode() {
            Ok(f) => log.frames.push(Frame {
                level: f
                    .level()
                    .map(|l| l.as_str().to_string())
                    .unwrap_or_default(),
                message: f.display_message().to_string(),
            }),
            Err(DecodeError::UnexpectedEof) => break,
            Err(DecodeError::Malformed) => log.malformed += 1,
        }
    }
    Ok(log)
}

/// The rendered record's leaf values with their column names, in order; `None` if `text` is not
/// a well-formed rendering.
pub fn flatten(text: &str) -> Option<Vec<(String, String)>> {
    let mut p = Parser {
        s: text.as_bytes(),
        i: 0,
    };
    let mut out = Vec::new();
    p.value("", &mut out)?;
    p.ws();
    (p.i == p.s.len()).then_some(out)
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

fn join(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}_{name}")
    }
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i] == b' ' {
            self.i += 1;
        }
    }
    fn eat(&mut self, c: u8) -> bool {
        self.ws();
        if self.s.get(self.i) == Some(&c) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn token(&mut self) -> Option<String> {
        self.ws();
        let start = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || b"_.-+".contains(&self.s[self.i]))
        {
            self.i += 1;
        }
        (self.i > start).then(|| String::from_utf8_lossy(&self.s[start..self.i]).into_owned())
    }
    fn value(&mut self, path: &str, out: &mut Vec<(String, String)>) -> Option<()> {
        if self.eat(b'[') {
            let mut k = 0;
            if self.eat(b']') {
                return Some(());
            }
            loop {
                self.value(&join(path, &k.to_string()), out)?;
                k += 1;
                if self.eat(b']') {
                    return Some(());
                }
                if !self.eat(b',') {
                    return None;
                }
            }
        }
        let token = self.token()?;
        if self.eat(b'{') {
            loop {
                if self.eat(b'}') {
                    return Some(());
                }
                let field = self.token()?;
                if !self.eat(b':') {
                    return None;
                }
                self.value(&join(path, &field), out)?;
                self.eat(b',');
            }
        }
        if self.eat(b'(') {
            self.value(path, out)?;
            return self.eat(b')').then_some(());
        }
        out.push((path.to_string(), token));
        Some(())
    }
}

/// The telemetry records of a log as rows of (column, value).
pub fn telemetry_rows(log: &Log) -> Vec<Vec<(String, String)>> {
    log.frames
        .iter()
        .filter(|f| f.message.starts_with("PipelineRecord {"))
        .filter_map(|f| flatten(&f.message))
        .collect()
}

/// Write rows (all with the first row's columns) as CSV, with `t_s` = tick / `rate_hz` first.
pub fn write_csv(
    path: &std::path::Path,
    rows: &[Vec<(String, String)>],
    rate_hz: u32,
) -> Result<(), FileError> {
    let mut file = AtomicFile::create(path).map_err(FileError::on(path, "cannot create"))?;
    let err = |e: csv::Error| FileError::on(path, "write failed")(e);
    let mut w = csv::Writer::from_writer(file.writer());
    let columns: Vec<&str> = rows
        .first()
        .map(|r| r.iter().map(|(c, _)| c.as_str()).collect())
        .unwrap_or_default();
    let mut header = vec!["t_s"];
    header.extend(&columns);
    w.write_record(&header).map_err(err)?;
    for row in rows {
        let tick: f64 = row
            .iter()
            .find(|(c, _)| c == "tick")
            .and_then(|(_, v)| v.parse().ok())
            .unwrap_or(f64::NAN);
        let mut record = vec![format!("{:.6}", tick / f64::from(rate_hz))];
        record.extend(row.iter().map(|(_, v)| v.clone()));
        w.write_record(&record).map_err(err)?;
    }
    w.flush().map_err(FileError::on(path, "write failed"))?;
    drop(w);
    file.commit().map_err(FileError::on(path, "cannot publish"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flattens_a_rendered_record() {
        let text = "TelemetryRecord { tick: 7, counts: [1, -2], probe_m: Vec3 { x: 0.5, y: -1e-3, z: 2 }, state: Rolling, flags: Flags(33), enable: true }";
        let cols = flatten(text).unwrap();
        let names: Vec<&str> = cols.iter().map(|(c, _)| c.as_str()).collect();
        assert_eq!(
            names,
            [
                "tick",
                "counts_0",
                "counts_1",
                "probe_m_x",
                "probe_m_y",
                "probe_m_z",
                "state",
                "flags",
                "enable"
            ]
        );
        assert_eq!(cols[4].1, "-1e-3");
        assert_eq!(cols[6].1, "Rolling");
        assert_eq!(cols[7].1, "33");
        assert!(flatten("{ tick: 7").is_none());
        assert!(flatten("{ tick 7 }").is_none());
    }
}
