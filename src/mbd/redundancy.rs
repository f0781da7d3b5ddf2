//! Redundancy analysis of the constraint Jacobian at the assembled configuration.
