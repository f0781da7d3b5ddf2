//! The kernels: each node over every lane of a block. Loops run over the whole block
//! (a partial last block computes lanes it then ignores), so their trip count is fixed
//! and the compiler vectorises them: three times, for the baseline x86-64 (two lanes a
//! vector instruction), AVX2 (four) and AVX-512 (eight; its masks, 64-bit shifts and
//! conversions also shorten the trigonometric loops), picked once per call by what the
//! processor has. All do the same IEEE operations on the same numbers (Rust never fuses
//! a multiply and an add by itself, even where AVX-512 brings FMA), so they give the
//! same bits.

use super::build::{Arg, Bin, Code, Law, Node};
use super::{Column, Lanes, Source, INPUT, LANES};
use crate::ir::Cmp;
use crate::vocab::func::Func;
use mbfx_runtime as rt;
use rt::math::trig;

/// One slot: a value per lane.
type Lane = [f64; LANES];

/// The block's inputs, one lane array each: a slice of the caller's column where a
/// whole block lies in it, a copy otherwise.
type Inputs<'a> = [&'a Lane];

/// The slots other than the one a node writes, and the inputs, read by slot number.
struct Others<'a> {
    below: &'a [Lane],
    above: &'a [Lane],
    at: u32,
    inputs: &'a Inputs<'a>,
}

impl Others<'_> {
    /// Slot `s` (never the destination: the builder gives every node a fresh slot).
    #[inline(always)]
    fn get(&self, s: u32) -> &Lane {
        if s & INPUT != 0 {
            self.inputs[(s & !INPUT) as usize]
        } else if s < self.at {
            &self.below[s as usize]
        } else {
            &self.above[(s - self.at - 1) as usize]
        }
    }
}

/// Slot `d`, to write, and the others.
#[inline(always)]
fn split<'a>(slots: &'a mut [Lane], inputs: &'a Inputs<'a>, d: u32) -> (&'a mut Lane, Others<'a>) {
    let (below, rest) = slots.split_at_mut(d as usize);
    let (dest, above) = rest
        .split_first_mut()
        .expect("the builder numbers every slot");
    let others = Others {
        below,
        above,
        at: d,
        inputs,
    };
    (dest, others)
}

/// Slot `s` to read, outside a node.
#[inline(always)]
fn read<'a>(slots: &'a [Lane], inputs: &'a Inputs<'a>, s: u32) -> &'a Lane {
    if s & INPUT != 0 {
        inputs[(s & !INPUT) as usize]
    } else {
        &slots[s as usize]
    }
}

#[inline(always)]
fn map1(d: &mut Lane, a: &Lane, f: impl Fn(f64) -> f64) {
    for (d, &a) in d.iter_mut().zip(a) {
        *d = f(a);
    }
}

#[inline(always)]
fn map2(d: &mut Lane, a: &Lane, b: &Lane, f: impl Fn(f64, f64) -> f64) {
    for ((d, &a), &b) in d.iter_mut().zip(a).zip(b) {
        *d = f(a, b);
    }
}

/// `d = test(a, b) ? then : otherwise` over lanes, for one comparison (matched outside
/// the loop, which then becomes masks and blends).
#[inline(always)]
fn select(d: &mut Lane, [a, b, then, otherwise]: [&Lane; 4], test: impl Fn(f64, f64) -> bool) {
    for i in 0..LANES {
        d[i] = blend(test(a[i], b[i]), then[i], otherwise[i]);
    }
}

