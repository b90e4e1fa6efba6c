//! The binary glTF container (glTF 2.0 §4.4), for tools and tests that
//! write glTF files: a 12-byte header, the JSON chunk padded with spaces
//! and the BIN chunk padded with zeros, both to four bytes.

/// A `.glb` file's bytes holding the glTF JSON document `json` and the
/// binary buffer `bin` (the document's buffer 0, given without a `uri`).
pub fn glb_bytes(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let padded = |len: usize| len.div_ceil(4) * 4;
    let (json_len, bin_len) = (padded(json.len()), padded(bin.len()));
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json_len as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(json);
    glb.resize(20 + json_len, b' ');
    glb.extend_from_slice(&(bin_len as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(bin);
    glb.resize(total, 0);
    glb
}
