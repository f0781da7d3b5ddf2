//! The LR driver that runs the LALRPOP-generated tables of `grammar/function.lalrpop`: it
//! shifts, reduces and recovers from syntax errors exactly as lalrpop-util's own driver
//! (`lalrpop_util::state_machine::Parser`, 0.23) does, so the trees and the errors are
//! the same, but its error recovery costs time in proportion to the input, not to the
//! input times the nesting depth. `build.rs` points the generated `ExprParser::parse` here.
//!
//! Why not lalrpop-util's driver: for each syntax error it asks, for every state on the
//! stack that can take the error token, whether that state would accept the lookahead,
//! by copying the stack below it and simulating the reductions on the copy; it does it
//! again for every token it drops, and lists the expected terminals by copying the stack
//! once per terminal. On `((((… 1 1 1` that is work and allocation quadratic in the
//! depth for each token, and it dominated the `parse_check` fuzzer under
//! AddressSanitizer. Here:
//! - a simulation reads the real stack below a small overlay of the states it pushed
//!   (kept between simulations), so it copies and allocates nothing;
//! - while tokens are dropped the stack does not change, so a token kind that no state
//!   accepted is not looked for again in the same recovery;
//! - the simulations from the states of one search often meet (below a chain of signs,
//!   each reduction leads where the one from the next state down starts): a simulation
//!   that reaches a point another one already left without accepting stops there;
//! - recovery works within a budget proportional to the number of tokens: past it the
//!   parse stops at the error at hand (reported like any other) instead of searching on.
//!   Real expressions use a small fraction of it; garbage stays linear;
//! - an error is reported as a [`SyntaxError`] (in LALRPOP's `ParseError::User`), whose
//!   expected terminals are a bit set, not a list of strings: one allocation per expected
//!   terminal per error was the next largest cost.
//!
//! It relies on lalrpop-util's `state_machine` interface (hidden in the docs, but the one
//! the generated code is written against); `Cargo.lock` pins its version.

use crate::syntax::lexer::Tok;
use lalrpop_util::state_machine::{
    ParseError, ParseResult, ParserAction, ParserDefinition, SimulatedReduce, SymbolTriple,
    TokenTriple,
};
use lalrpop_util::{ErrorRecovery, ParseError as Error};
use rustc_hash::FxHashSet;
use std::hash::Hash;

/// Recovery work allowed per token of input: states examined plus reductions simulated.
/// The 7 800 expressions of the fuzz corpora and the language corpus need at most 41 (a
/// chain of a hundred signs between errors); garbage that makes every error search a
/// deep stack (a thousand open brackets, then an error every few tokens) needs hundreds,
/// and is cut short.
const WORK_PER_TOKEN: usize = 128;

/// One token of each of the grammar's terminals, in the order of its `extern` block
/// (`terminals_match_the_grammar` checks them against `grammar/function.lalrpop`). Each
/// is looked up through the tables, so the order only numbers the bits of [`Expected`].
const TERMINALS: [Tok; 18] = [
    Tok::Num(0.0),
    Tok::Name(0),
    Tok::Call(0),
    Tok::If,
    Tok::Plus,
    Tok::Minus,
    Tok::Star,
    Tok::Pow,
    Tok::Slash,
    Tok::Percent,
    Tok::LParen,
    Tok::RParen,
    Tok::LBracket,
    Tok::RBracket,
    Tok::Comma,
    Tok::Colon,
    Tok::Relational,
    Tok::Invalid,
];

/// The terminals a parser state would take, as a set over [`TERMINALS`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Expected(u32);

impl Expected {
    /// Whether a token of the same kind as `tok` (whatever its value) is expected.
    pub fn contains(self, tok: Tok) -> bool {
        let kind = std::mem::discriminant(&tok);
        TERMINALS
            .iter()
            .position(|t| std::mem::discriminant(t) == kind)
            .is_some_and(|i| self.0 & (1 << i) != 0)
    }

    /// The set named by LALRPOP's expected-token list (terminals as the grammar writes
    /// them, quoted).
    pub fn from_names(names: &[String]) -> Self {
        let declared = declared_terminals();
        let mut bits = 0;
        for name in names {
            if let Some(i) = declared
                .iter()
                .position(|&(n, _)| n == name.trim_matches('"'))
            {
                bits |= 1 << i;
            }
        }
        Expected(bits)
    }
}

