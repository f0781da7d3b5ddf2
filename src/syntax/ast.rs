//! The syntax tree: an arena of nodes addressed by [`NodeId`].
//!
//! The parser's actions build nodes through [`Builder`]; nodes refer to children by index,
//! so a tree of any depth is dropped without recursion, and each node records its depth so
//! later passes know in advance how deep their recursion will go.

use crate::diag::Span;

/// Index of a node in [`Ast::nodes`].
pub type NodeId = u32;

/// Binary operators, in the language's spelling.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
    /// `%`: cross product of two vectors.
    Cross,
    /// `**`: power.
    Pow,
}

impl BinOp {
    /// The operator as written in the language.
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Cross => "%",
            BinOp::Pow => "**",
        }
    }
}

/// Unary sign operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnOp {
    /// `-a`.
    Neg,
    /// `+a`.
    Plus,
}

/// What a node is.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// A number literal.
    Num(f64),
    /// A bare name: index into [`Ast::names`].
    Name(u32),
    /// `NAME(args)`; `name_end` closes the name's span (which starts at the node's start);
    /// the arguments are `Ast::args[args.0..args.0 + args.1]` (see [`Ast::call_args`]).
    Call {
        /// Index into [`Ast::names`].
        name: u32,
        /// Byte offset where the name ends.
        name_end: u32,
        /// (start, count) in [`Ast::args`].
        args: (u32, u32),
    },
    /// `IF(test: neg, zero, pos)`.
    If([NodeId; 4]),
    /// A signed operand.
    Unary(UnOp, NodeId),
    /// `a op b`.
    Binary(BinOp, NodeId, NodeId),
    /// `[a, b, c]`.
    Vector([NodeId; 3]),
    /// Where the parser recovered from an error (already diagnosed).
    Error,
}

/// One node: its kind, byte span and depth (1 for a leaf).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// What the node is.
    pub kind: Kind,
    /// Byte offset where the node starts.
    pub start: u32,
    /// Byte offset where it ends.
    pub end: u32,
    /// 1 for a leaf, else 1 + the deepest child's.
    pub depth: u32,
}

impl Node {
    /// The node's byte range.
    pub fn span(&self) -> Span {
        self.start as usize..self.end as usize
    }
}

/// Upper-cased names in one buffer, addressed by index (no allocation per name).
#[derive(Clone, Debug, Default)]
pub struct Names {
    text: String,
    ends: Vec<u32>,
}

impl Names {
    /// Forgets every name, keeping the buffers.
    pub fn clear(&mut self) {
        self.text.clear();
        self.ends.clear();
    }

    /// Appends `name` upper-cased and returns its index.
    pub fn push(&mut self, name: &str) -> u32 {
        let start = self.text.len();
        self.text.push_str(name);
        self.text[start..].make_ascii_uppercase();
        self.ends.push(self.text.len() as u32);
        (self.ends.len() - 1) as u32
    }

    /// The name with this index.
    pub fn get(&self, idx: u32) -> &str {
        let i = idx as usize;
        let start = if i == 0 { 0 } else { self.ends[i - 1] as usize };
        &self.text[start..self.ends[i] as usize]
    }
}

/// A parsed expression: its nodes, the argument lists of its calls and the upper-cased
/// names they mention.
#[derive(Clone, Debug, Default)]
pub struct Ast {
    /// Every node; a [`NodeId`] indexes it.
    pub nodes: Vec<Node>,
    /// Argument lists of calls, each a contiguous run.
    pub args: Vec<NodeId>,
    /// The upper-cased names the nodes mention.
    pub names: Names,
}

impl Ast {
    /// The node `id` addresses.
    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id as usize]
    }

    /// The name with index `idx`, upper case.
    pub fn name(&self, idx: u32) -> &str {
        self.names.get(idx)
    }

    /// The arguments of a call node's `args` range.
    pub fn call_args(&self, (start, len): (u32, u32)) -> &[NodeId] {
        &self.args[start as usize..(start + len) as usize]
    }

    /// Children of a node, in source order.
    pub fn children(&self, id: NodeId) -> Vec<NodeId> {
        match &self.node(id).kind {
            Kind::Num(_) | Kind::Name(_) | Kind::Error => Vec::new(),
            Kind::Call { args, .. } => self.call_args(*args).to_vec(),
            Kind::If(c) => c.to_vec(),
            Kind::Unary(_, a) => vec![*a],
            Kind::Binary(_, a, b) => vec![*a, *b],
            Kind::Vector(c) => c.to_vec(),
        }
    }

    /// A span-free S-expression of the tree, for structural comparisons in tests.
    /// Iterative, so any depth is safe.
    pub fn sexpr(&self, root: NodeId) -> String {
        enum Step {
            Open(NodeId),
            Text(&'static str),
        }
        let mut out = String::new();
        let mut stack = vec![Step::Open(root)];
        while let Some(step) = stack.pop() {
            let id = match step {
                Step::Text(t) => {
                    out.push_str(t);
                    continue;
                }
                Step::Open(id) => id,
            };
            let head = match &self.node(id).kind {
                Kind::Num(v) => {
                    out.push_str(&format!("{v:?}"));
                    continue;
                }
                Kind::Name(n) => {
                    out.push_str(self.name(*n));
                    continue;
                }
                Kind::Error => {
                    out.push_str("<error>");
                    continue;
                }
                Kind::Call { name, .. } => self.name(*name).to_string(),
                Kind::If(_) => "IF".to_string(),
                Kind::Unary(UnOp::Neg, _) => "neg".to_string(),
                Kind::Unary(UnOp::Plus, _) => "pos".to_string(),
                Kind::Binary(op, _, _) => op.symbol().to_string(),
                Kind::Vector(_) => "vec".to_string(),
            };
            out.push('(');
            out.push_str(&head);
            stack.push(Step::Text(")"));
            for child in self.children(id).into_iter().rev() {
                stack.push(Step::Open(child));
                stack.push(Step::Text(" "));
            }
        }
        out
    }
}

