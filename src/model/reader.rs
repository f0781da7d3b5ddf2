//! The model reader: from the statements of an `.adm` dataset to a [`Model`] (spec §1–§2,
//! §4, §7, §8). A first pass collects the ids every statement kind defines (duplicates are
//! `E0603`), so references may point forward and expressions can be checked against the
//! whole dataset; then UNITS (the units check of expressions names its units), MARKER,
//! PART and JOINT statements are read (later statements look their parts and kinds up),
//! then everything else in file order. Each statement kind has
//! its reader in `read_*`, with the shared checks of marker references and expressions in
//! `resolve`; this module holds the passes and the whole-model checks (one GROUND).
//!
//! Statements and arguments outside the subset are warnings (`W0602`), never dropped
//! silently; errors point into the file. The model is built as far as the errors allow:
//! it is meant for the multibody core only when the read has no errors.

use super::elements::{Id, Ignored, Model, Omission};
use super::scope::ModelScope;
use super::statement::{read_statements, title_span, ItemKind, Statement};
use super::stmt_args::{statement_label, Args};
use super::{read_bodies, read_contact, read_data, read_graphics, read_links, read_states};
use crate::check::Expect;
use crate::diag::{has_errors, Code, Diagnostic};
use std::collections::{BTreeMap, HashMap, HashSet};

/// What [`read_model`] returns: the model and every diagnostic, in file order.
#[derive(Debug)]
pub struct ModelRead {
    /// The dataset, with every id reference checked.
    pub model: Model,
    /// Every diagnostic, in file order.
    pub diagnostics: Vec<Diagnostic>,
    /// The scope the dataset's expressions were checked in, kept for more expressions.
    scope: ModelScope,
}

impl ModelRead {
    /// True when the dataset has errors: the model is then incomplete.
    pub fn has_errors(&self) -> bool {
        has_errors(&self.diagnostics)
    }

    /// Checks and lowers one more expression against the model (`mbfx eval --model`, the
    /// REPL's `:load`): its measures become slots of `model.measures` like the dataset's
    /// own, and it may read the user `variables` too.
    pub fn compile(
        &mut self,
        text: &str,
        variables: &crate::check::Variables,
        expect: Expect,
    ) -> Result<crate::check::Checked, Vec<Diagnostic>> {
        let scope = super::scope::WithVariables {
            model: &self.scope,
            variables,
        };
        let result = crate::check::compile(text, &scope, expect);
        self.model.measures = self.scope.slots();
        let warnings = self.scope.take_warnings();
        result.map(|mut c| {
            c.warnings.extend(warnings);
            c
        })
    }
}

impl ModelRead {
    /// The scope the dataset's expressions were checked in: its units, measures and
    /// VARIABLEs (for the units of an expression typed against the model, `:units`).
    pub fn scope(&self) -> &ModelScope {
        &self.scope
    }
}

/// Reads a dataset text (already decoded, see [`super::decode`]) into a [`Model`].
pub fn read_model(text: &str) -> ModelRead {
    let (stmts, diags) = read_statements(text);
    let mut r = Reader {
        text,
        model: Model::default(),
        scope: ModelScope::default(),
        diags,
        markers: HashMap::new(),
        foreign_markers: HashSet::new(),
        unsupported: BTreeMap::new(),
        unknown: BTreeMap::new(),
        user_calls: Vec::new(),
        singletons: HashMap::new(),
    };
    r.model.title = text[title_span(text)].trim().to_string();
    // Keywords mbfx does not know are warned about one by one as they are read; kept
    // here so a run can say what it leaves out.
    for s in stmts.iter().filter(|s| s.canonical.is_none()) {
        if matches!(
            super::keywords::lookup_statement(&s.keyword),
            super::keywords::Lookup::Unknown
        ) {
            r.unknown.entry(s.keyword.clone()).or_default().push(s);
        }
    }
    let keep = r.collect_ids(&stmts);
    let kept: Vec<&Statement> = stmts
        .iter()
        .zip(&keep)
        .filter_map(|(s, k)| k.then_some(s))
        .collect();
    // UNITS first: the units check of every expression names the dataset's units.
    for phase in [
        Some("UNITS"),
        Some("MARKER"),
        Some("PART"),
        Some("JOINT"),
        None,
    ] {
        for stmt in &kept {
            let first = matches!(stmt.canonical, Some("UNITS" | "MARKER" | "PART" | "JOINT"));
            if phase.map_or(!first, |p| stmt.canonical == Some(p)) {
                r.statement(stmt);
            }
        }
    }
    r.finish()
}

