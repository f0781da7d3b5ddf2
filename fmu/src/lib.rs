//! The slave library of the FMUs `mbfx fmu` writes (FMI 2.0 co-simulation): a cdylib
//! that exports the standard's C functions and runs the dataset in the FMU's
//! `resources/` through mbfx's stepping API. Each FMU carries this library as
//! `binaries/linux64/<modelIdentifier>.so`; what it runs is decided by the resources
//! alone (`model.adm`, `settings.toml`), so one build serves every FMU.
//!
//! The C entry points ([`entry`]: the common functions; [`cosim`]: stepping, status,
//! snapshots) check every pointer and run under a panic guard ([`guard`]): a refusal or
//! a panic is `fmi2Error` with its reason sent to the importer's logger, never a crash
//! of the host. [`instance`] is the state machine in safe Rust, over the one file that
//! meets the stepping API ([`adapter`]); [`resources`] reads the FMU's folder and
//! [`types`] declares the standard's C types.

pub mod adapter;
pub mod cosim;
pub mod entry;
pub mod guard;
pub mod instance;
pub mod resources;
pub mod types;
