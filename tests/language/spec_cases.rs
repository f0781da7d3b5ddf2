//! Every case of spec §8.1–8.4 (and the model-free ones of §8.5) from
//! `tests/data/spec_cases.txt`, with the spec's expected values.

use crate::support::{eval, ulps};

struct Case {
    id: String,
    label: String,
    input: String,
    time: f64,
    expected: String,
}

fn cases() -> Vec<Case> {
    let text = include_str!("../data/spec_cases.txt");
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let parts: Vec<&str> = l.splitn(4, '|').map(str::trim).collect();
            assert_eq!(parts.len(), 4, "malformed case line: {l}");
            let mut input = parts[2].replace("\\n", "\n");
            let mut time = 0.5;
            if let Some((expr, t)) = input.clone().split_once(" @time=") {
                time = t.parse().expect("time");
                input = expr.to_string();
            }
            Case {
                id: parts[0].to_string(),
                label: parts[1].to_string(),
                input,
                time,
                expected: parts[3].to_string(),
            }
        })
        .collect()
}

#[test]
fn spec_conformance_cases() {
    let all = cases();
    assert!(all.len() >= 140, "only {} cases read", all.len());
    let mut failures = Vec::new();
    for c in &all {
        assert!(
            ["doc", "decision", "U"].contains(&c.label.as_str()),
            "{}: bad label",
            c.id
        );
        let got = eval(&c.input, [0.5, 0.5, 0.5], c.time);
        let ok = match (c.expected.strip_prefix("error "), &got) {
            (Some(code), Err(diags)) => diags.iter().any(|d| d.code.as_str() == code),
            (Some(_), Ok(_)) => false,
            (None, Err(_)) => false,
            (None, Ok(vals)) => {
                let v = vals[0];
                match c.expected.as_str() {
                    "NaN" => v.is_nan(),
                    "inf" => v == f64::INFINITY,
                    "-inf" => v == f64::NEG_INFINITY,
                    e => {
                        let (num, tol) = match e.split_once(" ~") {
                            Some((n, t)) => (n, t.parse::<f64>().expect("tolerance")),
                            None => (e, 0.0),
                        };
                        let want: f64 = num
                            .parse()
                            .unwrap_or_else(|_| panic!("{}: bad number {e}", c.id));
                        ulps(v, want) <= 2 || (v - want).abs() <= tol * want.abs()
                    }
                }
            }
        };
        if !ok {
            let got = match got {
                Ok(v) => format!("{v:?}"),
                Err(d) => d
                    .iter()
                    .map(|d| format!("{} {}", d.code.as_str(), d.message))
                    .collect::<Vec<_>>()
                    .join("; "),
            };
            failures.push(format!(
                "{} [{}] {:?}: expected {}, got {got}",
                c.id, c.label, c.input, c.expected
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} failing cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
