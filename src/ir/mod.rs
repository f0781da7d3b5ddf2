//! The typed IR both back ends execute.
//!
//! A [`Function`] is a list of SSA instructions in one arena, organised in blocks: the top
//! level block, and for each arithmetic IF three nested blocks of which exactly one runs
//! (so an untaken branch is never evaluated, spec §2.4). Every value is a scalar `f64`:
//! vector expressions are lowered to three scalars by the checker, and the types were
//! settled there, so no back end tests a type at run time. Constants live outside blocks.
//! [`builder::Builder`] folds constants and shares common subexpressions as it builds.
//! [`lower`] rewrites the cheap library functions into branch-free IR for the JIT;
//! [`deriv`] generates the IR of partial derivatives.

pub mod builder;
pub mod deriv;
pub mod fuse;
pub mod inline;
pub mod lower;
pub mod print;
mod rebuild;

use crate::diag::Span;
use crate::vocab::builtins::SplineKind;
use crate::vocab::func::Func;

/// Index of an instruction (and of the value it defines) in [`Function::insts`].
pub type Value = u32;

/// One instruction. Operands are values defined earlier in the same block or an
/// enclosing one, or constants.
#[derive(Clone, Debug, PartialEq)]
pub enum Inst {
    /// A constant (outside every block).
    Const(f64),
    /// User variable slot `n` of the evaluation context.
    Var(u32),
    /// The simulation time `TIME`.
    Time,
    /// The analysis mode `MODE`.
    Mode,
    /// Measure slot `n` of the evaluation context, filled by the multibody core.
    Measure(u32),
    /// −a.
    Neg(Value),
    /// a + b.
    Add(Value, Value),
    /// a − b.
    Sub(Value, Value),
    /// a × b.
    Mul(Value, Value),
    /// a ÷ b.
    Div(Value, Value),
    /// √a (IEEE, exactly rounded).
    Sqrt(Value),
    /// A library function of `mbfx-runtime` (fixed arguments, then any coefficients).
    Call(Func, Box<[Value]>),
    /// Interpolation of spline `spline` of the context at (x, z); `iord` = derivative order.
    Spline {
        /// Akima or cubic fit.
        kind: SplineKind,
        /// The abscissa.
        x: Value,
        /// The surface parameter z.
        z: Value,
        /// Index into the context's spline table.
        spline: u32,
        /// 0 for the value, 1 or 2 for a derivative along x.
        iord: u8,
    },
    /// Arithmetic IF: runs `arms[0]` when test < 0, `arms[1]` when test = 0 (either
    /// sign), `arms[2]` when test > 0; a NaN test runs no arm and gives NaN (a run-time
    /// error the caller reports, decision 2). Its value is the arm's `result`; an IF built
    /// by [`deriv`] also yields each arm's `extra` results, read by [`Inst::IfExtra`].
    If {
        /// The value whose sign picks the arm.
        test: Value,
        /// The negative, zero and positive arms.
        arms: Box<[Block; 3]>,
    },
    /// Extra result `index` of the IF `of` (NaN when its test was NaN); placed right after
    /// `of` in the same block.
    IfExtra {
        /// The IF instruction.
        of: Value,
        /// Index into each arm's `extra`.
        index: u32,
    },
    /// `if a <cmp> b { then } else { otherwise }` with IEEE comparisons, both choices
    /// already computed: a branch-free choice ([`lower`] builds the cheap library
    /// functions from it).
    Select {
        /// The comparison.
        cmp: Cmp,
        /// Left operand.
        a: Value,
        /// Right operand.
        b: Value,
        /// The value when the comparison holds.
        then: Value,
        /// The value when it does not.
        otherwise: Value,
    },
    /// ∂func/∂(argument `wrt`) at `args`, from the runtime's analytic derivative companion
    /// (`mbfx_<name>_grad`); emitted by [`deriv`].
    Partial {
        /// The library function.
        func: Func,
        /// Index of the argument to differentiate by.
        wrt: u32,
        /// The call's arguments.
        args: Box<[Value]>,
    },
}

/// Most arguments a library call takes: a series' three fixed arguments and 31
/// coefficients.
pub const MAX_CALL_ARGS: usize = 34;

/// A floating-point comparison with IEEE (Rust) meaning: every comparison with a NaN
/// operand is false, except `Uno`, which is true exactly then.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cmp {
    /// a < b.
    Lt,
    /// a ≤ b.
    Le,
    /// a = b.
    Eq,
    /// a > b.
    Gt,
    /// a ≥ b.
    Ge,
    /// Either operand is NaN.
    Uno,
}

