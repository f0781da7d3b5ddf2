//! The state elements of a dataset (issue 40 §3): DIFF (a user's first-order equation),
//! LSE (a linear state-space system on ARRAYs and MATRIXes) and TFSISO (a transfer
//! function), with the MATRIX data LSE reads. The reader fills [`StateElements`]; the
//! core ([`crate::mbd::states`]) integrates them. Both read the values the elements
//! expose (`DIF`, `DIF1`, `ARYVAL` of an X, U or Y array) through one layout,
//! [`StateElements::channel`], so an expression's measure slot and the core's vector of
//! state values agree.
//!
//! Every linear element is solved in one form, [`LinearSystem`]: ẋ = A·x + B·u,
//! y = C·x + D·u, dense, row-major. A TFSISO becomes it in controllable canonical form
//! ([`Tfsiso::realize`]).

use super::elements::{Array, Expr, Id, Named};

/// DIFF/id: ẋ = f(x, q, v, t), or with IMPLICIT 0 = f(ẋ, x, q, v, t).
#[derive(Clone, Debug)]
pub struct Diff {
    /// Id, view name and span.
    pub el: Named,
    /// FUNCTION: ẋ (explicit) or the residual (IMPLICIT).
    pub function: Expr,
    /// IC: x at the start.
    pub ic: f64,
    /// IC's second value: ẋ at the start (IMPLICIT only; the first guess of its solve).
    pub ic_rate: Option<f64>,
    /// IMPLICIT: FUNCTION is a residual that vanishes.
    pub implicit: bool,
    /// STATIC_HOLD: statics keeps x at its current value.
    pub static_hold: bool,
}

/// MATRIX/id: a dense matrix, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix {
    /// Id, view name and span.
    pub el: Named,
    /// ROWS.
    pub rows: usize,
    /// COLUMNS.
    pub cols: usize,
    /// The entries, row by row (FULL = CORDER and SPARSE are reordered on reading).
    pub values: Vec<f64>,
}

/// LSE/id: ẋ = A·x + B·u, y = C·x + D·u on ARRAYs X, U, Y (and IC).
#[derive(Clone, Debug, PartialEq)]
pub struct Lse {
    /// Id, view name and span.
    pub el: Named,
    /// ARRAY X (the states).
    pub x: Id,
    /// ARRAY U (its VARIABLES are the inputs).
    pub u: Option<Id>,
    /// ARRAY Y (the outputs).
    pub y: Option<Id>,
    /// ARRAY IC (the initial states; zero without).
    pub ic: Option<Id>,
    /// MATRIX A, B, C, D.
    pub a: Id,
    /// MATRIX B (needs U).
    pub b: Option<Id>,
    /// MATRIX C (needs Y).
    pub c: Option<Id>,
    /// MATRIX D (needs U and Y).
    pub d: Option<Id>,
    /// STATIC_HOLD: statics keeps the states at their current values.
    pub static_hold: bool,
}

/// TFSISO/id: Y(s) = N(s)/D(s)·U(s), coefficients in ascending powers of s.
#[derive(Clone, Debug, PartialEq)]
pub struct Tfsiso {
    /// Id, view name and span.
    pub el: Named,
    /// NUMERATOR: b₀, b₁, … (b₀ + b₁·s + …).
    pub numerator: Vec<f64>,
    /// DENOMINATOR: a₀, a₁, … (a₀ + a₁·s + …).
    pub denominator: Vec<f64>,
    /// ARRAY X (the states).
    pub x: Id,
    /// ARRAY U (one VARIABLE id, the input).
    pub u: Id,
    /// ARRAY Y (the output).
    pub y: Id,
    /// STATIC_HOLD.
    pub static_hold: bool,
}

/// The statement a state element's fault is placed on (`DIFF/3`, `ARRAY/7`): its
/// keyword and id, which the session's report turns into the statement's span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Statement {
    /// `DIFF`, `LSE`, `TFSISO`, `ARRAY`, `MATRIX` or `VARIABLE`.
    pub keyword: &'static str,
    /// Its id.
    pub id: Id,
}

