//! The dimension rules of the library functions (spec §4–§5), from their formulas:
//!
//! - ABS, AINT, ANINT, SIGN keep their (first) argument's dimension; SQRT halves it;
//!   MAX, MIN, DIM, MOD take two alike.
//! - SIN, COS, TAN, their hyperbolic forms, EXP, LOG, LOG10 need a dimensionless or angle
//!   argument and give a dimensionless value; ASIN, ACOS, ATAN need one and give an
//!   angle; ATAN2 takes y and x alike and gives an angle.
//! - STEP, STEP5, HAVSIN: x with x0 and x1, h0 with h1; the value is h's.
//! - IMPACT, BISTOP: x with x1 (x2) and d, ẋ = x/time; the value is a contact force: a
//!   force for a gap that is a length, a torque for an angle.
//! - POLY: x with x0, and every term a_j·(x − x0)^j alike; CHEBY needs a dimensionless
//!   x − x0 (its polynomials mix powers), coefficients alike; FORCOS, FORSIN: ω·(x − x0)
//!   dimensionless or an angle, coefficients alike; SHF: x with x0, ω·(x − x0) with φ and
//!   dimensionless or an angle, a with b; SWEEP: x with x0, x1 and dx, f0 with f1, f·x
//!   dimensionless (cycles), the value is a's.

use super::dim::Dim;
use super::infer::{Infer, D};
use crate::syntax::ast::{Kind, NodeId};
use crate::vocab::func::Func;

