//! Unit tests of the model layer, one file per topic: the statement layer
//! (`statement`), the model reader on small datasets (`model`), and both against the
//! whole `.adm` corpus (`corpus`, `model_corpus`); the units check of datasets (`units`);
//! GRAPHICS statements, per kind, per error and over the corpus (`graphics`).

mod corpus;
/// The corpus lister the integration tests use too (one walk of `../shared/corpus`).
#[path = "../../../tests/common/mod.rs"]
mod corpus_files;
mod graphics;
mod model;
mod model_corpus;
mod statement;
mod units;