/// The state of one read.
pub(super) struct Reader<'a> {
    pub text: &'a str,
    pub model: Model,
    pub scope: ModelScope,
    pub diags: Vec<Diagnostic>,
    /// Index in `model.markers` of each marker id.
    pub(super) markers: HashMap<Id, usize>,
    /// MARKER ids on something other than a rigid PART (warned and left out): a graphic
    /// may still name them.
    pub(super) foreign_markers: HashSet<i64>,
    /// Statements outside the subset, per keyword.
    unsupported: BTreeMap<&'static str, Vec<&'a Statement>>,
    /// Statements whose keyword mbfx does not know, per keyword as written.
    unknown: BTreeMap<String, Vec<&'a Statement>>,
    /// Statements of a modelled kind with a `USER(…)` value that may move something.
    user_calls: Vec<&'a Statement>,
    /// The first UNITS and ACCGRAV statement.
    singletons: HashMap<&'static str, &'a Statement>,
}

/// Statement kinds whose absence cannot change the motion: a run leaves them out without
/// a word (`check` still lists those outside the subset). Any other kind the reader does
/// not model, and any keyword it does not know, counts as physics left out. GRAPHICS is
/// read into `Model::graphics` for the kinds `read_graphics` knows; the others (contact
/// geometry such as POINT) stay outside the subset, quiet like these.
pub const QUIET_STATEMENTS: &[(&str, &str)] = &[
    // Output and display.
    ("DEBUG", "what the solver prints"),
    (
        "GRAPHICS",
        "shapes to draw (a CONTACT's geometry is warned with the CONTACT)",
    ),
    ("MREQUEST", "output columns"),
    (
        "REQUEST",
        "output columns (a USER one loses a column, not motion)",
    ),
    // How Adams solves, not what.
    ("PREFERENCES", "solver and contact-library preferences"),
    ("LSOLVER", "the linear-equation solver"),
    // Data only other statements read: a reader mbfx leaves out is warned itself.
    ("MATERIAL", "material data of flexible bodies and contacts"),
    ("SECTION", "beam cross-sections"),
    ("MATRIX", "data of LSE, GSE, FIELD and flexible bodies"),
    (
        "CURVE",
        "data of PTCV and CVCV (the CURVE function is an error)",
    ),
    ("SURFACE", "contact geometry"),
    ("STRING", "text passed to user subroutines"),
];

/// Whether leaving out statements of `kind` can change the motion.
fn is_physical(kind: &str) -> bool {
    !QUIET_STATEMENTS.iter().any(|(quiet, _)| *quiet == kind)
}

/// Markers not on a rigid PART (spec §2.3): arguments that put a marker elsewhere.
const FOREIGN_MARKER_ARGUMENTS: &[&str] =
    &["FLEX_BODY", "POINT_MASS", "FE_PART", "NODE_ID", "CURVE"];

impl<'a> Reader<'a> {
    /// First pass: the ids of every statement kind; returns which statements to read
    /// (duplicates and statements without their id are left out).
    fn collect_ids(&mut self, stmts: &'a [Statement]) -> Vec<bool> {
        let mut first: HashMap<(&str, i64), &Statement> = HashMap::new();
        let mut keep = vec![true; stmts.len()];
        for (k, s) in stmts.iter().enumerate() {
            let Some(kind) = s.canonical else {
                keep[k] = false;
                continue;
            };
            let needs_id = matches!(
                super::keywords::lookup_statement(kind),
                super::keywords::Lookup::Known(sk) if sk.has_id
            );
            let Some(id) = s.id else {
                keep[k] = !needs_id;
                continue;
            };
            if Id::try_from(id).is_err() {
                self.diags.push(Diagnostic::error(
                    Code::BadArgument,
                    s.id_span.clone().unwrap_or(s.keyword_span.clone()),
                    format!("{kind}/{id}: ids go up to {}", Id::MAX),
                ));
                keep[k] = false;
                continue;
            }
            if let Some(prev) = first.get(&(kind, id)) {
                self.diags.push(
                    Diagnostic::error(
                        Code::DuplicateId,
                        s.id_span.clone().unwrap_or(s.keyword_span.clone()),
                        format!("{kind}/{id} is defined twice"),
                    )
                    .with_label(prev.keyword_span.clone(), "first defined here")
                    .with_help("ids are unique per statement kind; this statement is ignored"),
                );
                keep[k] = false;
                continue;
            }
            first.insert((kind, id), s);
            match kind {
                "VARIABLE" => self.variable_source(id, s),
                "PINPUT" => self.controller_inputs(s),
                _ => {}
            }
            let foreign = kind == "MARKER"
                && s.args.iter().any(|a| {
                    FOREIGN_MARKER_ARGUMENTS
                        .iter()
                        .any(|f| super::keywords::abbreviates(&a.name, f, 4))
                });
            if foreign {
                self.foreign_markers.insert(id);
                self.diags.push(Diagnostic::warning(
                    Code::UnsupportedStatement,
                    s.keyword_span.clone(),
                    format!(
                        "{} (line {}) is not on a rigid PART; mbfx does not model it",
                        statement_label(s),
                        s.line
                    ),
                ));
                keep[k] = false;
                continue;
            }
            self.scope.ids.entry(kind).or_default().insert(id);
            if s.args.iter().any(|a| a.is_user_call) {
                self.scope.user.insert((kind, id));
            }
            // A SPLINE read from a file is warned about and left out of the model.
            if kind == "SPLINE" && s.arg("FILE", 3).is_none() {
                let surface = s.arg("Z", 1).is_some();
                self.scope.splines.push((id, surface));
            }
        }
        keep
    }

