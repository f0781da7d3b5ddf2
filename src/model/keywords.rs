//! Keyword tables of the `.adm` statement layer: the dataset statements mbfx knows (with
//! whether they carry an `/id`), the arguments whose value is a FUNCTION expression, and
//! the arguments whose value is free text. Adams accepts abbreviated keywords (multibody
//! spec §1.6): a written keyword matches a table entry when it is a prefix of the full
//! spelling and at least the entry's minimum length long.

/// A keyword and the shortest abbreviation Adams accepts for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Keyword {
    /// The full spelling, upper case.
    pub name: &'static str,
    /// The shortest accepted prefix.
    pub min_len: usize,
}

impl Keyword {
    const fn new(name: &'static str, min_len: usize) -> Self {
        Keyword { name, min_len }
    }

    /// True when `written` (any case) is this keyword or an accepted abbreviation of it.
    pub fn matches(&self, written: &str) -> bool {
        abbreviates(written, self.name, self.min_len)
    }
}

/// True when `written` (any case) is a prefix of `full` at least `min_len` long.
pub fn abbreviates(written: &str, full: &str, min_len: usize) -> bool {
    written.len() >= min_len.max(1)
        && written.len() <= full.len()
        && full.as_bytes()[..written.len()].eq_ignore_ascii_case(written.as_bytes())
}

/// An argument whose value is a FUNCTION expression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExpressionArgument {
    /// Only on this statement (canonical name); `None`: on every statement.
    pub statement: Option<&'static str>,
    /// The argument name and its shortest accepted abbreviation.
    pub keyword: Keyword,
}

const fn any(name: &'static str, min_len: usize) -> ExpressionArgument {
    ExpressionArgument {
        statement: None,
        keyword: Keyword::new(name, min_len),
    }
}

/// Arguments whose value is a FUNCTION expression (spec §7): it runs to a `\`, to a comma
/// outside brackets, or to the end of the statement. One table for the whole dataset; the
/// model layer adds rows here when it learns new expression arguments.
pub const EXPRESSION_ARGUMENTS: &[ExpressionArgument] = &[
    any("FUNCTION", 2),
    any("F1", 2),
    any("F2", 2),
    any("F3", 2),
    any("F4", 2),
    any("F5", 2),
    any("F6", 2),
    any("F7", 2),
    any("F8", 2),
    any("FX", 2),
    any("FY", 2),
    any("FZ", 2),
    any("TX", 2),
    any("TY", 2),
    any("TZ", 2),
    any("FXYZ", 4),
    any("TXYZ", 4),
    // CONTACT's user-subroutine arguments (`NORMAL_FUNCTION = USER(…)`), refused by name.
    ExpressionArgument {
        statement: Some("CONTACT"),
        keyword: Keyword::new("NORMAL_FUNCTION", 8),
    },
    ExpressionArgument {
        statement: Some("CONTACT"),
        keyword: Keyword::new("FRICTION_FUNCTION", 10),
    },
    // BEAM has a numeric CRATIO (`CRATIO = 0.01` followed by `, FORMULATION = …`).
    ExpressionArgument {
        statement: Some("FLEX_BODY"),
        keyword: Keyword::new("CRATIO", 6),
    },
];

/// True when argument `name` of a statement `canonical` holds an expression.
pub fn is_expression_argument(canonical: Option<&str>, name: &str) -> bool {
    EXPRESSION_ARGUMENTS
        .iter()
        .any(|e| e.statement.is_none_or(|s| Some(s) == canonical) && e.keyword.matches(name))
}

/// Arguments whose value is free text up to the end of the physical line, blanks, colons
/// and parentheses included (`C=DISPLACEMENT: X Y Z PSI THETA PHI`, `STRING = .\a.ipt`):
/// pairs of statement (canonical name) and argument keyword.
pub const TEXT_ARGUMENTS: &[(&str, Keyword)] = &[
    ("REQUEST", Keyword::new("COMMENT", 1)),
    ("MREQUEST", Keyword::new("COMMENT", 1)),
    ("RESULTS", Keyword::new("COMMENT", 4)),
    ("STRING", Keyword::new("STRING", 3)),
    // Command files (`.acf`): `file/model=C:\Users\…\test` is a path, `\` and all.
    ("FILE", Keyword::new("MODEL", 1)),
    ("FILE", Keyword::new("COMMAND", 1)),
];

/// True when argument `name` of a statement `canonical` holds free text.
pub fn is_text_argument(canonical: Option<&str>, name: &str) -> bool {
    canonical.is_some_and(|stmt| {
        TEXT_ARGUMENTS
            .iter()
            .any(|(s, k)| *s == stmt && k.matches(name))
    })
}

/// A dataset statement mbfx recognises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatementKind {
    /// The statement name and its shortest accepted abbreviation.
    pub keyword: Keyword,
    /// `NAME/id` (true) or a singleton such as `UNITS/` and `END` (false).
    pub has_id: bool,
}

