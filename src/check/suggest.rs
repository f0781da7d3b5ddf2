//! "Did you mean …?" hints: the closest known name by edit distance.

/// Levenshtein distance between two ASCII strings.
fn distance(a: &str, b: &str) -> usize {
    let b = b.as_bytes();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.bytes().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// The candidate closest to `name`, if it is close enough to be a plausible typo
/// (at most one edit for short names, two for longer ones).
pub fn closest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let limit = if name.len() <= 3 { 1 } else { 2 };
    candidates
        // The distance is at least the difference in length.
        .filter(|c| c.len().abs_diff(name.len()) <= limit)
        .map(|c| (distance(name, c), c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, c)| (d, c.len()))
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_typos() {
        let names = ["STEP", "STEP5", "SIN", "SQRT"];
        assert_eq!(closest("STPE", names.into_iter()), Some("STEP"));
        assert_eq!(closest("SEP", names.into_iter()), Some("STEP"));
        assert_eq!(closest("XYZZY", names.into_iter()), None);
        assert_eq!(distance("kitten", "sitting"), 3);
    }
}
