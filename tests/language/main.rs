//! Integration tests of the expression language: spec conformance cases, the parser's
//! round trip, the fast parser against the grammar, the corpus, the bad-input catalogue
//! and diagnostic snapshots.

mod bad_input;
mod corpus;
mod fast_parser;
mod host_data;
mod roundtrip;
mod snapshots;
mod spec_cases;
mod support;
