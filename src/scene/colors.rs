//! The colours of what is drawn (linear RGBA): one per part from a fixed palette, so a
//! part's graphics share it as Adams shows them, a neutral tone for glyphs, a strong
//! accent for force arrows, and red, green, blue for the ground triad's x, y, z.

/// The part palette, cycled by the part's place in the dataset (ground has its own).
const PALETTE: [[f32; 3]; 8] = [
    [0.12, 0.30, 0.70],
    [0.80, 0.35, 0.05],
    [0.10, 0.50, 0.15],
    [0.60, 0.10, 0.45],
    [0.05, 0.50, 0.55],
    [0.75, 0.60, 0.05],
    [0.35, 0.20, 0.70],
    [0.55, 0.25, 0.15],
];

/// Ground's graphics: a grey.
pub const GROUND: [f32; 4] = [0.35, 0.35, 0.35, 1.0];
/// Glyphs: a light neutral.
pub const GLYPH: [f32; 4] = [0.62, 0.60, 0.55, 1.0];
/// Force arrows: a strong magenta.
pub const ARROW: [f32; 4] = [0.95, 0.05, 0.45, 1.0];
/// The ground triad's x, y, z.
pub const AXES: [[f32; 4]; 3] = [
    [0.9, 0.05, 0.05, 1.0],
    [0.05, 0.7, 0.05, 1.0],
    [0.05, 0.15, 0.9, 1.0],
];

/// The colour of the part at `index` in the dataset (ground's when `ground`).
pub fn part(index: usize, ground: bool) -> [f32; 4] {
    if ground {
        return GROUND;
    }
    let [r, g, b] = PALETTE[index % PALETTE.len()];
    [r, g, b, 1.0]
}