/// The syntax errors the driver reports.
#[derive(Clone, Debug, PartialEq)]
pub enum SyntaxError {
    /// `token` cannot come here; `expected` could.
    Unexpected {
        token: (usize, Tok, usize),
        expected: Expected,
    },
    /// The input ends at `location`, where `expected` could come.
    End { location: usize, expected: Expected },
}

/// The `"name" => Tok::Variant` pairs of the grammar's `extern` block, in order.
fn declared_terminals() -> Vec<(&'static str, &'static str)> {
    let grammar = include_str!("../../grammar/function.lalrpop");
    let mut declared = Vec::new();
    for line in grammar.lines() {
        if let Some((name, tok)) = line.trim().split_once(" => Tok::") {
            let variant = tok.split(['(', ',']).next().unwrap_or_default();
            declared.push((name.trim_matches('"'), variant));
        }
    }
    declared
}

/// Parses `tokens` with the tables of `definition`: the generated `ExprParser::parse`
/// calls this in place of `lalrpop_util::state_machine::Parser::drive`.
pub fn drive<D, I>(definition: D, tokens: I) -> ParseResult<D>
where
    D: ParserDefinition<Token = Tok, TokenIndex = usize, Location = usize, Error = SyntaxError>,
    D::StateIndex: Eq + Hash,
    I: Iterator<Item = Result<TokenTriple<D>, ParseError<D>>>,
{
    let count = tokens.size_hint().0;
    // The stacks rarely grow deeper than this; deep nesting grows them as usual.
    let capacity = count.min(64) + 2;
    let mut states = Vec::with_capacity(capacity);
    states.push(definition.start_state());
    Driver {
        last_location: definition.start_location(),
        definition,
        tokens,
        states,
        symbols: Vec::with_capacity(capacity),
        overlay: Vec::new(),
        path: Vec::new(),
        refused: FxHashSet::default(),
        work: 0,
        budget: WORK_PER_TOKEN.saturating_mul(count + 1),
    }
    .parse()
}

struct Driver<D: ParserDefinition, I> {
    definition: D,
    tokens: I,
    states: Vec<D::StateIndex>,
    symbols: Vec<SymbolTriple<D>>,
    last_location: usize,
    /// States pushed by a simulation above the part of `states` it still stands on.
    overlay: Vec<D::StateIndex>,
    /// The points (stack depth below the overlay, the overlay's one state) a simulation
    /// passed, and those from which the current search's token is known to be refused.
    path: Vec<(usize, D::StateIndex)>,
    refused: FxHashSet<(usize, D::StateIndex)>,
    /// Recovery work done so far, and the most allowed.
    work: usize,
    budget: usize,
}

/// What the parse goes on with after fetching a token or recovering from an error.
enum Next<D: ParserDefinition> {
    Token(TokenTriple<D>, usize),
    Eof,
    Done(ParseResult<D>),
}