    fn statement(&mut self, stmt: &'a Statement) {
        if let Some(kind @ ("UNITS" | "ACCGRAV")) = stmt.canonical {
            if let Some(first) = self.singletons.insert(kind, stmt) {
                self.diags.push(
                    Diagnostic::warning(
                        Code::UnsupportedStatement,
                        stmt.keyword_span.clone(),
                        format!("{kind} is given again; this one replaces the first"),
                    )
                    .with_label(first.keyword_span.clone(), "first given here"),
                );
            }
        }
        let mut a = Args::new(stmt);
        match stmt.canonical.unwrap_or("") {
            "UNITS" => read_bodies::units(self, &mut a),
            "ACCGRAV" => read_bodies::accgrav(self, &mut a),
            "PART" => read_bodies::part(self, &mut a),
            "MARKER" => read_bodies::marker(self, &mut a),
            "JOINT" => read_links::joint(self, &mut a),
            "JPRIM" => read_links::jprim(self, &mut a),
            "GCON" => read_links::gcon(self, &mut a),
            "MOTION" => read_links::motion(self, &mut a),
            "SFORCE" => read_links::sforce(self, &mut a),
            "VFORCE" | "VTORQUE" | "GFORCE" => read_links::vector_force(self, &mut a),
            "SPRINGDAMPER" => read_links::spring_damper(self, &mut a),
            "BUSHING" => read_links::bushing(self, &mut a),
            "CONTACT" => read_contact::contact(self, &mut a),
            "BEAM" => super::beams::beam(self, &mut a),
            "FIELD" => super::beams::field(self, &mut a),
            "FRICTION" => super::friction::friction(self, &mut a),
            "VARIABLE" => read_data::variable(self, &mut a),
            "SPLINE" => read_data::spline(self, &mut a),
            "ARRAY" => read_data::array(self, &mut a),
            "PINPUT" => read_data::plant(self, &mut a, false),
            "POUTPUT" => read_data::plant(self, &mut a, true),
            "REQUEST" => read_data::request(self, &mut a),
            "INTEGRATOR" => read_data::integrator(self, &mut a),
            "EQUILIBRIUM" => read_data::equilibrium(self, &mut a),
            "OUTPUT" | "RESULTS" | "IC" => read_data::setting(self, &mut a),
            "KINEMATICS" => read_data::kinematics(self, &mut a),
            "GRAPHICS" if read_graphics::is_read(stmt) => read_graphics::graphics(self, &mut a),
            "DIFF" => read_states::diff(self, &mut a),
            "LSE" => read_states::lse(self, &mut a),
            "TFSISO" => read_states::tfsiso(self, &mut a),
            "MATRIX" => read_states::matrix(self, &mut a),
            "END" => {}
            _ => {
                if let Some(kind) = stmt.canonical {
                    self.unsupported.entry(kind).or_default().push(stmt);
                }
                if stmt.canonical == Some("GSE") {
                    self.diags.push(read_states::gse_refused(&a));
                }
                self.check_only(&mut a);
                let found = a.finish();
                self.diags.extend(found);
                return;
            }
        }
        // A USER value is warned at its argument and left out of the model.
        if stmt.canonical.is_some_and(is_physical) && stmt.args.iter().any(|a| a.is_user_call) {
            self.user_calls.push(stmt);
        }
        let found = a.finish();
        self.diags.extend(found);
    }

    /// Keeps the FUNCTION text of VARIABLE/`id` for the units check of VARVAL, which may
    /// come before the VARIABLE in the file.
    fn variable_source(&mut self, id: i64, s: &Statement) {
        let Some(arg) = s.arg("FUNCTION", 2).filter(|a| !a.is_user_call) else {
            return;
        };
        if let Some(text) = arg.expr_span().and_then(|span| self.text.get(span)) {
            self.scope.variable_dims.add(id, text);
        }
    }

    /// The VARIABLEs a PINPUT lists carry what a controller sends (Adams Controls): their
    /// FUNCTION is a stand-in for runs without it, so their dimension is free.
    fn controller_inputs(&mut self, s: &Statement) {
        let Some(arg) = s.arg("VARIABLES", 1) else {
            return;
        };
        for item in arg.items() {
            if let ItemKind::Number { value, .. } = item.kind {
                self.scope.variable_dims.free(value as i64);
            }
        }
    }

