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

/// Chunk type of the JSON chunk (`JSON` in ASCII, glTF 2.0 §4.4.3.2).
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type of the binary buffer chunk (`BIN\0`, glTF 2.0 §4.4.3.3).
const CHUNK_BIN: u32 = 0x004E_4942;

/// The two chunks of a `.glb` file, borrowed from its bytes.
#[derive(Debug)]
pub(super) struct Glb<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

fn word(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Parses a `.glb` container (glTF 2.0 §4.4) without trusting its
/// lengths: the header's `length` must not exceed the bytes there are
/// (§4.4.2), every chunk must lie within it (§4.4.3), the first chunk
/// must be JSON and the optional second BIN; later chunks of other types
/// are ignored, as §4.4.3.1 asks. Nothing is allocated: the chunks are
/// slices of `bytes`.
pub(super) fn parse(bytes: &[u8]) -> Result<Glb<'_>, String> {
    if bytes.len() < 12 {
        return Err(format!(
            "the binary glTF header needs 12 bytes, the file has {}",
            bytes.len()
        ));
    }
    let version = word(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(format!(
            "binary glTF version {version} is not supported: only version 2 is"
        ));
    }
    let length = word(bytes, 8).unwrap_or(0) as usize;
    if length > bytes.len() {
        return Err(format!(
            "the binary glTF header claims {length} bytes, but the file has {}",
            bytes.len()
        ));
    }
    let bytes = &bytes[..length];
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    let mut index = 0;
    while at < bytes.len() {
        let (Some(chunk_len), Some(chunk_type)) = (word(bytes, at), word(bytes, at + 4)) else {
            return Err(format!(
                "chunk {index} starts at byte {at} but its 8-byte header runs past the {length} bytes of the file"
            ));
        };
        let start = at + 8;
        let end = start
            .checked_add(chunk_len as usize)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| {
                format!(
                    "chunk {index} claims {chunk_len} bytes at byte {start}, past the {length} bytes of the file"
                )
            })?;
        let data = &bytes[start..end];
        match (index, chunk_type) {
            (0, CHUNK_JSON) => json = Some(data),
            (0, _) => return Err("the first chunk must be the JSON chunk".into()),
            (1, CHUNK_BIN) => bin = Some(data),
            (_, CHUNK_JSON) => return Err(format!("chunk {index} is a second JSON chunk")),
            (_, CHUNK_BIN) => {
                return Err(format!("chunk {index} is a second or misplaced BIN chunk"));
            }
            _ => {}
        }
        index += 1;
        // Chunks are padded to four bytes (§4.4.3.1).
        at = end.div_ceil(4).saturating_mul(4).max(end);
    }
    let json = json.ok_or("the binary glTF file has no JSON chunk")?;
    Ok(Glb { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_files_parse_back() {
        let glb = glb_bytes(b"{}", &[1, 2, 3]);
        let parsed = parse(&glb).unwrap();
        assert_eq!(parsed.json, b"{}  ");
        assert_eq!(parsed.bin, Some(&[1, 2, 3, 0][..]));
    }

    #[test]
    fn lengths_are_not_trusted() {
        let glb = glb_bytes(b"{}", &[1, 2, 3]);
        assert!(parse(&glb[..8]).unwrap_err().contains("12 bytes"));
        let mut long = glb.clone();
        long[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(
            parse(&long)
                .unwrap_err()
                .contains("claims 4294967295 bytes")
        );
        let mut chunk = glb.clone();
        chunk[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(parse(&chunk).unwrap_err().contains("chunk 0 claims"));
        let mut version = glb.clone();
        version[4] = 1;
        assert!(parse(&version).unwrap_err().contains("version 1"));
        let mut order = glb.clone();
        order[16..20].copy_from_slice(b"BIN\0");
        assert!(parse(&order).unwrap_err().contains("first chunk"));
        // A header cut inside the second chunk's header.
        let mut cut = glb[..glb.len() - 8].to_vec();
        let len = cut.len() as u32;
        cut[8..12].copy_from_slice(&len.to_le_bytes());
        assert!(parse(&cut).is_err());
    }
}
