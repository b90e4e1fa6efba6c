//! The bytes a glTF document refers to — buffers (glTF 2.0 §3.6.1) and
//! images (§3.8.3) — read with bounds: a `uri` must name a regular file
//! (not `/dev/zero`, a pipe or a directory), its size is checked before
//! it is read and no more than is needed is read; `data:` URIs (§2.8,
//! base64 only) are decoded here, their size bounded by the document's.

use std::io::Read;
use std::path::{Path, PathBuf};

/// Where a `uri` points (§2.8: relative paths are percent-encoded and
/// resolved against the document's directory).
enum Uri {
    /// The bytes of a base64 `data:` URI, still encoded.
    Data(String),
    File(PathBuf),
}

fn percent_decode(s: &str) -> Result<String, String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("the uri {s:?} has a malformed %-escape"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("the uri {s:?} does not decode to UTF-8"))
}

/// Whether `uri` starts with a scheme (`name:`, RFC 3986 §3.1).
fn has_scheme(uri: &str) -> bool {
    match uri.split_once(':') {
        Some((scheme, _)) => {
            let mut chars = scheme.chars();
            chars.next().is_some_and(|c| c.is_ascii_alphabetic())
                && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
        }
        None => false,
    }
}

fn parse(uri: &str, base: Option<&Path>) -> Result<Uri, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or("only base64 data: URIs are supported")?;
        return Ok(Uri::Data(data.to_string()));
    }
    let path = if let Some(rest) = uri.strip_prefix("file://").or(uri.strip_prefix("file:")) {
        PathBuf::from(percent_decode(rest)?)
    } else if has_scheme(uri) {
        return Err(format!("the uri {uri:?} has an unsupported scheme"));
    } else {
        PathBuf::from(percent_decode(uri)?)
    };
    let base = base.ok_or_else(|| {
        format!(
            "the uri {uri:?} names a file, but the document was given as bytes with no directory to resolve it in"
        )
    })?;
    Ok(Uri::File(base.join(path)))
}

/// Decodes standard base64 (RFC 4648 §4, padding optional, whitespace
/// refused).
pub(super) fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    fn value(c: u8) -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    }
    let trimmed = text.trim_end_matches('=');
    if text.len() - trimmed.len() > 2 {
        return Err("the data: URI's base64 has too much padding".into());
    }
    let mut out = Vec::with_capacity(trimmed.len() / 4 * 3 + 3);
    let (mut acc, mut bits) = (0u32, 0);
    for &c in trimmed.as_bytes() {
        let v = value(c)
            .ok_or_else(|| format!("the data: URI's base64 has a bad character {:?}", c as char))?;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits >= 6 {
        return Err("the data: URI's base64 has a dangling character".into());
    }
    Ok(out)
}

/// Opens `path` if it is a regular file and returns it with its size.
fn open_regular(path: &Path) -> Result<(std::fs::File, u64), String> {
    let file =
        std::fs::File::open(path).map_err(|e| format!("cannot open {}: {e}", path.display()))?;
    let metadata = file
        .metadata()
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if !metadata.is_file() {
        return Err(format!(
            "{} is not a regular file (a device, pipe or directory is not read)",
            path.display()
        ));
    }
    Ok((file, metadata.len()))
}

/// The first `length` bytes of buffer `uri` (§3.6.1: a buffer's data is
/// its first `byteLength` bytes): an error if there are fewer. Only
/// `length` bytes are read from a file.
pub(super) fn read_buffer(uri: &str, base: Option<&Path>, length: u64) -> Result<Vec<u8>, String> {
    let mut data = match parse(uri, base)? {
        Uri::Data(text) => base64_decode(&text)?,
        Uri::File(path) => {
            let (file, size) = open_regular(&path)?;
            if size < length {
                return Err(format!(
                    "{} is {size} bytes, shorter than the buffer's byteLength {length}",
                    path.display()
                ));
            }
            let mut data = Vec::new();
            file.take(length)
                .read_to_end(&mut data)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            data
        }
    };
    if (data.len() as u64) < length {
        return Err(format!(
            "the buffer holds {} bytes, fewer than its byteLength {length}",
            data.len()
        ));
    }
    data.truncate(length as usize);
    Ok(data)
}

/// The encoded bytes of image `uri`, at most `limit` of them (the file's
/// size is checked before it is read), and the file name (for guessing
/// the format from its extension).
pub(super) fn read_image(
    uri: &str,
    base: Option<&Path>,
    limit: u64,
) -> Result<(Vec<u8>, Option<String>), String> {
    match parse(uri, base)? {
        Uri::Data(text) => Ok((base64_decode(&text)?, None)),
        Uri::File(path) => {
            let (file, size) = open_regular(&path)?;
            if size > limit {
                return Err(format!(
                    "{} is {size} bytes, more than the {limit} an image file may be",
                    path.display()
                ));
            }
            let mut data = Vec::new();
            file.take(limit)
                .read_to_end(&mut data)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            Ok((data, Some(path.to_string_lossy().into_owned())))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips() {
        assert_eq!(base64_decode("aGVsbG8=").as_deref(), Ok(&b"hello"[..]));
        assert_eq!(base64_decode("aGVsbG8").as_deref(), Ok(&b"hello"[..]));
        assert_eq!(
            base64_decode("AAEC/w==").as_deref(),
            Ok(&[0u8, 1, 2, 255][..])
        );
        assert!(base64_decode("a").is_err());
        assert!(base64_decode("a b=").is_err());
    }

    #[test]
    fn dev_zero_is_not_read() {
        if Path::new("/dev/zero").exists() {
            let e = read_buffer("/dev/zero", Some(Path::new("/")), 4).unwrap_err();
            assert!(e.contains("not a regular file"), "{e}");
        }
    }
}
