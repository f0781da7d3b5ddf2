//! A dimension written by a user, for a variable of a plain expression (`mbfx eval --unit
//! v=velocity`, the REPL's `:let v: m/s = 2`, Python's `compile(..., units={"v":
//! "velocity"})`): a dimension's name ("velocity", "angular velocity", "stiffness"), a
//! base ("length"), a unit ("m", "newton", "rad") or a product, quotient and powers of
//! them (`m/s^2`, `N*m`, `kg*m/s^2`, `newton-meter`, `length^(1/2)`).
//!
//! Units stand for their dimension only: `mm` is a length as `m` is, since the check
//! compares dimensions, not scales. Names read case-insensitively; `*`, `/` and `-` (as
//! in "newton-meter") apply left to right as in arithmetic; `1`, `none` and
//! `dimensionless` are a pure number. The text `describe` prints ("a velocity
//! (meter/second)") reads back from its name or its unit.

use super::dim::Dim;
use super::names::NAMED;

/// Units and base names, and the dimension each stands for.
const UNITS: &[(&str, Dim)] = &[
    ("m", Dim::LENGTH),
    ("mm", Dim::LENGTH),
    ("cm", Dim::LENGTH),
    ("km", Dim::LENGTH),
    ("meter", Dim::LENGTH),
    ("millimeter", Dim::LENGTH),
    ("centimeter", Dim::LENGTH),
    ("kilometer", Dim::LENGTH),
    ("inch", Dim::LENGTH),
    ("foot", Dim::LENGTH),
    ("ft", Dim::LENGTH),
    ("in", Dim::LENGTH),
    ("s", Dim::TIME),
    ("ms", Dim::TIME),
    ("sec", Dim::TIME),
    ("second", Dim::TIME),
    ("millisecond", Dim::TIME),
    ("minute", Dim::TIME),
    ("min", Dim::TIME),
    ("hour", Dim::TIME),
    ("h", Dim::TIME),
    ("kg", Dim::MASS),
    ("g", Dim::MASS),
    ("kilogram", Dim::MASS),
    ("gram", Dim::MASS),
    ("tonne", Dim::MASS),
    ("slug", Dim::MASS),
    ("pound_mass", Dim::MASS),
    ("lbm", Dim::MASS),
    ("n", Dim::FORCE),
    ("kn", Dim::FORCE),
    ("newton", Dim::FORCE),
    ("kilonewton", Dim::FORCE),
    ("pound_force", Dim::FORCE),
    ("lbf", Dim::FORCE),
    ("rad", Dim::ANGLE),
    ("radian", Dim::ANGLE),
    ("deg", Dim::ANGLE),
    ("degree", Dim::ANGLE),
    ("hz", Dim::of(0, 0, -1, 0)),
    ("hertz", Dim::of(0, 0, -1, 0)),
    ("1", Dim::NONE),
    ("none", Dim::NONE),
    ("dimensionless", Dim::NONE),
];

/// Most characters a dimension may have: longer text is a mistake, not a unit.
const MAX_LEN: usize = 200;

/// Reads a dimension; the error says what is wrong and what would be read.
pub fn parse(text: &str) -> Result<Dim, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("a dimension is needed, e.g. length, velocity, force or m/s".into());
    }
    if t.len() > MAX_LEN {
        return Err(format!("a dimension of {} characters is too long", t.len()));
    }
    let mut tokens = tokens(t)?.into_iter().peekable();
    let mut dim = factor(&mut tokens, t)?;
    while let Some(op) = tokens.next() {
        let rhs = factor(&mut tokens, t)?;
        let combined = match op {
            Token::Times => dim.times(rhs),
            Token::Per => dim.per(rhs),
            _ => return Err(format!("`{t}`: expected `*` or `/` between units")),
        };
        dim = combined.ok_or_else(|| format!("`{t}`: an exponent is out of range"))?;
    }
    Ok(dim)
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Word(String),
    Times,
    Per,
    Power(f64),
}

/// `word [^ exponent]`.
fn factor(
    tokens: &mut std::iter::Peekable<std::vec::IntoIter<Token>>,
    t: &str,
) -> Result<Dim, String> {
    let base = match tokens.next() {
        Some(Token::Word(w)) => named(&w).ok_or_else(|| unknown(&w))?,
        _ => return Err(format!("`{t}`: expected a unit or a dimension's name")),
    };
    match tokens.peek() {
        Some(Token::Power(p)) => {
            let p = *p;
            tokens.next();
            base.pow(p).ok_or_else(|| {
                format!("`{t}`: the power {p} leaves the exponents' grid (multiples of 1/60)")
            })
        }
        _ => Ok(base),
    }
}

/// The dimension a word names: a unit, a base or a dimension's name ("angular_velocity"
/// for "angular velocity").
fn named(word: &str) -> Option<Dim> {
    if let Some((_, d)) = UNITS.iter().find(|(u, _)| *u == word) {
        return Some(*d);
    }
    let base = match word {
        "mass" => Some(Dim::MASS),
        "length" => Some(Dim::LENGTH),
        "time" => Some(Dim::TIME),
        "angle" => Some(Dim::ANGLE),
        _ => None,
    };
    base.or_else(|| {
        NAMED.iter().find_map(|(d, name)| {
            let bare = name.trim_start_matches("an ").trim_start_matches("a ");
            (bare.replace(' ', "_") == word).then_some(*d)
        })
    })
}

fn unknown(word: &str) -> String {
    format!(
        "`{}` is not a unit or a dimension; write e.g. length, velocity, force, angle, m/s or N*m",
        word.replace('_', " ")
    )
}

