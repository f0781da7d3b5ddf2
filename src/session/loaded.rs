//! A dataset loaded for questions: read, built, assembled and analysed once; expressions
//! are then checked against it (its markers and elements, plus user variables) and
//! evaluated at the assembled configuration. `mbfx eval --model` and the REPL's `:load`
//! stand on this.

use super::{analyze_model, Analysis, DimRequest, Failure};
use crate::check::{Checked, Expect, Variables};
use crate::diag::{has_errors, Code, Diagnostic, SourceFile};
use crate::ir::Function;
use crate::mbd::MbdError;
use crate::model::{read_model, ModelRead};
use mbfx_runtime::Spline;
use std::path::Path;

/// A model and its assembled system.
pub struct LoadedModel {
    /// The dataset as read.
    pub read: ModelRead,
    /// The assembled system and its analyses (the shells ask through the methods).
    analysis: Analysis,
}

/// A part at the assembled configuration (the REPL's `:parts`).
#[derive(Clone, Debug, PartialEq)]
pub struct PartPose {
    /// The PART id (None for a part mbfx made).
    pub id: Option<u32>,
    /// The `adams_view_name`, when the dataset gives one.
    pub name: Option<String>,
    /// The origin of its body frame, global.
    pub origin: [f64; 3],
    /// Its orientation as 3-1-3 Euler angles (psi, theta, phi), degrees.
    pub euler_313_degrees: [f64; 3],
}

/// A marker at the assembled configuration (the REPL's `:markers`).
#[derive(Clone, Debug, PartialEq)]
pub struct MarkerPlace {
    /// The MARKER id (None for a marker mbfx made).
    pub id: Option<u32>,
    /// The id of the part it is on.
    pub part: Option<u32>,
    /// The `adams_view_name`, when the dataset gives one.
    pub name: Option<String>,
    /// Its origin, global.
    pub origin: [f64; 3],
}

/// Why a dataset file could not be loaded, ready to be shown: diagnostics in the file, and
/// where the pipeline stopped when no error among them says so.
pub struct LoadError {
    /// The dataset (empty when it could not be read), for rendering the diagnostics.
    pub source: SourceFile,
    /// The reader's diagnostics, or those of the failed analysis at the element at fault.
    pub diagnostics: Vec<Diagnostic>,
    /// The failure in words, when `diagnostics` holds no error.
    pub failure: Option<String>,
}

impl LoadedModel {
    /// Reads the dataset file at `path` and loads it ([`LoadedModel::load`]). The dataset's
    /// own warnings are dropped on success: they belong to `mbfx check`, not to each
    /// expression evaluated against the model.
    pub fn open(path: &Path, dim: DimRequest) -> Result<LoadedModel, Box<LoadError>> {
        let (text, mut diagnostics) = super::files::read_dataset(path).map_err(|u| {
            Box::new(LoadError {
                source: u.source,
                diagnostics: vec![u.diagnostic],
                failure: None,
            })
        })?;
        let (read, failure) = match LoadedModel::load(&text, dim) {
            Ok(m) => return Ok(m),
            Err(failed) => *failed,
        };
        let mut said = None;
        match failure {
            Failure::Read(d) => diagnostics.extend(d),
            f => {
                diagnostics.extend(super::report::diagnostics(&f, &read.model));
                if !has_errors(&diagnostics) {
                    diagnostics.clear();
                    said = Some(f.to_string());
                }
            }
        }
        Err(Box::new(LoadError {
            source: SourceFile::new(path.display().to_string(), text),
            diagnostics,
            failure: said,
        }))
    }

    /// Reads and analyses a dataset text; the failure says where the pipeline stopped
    /// (with the reader's diagnostics when the dataset has errors).
    pub fn load(text: &str, dim: DimRequest) -> Result<LoadedModel, Box<(ModelRead, Failure)>> {
        let read = read_model(text);
        if read.has_errors() {
            let diags = read.diagnostics.clone();
            return Err(Box::new((read, Failure::Read(diags))));
        }
        match analyze_model(&read.model, dim) {
            Ok(analysis) => Ok(LoadedModel { read, analysis }),
            Err(f) => Err(Box::new((read, f))),
        }
    }

    /// What `:load` says of the model: its parts, markers and degrees of freedom, and why
    /// it is 2D or 3D.
    pub fn summary(&self) -> String {
        let s = &self.analysis.system;
        format!(
            "{} parts, {} markers, {} DOF; {}",
            s.parts.len(),
            s.markers.len(),
            self.analysis.redundancy.dof(),
            s.dim_reason
        )
    }

    /// Each part at the assembled configuration, in the system's order.
    pub fn part_poses(&self) -> Vec<PartPose> {
        (self.analysis.system.parts.iter())
            .map(|p| {
                let rot = p.rot.to_rotation_matrix().into_inner();
                let euler = crate::model::frames::euler_313(&rot).map(f64::to_degrees);
                let r = p.bcs_origin();
                PartPose {
                    id: p.id,
                    name: p.name.clone(),
                    origin: [r.x, r.y, r.z],
                    euler_313_degrees: euler,
                }
            })
            .collect()
    }

