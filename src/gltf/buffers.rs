//! The one binary buffer of a .glb and the bufferViews and accessors into it: each
//! array is appended 4-byte aligned in its own bufferView (with its target where it
//! holds vertices or indices), and its accessor carries min/max where the spec asks
//! (POSITION, animation inputs) or always for float data, which costs little.

use serde_json::{json, Value};

/// `ARRAY_BUFFER` and `ELEMENT_ARRAY_BUFFER`: a bufferView's target.
pub(super) const VERTICES: u32 = 34962;
pub(super) const INDICES: u32 = 34963;
/// Component types: `FLOAT` and `UNSIGNED_INT`.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// The buffer as it grows, with its bufferViews and accessors (JSON).
#[derive(Default)]
pub(super) struct Buffers {
    pub(super) bin: Vec<u8>,
    pub(super) views: Vec<Value>,
    pub(super) accessors: Vec<Value>,
}

impl Buffers {
    /// Appends `bytes` as a bufferView (with `target`, if any); returns its index.
    fn view(&mut self, bytes: impl Iterator<Item = [u8; 4]>, target: Option<u32>) -> usize {
        let start = self.bin.len();
        self.bin.extend(bytes.flatten());
        let mut view =
            json!({"buffer": 0, "byteOffset": start, "byteLength": self.bin.len() - start});
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.views.push(view);
        self.views.len() - 1
    }

    /// An accessor of float vectors (`VEC3`, `VEC4`, or `SCALAR` for one component)
    /// with their min and max; returns its index.
    pub(super) fn floats<const N: usize>(
        &mut self,
        data: &[[f32; N]],
        target: Option<u32>,
    ) -> usize {
        let mut min = [f32::INFINITY; N];
        let mut max = [f32::NEG_INFINITY; N];
        for v in data {
            for c in 0..N {
                min[c] = min[c].min(v[c]);
                max[c] = max[c].max(v[c]);
            }
        }
        let view = self.view(data.iter().flatten().map(|x| x.to_le_bytes()), target);
        let kind = match N {
            1 => "SCALAR",
            2 => "VEC2",
            3 => "VEC3",
            _ => "VEC4",
        };
        self.accessors.push(json!({
            "bufferView": view, "componentType": FLOAT, "count": data.len(), "type": kind,
            "min": min.to_vec(), "max": max.to_vec(),
        }));
        self.accessors.len() - 1
    }

    /// An accessor of vertex indices; returns its index.
    pub(super) fn indices(&mut self, data: &[u32]) -> usize {
        let view = self.view(data.iter().map(|i| i.to_le_bytes()), Some(INDICES));
        self.accessors.push(json!({
            "bufferView": view, "componentType": UNSIGNED_INT, "count": data.len(), "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accessors_carry_bounds_and_views_stay_aligned() {
        let mut b = Buffers::default();
        let i = b.indices(&[0, 1, 2]);
        let p = b.floats(&[[1.0, -2.0, 3.0], [-1.0, 2.0, 0.5]], Some(VERTICES));
        assert_eq!((i, p), (0, 1));
        assert_eq!(b.accessors[1]["min"], json!([-1.0, -2.0, 0.5]));
        assert_eq!(b.accessors[1]["max"], json!([1.0, 2.0, 3.0]));
        assert_eq!(b.views[1]["byteOffset"], json!(12));
        assert_eq!(b.views[1]["byteLength"], json!(24));
        assert_eq!(b.bin.len(), 36);
    }
}
