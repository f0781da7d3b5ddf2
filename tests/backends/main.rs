//! Back-end tests: the JIT against the interpreter (bit for bit, on generated expressions
//! and on the corpus), the JIT's own contracts (symbol table, lazy IF, batches, memory),
//! the branch-free lowering against the runtime, and derivatives against analytic
//! formulas and finite differences.

mod corpus;
mod deriv;
mod differential;
mod jit;
mod support;