const fn id(name: &'static str) -> StatementKind {
    StatementKind {
        keyword: Keyword::new(name, 3),
        has_id: true,
    }
}

const fn single(name: &'static str) -> StatementKind {
    StatementKind {
        keyword: Keyword::new(name, if name.len() < 3 { name.len() } else { 3 }),
        has_id: false,
    }
}

/// The Adams Solver dataset statements (multibody spec §1.5, §2.5). Any unique prefix of
/// at least three letters is accepted (`JOI` for `JOINT`).
pub const STATEMENTS: &[StatementKind] = &[
    single("ACCGRAV"),
    id("ARRAY"),
    id("BEAM"),
    id("BUSHING"),
    id("CLEARANCE"),
    id("CONTACT"),
    id("COUPLER"),
    id("CURVE"),
    id("CVCV"),
    single("DEBUG"),
    id("DIFF"),
    single("END"),
    single("ENVIRONMENT"),
    single("EQUILIBRIUM"),
    id("FE_LOAD"),
    id("FE_NODE"),
    id("FE_PART"),
    id("FIELD"),
    id("FLEX_BODY"),
    id("FRICTION"),
    id("GCON"),
    id("GEAR"),
    id("GFORCE"),
    id("GRAPHICS"),
    id("GSE"),
    single("IC"),
    single("INTEGRATOR"),
    id("JOINT"),
    id("JPRIM"),
    single("KINEMATICS"),
    id("LSE"),
    single("LSOLVER"),
    id("MARKER"),
    id("MATERIAL"),
    id("MATRIX"),
    id("MFORCE"),
    id("MOTION"),
    id("MREQUEST"),
    id("NFORCE"),
    single("OUTPUT"),
    id("PART"),
    id("PINPUT"),
    id("POINT_MASS"),
    id("POUTPUT"),
    single("PREFERENCES"),
    id("PTCV"),
    id("REQUEST"),
    single("RESULTS"),
    id("SECTION"),
    id("SENSOR"),
    id("SFORCE"),
    id("SPLINE"),
    id("SPRINGDAMPER"),
    id("STRING"),
    id("SURFACE"),
    id("TFSISO"),
    single("UNITS"),
    id("VARIABLE"),
    id("VFORCE"),
    id("VTORQUE"),
];

/// What a written statement keyword names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// One statement, or an abbreviation of only that one.
    Known(StatementKind),
    /// A prefix of several statements.
    Ambiguous(Vec<&'static str>),
    /// No statement mbfx knows.
    Unknown,
}

/// Looks a written statement keyword up in [`STATEMENTS`]: an exact spelling wins, then
/// a unique accepted abbreviation.
pub fn lookup_statement(written: &str) -> Lookup {
    if let Some(k) = STATEMENTS
        .iter()
        .find(|k| k.keyword.name.eq_ignore_ascii_case(written))
    {
        return Lookup::Known(*k);
    }
    let hits: Vec<&StatementKind> = STATEMENTS
        .iter()
        .filter(|k| k.keyword.matches(written))
        .collect();
    match hits.as_slice() {
        [] => Lookup::Unknown,
        [one] => Lookup::Known(**one),
        many => Lookup::Ambiguous(many.iter().map(|k| k.keyword.name).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn function_abbreviations_are_expression_arguments() {
        for name in [
            "FU", "fun", "FUNC", "Functio", "FUNCTION", "F1", "f8", "FX", "TZ",
        ] {
            assert!(is_expression_argument(Some("SFORCE"), name), "{name}");
            assert!(is_expression_argument(None, name), "{name}");
        }
        for name in ["F", "F9", "FUNCTIONS", "FORCE", "I", "TXY", "CRATI"] {
            assert!(!is_expression_argument(Some("FLEX_BODY"), name), "{name}");
        }
        assert!(is_expression_argument(Some("FLEX_BODY"), "CRATIO"));
        assert!(!is_expression_argument(Some("BEAM"), "CRATIO"));
    }

    #[test]
    fn statement_prefixes_resolve_when_unique() {
        assert!(matches!(lookup_statement("JOI"), Lookup::Known(k) if k.keyword.name == "JOINT"));
        assert!(matches!(lookup_statement("ic"), Lookup::Known(k) if !k.has_id));
        assert!(matches!(lookup_statement("END"), Lookup::Known(k) if !k.has_id));
        assert!(matches!(lookup_statement("MAT"), Lookup::Ambiguous(v) if v.len() == 2));
        assert_eq!(lookup_statement("JO"), Lookup::Unknown);
        assert_eq!(lookup_statement("LEONARDO"), Lookup::Unknown);
    }

    #[test]
    fn text_arguments_depend_on_the_statement() {
        assert!(is_text_argument(Some("REQUEST"), "C"));
        assert!(is_text_argument(Some("STRING"), "STRING"));
        assert!(!is_text_argument(Some("SPRINGDAMPER"), "C"));
        assert!(!is_text_argument(None, "COMMENT"));
    }
}
