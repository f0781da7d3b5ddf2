//! Placeholder until the scenes branch lands (replaced by the generator).

/// The dataset of a generated scene.
pub fn generate(_kind: &str, _n: usize) -> Option<String> {
    None
}
