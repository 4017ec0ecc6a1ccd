//! Append-only CSV files whose rows survive `kill -9` whole (docs/scene-format.md, Outputs:
//! "Row layout").
//!
//! A step's rows go out in one write, but Linux copies a write into the page cache one page at
//! a time and, when the process has a fatal signal (SIGKILL), stops between pages: a write
//! can end at any 4096-byte boundary of the file it crosses. A row that straddles such a
//! boundary could therefore be cut. So no row straddles one: a row that would is moved to start
//! at the boundary, and the row before it is lengthened to fill the gap by writing its decimal
//! numbers with more digits of the same value (`0.25` → `0.2500`, `5e-9` → `5.00e-9`, `3` →
//! `3.00` or `03`; integer and text columns, named in [`FIXED`], are never touched). When the
//! row before is already in the file, it is written again in the same write; it lies in the
//! page that ends at the boundary, so the kernel replaces it whole or not at all. Pages larger
//! than 4096 bytes (16 or 64 KiB on some kernels) have boundaries at multiples of 4096 too.
//!
//! What a reader gets is the same values in every row; only the digits of one row in about
//! every 4096 bytes differ from the shortest form. A row longer than 4096 bytes, or one before
//! which no row can be lengthened (a header), is written as it is.

use std::fs::{self, File};
use std::io::{self, Seek, SeekFrom, Write};
use std::path::Path;

/// The boundary the kernel may cut a write at (the smallest page size of Linux).
pub const PAGE: u64 = 4096;

/// Columns never lengthened: integers and text (every other column holds decimal numbers).
pub const FIXED: [&str; 12] = [
    "step",
    "body",
    "body_a",
    "body_b",
    "kind",
    "state",
    "monitor",
    "connector",
    "contacts",
    "outer_iterations",
    "inner_iterations",
    "method",
];

/// One append-only file of rows and the rows of the current step, not yet written.
pub struct RowFile {
    file: File,
    /// Bytes in the file.
    len: u64,
    /// The file's last row (its bytes end at `len`), kept to be lengthened if need be.
    last: Vec<u8>,
    /// Per column: may its numbers be lengthened (from the header; none for a file without one).
    padded: Vec<bool>,
    /// Rows of the current step, each ending with a newline.
    pub rows: Vec<u8>,
    /// The bytes of the last write, kept for their storage.
    out: Vec<u8>,
}

impl RowFile {
    /// Creates the file at `path` (replacing any), with `header` as its first row unless empty.
    pub fn create(path: &Path, header: &str) -> io::Result<RowFile> {
        let file = File::create(path)?;
        let mut rows = RowFile {
            file,
            len: 0,
            last: Vec::new(),
            padded: columns(header),
            rows: Vec::new(),
            out: Vec::new(),
        };
        if !header.is_empty() {
            rows.rows.extend_from_slice(header.as_bytes());
            rows.rows.push(b'\n');
            rows.commit()?;
        }
        Ok(rows)
    }

    /// Opens the file at `path` to append to it: a CSV (`cut = Some(step)`) is first cut back
    /// after its last row of a step ≤ `step` ([`truncate_after_step`]); another file (`None`,
    /// `run.log`) is appended to as it is.
    pub fn reopen(path: &Path, cut: Option<usize>) -> io::Result<RowFile> {
        let (len, last, padded) = match cut {
            Some(step) => {
                let text = truncate_after_step(path, step)?;
                let header = text.split(|&b| b == b'\n').next().unwrap_or_default();
                let padded = columns(&String::from_utf8_lossy(header));
                let body = text.strip_suffix(b"\n").unwrap_or(&text);
                let start = body.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
                (text.len() as u64, text[start..].to_vec(), padded)
            }
            None => (fs::metadata(path)?.len(), Vec::new(), Vec::new()),
        };
        let file = fs::OpenOptions::new().write(true).open(path)?;
        Ok(RowFile { file, len, last, padded, rows: Vec::new(), out: Vec::new() })
    }

    /// Writes the current step's rows in one write, laid out so that none straddles a
    /// 4096-byte boundary of the file (module docs).
    pub fn commit(&mut self) -> io::Result<()> {
        if self.rows.is_empty() {
            return Ok(());
        }
        let (at, last) = layout(self.len, &self.last, &self.rows, &self.padded, &mut self.out);
        self.file.seek(SeekFrom::Start(at))?;
        self.file.write_all(&self.out)?;
        self.len = at + self.out.len() as u64;
        self.last.clear();
        self.last.extend_from_slice(&self.out[last..]);
        self.rows.clear();
        Ok(())
    }
}