impl<D, I> Driver<D, I>
where
    D: ParserDefinition<Token = Tok, TokenIndex = usize, Location = usize, Error = SyntaxError>,
    D::StateIndex: Eq + Hash,
    I: Iterator<Item = Result<TokenTriple<D>, ParseError<D>>>,
{
    fn top_state(&self) -> D::StateIndex {
        self.states[self.states.len() - 1]
    }

    fn parse(&mut self) -> ParseResult<D> {
        'shift: loop {
            let (mut lookahead, mut index) = match self.next_token() {
                Next::Token(t, i) => (t, i),
                Next::Eof => return self.parse_eof(),
                Next::Done(result) => return result,
            };
            loop {
                let action = self.definition.action(self.top_state(), index);
                if let Some(target) = action.as_shift() {
                    let symbol = self.definition.token_to_symbol(index, lookahead.1);
                    self.states.push(target);
                    self.symbols.push((lookahead.0, symbol, lookahead.2));
                    continue 'shift;
                } else if let Some(reduction) = action.as_reduce() {
                    if let Some(result) = self.reduce(reduction, Some(&lookahead.0)) {
                        // The start symbol was reduced with input left over.
                        return match result {
                            Ok(_) => Err(Error::ExtraToken { token: lookahead }),
                            Err(e) => Err(e),
                        };
                    }
                } else {
                    match self.recover(Some((lookahead, index))) {
                        Next::Token(t, i) => (lookahead, index) = (t, i),
                        Next::Eof => return self.parse_eof(),
                        Next::Done(result) => return result,
                    }
                }
            }
        }
    }

    /// Reduces at the end of the input until the start symbol is reduced.
    fn parse_eof(&mut self) -> ParseResult<D> {
        loop {
            let action = self.definition.eof_action(self.top_state());
            if let Some(reduction) = action.as_reduce() {
                if let Some(result) = self.reduce(reduction, None) {
                    return result;
                }
            } else {
                match self.recover(None) {
                    Next::Eof => {}
                    Next::Done(result) => return result,
                    Next::Token(..) => unreachable!("recovery at the end resumes at the end"),
                }
            }
        }
    }

    fn reduce(
        &mut self,
        reduction: D::ReduceIndex,
        lookahead_start: Option<&usize>,
    ) -> Option<ParseResult<D>> {
        self.definition.reduce(
            reduction,
            lookahead_start,
            &mut self.states,
            &mut self.symbols,
        )
    }

    fn next_token(&mut self) -> Next<D> {
        let token = match self.tokens.next() {
            Some(Ok(t)) => t,
            Some(Err(e)) => return Next::Done(Err(e)),
            None => return Next::Eof,
        };
        self.last_location = token.2;
        match self.definition.token_to_index(&token.1) {
            Some(i) => Next::Token(token, i),
            None => Next::Done(Err(self.unrecognized(Some(token)))),
        }
    }

    /// The error for `token` (`None`: the end of the input) on the current stack.
    fn unrecognized(&mut self, token: Option<TokenTriple<D>>) -> ParseError<D> {
        let expected = self.expected();
        Error::User {
            error: match token {
                Some(token) => SyntaxError::Unexpected { token, expected },
                None => SyntaxError::End {
                    location: self.last_location,
                    expected,
                },
            },
        }
    }

    /// The terminals that the current stack would shift (after reductions).
    fn expected(&mut self) -> Expected {
        let depth = self.states.len();
        let mut bits = 0;
        for (bit, tok) in TERMINALS.iter().enumerate() {
            let Some(index) = self.definition.token_to_index(tok) else {
                continue;
            };
            if self.accepts(depth, None, Some(index), false) {
                bits |= 1 << bit;
            }
        }
        Expected(bits)
    }

    /// Error recovery, as lalrpop-util does it: reduce what the error token lets us reduce;
    /// then find the topmost state that can shift the error token and, once it has, go on
    /// with the lookahead; if none can, drop the lookahead and try with the next token.
    /// The recovered error replaces the popped symbols and dropped tokens.
    fn recover(&mut self, mut lookahead: Option<(TokenTriple<D>, usize)>) -> Next<D> {
        let error = self.unrecognized(lookahead.as_ref().map(|(t, _)| *t));
        if self.work > self.budget {
            return Next::Done(Err(error));
        }
        loop {
            let action = self.definition.error_action(self.top_state());
            let Some(reduction) = action.as_reduce() else {
                break;
            };
            let start = lookahead.as_ref().map(|(t, _)| &t.0);
            if let Some(result) = self.reduce(reduction, start) {
                return Next::Done(result);
            }
        }

        let depth = self.states.len();
        // Token kinds (bit i for index i < 63, bit 63 for the end of input) that no state
        // accepts: the stack does not change while tokens are dropped, so neither does the
        // answer.
        let mut refused_kinds: u64 = 0;
        let mut dropped: Option<(usize, usize)> = None;
        let top = 'find: loop {
            let index = lookahead.as_ref().map(|&(_, i)| i);
            let bit = match index {
                None => 1 << 63,
                Some(i) if i < 63 => 1 << i,
                Some(_) => 0,
            };
            if bit == 0 || refused_kinds & bit == 0 {
                self.refused.clear();
                for top in (0..depth).rev() {
                    self.work += 1;
                    if self.work > self.budget {
                        return Next::Done(Err(error));
                    }
                    let Some(error_state) =
                        self.definition.error_action(self.states[top]).as_shift()
                    else {
                        continue;
                    };
                    if self.accepts(top + 1, Some(error_state), index, true) {
                        break 'find top;
                    }
                }
                refused_kinds |= bit;
            }
            // No state takes the lookahead after an error: drop it, or give up at the end.
            let Some((token, _)) = lookahead.take() else {
                return Next::Done(Err(error));
            };
            dropped = Some(match dropped {
                Some((start, _)) => (start, token.2),
                None => (token.0, token.2),
            });
            match self.next_token() {
                Next::Token(t, i) => lookahead = Some((t, i)),
                Next::Eof => {}
                Next::Done(result) => return Next::Done(result),
            }
        };

        // The error's span: from the first popped symbol, else the first dropped token,
        // else the end of what stays; to the last dropped token, else the last popped
        // symbol, else the lookahead's start.
        let start = if let Some(popped) = self.symbols.get(top) {
            popped.0
        } else if let Some((first, _)) = &dropped {
            *first
        } else if top > 0 {
            self.symbols[top - 1].2
        } else {
            self.definition.start_location()
        };
        let end = if let Some((_, last)) = &dropped {
            *last
        } else if depth - 1 > top {
            self.symbols[self.symbols.len() - 1].2
        } else if let Some((token, _)) = &lookahead {
            token.0
        } else {
            start
        };

        self.states.truncate(top + 1);
        self.symbols.truncate(top);
        let Some(error_state) = self.definition.error_action(self.states[top]).as_shift() else {
            unreachable!("the recovery state shifts the error token");
        };
        self.states.push(error_state);
        // The dropped tokens are not kept: only the span above uses them.
        let recovery = self.definition.error_recovery_symbol(ErrorRecovery {
            error,
            dropped_tokens: Vec::new(),
        });
        self.symbols.push((start, recovery, end));
        match lookahead {
            Some((t, i)) => Next::Token(t, i),
            None => Next::Eof,
        }
    }

    /// Whether `token` (`None`: the end of the input) would be shifted, or the input
    /// accepted, from the stack made of the first `depth` states with `pushed` on top,
    /// reductions included. The real stack is only read: the states a simulated reduction
    /// pushes go on `overlay`, and pops take from the overlay first. With `remember`, the
    /// points where a refusal went through are kept in `refused` for the next call with
    /// the same token and stack.
    fn accepts(
        &mut self,
        depth: usize,
        pushed: Option<D::StateIndex>,
        token: Option<usize>,
        remember: bool,
    ) -> bool {
        let overlay = &mut self.overlay;
        overlay.clear();
        overlay.extend(pushed);
        self.path.clear();
        // The search goes down the stack, so later simulations start below `depth` and
        // can only meet this one at points below it.
        let start = depth;
        let mut depth = depth;
        let states = &self.states[..];
        let top = |overlay: &Vec<D::StateIndex>, depth: usize| {
            overlay.last().copied().unwrap_or(states[depth - 1])
        };
        loop {
            let state = top(overlay, depth);
            if remember && overlay.len() == 1 {
                // Where the simulation goes from here depends on this point alone.
                if depth < start {
                    if self.refused.contains(&(depth, state)) {
                        self.refused.extend(self.path.drain(..));
                        return false;
                    }
                    self.path.push((depth, state));
                }
            }
            let action = match token {
                None => self.definition.eof_action(state),
                Some(i) => self.definition.action(state, i),
            };
            if action.is_error() {
                if remember {
                    self.refused.extend(self.path.drain(..));
                }
                return false;
            }
            let Some(reduction) = action.as_reduce() else {
                return true;
            };
            self.work += 1;
            match self.definition.simulate_reduce(reduction) {
                SimulatedReduce::Accept => return true,
                SimulatedReduce::Reduce {
                    states_to_pop,
                    nonterminal_produced,
                } => {
                    let from_overlay = states_to_pop.min(overlay.len());
                    overlay.truncate(overlay.len() - from_overlay);
                    depth -= states_to_pop - from_overlay;
                    let next = self
                        .definition
                        .goto(top(overlay, depth), nonterminal_produced);
                    overlay.push(next);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{declared_terminals, Expected, TERMINALS};
    use crate::syntax::lexer::Tok;

    /// One token per terminal of the grammar's `extern` block, in its order.
    #[test]
    fn terminals_match_the_grammar() {
        let declared: Vec<&str> = declared_terminals().iter().map(|&(_, v)| v).collect();
        let ours: Vec<String> = TERMINALS
            .iter()
            .map(|tok| {
                format!("{tok:?}")
                    .split('(')
                    .next()
                    .unwrap_or_default()
                    .to_string()
            })
            .collect();
        assert_eq!(ours, declared);
    }

    #[test]
    fn expected_sets_read_lalrpop_names() {
        let set = Expected::from_names(&["\"number\"".to_string(), "\")\"".to_string()]);
        assert!(set.contains(Tok::Num(2.5)));
        assert!(set.contains(Tok::RParen));
        assert!(!set.contains(Tok::Name(0)));
        assert!(!set.contains(Tok::Plus));
    }
}
