//! Meshes (EXTERNAL): one incident per connected region.