/// Which columns of `header` may be lengthened.
fn columns(header: &str) -> Vec<bool> {
    if header.is_empty() {
        return Vec::new();
    }
    header.split(',').map(|name| !FIXED.contains(&name)).collect()
}

/// Where and what to write for `rows` after a file of `len` bytes whose last row is `last`:
/// the bytes go into `out` (cleared first), and `(offset, start of the last row in out)` is
/// returned. The offset is `len`, or the start of `last` when that row is lengthened so that
/// the first new row starts at a boundary.
///
/// Only a row that holds a boundary can need work, so the rows are not visited one by one: the
/// bytes up to the row that holds the next boundary are copied as they are, and that row is
/// handled as the row-by-row rule says (the tests check the two agree,
/// `hopping_from_boundary_to_boundary_is_row_by_row`).
pub(crate) fn layout(len: u64, last: &[u8], rows: &[u8], padded: &[bool], out: &mut Vec<u8>) -> (u64, usize) {
    let mut at = len;
    out.clear();
    let mut prev: Option<usize> = None; // start in `out` of the row before, when it is there
    let mut i = 0; // the next row of `rows` to copy
    while i < rows.len() {
        let here = at + out.len() as u64;
        let k = i + (PAGE - here % PAGE) as usize; // the byte of `rows` after the next boundary
        if k >= rows.len() {
            copy_rows(out, &mut prev, &rows[i..]);
            break;
        }
        let s = row_start(rows, i, k);
        copy_rows(out, &mut prev, &rows[i..s]);
        if s == k {
            i = s; // a row starts at the boundary
            continue;
        }
        let e = rows[k..].iter().position(|&b| b == b'\n').map_or(rows.len(), |n| k + n + 1);
        let row = &rows[s..e];
        let gap = PAGE - (at + out.len() as u64) % PAGE; // bytes to the next boundary
        if (row.len() as u64) > gap && (row.len() as u64) <= PAGE {
            to_boundary(&mut at, out, prev, (len, last), padded);
        }
        prev = Some(out.len());
        out.extend_from_slice(row);
        i = e;
    }
    (at, prev.unwrap_or(0))
}

/// Moves the next row to the boundary ahead of `at + out.len()` by lengthening the row before
/// it (at `prev` in `out`, or the file's last row `file.1`, which ends at `file.0`), if that
/// row lies in the page that ends at the boundary and has a number to lengthen; `at` moves
/// back to the start of the file's last row when that one is written again.
fn to_boundary(at: &mut u64, out: &mut Vec<u8>, prev: Option<usize>, file: (u64, &[u8]), padded: &[bool]) {
    let start = *at + out.len() as u64;
    let gap = PAGE - start % PAGE;
    let (before, before_start) = match prev {
        Some(i) => (&out[i..], *at + i as u64),
        None => (file.1, file.0 - file.1.len() as u64),
    };
    if before_start / PAGE == start / PAGE
        && let Some(longer) = lengthen(before, gap as usize, padded)
    {
        match prev {
            Some(i) => out.truncate(i),
            None => *at = before_start,
        }
        out.extend_from_slice(&longer);
        debug_assert_eq!((*at + out.len() as u64) % PAGE, 0);
    }
}

/// Start of the row of `rows` that holds byte `k`, searching back no further than `i` (a row
/// start).
fn row_start(rows: &[u8], i: usize, k: usize) -> usize {
    rows[i..k].iter().rposition(|&b| b == b'\n').map_or(i, |n| i + n + 1)
}

/// Appends whole rows to `out`, with `prev` set to the start of the last of them.
fn copy_rows(out: &mut Vec<u8>, prev: &mut Option<usize>, rows: &[u8]) {
    if let Some(last) = rows.len().checked_sub(1) {
        *prev = Some(out.len() + row_start(rows, 0, last));
        out.extend_from_slice(rows);
    }
}

/// `row` (ending with a newline) with `extra` more bytes, spread over its decimal numbers in
/// columns that may be lengthened, each keeping its value; None if it has no such number.
fn lengthen(row: &[u8], extra: usize, padded: &[bool]) -> Option<Vec<u8>> {
    let text = std::str::from_utf8(row.strip_suffix(b"\n")?).ok()?;
    let fields: Vec<&str> = text.split(',').collect();
    let numbers: Vec<usize> = (0..fields.len())
        .filter(|&i| padded.get(i).copied().unwrap_or(false) && is_decimal(fields[i]))
        .collect();
    if numbers.is_empty() {
        return None;
    }
    let mut longer: Vec<String> = fields.iter().map(|f| f.to_string()).collect();
    for (k, &i) in numbers.iter().enumerate() {
        let share = extra / numbers.len() + usize::from(k < extra % numbers.len());
        longer[i] = more_digits(fields[i], share);
    }
    let mut out = longer.join(",").into_bytes();
    out.push(b'\n');
    Some(out)
}