impl Infer<'_> {
    /// The dimension of a call of `f` (builtin `name`) with `args`.
    #[inline(never)]
    pub(super) fn function(&mut self, f: Func, name: &str, args: &[NodeId]) -> D {
        use Func as F;
        let fixed = f.fixed_args();
        // The checker has seen to the arity; bad input is free rather than a panic.
        if args.len() < fixed || fixed > 8 {
            return None;
        }
        let mut d: [D; 8] = [None; 8];
        for (slot, &a) in d.iter_mut().zip(&args[..fixed]) {
            *slot = self.dim(a);
        }
        let arg = |i: usize, role: &'static str| (d[i], args[i], role);
        match f {
            F::Abs | F::Aint | F::Anint | F::Sign => d[0],
            F::Sqrt => d[0]?.pow(0.5),
            F::Sin | F::Cos | F::Tan | F::Sinh | F::Cosh | F::Tanh | F::Exp | F::Log | F::Log10 => {
                self.transcendental(name, d[0], args[0]);
                Some(Dim::NONE)
            }
            F::Asin | F::Acos | F::Atan => {
                self.transcendental(name, d[0], args[0]);
                Some(Dim::ANGLE)
            }
            F::Atan2 => {
                self.agree(name, &[arg(0, "y"), arg(1, "x")]);
                Some(Dim::ANGLE)
            }
            F::Mod | F::Max | F::Min | F::Dim => self.agree(name, &[arg(0, "a1"), arg(1, "a2")]),
            // Written as `**`, never as a call.
            F::Pow | F::PowLibm => None,
            F::Step | F::Step5 | F::Havsin => {
                self.agree(name, &[arg(0, "x"), arg(1, "x0"), arg(3, "x1")]);
                self.agree(name, &[arg(2, "h0"), arg(4, "h1")])
            }
            F::Impact => {
                let bounds = [arg(0, "x"), arg(2, "x1"), arg(6, "d")];
                self.contact(name, &bounds, (d[1], args[1]))
            }
            F::Bistop => {
                let bounds = [arg(0, "x"), arg(2, "x1"), arg(3, "x2"), arg(7, "d")];
                self.contact(name, &bounds, (d[1], args[1]))
            }
            F::Shf => {
                let x = self.agree(name, &[arg(0, "x"), arg(1, "x0")]);
                let wx = d[3].zip(x).and_then(|(w, x)| w.times(x));
                let phase = self.agree(name, &[(wx, args[3], "ω·(x − x0)"), arg(4, "φ")]);
                // The caret on φ when φ fixes the phase, else on ω.
                let at = if d[4].is_some() { args[4] } else { args[3] };
                let what = || format!("{name}: the phase ω·(x − x0) − φ");
                self.needs_number(phase, at, what, |_, _| None);
                self.agree(name, &[arg(2, "a"), arg(5, "b")])
            }
            F::Sweep => {
                let x = self.agree(
                    name,
                    &[arg(0, "x"), arg(2, "x0"), arg(4, "x1"), arg(6, "dx")],
                );
                let f = self.agree(name, &[arg(3, "f0"), arg(5, "f1")]);
                let cycles = f.zip(x).and_then(|(f, x)| f.times(x));
                let what = || format!("{name}: f0·x (a number of cycles)");
                self.needs_number(cycles, args[3], what, |_, _| None);
                d[1]
            }
            F::Poly | F::Cheby | F::Forcos | F::Forsin => self.series(f, name, &d, args),
        }
    }

    /// The argument of SIN, EXP, ASIN, ...: dimensionless or an angle.
    fn transcendental(&mut self, name: &str, d: D, at: NodeId) {
        let help = |inf: &Self, d: Dim| {
            if d.agrees(Dim::TIME) {
                let time = inf.names.map_or("time".into(), |n| n.time.to_string());
                Some(format!(
                    "give the time a coefficient in radian/{time}: {name}(w*TIME), w a number"
                ))
            } else if d.agrees(Dim::LENGTH) {
                Some("divide the length by another to make a ratio".to_string())
            } else {
                None
            }
        };
        self.needs_number(d, at, || format!("the argument of {name}"), help);
    }

    /// IMPACT and BISTOP: the gap and its bounds alike, the rate the gap per time; the
    /// value is the contact force (a torque for an angular gap).
    fn contact(&mut self, name: &str, bounds: &[(D, NodeId, &str)], rate: (D, NodeId)) -> D {
        let gap = self.agree(name, bounds);
        let gap = match (gap, rate.0) {
            (Some(g), Some(r)) => {
                let want = g.per(Dim::TIME)?;
                if !want.agrees(r) {
                    self.wrong_rate(name, (g, bounds[0].1), want, (r, rate.1));
                    return None;
                }
                g
            }
            (Some(g), None) => g,
            (None, Some(r)) => r.times(Dim::TIME)?,
            (None, None) => return None,
        };
        if gap.agrees(Dim::LENGTH) {
            Some(Dim::FORCE)
        } else if gap == Dim::ANGLE {
            Some(Dim::TORQUE)
        } else {
            None
        }
    }

    /// "IMPACT: ẋ is a length (meter) where the rate of x, a velocity (meter/second),
    /// belongs", with the velocity measure that matches x when x is a displacement.
    fn wrong_rate(&mut self, name: &str, (g, x): (Dim, NodeId), want: Dim, (r, at): (Dim, NodeId)) {
        let msg = format!(
            "{name}: ẋ is {} where the rate of x, {}, belongs",
            self.describe(r),
            self.describe(want)
        );
        let help = if r.agrees(g) {
            // A displacement where its rate belongs (the mistake of `IMPACT(DZ, DZ, …)`).
            match self.rate_of(x) {
                Some(v) => format!("ẋ is the time derivative of x: pass {v}"),
                None => "ẋ is the time derivative of x: pass its rate".to_string(),
            }
        } else if r.per(Dim::TIME).is_some_and(|v| v.agrees(g)) {
            "x and ẋ look swapped: x comes first, then its rate".to_string()
        } else {
            "ẋ is the time derivative of x".to_string()
        };
        let d =
            crate::diag::Diagnostic::warning(crate::diag::Code::UnitMismatch, self.span(at), msg)
                .with_label(self.span(x), format!("x: {}", self.describe(g)))
                .with_help(help);
        self.warn(d);
    }

    /// The velocity measure of a displacement measure call (`DZ(11,21,21)` →
    /// `VZ(11,21,21,21)`, the rate seen from K as the spec's IMPACT example takes it;
    /// `DM(i,j)` → `VR(i,j)`; `AZ(i,j)` → `WZ(i,j,j)`).
    fn rate_of(&self, x: NodeId) -> Option<String> {
        let Kind::Call { name, args, .. } = self.ast.node(x).kind else {
            return None;
        };
        let args: Vec<&str> = self
            .ast
            .call_args(args)
            .iter()
            .map(|&a| self.text(a))
            .collect();
        let (rate, mut args) = match self.ast.name(name) {
            "DX" => ("VX", args),
            "DY" => ("VY", args),
            "DZ" => ("VZ", args),
            "DM" => ("VR", args),
            "AX" => ("WX", args),
            "AY" => ("WY", args),
            "AZ" => ("WZ", args),
            _ => return None,
        };
        if rate.starts_with('V') && args.len() == 3 {
            args.push(args[2]);
        } else if rate.starts_with('W') && args.len() == 2 {
            args.push(args[1]);
        }
        Some(format!("{rate}({})", args.join(",")))
    }

    /// POLY, CHEBY, FORCOS, FORSIN: x with x0, then the coefficient terms alike.
    fn series(&mut self, f: Func, name: &str, d: &[D; 8], args: &[NodeId]) -> D {
        let x = self.agree(name, &[(d[0], args[0], "x"), (d[1], args[1], "x0")]);
        let first = f.fixed_args();
        match f {
            Func::Cheby => {
                self.needs_number(x, args[0], || format!("{name}: x − x0"), |_, _| None);
            }
            Func::Forcos | Func::Forsin => {
                let phase = d[2].zip(x).and_then(|(w, x)| w.times(x));
                let what = || format!("{name}: ω·(x − x0)");
                self.needs_number(phase, args[2], what, |_, _| None);
            }
            _ => {}
        }
        let mut agreed: Option<(Dim, NodeId, usize)> = None;
        for (j, &a) in args.iter().enumerate().skip(first) {
            let k = j - first;
            let coefficient = self.dim(a);
            let term = match f {
                // a_j·(x − x0)^j: the power of a free x is free, except for a0.
                Func::Poly if k > 0 => {
                    let power = x.and_then(|x| x.pow(k as f64));
                    coefficient.zip(power).and_then(|(c, p)| c.times(p))
                }
                _ => coefficient,
            };
            let Some(t) = term else { continue };
            match agreed {
                None => agreed = Some((t, a, k)),
                Some((u, at, i)) if !u.agrees(t) => {
                    let role = |i: usize| match (f, i) {
                        (Func::Poly, 0) | (Func::Cheby | Func::Forcos | Func::Forsin, _) => {
                            format!("a{i}")
                        }
                        (_, 1) => "a1·(x − x0)".to_string(),
                        (_, i) => format!("a{i}·(x − x0)^{i}"),
                    };
                    let (ra, rb) = (role(i), role(k));
                    self.mismatch(name, (u, at, &ra), (t, a, &rb));
                    return None;
                }
                Some(_) => {}
            }
        }
        agreed.map(|a| a.0)
    }
}
