//! Values set from outside a dataset: `mbfx run --set 'SPRINGDAMPER/1.K=2E4'` and Python's
//! `Model.with_values({"PART/2.MASS": 1.5})`.
//!
//! A setting names one argument of one statement, `KIND/ID.FIELD=VALUE` (`KIND.FIELD=VALUE`
//! for a statement without an id, such as ACCGRAV), with Adams' abbreviations for the kind
//! and the field. It replaces that argument's value in the dataset text, or adds the
//! argument to the statement when it is not written there, and the edited text is read
//! again: line numbers do not move, so every later diagnostic points at the line it would
//! in the file. The argument is written with the setting's own spelling of the field, so
//! the reader judges it as it judges a dataset: a field longer than the argument
//! (`MASSS`, `QPX`) or an abbreviation shorter than Adams' shortest is refused, not taken
//! for the argument it starts with, and the refusal names the nearest argument the
//! statement writes. Nothing is ignored: a statement the dataset does not have, a field the
//! statement does not take (the reader's W0602) and a value the reader refuses are each an
//! E0611 error at the setting, naming the statement.

use super::keywords::{abbreviates, lookup_statement, Lookup};
use super::reader::read_model;
use super::statement::{read_statements, Statement};
use crate::check::closest;
use crate::diag::{Code, Diagnostic, Severity, Span};

/// One parsed setting; spans index [`Settings::text`].
#[derive(Clone, Debug)]
struct Setting {
    /// The statement kind (canonical spelling).
    kind: &'static str,
    id: Option<i64>,
    field: String,
    value: String,
    /// `KIND/ID`, `FIELD` and `VALUE` as written.
    target_span: Span,
    field_span: Span,
    value_span: Span,
}

impl Setting {
    /// `KIND/ID`, the way messages name the statement.
    fn label(&self) -> String {
        match self.id {
            Some(id) => format!("{}/{id}", self.kind),
            None => self.kind.to_string(),
        }
    }
}

/// Settings as given, one a line of [`Settings::text`] (the source their diagnostics
/// point into).
#[derive(Clone, Debug, Default)]
pub struct Settings {
    text: String,
    items: Vec<Setting>,
}

/// One change to the dataset text: `old` replaced by `new`, which ends with the value
/// of setting `setting`.
struct Edit {
    old: Span,
    new: String,
    setting: usize,
    /// Where the statement starts, and the field as the statement spells it (or as the
    /// setting does when the statement lacks it): two edits with one key set one value.
    statement: usize,
    field: String,
}

impl Edit {
    /// True when `self` and `other` set the same field of the same statement; an added
    /// field matches any abbreviation of it.
    fn same_value(&self, other: &Edit) -> bool {
        self.statement == other.statement
            && (self.field == other.field
                || abbreviates(&self.field, &other.field, 2)
                || abbreviates(&other.field, &self.field, 2))
    }
}

/// Where an edit landed in the edited text: all of it, and its value.
struct Spliced {
    edit: Span,
    value: Span,
    setting: usize,
}

impl Settings {
    /// Parses `written` (each `KIND/ID.FIELD=VALUE`). The error's diagnostics index
    /// `Err.0`, the settings one a line.
    pub fn parse<S: AsRef<str>>(written: &[S]) -> Result<Settings, (String, Vec<Diagnostic>)> {
        if written.is_empty() {
            return Ok(Settings::default());
        }
        let text = written
            .iter()
            .map(|w| w.as_ref().replace('\n', " "))
            .collect::<Vec<_>>()
            .join("\n");
        let mut items = Vec::new();
        let mut errors = Vec::new();
        let mut start = 0;
        for line in text.split('\n') {
            match parse_one(line, start) {
                Ok(s) => items.push(s),
                Err(d) => errors.push(d),
            }
            start += line.len() + 1;
        }
        match errors.is_empty() {
            true => Ok(Settings { text, items }),
            false => Err((text, errors)),
        }
    }

    /// The settings, one a line: the source of [`Settings::apply`]'s diagnostics.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// True when every setting gives a design variable a number,
    /// `VARIABLE/ID.FUNCTION=NUMBER`: such settings can change a built simulation
    /// without reading or compiling the dataset again ([`Settings::design_values`]).
    pub fn only_design(&self) -> bool {
        self.items.iter().all(|s| design_setting(s).is_some())
    }

    /// The settings as design values (VARIABLE id, value), or None unless every setting
    /// gives a number to a VARIABLE that `is_design` accepts (a design variable of the
    /// dataset, [`super::elements::Model::design_value`], that the built simulation reads). A number reads
    /// as the dataset's expressions read it, so the value is the one [`Settings::apply`]
    /// would give the read model.
    pub fn design_values(&self, is_design: impl Fn(i64) -> bool) -> Option<Vec<(i64, f64)>> {
        self.items
            .iter()
            .map(|s| design_setting(s).filter(|&(id, _)| is_design(id)))
            .collect()
    }

