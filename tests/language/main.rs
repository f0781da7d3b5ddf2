//! Integration tests of the expression language: spec conformance cases, the parser's
//! round trip, the corpus, the bad-input catalogue and diagnostic snapshots.

mod bad_input;
mod corpus;
mod host_data;
mod roundtrip;
mod snapshots;
mod spec_cases;
mod support;