    /// Checks the expressions of a statement outside the subset against the model, so
    /// their errors are reported, without adding measure slots; marks every argument used
    /// (the statement as a whole is reported).
    fn check_only(&mut self, a: &mut Args) {
        self.scope.check_only.set(true);
        for arg in &a.stmt.args {
            if arg.expr_span().is_some() {
                let _ = self.expr(a, &arg.name, arg.name.len(), Expect::Any);
            } else {
                a.find(&arg.name, arg.name.len());
            }
        }
        self.scope.check_only.set(false);
    }

    /// What the model leaves out: the kinds outside the subset by name, then the unknown
    /// keywords by name, then the statements with a USER value.
    fn ignored(&mut self) -> Vec<Ignored> {
        let group = |kind: String, why, stmts: &[&Statement]| Ignored {
            physical: why != Omission::Unsupported || is_physical(&kind),
            kind,
            why,
            statements: (stmts.iter())
                .map(|s| (statement_label(s), s.line))
                .collect(),
            span: stmts[0].keyword_span.clone(),
        };
        let unsupported = std::mem::take(&mut self.unsupported).into_iter();
        let unknown = std::mem::take(&mut self.unknown).into_iter();
        let mut ignored: Vec<Ignored> = unsupported
            .map(|(kind, stmts)| group(kind.into(), Omission::Unsupported, &stmts))
            .chain(unknown.map(|(kind, stmts)| group(kind, Omission::Unknown, &stmts)))
            .collect();
        if !self.user_calls.is_empty() {
            ignored.push(group("USER".into(), Omission::UserCall, &self.user_calls));
        }
        ignored
    }

    /// Whole-model checks, the unsupported-statement summary, and the measure slots.
    fn finish(mut self) -> ModelRead {
        let grounds: Vec<_> = self.model.parts.iter().filter(|p| p.ground).collect();
        match grounds.as_slice() {
            [] => self.diags.push(
                Diagnostic::error(
                    Code::Topology,
                    title_span(self.text),
                    "the dataset has no GROUND part",
                )
                .with_help("add PART/id, GROUND"),
            ),
            [_] => {}
            [first, rest @ ..] => {
                for p in rest {
                    self.diags.push(
                        Diagnostic::error(
                            Code::Topology,
                            p.el.span.clone(),
                            format!("PART/{} is a second GROUND part", p.el.id),
                        )
                        .with_label(first.el.span.clone(), "first GROUND"),
                    );
                }
            }
        }
        self.model.ignored = self.ignored();
        // The unknown keywords and USER values were warned one by one as they were read.
        let summaries = (self.model.ignored.iter())
            .filter(|i| i.why == Omission::Unsupported)
            .map(super::report::ignored_warning);
        self.diags.extend(summaries);
        self.model.measures = self.scope.slots();
        super::motion_time::check(&self.model, &mut self.diags);
        self.diags.sort_by_key(|d| d.span.start);
        ModelRead {
            model: self.model,
            diagnostics: self.diags,
            scope: self.scope,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_quiet_statement_is_a_kind_the_reader_knows() {
        for (kind, _) in QUIET_STATEMENTS {
            assert!(
                matches!(
                    super::super::keywords::lookup_statement(kind),
                    super::super::keywords::Lookup::Known(k) if k.keyword.name == *kind
                ),
                "{kind}"
            );
        }
    }

    #[test]
    fn the_model_carries_what_it_leaves_out_with_counts_and_lines() {
        let read = read_model(
            "t\nPART/1, GROUND\nMARKER/10, PART = 1\nGRAPHICS/1, POINT, RM = 10\n\
             COUPLER/1, TYPE = 1\nCOUPLER/2, TYPE = 1\nWIDGET/3\n\
             SFORCE/4, I = 10, J = 10, FUNCTION = USER(1)\nEND\n",
        );
        let got: Vec<_> = (read.model.ignored.iter())
            .map(|i| (i.kind.as_str(), i.why, i.physical, i.count(), i.line()))
            .collect();
        assert_eq!(
            got,
            [
                ("COUPLER", Omission::Unsupported, true, 2, 5),
                ("GRAPHICS", Omission::Unsupported, false, 1, 4),
                ("WIDGET", Omission::Unknown, true, 1, 7),
                ("USER", Omission::UserCall, true, 1, 8),
            ]
        );
        let line = super::super::report::not_modelled(&read.model.ignored);
        assert_eq!(
            line.as_deref(),
            Some("not modelled: 2 COUPLER, 1 WIDGET, 1 USER subroutine — the results leave out their physics")
        );
    }
}