/// The tokens of a dimension's text: words (letters and digits, with the spaces between
/// words of one name joined by `_`), `*`, `·` and `-` (products), `/`, and `^EXP` where
/// EXP is a number or `(n/d)`.
fn tokens(t: &str) -> Result<Vec<Token>, String> {
    let lower = t.to_ascii_lowercase();
    let mut out = Vec::new();
    let mut chars = lower.char_indices().peekable();
    while let Some(&(i, c)) = chars.peek() {
        match c {
            ' ' | '\t' => {
                chars.next();
            }
            '*' | '·' | '-' => {
                chars.next();
                out.push(Token::Times);
            }
            '/' => {
                chars.next();
                out.push(Token::Per);
            }
            '^' => {
                chars.next();
                let rest = &lower[i + 1..];
                let (p, used) = exponent(rest).ok_or_else(|| {
                    format!("`{t}`: expected an exponent after `^`, e.g. ^2, ^-1 or ^(1/2)")
                })?;
                out.push(Token::Power(p));
                let end = i + 1 + used;
                while chars.peek().is_some_and(|&(j, _)| j < end) {
                    chars.next();
                }
            }
            c if c.is_ascii_alphanumeric() || c == '_' => {
                let mut word = String::new();
                while let Some(&(_, c)) = chars.peek() {
                    if c.is_ascii_alphanumeric() || c == '_' {
                        word.push(c);
                        chars.next();
                    } else if c == ' ' {
                        // "angular velocity" is one name.
                        let mut ahead = chars.clone();
                        ahead.next();
                        match ahead.peek() {
                            Some(&(_, n)) if n.is_ascii_alphabetic() => {
                                word.push('_');
                                chars.next();
                            }
                            _ => break,
                        }
                    } else {
                        break;
                    }
                }
                out.push(Token::Word(word));
            }
            other => return Err(format!("`{t}`: `{other}` has no place in a dimension")),
        }
    }
    // `-` only multiplies between words ("newton-meter"); elsewhere it is a mistake.
    Ok(out)
}

/// An exponent at the start of `s` (`2`, `-1`, `0.5`, `(1/2)`, `(-3/2)`) and the bytes it
/// takes.
fn exponent(s: &str) -> Option<(f64, usize)> {
    let s_trim = s.trim_start();
    let skipped = s.len() - s_trim.len();
    if let Some(inner) = s_trim.strip_prefix('(') {
        let close = inner.find(')')?;
        let body = &inner[..close];
        let value = match body.split_once('/') {
            Some((n, d)) => {
                let (n, d): (f64, f64) = (n.trim().parse().ok()?, d.trim().parse().ok()?);
                (d != 0.0).then(|| n / d)?
            }
            None => body.trim().parse().ok()?,
        };
        return Some((value, skipped + close + 2));
    }
    let len = s_trim
        .char_indices()
        .take_while(|&(k, c)| c.is_ascii_digit() || c == '.' || (k == 0 && (c == '-' || c == '+')))
        .count();
    let value: f64 = s_trim[..len].parse().ok()?;
    Some((value, skipped + len))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(t: &str) -> Dim {
        parse(t).unwrap_or_else(|e| panic!("{t}: {e}"))
    }

    #[test]
    fn names_bases_and_units_read_as_their_dimension() {
        assert_eq!(d("velocity"), Dim::VELOCITY);
        assert_eq!(d("Angular Velocity"), Dim::ANGULAR_VELOCITY);
        assert_eq!(d("length"), Dim::LENGTH);
        assert_eq!(d("stiffness"), Dim::of(1, 0, -2, 0));
        assert_eq!(d("torsional stiffness"), Dim::of(1, 2, -2, -1));
        assert_eq!(d("mm"), Dim::LENGTH);
        assert_eq!(d("N"), Dim::FORCE);
        assert_eq!(d("rad"), Dim::ANGLE);
        assert_eq!(d("dimensionless"), Dim::NONE);
        assert_eq!(d("1"), Dim::NONE);
    }

    #[test]
    fn products_quotients_and_powers_combine_left_to_right() {
        assert_eq!(d("m/s"), Dim::VELOCITY);
        assert_eq!(d("m/s^2"), Dim::ACCELERATION);
        assert_eq!(d("kg*m/s^2"), Dim::FORCE);
        assert_eq!(d("N*m"), Dim::TORQUE);
        assert_eq!(d("newton-meter"), Dim::TORQUE);
        assert_eq!(d("N/m"), Dim::of(1, 0, -2, 0));
        assert_eq!(d("s^-1"), Dim::of(0, 0, -1, 0));
        assert_eq!(
            d("length^(1/2)"),
            Dim::LENGTH.pow(0.5).expect("on the grid")
        );
        assert_eq!(d("m^0.5 * m^0.5"), Dim::LENGTH);
    }

    #[test]
    fn what_describe_prints_reads_back() {
        for (dim, _) in NAMED {
            let unit = super::super::names::unit(*dim, Some(&super::super::UnitNames::SI));
            if !unit.is_empty() {
                assert_eq!(d(&unit), *dim, "{unit}");
            }
        }
    }

    #[test]
    fn mistakes_are_named_not_guessed() {
        assert!(parse("").is_err());
        assert!(parse("furlong")
            .unwrap_err()
            .contains("`furlong` is not a unit"));
        assert!(parse("m/").is_err());
        assert!(parse("m^").unwrap_err().contains("exponent"));
        assert!(parse("m^(1/7)").unwrap_err().contains("grid"));
        assert!(parse("m % s").unwrap_err().contains("`%`"));
        assert!(parse("m s").is_err());
        assert!(parse(&"m*".repeat(300)).unwrap_err().contains("too long"));
        assert!(parse("m^(1/0)").is_err());
    }
}