impl Statement {
    /// `keyword/id`.
    pub fn new(keyword: &'static str, id: Id) -> Statement {
        Statement { keyword, id }
    }
}

impl std::fmt::Display for Statement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.keyword, self.id)
    }
}

/// Why a state element cannot be built, and the statement at fault.
pub type StateFault = (Statement, String);

/// A linear element in the one form the core solves: ẋ = A·x + B·u, y = C·x + D·u.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearSystem {
    /// The statement (`LSE/3`, `TFSISO/2`).
    pub label: String,
    /// The same, as a place for diagnostics.
    pub statement: Statement,
    /// States, inputs, outputs.
    pub n: usize,
    /// Inputs.
    pub m: usize,
    /// Outputs.
    pub p: usize,
    /// n×n, row-major.
    pub a: Vec<f64>,
    /// n×m.
    pub b: Vec<f64>,
    /// p×n.
    pub c: Vec<f64>,
    /// p×m.
    pub d: Vec<f64>,
    /// The initial states.
    pub ic: Vec<f64>,
    /// The VARIABLE each input is (a TFSISO's from its U array, filled by
    /// [`StateElements::linear_systems`]).
    pub inputs: Vec<Id>,
    /// STATIC_HOLD.
    pub static_hold: bool,
    /// ARRAY ids of X, U and Y (for ARYVAL).
    pub arrays: [Option<Id>; 3],
}

/// The state elements of a dataset.
#[derive(Clone, Debug, Default)]
pub struct StateElements {
    /// DIFF statements, in file order.
    pub diffs: Vec<Diff>,
    /// LSE statements.
    pub lses: Vec<Lse>,
    /// TFSISO statements.
    pub tfsisos: Vec<Tfsiso>,
    /// MATRIX statements.
    pub matrices: Vec<Matrix>,
}

/// What one state value is, by the element that owns it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    /// DIF(id): x of DIFF number `k` (file order).
    Dif(usize),
    /// DIF1(id): ẋ.
    Dif1(usize),
}

impl Tfsiso {
    /// The controllable canonical realization of N(s)/D(s) (a₀ + … + aₙ·sⁿ, made monic
    /// by aₙ): states x₁ … xₙ with ẋₖ = xₖ₊₁ (k < n), ẋₙ = u − Σ (aₖ₋₁/aₙ)·xₖ, and
    /// y = Σ (b̃ₖ₋₁ − b̃ₙ·aₖ₋₁/aₙ)·xₖ + b̃ₙ·u with b̃ = b/aₙ (b̃ₙ = 0 for a strictly
    /// proper one). Err says why none exists (a numerator of higher degree, aₙ = 0).
    pub fn realize(&self) -> Result<LinearSystem, String> {
        let statement = Statement::new("TFSISO", self.el.id);
        let label = statement.to_string();
        let trim = |v: &[f64]| {
            let mut v = v.to_vec();
            while v.len() > 1 && v.last() == Some(&0.0) {
                v.pop();
            }
            v
        };
        let (num, den) = (trim(&self.numerator), trim(&self.denominator));
        let n = den.len().saturating_sub(1);
        if n == 0 || den[n] == 0.0 {
            return Err(format!(
                "{label}: its DENOMINATOR must be of degree one or more"
            ));
        }
        if num.len() > den.len() {
            return Err(format!(
                "{label}: its NUMERATOR is of higher degree than its DENOMINATOR (not proper)"
            ));
        }
        let an = den[n];
        let mut b = vec![0.0; n + 1];
        for (k, v) in num.iter().enumerate() {
            b[k] = v / an;
        }
        let mut a = vec![0.0; n * n];
        for k in 0..n - 1 {
            a[k * n + k + 1] = 1.0;
        }
        for k in 0..n {
            a[(n - 1) * n + k] = -den[k] / an;
        }
        let mut bb = vec![0.0; n];
        bb[n - 1] = 1.0;
        let c: Vec<f64> = (0..n).map(|k| b[k] - b[n] * den[k] / an).collect();
        Ok(LinearSystem {
            label,
            statement,
            n,
            m: 1,
            p: 1,
            a,
            b: bb,
            c,
            d: vec![b[n]],
            ic: vec![0.0; n],
            inputs: Vec::new(),
            static_hold: self.static_hold,
            arrays: [Some(self.x), Some(self.u), Some(self.y)],
        })
    }
}