/// A finite decimal number as `Num` writes it: digits, a point, an exponent, a sign.
fn is_decimal(field: &str) -> bool {
    field.bytes().any(|b| b.is_ascii_digit())
        && field.bytes().all(|b| b.is_ascii_digit() || b".eE+-".contains(&b))
}

/// `field` written `n` bytes longer with the same value: zeros after the last digit of a
/// mantissa with a point, else a point and zeros (`n` ≥ 2) or a leading zero (`n` = 1).
fn more_digits(field: &str, n: usize) -> String {
    if n == 0 {
        return field.to_string();
    }
    let end = field.find(['e', 'E']).unwrap_or(field.len());
    let (mantissa, exponent) = field.split_at(end);
    if mantissa.contains('.') {
        format!("{mantissa}{}{exponent}", "0".repeat(n))
    } else if n >= 2 {
        format!("{mantissa}.{}{exponent}", "0".repeat(n - 1))
    } else {
        let sign = usize::from(field.starts_with(['-', '+']));
        format!("{}0{}", &field[..sign], &field[sign..])
    }
}

/// Cuts the CSV file at `path` after its last row of a step ≤ `step` (the header kept) and
/// returns what is left. Rows are in step order, so this keeps a prefix; a cut last row (no
/// newline) goes too.
pub(crate) fn truncate_after_step(path: &Path, step: usize) -> io::Result<Vec<u8>> {
    let mut text = fs::read(path)?;
    let mut keep = 0;
    let mut first = true;
    for line in text.split_inclusive(|&b| b == b'\n') {
        if !line.ends_with(b"\n") {
            break;
        }
        if !first {
            let field = line.split(|&b| b == b',').next().unwrap_or_default();
            let row_step = std::str::from_utf8(field).ok().and_then(|f| f.parse::<usize>().ok());
            if row_step.is_none_or(|r| r > step) {
                break;
            }
        }
        first = false;
        keep += line.len();
    }
    fs::OpenOptions::new().write(true).open(path)?.set_len(keep as u64)?;
    text.truncate(keep);
    Ok(text)
}

#[cfg(test)]
mod tests {
    //! The layout against its two promises, on random rows written in random steps: (1) every
    //! state a SIGKILL can leave (the file before a write, plus the write's bytes up to any
    //! 4096-byte boundary it crosses) holds whole rows only; (2) those rows hold the values
    //! written, integer and text fields byte for byte and decimal numbers as the same `f64`.
    use super::*;
    use crate::output::csv::Num;
    use proptest::prelude::*;

    const HEADER: &str = "step,time,body,x,vx,stress_x,state";

    /// One row of HEADER's columns from a seed: numbers of all magnitudes, some integral.
    fn row(step: usize, seed: u64) -> Vec<String> {
        let x = |k: u64| {
            let m = (seed.rotate_left(k as u32 * 7) % 100_000) as f64 / 7.0;
            match (seed >> k) % 5 {
                0 => 0.0,
                1 => m.round(),
                2 => -m * 1e-12,
                3 => m * 1e17,
                _ => m,
            }
        };
        let name =
            if seed.is_multiple_of(3) { format!("{}", seed % 50) } else { format!("disk{}", seed % 1000) };
        let state = if seed.is_multiple_of(2) { "stick" } else { "" };
        vec![
            step.to_string(),
            Num(step as f64 * 1e-3).to_string(),
            name,
            Num(x(1)).to_string(),
            Num(x(2)).to_string(),
            if seed.is_multiple_of(4) { String::new() } else { Num(x(3)).to_string() },
            state.to_string(),
        ]
    }

    /// Every whole row of `text` after the header, as fields; the rest must be empty.
    fn whole_rows(text: &[u8]) -> Vec<Vec<String>> {
        let tail = String::from_utf8_lossy(&text[text.len().saturating_sub(80)..]);
        assert!(text.is_empty() || text.ends_with(b"\n"), "a cut row at the end of …{tail:?}");
        let text = std::str::from_utf8(text).unwrap();
        text.lines().skip(1).map(|l| l.split(',').map(str::to_string).collect()).collect()
    }

    fn same_values(got: &[Vec<String>], want: &[Vec<String>]) {
        let padded = columns(HEADER);
        assert!(got.len() <= want.len());
        for (g, w) in got.iter().zip(want) {
            assert_eq!(g.len(), w.len());
            for (i, (a, b)) in g.iter().zip(w).enumerate() {
                if padded[i] && !b.is_empty() {
                    assert_eq!(
                        a.parse::<f64>().unwrap().to_bits(),
                        b.parse::<f64>().unwrap().to_bits(),
                        "{a} / {b}"
                    );
                } else {
                    assert_eq!(a, b);
                }
            }
        }
    }

