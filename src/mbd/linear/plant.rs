//! The plant's input and output matrices of a linearization (Adams' LINEAR/STATEMAT with
//! PINPUT and POUTPUT): with inputs u (design variables: constant VARIABLEs the force
//! expressions read through VARVAL) and outputs y (VARIABLEs, functions of the state and
//! the inputs),
//!
//! ```text
//! ẋ = A·x + B·u,   y = C·x + D·u,   x = (z, ż),
//! B = [0; M̃⁻¹·Tᵀ·∂Q/∂u],   C = [∂y/∂q·T, ∂y/∂v·T],   D = ∂y/∂u,
//! ```
//!
//! ∂Q/∂u from the forces evaluated forward along u ([`crate::mbd::forces`]), ∂y/∂q and
//! ∂y/∂v from the output's compiled gradient chained with its measures' duals (as a
//! GCON row's Jacobian), ∂y/∂u from that gradient in the inputs' slots.

use super::Linearized;
use crate::mbd::dynamics::{DynError, Dynamics};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprFn;
use crate::mbd::measure_set::Measure;
use crate::vocab::math::{DMat, DVec};

/// An output: a VARIABLE's expression compiled, with its slots' measures.
pub struct Output {
    /// `VARIABLE/id`.
    pub name: String,
    /// The expression (VARIABLEs inlined, design variables kept as inputs).
    pub f: Box<dyn ExprFn>,
    /// The measure index of each slot `f` reads.
    pub map: Vec<usize>,
}

/// B, C and D.
#[derive(Clone, Debug)]
pub struct InputsOutputs {
    /// B: 2f × inputs.
    pub b: DMat,
    /// C: outputs × 2f.
    pub c: DMat,
    /// D: outputs × inputs.
    pub d: DMat,
}

/// B, C and D of `lin` (linearized from `d`, whose last evaluations it leaves as they
/// are) for the design variables `inputs` and the expressions `outputs`.
///
/// With state elements, B has a row per state (∂ẋ/∂u, [`super::states::input_rates`]) and
/// C a column per state (an output's partial in a DIF or ARYVAL of an X array; one that
/// reads a rate, an input or an output of a state element gets no partial through it).
pub fn inputs_outputs(
    lin: &Linearized,
    d: &mut Dynamics,
    inputs: &[i64],
    outputs: &[&Output],
) -> Result<InputsOutputs, DynError> {
    let (f, n, s) = (lin.freedom(), d.n, lin.states.len());
    let t = &lin.basis;
    let mut b = DMat::zeros(2 * f + s, inputs.len());
    if s > 0 {
        for (k, &id) in inputs.iter().enumerate() {
            let rates = super::states::input_rates(d, id)?;
            b.view_mut((2 * f, k), (s, 1)).copy_from(&rates);
        }
    }
    let d: &Dynamics = d;
    if f > 0 && !inputs.is_empty() {
        let mut qu = DMat::zeros(n, inputs.len());
        for (k, &id) in inputs.iter().enumerate() {
            qu.set_column(k, &d.forces.input_partials(&d.sys, id, n)?);
        }
        let reduced = t.transpose() * qu;
        let lower = lin
            .mass
            .clone()
            .lu()
            .solve(&reduced)
            .ok_or(DynError::Massless {
                part: lin
                    .coords
                    .first()
                    .map_or_else(String::new, |c| c.name.clone()),
                directions: 1,
            })?;
        b.view_mut((f, 0), (f, inputs.len())).copy_from(&lower);
    }
    let mut c = DMat::zeros(outputs.len(), 2 * f + s);
    let mut dd = DMat::zeros(outputs.len(), inputs.len());
    for (row, out) in outputs.iter().enumerate() {
        let (dq, dv, du, dx) = partials(d, out, inputs)?;
        for (k, x) in dx {
            c[(row, 2 * f + k)] += x;
        }
        let (cq, cv) = (t.transpose() * dq, t.transpose() * dv);
        for j in 0..f {
            c[(row, j)] = cq[j];
            c[(row, f + j)] = cv[j];
        }
        for (k, x) in du.iter().enumerate() {
            dd[(row, k)] = *x;
        }
    }
    Ok(InputsOutputs { b, c, d: dd })
}

/// ∂y/∂q and ∂y/∂v over the velocity-layout columns, ∂y/∂u for each input, and
/// (state, ∂y/∂x) for the state elements' states it reads.
fn partials(d: &Dynamics, out: &Output, inputs: &[i64]) -> Result<Partials, DynError> {
    let sys = &d.sys;
    let slots = out.f.slots();
    let mut vals = vec![0.0; slots.last().map_or(0, |&s| s as usize + 1)];
    let evs: Vec<_> = out.map.iter().map(|&m| sys.measures.eval(sys, m)).collect();
    for (ev, &s) in evs.iter().zip(slots) {
        vals[s as usize] = ev.value();
    }
    let mut grad = vec![0.0; slots.len()];
    out.f
        .gradient(sys.time, &vals, &mut grad)
        .map_err(|why| MbdError::Plant(format!("{}: {why}", out.name)))?;
    let (mut dq, mut dv) = (DVec::zeros(d.n), DVec::zeros(d.n));
    let mut du = vec![0.0; inputs.len()];
    let mut dx = Vec::new();
    for ((ev, &g), &m) in evs.iter().zip(&grad).zip(&out.map) {
        if g == 0.0 {
            continue;
        }
        if let Measure::Design { id } = sys.measures.list[m] {
            if let Some(k) = inputs.iter().position(|&u| u == id) {
                du[k] += g;
            }
            continue;
        }
        if let Measure::State { channel } = sys.measures.list[m] {
            if let Some(k) = d.forces.states.state_of_channel(channel as usize) {
                dx.push((k, g));
            }
            continue;
        }
        ev.scatter(sys, &mut |col, x| dq[col] += g * x, &mut |col, x| {
            dv[col] += g * x
        });
    }
    Ok((dq, dv, du, dx))
}

/// ∂y/∂q, ∂y/∂v, ∂y/∂u and the (state, ∂y/∂x) pairs of one output.
type Partials = (DVec, DVec, Vec<f64>, Vec<(usize, f64)>);
