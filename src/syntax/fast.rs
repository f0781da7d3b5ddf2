//! Fast path of the parser: a hand-written precedence-climbing parser for input without
//! errors. It builds, through the same [`Builder`] actions, exactly the tree the LALRPOP
//! grammar (`grammar/function.lalrpop`, the grammar of record) builds: same nodes in the
//! same order, same spans. On the first token the grammar would not accept it gives up,
//! and the caller re-parses with the LALRPOP parser, which reports every error; so
//! diagnostics come from the grammar alone. `tests/language/fast_parser.rs` checks the
//! two parsers against each other on generated token sequences and on the whole corpus.
//!
//! Operator chains and signs are parsed in loops; besides one step from `+ -` to `* / %`,
//! only brackets recurse, and the lexer bounds their depth.

use crate::syntax::ast::{BinOp, Builder, NodeId, UnOp};
use crate::syntax::lexer::Tok;

/// The input is not a valid expression (the grammar decides why).
#[derive(Debug, PartialEq, Eq)]
pub struct Reject;

/// A parsed subexpression: its node, and the bounds of the tokens it spans (which for a
/// bracketed operand include the brackets, as the grammar's `@L`/`@R` do). Small enough
/// to be returned in registers.
#[derive(Clone, Copy)]
struct Sub {
    id: NodeId,
    start: u32,
    end: u32,
}

/// A pending prefix of a unary chain: a sign, or the base of a `**`.
#[derive(Clone, Copy)]
pub enum Frame {
    /// A sign, with the byte offset where it starts.
    Sign(UnOp, u32),
    /// The base of a `**`, with the byte offset where it starts.
    PowBase(NodeId, u32),
}

/// Parses `tokens` (which hold no [`Tok::Invalid`] or [`Tok::Relational`]: the lexer
/// diagnosed those) into `b`, returning the root. `frames` is scratch space, kept by the
/// caller so that parsing allocates nothing once warm.
pub fn parse(
    tokens: &[(usize, Tok, usize)],
    b: &mut Builder,
    frames: &mut Vec<Frame>,
) -> Result<NodeId, Reject> {
    frames.clear();
    let mut p = Parser {
        tokens,
        pos: 0,
        b,
        frames,
        depth: 0,
    };
    let root = p.expr(EXPR)?;
    if p.pos == tokens.len() {
        Ok(root.id)
    } else {
        Err(Reject)
    }
}

/// Precedence levels of the binary operators: `+ -` (`Expr`), then `* / %` (`Term`).
const EXPR: u8 = 1;
const TERM: u8 = 2;

/// The binary operator a token denotes, with its precedence level.
fn binary_op(t: Tok) -> Option<(BinOp, u8)> {
    Some(match t {
        Tok::Plus => (BinOp::Add, EXPR),
        Tok::Minus => (BinOp::Sub, EXPR),
        Tok::Star => (BinOp::Mul, TERM),
        Tok::Slash => (BinOp::Div, TERM),
        Tok::Percent => (BinOp::Cross, TERM),
        _ => return None,
    })
}

struct Parser<'t, 'b> {
    tokens: &'t [(usize, Tok, usize)],
    pos: usize,
    b: &'b mut Builder,
    frames: &'b mut Vec<Frame>,
    /// Bracket nesting at the current position.
    depth: u32,
}

impl Parser<'_, '_> {
    fn peek(&self) -> Option<Tok> {
        self.tokens.get(self.pos).map(|t| t.1)
    }

    /// Takes the next token, whatever it is.
    fn next(&mut self) -> Result<(usize, Tok, usize), Reject> {
        let t = *self.tokens.get(self.pos).ok_or(Reject)?;
        self.pos += 1;
        Ok(t)
    }

    /// Takes the next token, which must be `want`; returns its end.
    fn expect(&mut self, want: Tok) -> Result<usize, Reject> {
        match self.next()? {
            (_, t, end) if t == want => Ok(end),
            _ => Err(Reject),
        }
    }

    /// `Expr: Expr ("+" | "-") Term | Term` and `Term: Term ("*" | "/" | "%") Unary | Unary`
    /// by precedence climbing: the operands of this level's operators are parsed at the
    /// next level up, so left-associative chains are loops and operands at the level of
    /// `min` or above build their nodes in the order the grammar reduces them.
    fn expr(&mut self, min: u8) -> Result<Sub, Reject> {
        let mut a = self.unary()?;
        while let Some((op, level)) = self.peek().and_then(binary_op) {
            if level < min {
                break;
            }
            self.pos += 1;
            let c = if level == TERM {
                self.unary()?
            } else {
                self.expr(TERM)?
            };
            a = self.binary(op, a, c);
        }
        Ok(a)
    }