    /// The dataset `dataset` with every setting applied, read again to check them; the
    /// diagnostics of a refusal index [`Settings::text`].
    pub fn apply(&self, dataset: &str) -> Result<String, Vec<Diagnostic>> {
        if self.items.is_empty() {
            return Ok(dataset.to_string());
        }
        let (stmts, _) = read_statements(dataset);
        let mut edits: Vec<Edit> = Vec::new();
        let mut errors = Vec::new();
        for (k, s) in self.items.iter().enumerate() {
            match edit_for(&stmts, s, k) {
                Ok(e) => {
                    if let Some(prev) = edits.iter().find(|p| p.same_value(&e)) {
                        let first = &self.items[prev.setting];
                        errors.push(
                            Diagnostic::error(
                                Code::BadSetting,
                                s.field_span.clone(),
                                format!("{}.{} is set twice", s.label(), s.field),
                            )
                            .with_label(first.field_span.clone(), "first set here"),
                        );
                    } else {
                        edits.push(e);
                    }
                }
                Err(d) => errors.push(d),
            }
        }
        // The edits that apply are read even when others did not, so that one run
        // reports every bad setting.
        let (edited, ranges) = splice(dataset, &mut edits, &self.items);
        let read = read_model(&edited);
        for d in &read.diagnostics {
            let refused = d.severity == Severity::Error || d.code == Code::UnsupportedStatement;
            let at = ranges.iter().find(|r| overlaps(&r.edit, &d.span));
            if let (
                true,
                Some(Spliced {
                    value, setting: k, ..
                }),
            ) = (refused, at)
            {
                let s = &self.items[*k];
                let message = match d.code {
                    Code::UnsupportedStatement => unknown_field(&stmts, s),
                    _ => format!("{}.{}: {}", s.label(), s.field, d.message),
                };
                let span = match d.code {
                    Code::UnsupportedStatement => s.field_span.clone(),
                    _ => within_value(s, &d.span, value),
                };
                let mut e = Diagnostic::error(Code::BadSetting, span, message);
                e.notes.clone_from(&d.notes);
                e.help.clone_from(&d.help);
                errors.push(e);
            }
        }
        match errors.is_empty() {
            true => Ok(edited),
            false => Err(errors),
        }
    }
}

/// `VARIABLE/ID.FUNCTION=NUMBER` as (ID, NUMBER): a number as the expression lexer
/// reads one (digits, a point, an exponent; no degree suffix), with a sign.
fn design_setting(s: &Setting) -> Option<(i64, f64)> {
    if s.kind != "VARIABLE" || !abbreviates(&s.field, "FUNCTION", 3) {
        return None;
    }
    let (negative, digits) = match s.value.as_bytes().first()? {
        b'-' => (true, s.value[1..].trim_start()),
        b'+' => (false, s.value[1..].trim_start()),
        _ => (false, s.value.as_str()),
    };
    let lexeme = digits
        .bytes()
        .all(|b| b.is_ascii_digit() || b".eE+-".contains(&b))
        && digits
            .bytes()
            .next()
            .is_some_and(|b| b.is_ascii_digit() || b == b'.');
    let x: f64 = digits.parse().ok().filter(|_| lexeme)?;
    Some((s.id?, if negative { -x } else { x }))
}

/// The part of `s`'s value that `span` marks in the edited text, where the value lies
/// at `value`; the whole value when `span` reaches outside it.
fn within_value(s: &Setting, span: &Span, value: &Span) -> Span {
    if span.start >= value.start && span.end <= value.end && span.start <= span.end {
        let from = s.value_span.start + (span.start - value.start);
        from..from + span.len()
    } else {
        s.value_span.clone()
    }
}

fn overlaps(a: &Span, b: &Span) -> bool {
    a.start < b.end.max(b.start + 1) && b.start < a.end
}

/// Applies `edits` (any order) to `text`: the new text and where each edit landed.
fn splice(text: &str, edits: &mut [Edit], items: &[Setting]) -> (String, Vec<Spliced>) {
    edits.sort_by_key(|e| e.old.start);
    let mut out = String::with_capacity(text.len() + 64);
    let mut landed = Vec::with_capacity(edits.len());
    let mut at = 0;
    for e in edits.iter() {
        out.push_str(&text[at..e.old.start]);
        let start = out.len();
        out.push_str(&e.new);
        let value_len = items[e.setting].value.len();
        landed.push(Spliced {
            edit: start..out.len(),
            value: out.len() - value_len..out.len(),
            setting: e.setting,
        });
        at = e.old.end;
    }
    out.push_str(&text[at..]);
    (out, landed)
}