/// Builds nodes for the parser's actions; also collects the parser's recovered errors.
#[derive(Default)]
pub struct Builder {
    /// The tree built so far.
    pub ast: Ast,
    /// Errors the parser recovered from, in order.
    pub recovered: Vec<crate::syntax::parser::Recovered>,
    /// Arguments of the calls being parsed, innermost last: a call's arguments are the
    /// top of this stack when its `)` is reduced (inner calls finish first).
    pending_args: Vec<NodeId>,
}

impl Builder {
    /// An empty builder.
    pub fn new() -> Self {
        Builder {
            ast: Ast::default(),
            recovered: Vec::new(),
            pending_args: Vec::new(),
        }
    }

    /// Forgets the tree built so far (names included), keeping the buffers.
    pub fn clear(&mut self) {
        self.ast.nodes.clear();
        self.ast.args.clear();
        self.ast.names.clear();
        self.recovered.clear();
        self.pending_args.clear();
    }

    /// Records one argument of the call being parsed.
    pub fn arg(&mut self, e: NodeId) {
        self.pending_args.push(e);
    }

    fn push(&mut self, kind: Kind, start: usize, end: usize, depth: u32) -> NodeId {
        let id = self.ast.nodes.len() as NodeId;
        self.ast.nodes.push(Node {
            kind,
            start: start as u32,
            end: end as u32,
            depth,
        });
        id
    }

    fn depth_of(&self, ids: &[NodeId]) -> u32 {
        1 + ids
            .iter()
            .map(|&i| self.ast.node(i).depth)
            .max()
            .unwrap_or(0)
    }

    /// A number literal.
    pub fn num(&mut self, v: f64, l: usize, r: usize) -> NodeId {
        self.push(Kind::Num(v), l, r, 1)
    }

    /// A bare name (index into the names).
    pub fn name(&mut self, n: u32, l: usize, r: usize) -> NodeId {
        self.push(Kind::Name(n), l, r, 1)
    }

    /// A call whose `count` arguments are the top of the pending-argument stack.
    pub fn call(&mut self, name: u32, name_end: usize, count: u32, l: usize, r: usize) -> NodeId {
        let from = self.pending_args.len().saturating_sub(count as usize);
        let start = self.ast.args.len() as u32;
        self.ast.args.extend(self.pending_args.drain(from..));
        let args = (start, self.ast.args.len() as u32 - start);
        let depth = 1 + self
            .ast
            .call_args(args)
            .iter()
            .map(|&i| self.ast.node(i).depth)
            .max()
            .unwrap_or(0);
        let kind = Kind::Call {
            name,
            name_end: name_end as u32,
            args,
        };
        self.push(kind, l, r, depth)
    }

    /// `IF(test: neg, zero, pos)`.
    pub fn if_(&mut self, parts: [NodeId; 4], l: usize, r: usize) -> NodeId {
        let depth = self.depth_of(&parts);
        self.push(Kind::If(parts), l, r, depth)
    }

    /// A signed operand.
    pub fn unary(&mut self, op: UnOp, a: NodeId, l: usize, r: usize) -> NodeId {
        let depth = self.depth_of(&[a]);
        self.push(Kind::Unary(op, a), l, r, depth)
    }

    /// `a op b`.
    pub fn binary(&mut self, op: BinOp, a: NodeId, b: NodeId, l: usize, r: usize) -> NodeId {
        let depth = self.depth_of(&[a, b]);
        self.push(Kind::Binary(op, a, b), l, r, depth)
    }

    /// `[a, b, c]`.
    pub fn vector(&mut self, parts: [NodeId; 3], l: usize, r: usize) -> NodeId {
        let depth = self.depth_of(&parts);
        self.push(Kind::Vector(parts), l, r, depth)
    }

    /// An error node where the parser recovered.
    pub fn error(&mut self, l: usize, r: usize) -> NodeId {
        self.push(Kind::Error, l, r, 1)
    }

    /// Records an error the parser recovered from and stands an error node in its place.
    pub fn recover(&mut self, e: crate::syntax::parser::Recovered, l: usize, r: usize) -> NodeId {
        self.recovered.push(e);
        self.error(l, r)
    }
}
