//! The constraint rows' expressions evaluated by one call a state ([`crate::ir::fuse`]),
//! as the force expressions are ([`super::forces::ForceSet::fuse`]): every GCON's and
//! every displacement MOTION's drive g(t). Their values and, when the Newton matrix is
//! built, their values and partials (f, ∂f/∂slot, ∂f/∂t each), the measure slots they
//! read filled once. The dynamics computes them before it evaluates the rows
//! ([`System::eval_fused_rows`]) and the rows read them ([`System::fused_row`]); other
//! callers (assembly) evaluate each row on its own. (A VELOCITY or ACCELERATION MOTION
//! integrates its function by quadrature, several values a call: not fused.)

use super::expr::ExprError;
use super::rows::{FusedRow, FusedRows, Row};
use super::system::System;
use crate::ir::Function;
use std::cell::{Cell, RefCell};

impl System {
    /// Fuses the rows' expressions `rows` (GCON or displacement-MOTION element index,
    /// the expression's IR) with `exprs`, when it fuses.
    pub fn fuse_rows(&mut self, exprs: &dyn super::expr::ExprCompiler, rows: &[(usize, Function)]) {
        if rows.is_empty() {
            return;
        }
        let functions: Vec<&Function> = rows.iter().map(|(_, f)| f).collect();
        let Some(values) = exprs.fuse(&functions) else {
            return;
        };
        let (partials, offsets, width) = match super::expr::fuse_partials(exprs, &functions) {
            Some((p, o, w)) => (Some(p), o, w),
            None => (None, Vec::new(), 0),
        };
        let mut slots = Vec::new();
        let mut at = vec![None; self.elements.len()];
        for (k, (e, _)) in rows.iter().enumerate() {
            for eq in &self.elements[*e].eqs {
                if let Row::Gcon { f, map } = &eq.row {
                    slots.extend(f.slots().iter().copied().zip(map.iter().copied()));
                }
            }
            at[*e] = Some((k, offsets.get(k).copied().unwrap_or(usize::MAX)));
        }
        slots.sort_unstable();
        slots.dedup();
        self.fused_rows = Some(FusedRows {
            values,
            partials,
            slots,
            at,
            out_values: RefCell::new(vec![0.0; rows.len()]),
            out_partials: RefCell::new(vec![0.0; width]),
            current: Cell::new(None),
        });
    }

    /// Evaluates the fused rows at the current state (with `partials`, their partials
    /// too, when they have them); [`System::fused_row`] reads them until
    /// [`System::forget_fused_rows`].
    pub fn eval_fused_rows(&self, partials: bool) {
        let Some(fz) = &self.fused_rows else { return };
        let partials = partials && fz.partials.is_some();
        let mut shared = self.scratch.borrow_mut();
        let vals = shared.slots_to(fz.slots.last().map(|s| s.0));
        for &(slot, m) in &fz.slots {
            vals[slot as usize] = super::forces::measure_value(self, m);
        }
        match (partials, &fz.partials) {
            (true, Some(p)) => p.eval_into(self.time, vals, &mut fz.out_partials.borrow_mut()),
            _ => fz
                .values
                .eval_into(self.time, vals, &mut fz.out_values.borrow_mut()),
        }
        fz.current.set(Some(partials));
    }

    /// The fused outputs no longer describe the state.
    pub fn forget_fused_rows(&self) {
        if let Some(fz) = &self.fused_rows {
            fz.current.set(None);
        }
    }

    /// Element `e`'s expression value (and with `partials`, its partials into `grad` and
    /// ∂f/∂t) from the current fused evaluation; None when there is none that has them.
    pub fn fused_row(
        &self,
        e: usize,
        partials: bool,
        grad: &mut [f64],
    ) -> Option<Result<FusedRow, ExprError>> {
        let fz = self.fused_rows.as_ref()?;
        let with_partials = fz.current.get()?;
        let (v, at) = (*fz.at.get(e)?)?;
        let finite = |x: f64| match x.is_finite() {
            true => Ok(x),
            false => Err(ExprError::NotFinite {
                value: x,
                time: self.time,
            }),
        };
        if !with_partials {
            if partials {
                return None;
            }
            let value = fz.out_values.borrow()[v];
            return Some(finite(value).map(|value| FusedRow {
                value,
                dt: f64::NAN,
            }));
        }
        let out = fz.out_partials.borrow();
        let k = grad.len();
        let mut row = || -> Result<FusedRow, ExprError> {
            for (g, &x) in grad.iter_mut().zip(&out[at + 1..=at + k]) {
                *g = finite(x)?;
            }
            let dt = finite(out[at + k + 1])?;
            Ok(FusedRow {
                value: finite(out[at])?,
                dt,
            })
        };
        Some(row())
    }
}

#[cfg(test)]
mod tests {
    use crate::mbd::compiled::CompiledExprs;
    use crate::mbd::planar::Dim;
    use crate::mbd::system::System;
    use crate::model::read_model;

    /// A part held by two GCONs (one reading TIME) and driven by a MOTION, every row's
    /// value, partials and ∂/∂t from the fused call equal to the row's own evaluation,
    /// bit for bit.
    #[test]
    fn fused_gcon_and_motion_rows_are_each_rows_own() {
        let text = "two gcons\nPART/1, GROUND\nMARKER/101, PART = 1\n\
            MARKER/102, PART = 1, REULER = 120D, 90D, 0D\n\
            PART/2, MASS = 2, CM = 201, IP = 1, 1, 1, VX = 0.2\nMARKER/201, PART = 2\n\
            MARKER/202, PART = 2, REULER = 120D, 90D, 0D\n\
            GCON/1, I = 202, FUNCTION = SIN(DZ(202, 102, 102)) - 0.5*SIN(2*TIME)\n\
            GCON/2, I = 202, FUNCTION = DX(202, 102)*VY(202, 102) + DY(202, 102)**2\n\
            MOTION/3, I = 202, J = 102, X, \
            FUNCTION = 0.1*SIN(3*TIME) + STEP(TIME, 0, 0, 1, 0.2)\n\
            END\n";
        let read = read_model(text);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        for exprs in [CompiledExprs::new(), CompiledExprs::interpreted()] {
            let mut sys = System::from_model(&read.model, Dim::Three, &exprs).unwrap();
            sys.time = 0.37;
            assert!(sys.fused_rows.is_some());
            let bits = |sys: &System| -> Vec<u64> {
                let mut out = Vec::new();
                for e in 0..sys.elements.len() {
                    let r = sys.eval_row(e, 0).unwrap();
                    out.push(r.value.to_bits());
                    out.push(r.dt.to_bits());
                    out.extend(r.dq.iter().chain(&r.dv).map(|x| x.1.to_bits()));
                    out.push(sys.row_value(e, 0).unwrap().to_bits());
                }
                out
            };
            let alone = bits(&sys);
            sys.eval_fused_rows(true);
            // Both GCONs and the MOTION are read from the fused call (they read 1, 3 and
            // 0 slots).
            for (e, k) in [(0, 1), (1, 3), (2, 0)] {
                let mut grad = vec![0.0; k];
                assert!(sys.fused_row(e, true, &mut grad).is_some_and(|r| r.is_ok()));
            }
            let with_partials = bits(&sys);
            sys.eval_fused_rows(false);
            let values_only = bits(&sys);
            sys.forget_fused_rows();
            assert_eq!(with_partials, alone);
            assert_eq!(values_only, alone);
        }
    }
}