/// `if pick { a } else { b }` as bit masks: no branch, so the loops around it vectorise
/// and unpredictable lanes cost nothing extra; the bits are `a`'s or `b`'s exactly.
#[inline(always)]
fn blend(pick: bool, a: f64, b: f64) -> f64 {
    let mask = 0u64.wrapping_sub(u64::from(pick));
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// `d = f(args)` lane by lane, the arguments gathered into a buffer (the rare calls
/// with more than two arguments, series and partials).
fn per_lane(d: &mut Lane, s: &Others, args: &[u32], f: impl Fn(&[f64]) -> f64) {
    let mut buf = [0.0; crate::ir::MAX_CALL_ARGS];
    let buf = &mut buf[..args.len()];
    for (i, d) in d.iter_mut().enumerate() {
        for (b, &a) in buf.iter_mut().zip(args) {
            *b = s.get(a)[i];
        }
        *d = f(buf);
    }
}

/// `d = a • b` over lanes for one operation `f`, each operand a slot or a scalar.
#[inline(always)]
fn arith(d: &mut Lane, s: &Others, a: Arg, b: Arg, f: impl Fn(f64, f64) -> f64) {
    match (a, b) {
        (Arg::Slot(a), Arg::Slot(b)) => map2(d, s.get(a), s.get(b), f),
        (Arg::Slot(a), Arg::Const(c)) => map1(d, s.get(a), |a| f(a, c)),
        (Arg::Const(c), Arg::Slot(b)) => map1(d, s.get(b), |b| f(c, b)),
        (Arg::Const(a), Arg::Const(b)) => d.fill(f(a, b)),
    }
}

impl Lanes {
    /// See [`Lanes::eval`], whose checks this relies on.
    pub(super) fn run(&self, columns: &[Column], time: Column, n: usize, out: &mut [f64]) {
        self.run_at(Level::detect(), columns, time, n, out)
    }

    /// [`Lanes::run`] with the kernels of `level` (the tests run each).
    pub(super) fn run_at(
        &self,
        level: Level,
        columns: &[Column],
        time: Column,
        n: usize,
        out: &mut [f64],
    ) {
        let mut slots = vec![[0.0; LANES]; self.slots];
        for &(s, c) in &self.consts {
            slots[s as usize] = [c; LANES];
        }
        let sources: Vec<Column> = self
            .inputs
            .iter()
            .map(|source| match source {
                Source::Var(k) => columns[*k as usize],
                Source::Time => time,
            })
            .collect();
        // A constant column's lanes, once; a column of values' last, partial block.
        let mut own: Vec<Lane> = sources
            .iter()
            .map(|c| match c {
                Column::Const(x) => [*x; LANES],
                Column::Values(_) => [0.0; LANES],
            })
            .collect();
        let whole = n / LANES;
        let mut inputs: Vec<&Lane> = Vec::with_capacity(sources.len());
        for b in 0..whole {
            let first = b * LANES;
            inputs.clear();
            inputs.extend(sources.iter().zip(&own).map(|(c, own)| match c {
                Column::Values(v) => v[first..first + LANES].try_into().unwrap_or(own),
                Column::Const(_) => own,
            }));
            level.code(&self.code, &mut slots, &inputs);
            self.write(&slots, &inputs, first, LANES, out);
        }
        drop(inputs);
        let first = whole * LANES;
        let m = n - first;
        if m > 0 {
            for (c, own) in sources.iter().zip(&mut own) {
                if let Column::Values(v) = c {
                    own[..m].copy_from_slice(&v[first..n]);
                }
            }
            let inputs: Vec<&Lane> = own.iter().collect();
            level.code(&self.code, &mut slots, &inputs);
            self.write(&slots, &inputs, first, m, out);
        }
    }

    /// Copies the outputs of the block's first `m` lanes to points `first..` of `out`.
    fn write(&self, slots: &[Lane], inputs: &Inputs, first: usize, m: usize, out: &mut [f64]) {
        let k = self.outputs.len();
        let block = &mut out[first * k..(first + m) * k];
        if let [o] = self.outputs[..] {
            block.copy_from_slice(&read(slots, inputs, o)[..m]);
        } else {
            for (j, &o) in self.outputs.iter().enumerate() {
                let lane = read(slots, inputs, o);
                for (dst, &x) in block[j..].iter_mut().step_by(k).zip(lane) {
                    *dst = x;
                }
            }
        }
    }
}

/// The instruction set the kernels are compiled for.
#[derive(Clone, Copy, Debug)]
pub(super) enum Level {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Level {
    /// The widest level the processor has (std caches the answers).
    fn detect() -> Level {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            if has!("avx512f") && has!("avx512dq") && has!("avx512vl") {
                return Level::Avx512;
            }
            if has!("avx2") {
                return Level::Avx2;
            }
        }
        Level::Baseline
    }

    /// Every level this processor can run (the baseline first).
    #[cfg(test)]
    pub(super) fn available() -> Vec<Level> {
        match Level::detect() {
            Level::Baseline => vec![Level::Baseline],
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => vec![Level::Baseline, Level::Avx2],
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => vec![Level::Baseline, Level::Avx2, Level::Avx512],
        }
    }

    /// Runs `code` over one block with the kernels of this level.
    fn code(self, code: &Code, slots: &mut [Lane], inputs: &Inputs) {
        match self {
            Level::Baseline => run_code(self, code, slots, inputs),
            // SAFETY: `Avx2` is only made by `detect`, when the processor has AVX2.
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => unsafe { run_code_avx2(code, slots, inputs) },
            // SAFETY: `Avx512` is only made by `detect`, when the processor has these.
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => unsafe { run_code_avx512(code, slots, inputs) },
        }
    }
}

/// [`run_code`] with AVX2 instructions: everything below it down to the loops is
/// inlined into it, so it is all compiled with them (calls to the runtime stay calls).
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_code_avx2(code: &Code, slots: &mut [Lane], inputs: &Inputs) {
    run_code(Level::Avx2, code, slots, inputs)
}

/// [`run_code`] with AVX-512 instructions (F, DQ, VL), as [`run_code_avx2`].
///
/// # Safety
/// The processor must have AVX-512 F, DQ and VL.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl")]
unsafe fn run_code_avx512(code: &Code, slots: &mut [Lane], inputs: &Inputs) {
    run_code(Level::Avx512, code, slots, inputs)
}

#[inline(always)]
fn run_code(level: Level, code: &Code, slots: &mut [Lane], inputs: &Inputs) {
    for node in &code.nodes {
        match node {
            Node::If { test, arms, dests } => run_if(level, *test, arms, dests, slots, inputs),
            node => run_node(node, slots, inputs),
        }
    }
}

/// The IF: the arm of each lane, each arm some lane picks (run at `level`: the arms
/// recurse through [`Level::code`]), then its results merged into `dests` at its lanes;
/// NaN at the lanes whose test is NaN.
#[inline(always)]
fn run_if(
    level: Level,
    test: u32,
    arms: &[Code; 3],
    dests: &[u32],
    slots: &mut [Lane],
    inputs: &Inputs,
) {
    const NAN_TEST: u8 = 3;
    let mut pick = [NAN_TEST; LANES];
    for (p, &t) in pick.iter_mut().zip(read(slots, inputs, test)) {
        // 0 below zero, 1 at ±0, 2 above, 3 for NaN (`if_arm`), without branches.
        let ordered = u8::from(!t.is_nan());
        *p = ordered * (u8::from(t >= 0.0) + u8::from(t > 0.0)) + (1 - ordered) * NAN_TEST;
    }
    let picked = pick.iter().fold(0u8, |seen, &p| seen | 1 << p);
    for (k, arm) in arms.iter().enumerate() {
        if picked & 1 << k == 0 {
            continue;
        }
        level.code(arm, slots, inputs);
        for (&d, &r) in dests.iter().zip(&arm.results) {
            let (dest, s) = split(slots, inputs, d);
            for ((d, &r), &p) in dest.iter_mut().zip(s.get(r)).zip(&pick) {
                *d = blend(p == k as u8, r, *d);
            }
        }
    }
    if picked & 1 << NAN_TEST != 0 {
        for &d in dests {
            for (d, &p) in slots[d as usize].iter_mut().zip(&pick) {
                *d = blend(p == NAN_TEST, f64::NAN, *d);
            }
        }
    }
}

/// A one-argument library function, called directly (so the loop holds a plain call to
/// the runtime, not one through a pointer).
macro_rules! unary {
    ($func:expr, $d:expr, $a:expr, [$($f:ident => $rt:path),* $(,)?]) => {
        match $func {
            $(Func::$f => map1($d, $a, $rt),)*
            other => map1($d, $a, |x| other.eval(&[x])),
        }
    };
}

macro_rules! binary {
    ($func:expr, $d:expr, $a:expr, $b:expr, [$($f:ident => $rt:path),* $(,)?]) => {
        match $func {
            $(Func::$f => map2($d, $a, $b, $rt),)*
            other => map2($d, $a, $b, |x, y| other.eval(&[x, y])),
        }
    };
}

#[inline(always)]
fn run_node(node: &Node, slots: &mut [Lane], inputs: &Inputs) {
    match node {
        Node::Neg { d, a } => {
            let (dest, s) = split(slots, inputs, *d);
            map1(dest, s.get(*a), |a| -a)
        }
        Node::Sqrt { d, a } => {
            let (dest, s) = split(slots, inputs, *d);
            map1(dest, s.get(*a), f64::sqrt)
        }
        Node::Bin { op, d, a, b } => {
            let (dest, s) = split(slots, inputs, *d);
            match op {
                Bin::Add => arith(dest, &s, *a, *b, |a, b| a + b),
                Bin::Sub => arith(dest, &s, *a, *b, |a, b| a - b),
                Bin::Mul => arith(dest, &s, *a, *b, |a, b| a * b),
                Bin::Div => arith(dest, &s, *a, *b, |a, b| a / b),
            }
        }
        Node::Select {
            cmp,
            d,
            a,
            b,
            then,
            otherwise,
        } => {
            let (dest, s) = split(slots, inputs, *d);
            let ops = [s.get(*a), s.get(*b), s.get(*then), s.get(*otherwise)];
            match cmp {
                Cmp::Lt => select(dest, ops, |a, b| a < b),
                Cmp::Le => select(dest, ops, |a, b| a <= b),
                Cmp::Eq => select(dest, ops, |a, b| a == b),
                Cmp::Gt => select(dest, ops, |a, b| a > b),
                Cmp::Ge => select(dest, ops, |a, b| a >= b),
                Cmp::Uno => select(dest, ops, |a, b| a.is_nan() || b.is_nan()),
            }
        }
        // The runtime's own SIN, COS and ATAN2 come as block loops (vectorised here).
        Node::Call1 {
            func: Func::Sin,
            d,
            a,
        } => {
            let (dest, s) = split(slots, inputs, *d);
            trig::sin_lanes(dest, s.get(*a))
        }
        Node::Call1 {
            func: Func::Cos,
            d,
            a,
        } => {
            let (dest, s) = split(slots, inputs, *d);
            trig::cos_lanes(dest, s.get(*a))
        }
        Node::Call2 {
            func: Func::Atan2,
            d,
            a,
            b,
        } => {
            let (dest, s) = split(slots, inputs, *d);
            trig::atan2_lanes(dest, s.get(*a), s.get(*b))
        }
        Node::Call1 { func, d, a } => {
            let (dest, s) = split(slots, inputs, *d);
            unary!(*func, dest, s.get(*a), [
                Abs => rt::abs, Tan => rt::tan,
                Atan => rt::atan, Asin => rt::asin, Acos => rt::acos, Exp => rt::exp,
                Log => rt::log, Log10 => rt::log10, Sqrt => rt::sqrt, Sinh => rt::sinh,
                Cosh => rt::cosh, Tanh => rt::tanh, Aint => rt::aint, Anint => rt::anint,
            ])
        }
        Node::Call2 { func, d, a, b } => {
            let (dest, s) = split(slots, inputs, *d);
            binary!(*func, dest, s.get(*a), s.get(*b), [
                Pow => rt::pow, PowLibm => rt::pow_libm, Mod => rt::amod,
                Min => rt::min, Max => rt::max, Dim => rt::dim, Sign => rt::sign,
            ])
        }
        Node::Contact { d, x, xd, law } => {
            let (dest, s) = split(slots, inputs, *d);
            let (x, xd) = (s.get(*x), s.get(*xd));
            match &**law {
                Law::Impact(p) => map2(dest, x, xd, |x, xd| p.force(x, xd)),
                Law::Bistop(p) => map2(dest, x, xd, |x, xd| p.force(x, xd)),
            }
        }
        Node::Call { func, d, args } => {
            let (dest, s) = split(slots, inputs, *d);
            per_lane(dest, &s, args, |a| func.eval(a))
        }
        Node::Partial { func, wrt, d, args } => {
            let (dest, s) = split(slots, inputs, *d);
            per_lane(dest, &s, args, |a| func.partial(*wrt as usize, a))
        }
        Node::If { .. } => {}
    }
}