    proptest! {
        #[test]
        fn a_kill_leaves_whole_rows_of_the_values_written(
            steps in prop::collection::vec((1usize..40, any::<u64>()), 1..60),
        ) {
            let mut file = format!("{HEADER}\n").into_bytes();
            let (padded, mut last) = (columns(HEADER), file.clone());
            let mut want = Vec::new();
            for (step, &(n, seed)) in steps.iter().enumerate() {
                let mut rows = Vec::new();
                for k in 0..n {
                    let r = row(step, seed.wrapping_mul(k as u64 + 1));
                    rows.extend_from_slice(r.join(",").as_bytes());
                    rows.push(b'\n');
                    want.push(r);
                }
                let mut out = Vec::new();
                let (at, start) = layout(file.len() as u64, &last, &rows, &padded, &mut out);
                let at = at as usize;
                prop_assert!(at <= file.len());
                // a kill at every boundary the write crosses
                for b in (at / 4096 + 1..).map(|p| p * 4096).take_while(|&b| b < at + out.len()) {
                    let mut state = file[..at].to_vec();
                    state.extend_from_slice(&out[..b - at]);
                    same_values(&whole_rows(&state), &want);
                }
                file.truncate(at);
                file.extend_from_slice(&out);
                last = out[start..].to_vec();
            }
            let rows = whole_rows(&file);
            prop_assert_eq!(rows.len(), want.len());
            same_values(&rows, &want);
        }
    }

    /// The layout rule as the module docs state it, one row at a time: every row that would
    /// straddle a boundary is moved to it ([`to_boundary`]). The specification [`layout`]
    /// hops through.
    fn layout_row_by_row(len: u64, last: &[u8], rows: &[u8], padded: &[bool]) -> (u64, Vec<u8>, usize) {
        let (mut at, mut out, mut prev) = (len, Vec::new(), None::<usize>);
        for row in rows.split_inclusive(|&b| b == b'\n') {
            let start = at + out.len() as u64;
            let gap = PAGE - start % PAGE;
            if !start.is_multiple_of(PAGE) && (row.len() as u64) > gap && (row.len() as u64) <= PAGE {
                to_boundary(&mut at, &mut out, prev, (len, last), padded);
            }
            prev = Some(out.len());
            out.extend_from_slice(row);
        }
        (at, out, prev.unwrap_or(0))
    }

    proptest! {
        /// Rows of any length from 1 byte to over a page (a long name), after a file of any
        /// length: the same bytes, offset and last row as the row-by-row rule.
        #[test]
        fn hopping_from_boundary_to_boundary_is_row_by_row(
            len in 0u64..20_000,
            last_len in 0usize..200,
            rows in prop::collection::vec((any::<u64>(), 0usize..6000, any::<bool>()), 0..400),
        ) {
            let padded = columns(HEADER);
            let last_len = last_len.min(len as usize);
            let mut last = row(0, len).join(",").into_bytes();
            last.push(b'\n');
            last.truncate(last_len); // a last row too short to lengthen is also a case
            let mut text = Vec::new();
            for &(seed, name, long) in &rows {
                let mut r = row(1, seed);
                if long {
                    r[2] = "n".repeat(name);
                }
                text.extend_from_slice(r.join(",").as_bytes());
                text.push(b'\n');
            }
            let mut out = vec![b'x'; 10]; // storage from an earlier write
            let (at, start) = layout(len, &last, &text, &padded, &mut out);
            prop_assert_eq!((at, out, start), layout_row_by_row(len, &last, &text, &padded));
        }
    }

    #[test]
    fn numbers_written_longer_keep_their_value() {
        assert_eq!(more_digits("0.25", 2), "0.2500");
        assert_eq!(more_digits("5e-9", 2), "5.0e-9");
        assert_eq!(more_digits("1.5e-28", 3), "1.5000e-28");
        assert_eq!(more_digits("3", 1), "03");
        assert_eq!(more_digits("-3", 1), "-03");
        assert_eq!(more_digits("-3", 4), "-3.000");
        // the step, body and state columns are never touched; 7 bytes over time and x
        let longer = lengthen(b"12,0.5,7,3,,NaN,stick\n", 7, &columns(HEADER)).unwrap();
        assert_eq!(String::from_utf8(longer).unwrap(), "12,0.50000,7,3.00,,NaN,stick\n");
    }
}