/// The statement `s` names and the change to its field.
fn edit_for(stmts: &[Statement], s: &Setting, k: usize) -> Result<Edit, Diagnostic> {
    let Some(stmt) = stmts
        .iter()
        .find(|st| st.canonical == Some(s.kind) && st.id == s.id)
    else {
        let ids: Vec<String> = stmts
            .iter()
            .filter(|st| st.canonical == Some(s.kind))
            .filter_map(|st| st.id.map(|i| i.to_string()))
            .take(12)
            .collect();
        let d = Diagnostic::error(
            Code::BadSetting,
            s.target_span.clone(),
            format!("the dataset has no {}", s.label()),
        );
        return Err(match ids.is_empty() {
            true => d.with_note(format!("it has no {} statement", s.kind)),
            false => d.with_note(format!("its {} ids: {}", s.kind, ids.join(", "))),
        });
    };
    let field = &s.field;
    // The argument the setting replaces: the one written with the same name, else one
    // whose name starts the field's or starts with it. The field is written in its
    // place as the setting spells it, so the reader refuses one it does not know.
    let found = stmt
        .args
        .iter()
        .find(|a| a.name.eq_ignore_ascii_case(field))
        .or_else(|| stmt.args.iter().find(|a| abbreviates(&a.name, field, 2)))
        .or_else(|| stmt.args.iter().find(|a| abbreviates(field, &a.name, 2)));
    Ok(match found {
        Some(a) => Edit {
            old: a.span.clone(),
            new: format!("{}={}", s.field, s.value),
            setting: k,
            statement: stmt.span.start,
            field: a.name.to_ascii_uppercase(),
        },
        None => Edit {
            old: stmt.span.end..stmt.span.end,
            new: format!(", {}={}", s.field, s.value),
            setting: k,
            statement: stmt.span.start,
            field: s.field.clone(),
        },
    })
}

/// The refusal of a field the reader does not know on `s`'s statement, naming the
/// nearest argument the statement writes (the typo `MASSS` of `MASS`).
fn unknown_field(stmts: &[Statement], s: &Setting) -> String {
    let written: Vec<&str> = stmts
        .iter()
        .filter(|st| st.canonical == Some(s.kind) && st.id == s.id)
        .flat_map(|st| st.args.iter().map(|a| a.name.as_str()))
        .filter(|name| !name.eq_ignore_ascii_case(&s.field))
        .collect();
    let nearest = closest(&s.field, written.iter().copied()).or_else(|| {
        // A field that runs past an argument's name (`QPX` of `QP`).
        written
            .iter()
            .copied()
            .filter(|name| abbreviates(name, &s.field, 2))
            .max_by_key(|name| name.len())
    });
    let base = format!("{} takes no field {} that mbfx reads", s.label(), s.field);
    match nearest {
        Some(name) => format!("{base}; did you mean {name}?"),
        None => base,
    }
}

/// Parses one setting written at `offset` of the settings' text.
fn parse_one(line: &str, offset: usize) -> Result<Setting, Diagnostic> {
    let whole = offset..offset + line.len();
    let bad = |span: Span, msg: String| {
        Diagnostic::error(Code::BadSetting, span, msg)
            .with_help("write KIND/ID.FIELD=VALUE, e.g. --set SPRINGDAMPER/1.K=2E4")
    };
    let Some(eq) = line.find('=') else {
        return Err(bad(whole, format!("`{line}`: no `=`")));
    };
    let (left, value) = (&line[..eq], &line[eq + 1..]);
    let lead = value.len() - value.trim_start().len();
    let value_span = offset + eq + 1 + lead..offset + line.trim_end().len().max(eq + 1 + lead);
    if value.trim().is_empty() {
        return Err(bad(
            offset + eq..offset + eq + 1,
            format!("`{line}`: no value after `=`"),
        ));
    }
    let Some(dot) = left.find('.') else {
        return Err(bad(offset..offset + eq, format!("`{left}`: no `.FIELD`")));
    };
    let (target, field) = (left[..dot].trim(), left[dot + 1..].trim());
    let target_span = offset..offset + dot;
    let field_span = offset + dot + 1..offset + eq;
    if field.is_empty()
        || !field
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_')
    {
        return Err(bad(field_span, format!("`{field}` is not a field name")));
    }
    let (kind_text, id_text) = match target.split_once('/') {
        Some((k, i)) => (k.trim(), Some(i.trim())),
        None => (target, None),
    };
    let kind = match lookup_statement(kind_text) {
        Lookup::Known(k) => k,
        Lookup::Ambiguous(names) => {
            return Err(bad(
                target_span,
                format!("`{kind_text}` may be any of {}", names.join(", ")),
            ))
        }
        Lookup::Unknown => {
            return Err(bad(
                target_span,
                format!("no dataset statement is called `{kind_text}`"),
            ))
        }
    };
    let id = match (id_text, kind.has_id) {
        (Some(i), true) => match i.parse::<i64>() {
            Ok(id) => Some(id),
            Err(_) => return Err(bad(target_span, format!("`{i}` is not a statement id"))),
        },
        (None, true) => {
            return Err(bad(
                target_span,
                format!(
                    "{} needs an id: {}/ID.{field}",
                    kind.keyword.name, kind.keyword.name
                ),
            ))
        }
        (Some(_), false) => {
            return Err(bad(
                target_span,
                format!(
                    "{} has no id: {}.{field}",
                    kind.keyword.name, kind.keyword.name
                ),
            ))
        }
        (None, false) => None,
    };
    Ok(Setting {
        kind: kind.keyword.name,
        id,
        field: field.to_ascii_uppercase(),
        value: value.trim().to_string(),
        target_span,
        field_span,
        value_span,
    })
}

#[cfg(test)]
mod tests;