    /// Each marker at the assembled configuration, in the system's order.
    pub fn marker_places(&self) -> Vec<MarkerPlace> {
        let system = &self.analysis.system;
        (system.markers.iter())
            .map(|k| {
                let part = system.part(k.part);
                let r = part.r + part.rot * k.s;
                let name = (k.id.and_then(|id| self.read.model.marker(id)))
                    .and_then(|mk| mk.el.name.clone());
                MarkerPlace {
                    id: k.id,
                    part: part.id,
                    name,
                    origin: [r.x, r.y, r.z],
                }
            })
            .collect()
    }

    /// The dataset's splines, for the evaluation context of its expressions.
    pub fn splines(&self) -> &[Spline] {
        &self.analysis.splines
    }

    /// Checks and lowers an expression of the kind `expect` asks for against the model and
    /// `variables`, with the dataset's VARIABLEs inlined where it reads them (`VARVAL`).
    pub fn compile(
        &mut self,
        text: &str,
        variables: &Variables,
        expect: Expect,
    ) -> Result<Checked, Vec<Diagnostic>> {
        let mut checked = self.read.compile(text, variables, expect)?;
        let e = crate::model::elements::Expr {
            span: 0..text.len(),
            function: std::mem::take(&mut checked.function),
        };
        checked.function = self
            .read
            .model
            .inline_variables(&e)
            .map_err(|why| vec![Diagnostic::error(Code::Unsupported, 0..text.len(), why)])?
            .function;
        Ok(checked)
    }

    /// The measure array for `f` at the assembled configuration: every slot `f` reads is
    /// computed (and nothing else), the rest are zero.
    pub fn measures_for(&mut self, f: &Function) -> Result<Vec<f64>, MbdError> {
        let slots = &f.uses.measures;
        let system = &mut self.analysis.system;
        let map = system.resolve_slots(&self.read.model, slots)?;
        let mut out = vec![0.0; self.read.model.measures.len()];
        system.fill_slots(&map, slots, &mut out);
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::context::Context;
    use crate::interp::Program;

    /// A pendulum hinged at the origin whose bob marker starts at (0.6, 0.8, 0) (a
    /// length of 1): its measures at the assembled configuration are those numbers.
    const PENDULUM: &str = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2, QP = 0.6, 0.8, 0\n\
        MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nEND\n";

    #[test]
    fn measures_of_a_typed_expression_come_from_the_assembled_system() {
        let Ok(mut m) = LoadedModel::load(PENDULUM, DimRequest::Auto) else {
            panic!("the pendulum loads");
        };
        let mut vars = Variables::new();
        let k = vars.define("k");
        assert_eq!(k, 0);
        let c = m
            .compile("k*DM(20, 10) + DX(20, 10) - DY(20)", &vars, Expect::Any)
            .unwrap();
        let measures = m.measures_for(&c.function).unwrap();
        let v = Program::new(c.function).eval(&Context::new(0.0, &[2.0]).with_measures(&measures));
        assert!((v - (2.0 * 1.0 + 0.6 - 0.8)).abs() < 1e-12, "{v}");
    }

    #[test]
    fn variables_are_read_through_their_expressions() {
        let text = PENDULUM.replace(
            "END\n",
            "VARIABLE/1, FUNCTION = DX(20, 10)\nVARIABLE/2, FUNCTION = 3*VARVAL(1)\n\
             VARIABLE/3, FUNCTION = VARVAL(3)\nEND\n",
        );
        let Ok(mut m) = LoadedModel::load(&text, DimRequest::Auto) else {
            panic!("the pendulum with variables loads");
        };
        let c = m
            .compile("VARVAL(2) + DY(20, 10)", &Variables::new(), Expect::Any)
            .unwrap();
        let measures = m.measures_for(&c.function).unwrap();
        let v = Program::new(c.function).eval(&Context::new(0.0, &[]).with_measures(&measures));
        assert!((v - (3.0 * 0.6 + 0.8)).abs() < 1e-12, "{v}");
        let errors = m
            .compile("VARVAL(3)", &Variables::new(), Expect::Any)
            .err()
            .unwrap();
        assert!(
            errors[0].message.contains("VARIABLE/3 → VARIABLE/3"),
            "{errors:?}"
        );
    }

    #[test]
    fn splines_are_in_the_evaluation_context() {
        // y = x² at five knots; the natural cubic fit of x² is not x², but it passes
        // through the knots, and DX of the bob is the knot 0.6.
        let text = PENDULUM.replace(
            "END\n",
            "SPLINE/7, X = 0, 0.3, 0.6, 0.9, 1.2, Y = 0, 0.09, 0.36, 0.81, 1.44\nEND\n",
        );
        let Ok(mut m) = LoadedModel::load(&text, DimRequest::Auto) else {
            panic!("the pendulum with a spline loads");
        };
        let c = m
            .compile("CUBSPL(DX(20, 10), 0, 7)", &Variables::new(), Expect::Any)
            .unwrap();
        let measures = m.measures_for(&c.function).unwrap();
        let ctx = Context::new(0.0, &[])
            .with_measures(&measures)
            .with_splines(m.splines());
        let v = Program::new(c.function).eval(&ctx);
        assert!((v - 0.36).abs() < 1e-12, "{v}");
    }

    #[test]
    fn unknown_markers_are_diagnosed_against_the_model() {
        let Ok(mut m) = LoadedModel::load(PENDULUM, DimRequest::Auto) else {
            panic!("the pendulum loads");
        };
        let errors = m
            .compile("DX(99)", &Variables::new(), Expect::Any)
            .err()
            .unwrap();
        assert_eq!(errors[0].code, crate::diag::Code::UndefinedElement);
    }
}