impl StateElements {
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.diffs.is_empty() && self.lses.is_empty() && self.tfsisos.is_empty()
    }

    /// MATRIX/`id`.
    pub fn matrix(&self, id: Id) -> Option<&Matrix> {
        self.matrices.iter().find(|m| m.el.id == id)
    }

    /// Every LSE, then every TFSISO, in the form the core solves, with `arrays` the
    /// dataset's ARRAYs; Err names the first that has none (a missing MATRIX or ARRAY,
    /// sizes that do not agree) and the statement at fault: the element, or the ARRAY
    /// or MATRIX whose contents are wrong.
    pub fn linear_systems(&self, arrays: &[Array]) -> Result<Vec<LinearSystem>, StateFault> {
        let mut out: Vec<LinearSystem> = Vec::new();
        for l in &self.lses {
            out.push(self.lse(l, arrays)?);
        }
        for t in &self.tfsisos {
            let mut s = t
                .realize()
                .map_err(|why| (Statement::new("TFSISO", t.el.id), why))?;
            // Its U array lists the one VARIABLE that is its input.
            let u = arrays.iter().find(|a| a.el.id == t.u).ok_or_else(|| {
                let why = format!("{}: ARRAY/{} is not in the dataset", s.label, t.u);
                (s.statement, why)
            })?;
            match u.numbers.as_slice() {
                [v] if *v >= 1.0 && v.fract() == 0.0 => s.inputs = vec![*v as Id],
                _ => {
                    let why = format!(
                        "{}: its U array (ARRAY/{}) must list one VARIABLE id",
                        s.label, t.u
                    );
                    return Err((Statement::new("ARRAY", t.u), why));
                }
            }
            out.push(s);
        }
        Ok(out)
    }

    fn lse(&self, l: &Lse, arrays: &[Array]) -> Result<LinearSystem, StateFault> {
        let statement = Statement::new("LSE", l.el.id);
        let label = statement.to_string();
        let matrix = |id: Id| {
            self.matrix(id).ok_or_else(|| {
                let why = format!("{label}: MATRIX/{id} is not in the dataset");
                (statement, why)
            })
        };
        let array = |id: Id| {
            arrays.iter().find(|a| a.el.id == id).ok_or_else(|| {
                let why = format!("{label}: ARRAY/{id} is not in the dataset");
                (statement, why)
            })
        };
        let a = matrix(l.a)?;
        if a.rows != a.cols || a.rows == 0 {
            let why = format!(
                "{label}: A (MATRIX/{}) must be square, it is {}×{}",
                l.a, a.rows, a.cols
            );
            return Err((Statement::new("MATRIX", l.a), why));
        }
        let n = a.rows;
        let inputs: Vec<Id> = match l.u {
            Some(u) => (array(u)?.numbers.iter()).map(|&v| v as Id).collect(),
            None => Vec::new(),
        };
        let m = inputs.len();
        let p = match (l.y, l.c) {
            (Some(_), Some(c)) => matrix(c)?.rows,
            _ => 0,
        };
        let sized = |id: Option<Id>, rows: usize, cols: usize, what: &str| {
            let Some(id) = id else {
                return Ok(vec![0.0; rows * cols]);
            };
            let mx = matrix(id)?;
            if (mx.rows, mx.cols) != (rows, cols) {
                let why = format!(
                    "{label}: {what} (MATRIX/{id}) is {}×{}, it must be {rows}×{cols}",
                    mx.rows, mx.cols
                );
                return Err((Statement::new("MATRIX", id), why));
            }
            Ok(mx.values.clone())
        };
        let ic = match l.ic {
            Some(id) => {
                let v = array(id)?.numbers.clone();
                if v.len() != n {
                    let why = format!(
                        "{label}: IC (ARRAY/{id}) has {} numbers for {n} states",
                        v.len()
                    );
                    return Err((Statement::new("ARRAY", id), why));
                }
                v
            }
            None => vec![0.0; n],
        };
        Ok(LinearSystem {
            n,
            m,
            p,
            a: a.values.clone(),
            b: sized(l.b, n, m, "B")?,
            c: sized(l.c, p, n, "C")?,
            d: sized(l.d, p, m, "D")?,
            ic,
            inputs,
            static_hold: l.static_hold,
            arrays: [Some(l.x), l.u, l.y],
            label,
            statement,
        })
    }

    /// Where the value an expression reads (`DIF(id)`, `DIF1(id)`, `ARYVAL(id, k)`)
    /// sits in the core's vector of state values: per DIFF (file order) x then ẋ, then
    /// per linear system ([`StateElements::linear_systems`]) x, ẋ, u and y. None when
    /// it names no state element's value.
    pub fn channel(&self, name: &str, ids: &[i64], arrays: &[Array]) -> Option<usize> {
        let id = *ids.first()?;
        match name {
            "DIF" | "DIF1" => {
                let k = self.diffs.iter().position(|d| i64::from(d.el.id) == id)?;
                Some(2 * k + usize::from(name == "DIF1"))
            }
            "ARYVAL" => {
                let k = usize::try_from(*ids.get(1)?).ok()?.checked_sub(1)?;
                let systems = self.linear_systems(arrays).ok()?;
                let mut base = 2 * self.diffs.len();
                for s in &systems {
                    let starts = [0, 2 * s.n, 2 * s.n + s.m];
                    let sizes = [s.n, s.m, s.p];
                    for w in 0..3 {
                        if s.arrays[w].map(i64::from) == Some(id) {
                            return (k < sizes[w]).then_some(base + starts[w] + k);
                        }
                    }
                    base += 2 * s.n + s.m + s.p;
                }
                None
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_order_transfer_function_realizes_in_controllable_canonical_form() {
        // ωn²/(s² + 2ζωn·s + ωn²) with ωn = 2, ζ = 0.5: a₀ = 4, a₁ = 2, a₂ = 1.
        let t = Tfsiso {
            el: Named::default(),
            numerator: vec![4.0],
            denominator: vec![4.0, 2.0, 1.0],
            x: 1,
            u: 2,
            y: 3,
            static_hold: false,
        };
        let s = t.realize().unwrap();
        assert_eq!((s.n, s.m, s.p), (2, 1, 1));
        assert_eq!(s.a, [0.0, 1.0, -4.0, -2.0]);
        assert_eq!(s.b, [0.0, 1.0]);
        assert_eq!(s.c, [4.0, 0.0]);
        assert_eq!(s.d, [0.0]);
        // A biproper one, (1 + 3s)/(2 + s): y = 3u + (1 − 3·2)·x.
        let t = Tfsiso {
            numerator: vec![1.0, 3.0],
            denominator: vec![2.0, 1.0],
            ..t
        };
        let s = t.realize().unwrap();
        assert_eq!(
            (s.a.as_slice(), s.c.as_slice(), s.d.as_slice()),
            (&[-2.0][..], &[-5.0][..], &[3.0][..])
        );
        let improper = Tfsiso {
            numerator: vec![1.0, 1.0, 1.0],
            ..t
        };
        assert!(improper.realize().unwrap_err().contains("not proper"));
    }
}