    fn binary(&mut self, op: BinOp, a: Sub, c: Sub) -> Sub {
        Sub {
            id: self
                .b
                .binary(op, a.id, c.id, a.start as usize, c.end as usize),
            start: a.start,
            end: c.end,
        }
    }

    /// `Unary: ("-" | "+") Unary | Primary "**" Unary | Primary`, in a loop: signs and
    /// power bases are stacked as frames, then applied innermost first once the last
    /// primary is read (the order in which the grammar reduces them).
    fn unary(&mut self) -> Result<Sub, Reject> {
        let base = self.frames.len();
        let last = loop {
            while let Some((start, t, _)) = self.tokens.get(self.pos).copied() {
                let op = match t {
                    Tok::Minus => UnOp::Neg,
                    Tok::Plus => UnOp::Plus,
                    _ => break,
                };
                self.frames.push(Frame::Sign(op, start as u32));
                self.pos += 1;
            }
            let p = self.primary()?;
            if self.peek() != Some(Tok::Pow) {
                break p;
            }
            self.pos += 1;
            self.frames.push(Frame::PowBase(p.id, p.start));
        };
        let end = last.end;
        let mut sub = last;
        while self.frames.len() > base {
            let Some(frame) = self.frames.pop() else {
                break;
            };
            sub = match frame {
                Frame::Sign(op, start) => Sub {
                    id: self.b.unary(op, sub.id, start as usize, end as usize),
                    start,
                    end,
                },
                Frame::PowBase(id, start) => Sub {
                    id: self
                        .b
                        .binary(BinOp::Pow, id, sub.id, start as usize, end as usize),
                    start,
                    end,
                },
            };
        }
        Ok(sub)
    }

    /// An expression inside brackets: the one place the parser recurses (the lexer
    /// bounds bracket depth), on a stack that grows on demand.
    fn nested(&mut self) -> Result<Sub, Reject> {
        self.depth += 1;
        let sub = crate::stack::every_few_levels(self.depth, || self.expr(EXPR));
        self.depth -= 1;
        sub
    }

    /// `Primary`: a number, a name, a call, an IF, a bracketed expression or a vector.
    fn primary(&mut self) -> Result<Sub, Reject> {
        let (start, tok, end) = self.next()?;
        let (id, end) = match tok {
            Tok::Num(v) => (self.b.num(v, start, end), end),
            Tok::Name(n) => (self.b.name(n, start, end), end),
            Tok::Call(n) => {
                self.expect(Tok::LParen)?;
                let mut count = 0;
                let close = if self.peek() == Some(Tok::RParen) {
                    self.next()?.2
                } else {
                    loop {
                        let a = self.nested()?;
                        self.b.arg(a.id);
                        count += 1;
                        match self.next()? {
                            (_, Tok::Comma, _) => {}
                            (_, Tok::RParen, close) => break close,
                            _ => return Err(Reject),
                        }
                    }
                };
                (self.b.call(n, end, count, start, close), close)
            }
            Tok::If => {
                self.expect(Tok::LParen)?;
                let t = self.nested()?;
                self.expect(Tok::Colon)?;
                let [n, z, p] = self.list::<3>(Tok::RParen)?;
                let close = self.tokens[self.pos - 1].2;
                (self.b.if_([t.id, n, z, p], start, close), close)
            }
            Tok::LParen => {
                let inner = self.nested()?;
                let close = self.expect(Tok::RParen)?;
                (inner.id, close)
            }
            Tok::LBracket => {
                let parts = self.list::<3>(Tok::RBracket)?;
                let close = self.tokens[self.pos - 1].2;
                (self.b.vector(parts, start, close), close)
            }
            _ => return Err(Reject),
        };
        // Positions fit in u32: the tree stores them so.
        Ok(Sub {
            id,
            start: start as u32,
            end: end as u32,
        })
    }

    /// `N` expressions separated by commas and closed by `close`.
    fn list<const N: usize>(&mut self, close: Tok) -> Result<[NodeId; N], Reject> {
        let mut out = [0; N];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = self.nested()?.id;
            self.expect(if i + 1 == N { close } else { Tok::Comma })?;
        }
        Ok(out)
    }
}