impl Cmp {
    /// The comparison of `a` and `b`, as Rust's operators give it.
    #[inline(always)]
    pub fn test(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Eq => a == b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
            Cmp::Uno => a.is_nan() || b.is_nan(),
        }
    }

    /// The operator as the IR printer writes it.
    pub fn symbol(self) -> &'static str {
        match self {
            Cmp::Lt => "<",
            Cmp::Le => "<=",
            Cmp::Eq => "==",
            Cmp::Gt => ">",
            Cmp::Ge => ">=",
            Cmp::Uno => "uno",
        }
    }
}

/// Which arm of an arithmetic IF a test value selects: 0 when negative, 1 when zero
/// (either sign), 2 when positive, `None` when NaN (spec §2.4, decision 2). The one
/// definition the constant folder and every back end follow.
#[inline(always)]
pub fn if_arm(t: f64) -> Option<usize> {
    if t < 0.0 {
        Some(0)
    } else if t == 0.0 {
        Some(1)
    } else if t > 0.0 {
        Some(2)
    } else {
        None
    }
}

/// A straight-line sequence of instructions and the value it yields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Block {
    /// The block's instructions, in order.
    pub insts: Vec<Value>,
    /// The value the block yields.
    pub result: Value,
    /// Further results (derivative code: a value and its partials leave an IF together);
    /// every arm of one IF has the same number.
    pub extra: Vec<Value>,
}

/// A compiled expression: instructions, their source spans, the top-level block and the
/// outputs (one value for a scalar expression, three for a vector).
#[derive(Clone, Debug, Default)]
pub struct Function {
    /// The instruction arena; a [`Value`] indexes it.
    pub insts: Vec<Inst>,
    /// Source span of each instruction, same indexing.
    pub spans: Vec<Span>,
    /// The top-level block's instructions.
    pub body: Vec<Value>,
    /// The values the expression yields.
    pub outputs: Vec<Value>,
    /// What the function reads from the context, so hosts compute no more than that.
    pub uses: Uses,
}

/// The parts of the evaluation context a function reads.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Uses {
    /// Reads `TIME`.
    pub time: bool,
    /// Reads `MODE`.
    pub mode: bool,
    /// Variable slots read, sorted.
    pub vars: Vec<u32>,
    /// Measure slots read, sorted.
    pub measures: Vec<u32>,
    /// Spline indices read, sorted.
    pub splines: Vec<u32>,
}

impl Uses {
    /// Smallest variable array the function may be given.
    pub fn vars_len(&self) -> usize {
        self.vars.last().map_or(0, |&v| v as usize + 1)
    }

    /// Smallest measure array the function may be given.
    pub fn measures_len(&self) -> usize {
        self.measures.last().map_or(0, |&v| v as usize + 1)
    }

    /// Smallest spline table the function may be given.
    pub fn splines_len(&self) -> usize {
        self.splines.last().map_or(0, |&v| v as usize + 1)
    }
}

impl Inst {
    /// Calls `f` on each value this instruction reads directly: for an IF its test only
    /// (its arms are blocks of their own), for `IfExtra` the IF.
    pub fn each_operand(&self, mut f: impl FnMut(Value)) {
        match self {
            Inst::Const(_) | Inst::Var(_) | Inst::Time | Inst::Mode | Inst::Measure(_) => {}
            Inst::Neg(a) | Inst::Sqrt(a) => f(*a),
            Inst::Add(a, b) | Inst::Sub(a, b) | Inst::Mul(a, b) | Inst::Div(a, b) => {
                f(*a);
                f(*b);
            }
            Inst::Call(_, args) | Inst::Partial { args, .. } => args.iter().copied().for_each(f),
            Inst::Spline { x, z, .. } => {
                f(*x);
                f(*z);
            }
            Inst::If { test, .. } => f(*test),
            Inst::IfExtra { of, .. } => f(*of),
            Inst::Select {
                a,
                b,
                then,
                otherwise,
                ..
            } => [*a, *b, *then, *otherwise].into_iter().for_each(f),
        }
    }
}

impl Function {
    /// The instruction that defines `v`.
    pub fn inst(&self, v: Value) -> &Inst {
        &self.insts[v as usize]
    }

    /// True when the function yields a vector.
    pub fn is_vector(&self) -> bool {
        self.outputs.len() == 3
    }

    /// The constant a value holds, if it is one.
    pub fn constant(&self, v: Value) -> Option<f64> {
        match self.inst(v) {
            Inst::Const(c) => Some(*c),
            _ => None,
        }
    }
}
