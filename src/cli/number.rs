//! Numbers as CSV text: the shortest text that reads back to the same bits, written
//! without an allocation. Rust's `{:?}` gives such a text too, but costs some 130 ns a
//! number here (Grisu through the formatting machinery), which made a run's text cost
//! more than its integration once rows come from dense output; Ryū takes about 40 ns.
//! The two texts differ only where neither is wrong: Ryū writes 1e-5 ≤ |x| < 1e-4 as
//! decimals, and breaks a tie between two 17-digit texts of the same number the other way.

/// Scratch for [`Shortest::text`].
#[derive(Default)]
pub struct Shortest {
    ryu: ryu::Buffer,
}

impl Shortest {
    /// The shortest text of `x` that parses back to `x` bit for bit (`NaN`, `inf` and
    /// `-inf` as Rust writes them).
    pub fn text(&mut self, x: f64) -> &str {
        self.ryu.format(x)
    }

    /// Appends the CSV line of `row` to `line`: each number's [`Shortest::text`],
    /// comma-separated, then a newline. A number's text never needs quoting, so the
    /// line is written straight, not field by field through a CSV writer (whose
    /// per-field checks cost as much as the number's digits).
    pub fn line(&mut self, row: &[f64], line: &mut Vec<u8>) {
        for (k, &x) in row.iter().enumerate() {
            if k > 0 {
                line.push(b',');
            }
            line.extend_from_slice(self.text(x).as_bytes());
        }
        line.push(b'\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_text_reads_back_to_its_bits_and_is_no_longer_than_rusts() {
        let mut s = Shortest::default();
        let edges = [
            0.0,
            -0.0,
            1.0,
            0.1,
            9.9e-5,
            1e16,
            1658206780088562.3,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
        ];
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let random = (0..200_000).map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            f64::from_bits(x)
        });
        let scaled = (0..20_000).map(|i| (i as f64 * 0.37).sin() * 10f64.powi(i % 40 - 20));
        for v in edges.into_iter().chain(random).chain(scaled) {
            let text = s.text(v);
            if v.is_nan() {
                assert_eq!(text, "NaN");
                continue;
            }
            let back: f64 = text.parse().expect("a number");
            assert_eq!(back.to_bits(), v.to_bits(), "{text}");
            let debug = format!("{v:?}");
            let digits = |t: &str| {
                t.split('e')
                    .next()
                    .map_or(0, |m| m.trim_start_matches(['-', '0', '.']).len())
            };
            assert!(digits(text) <= digits(&debug), "{text} against {debug}");
        }
        assert_eq!(s.text(f64::INFINITY), "inf");
        assert_eq!(s.text(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn a_line_is_what_a_csv_reader_reads_back() {
        let row = [0.0, -1.5e-7, 0.1, f64::MAX, 3.0];
        let mut line = Vec::new();
        let mut s = Shortest::default();
        s.line(&row, &mut line);
        s.line(&row[..1], &mut line);
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(line.as_slice());
        let records: Vec<csv::StringRecord> =
            reader.records().map(|r| r.expect("a record")).collect();
        assert_eq!(records.len(), 2);
        let back: Vec<f64> = records[0]
            .iter()
            .map(|f| f.parse().expect("a number"))
            .collect();
        assert_eq!(back, row);
        assert_eq!(&records[1][0], "0.0");
        assert!(line.ends_with(b"\n0.0\n"));
    }
}
