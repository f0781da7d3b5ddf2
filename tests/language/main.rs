//! Integration tests of the expression language: spec conformance cases, the parser's
//! round trip, the fast parser against the grammar, the corpus, the bad-input catalogue,
//! diagnostic snapshots and the post order of the syntax tree's arena.

mod bad_input;
mod corpus;
mod fast_parser;
mod host_data;
mod post_order;
mod roundtrip;
mod snapshots;
mod spec_cases;
mod support;
