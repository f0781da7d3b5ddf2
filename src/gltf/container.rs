//! The GLB container (glTF 2.0 §4.4): a 12-byte header, the JSON chunk padded with
//! spaces to 4 bytes, then the BIN chunk padded with zeros.

/// `glTF` read as a little-endian u32.
const MAGIC: u32 = 0x4654_6C67;
/// The chunk types `JSON` and `BIN\0`.
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

/// The binary glTF of `json` (the document) and `bin` (its one buffer; no BIN chunk when
/// empty).
pub(super) fn pack(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let json_len = json.len().next_multiple_of(4);
    let bin_len = bin.len().next_multiple_of(4);
    let total = 12 + 8 + json_len + if bin.is_empty() { 0 } else { 8 + bin_len };
    let mut out = Vec::with_capacity(total);
    let u32le = |out: &mut Vec<u8>, x: usize| out.extend_from_slice(&(x as u32).to_le_bytes());
    u32le(&mut out, MAGIC as usize);
    u32le(&mut out, 2);
    u32le(&mut out, total);
    u32le(&mut out, json_len);
    u32le(&mut out, JSON_CHUNK as usize);
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    if !bin.is_empty() {
        u32le(&mut out, bin_len);
        u32le(&mut out, BIN_CHUNK as usize);
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::pack;

    #[test]
    fn chunks_are_padded_and_the_length_is_the_files() {
        let glb = pack(b"{\"a\":1}", &[1, 2, 3, 4, 5]);
        // 12 header + 8 + 8 (7 padded) + 8 + 8 (5 padded), the spec's layout.
        assert_eq!(glb.len(), 44);
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()), 44);
        assert_eq!(&glb[16..20], b"JSON");
        assert_eq!(glb[27], b' ');
        assert_eq!(&glb[32..36], b"BIN\0");
        assert_eq!(&glb[36..44], &[1, 2, 3, 4, 5, 0, 0, 0]);
    }
}
