//! A bounded little-endian reader over the bytes of a whole `.vdb` file.
//!
//! OpenVDB writes every number in the machine's byte order, which is
//! little-endian on every platform it supports (io/Archive.cc writes raw
//! `sizeof(T)` bytes). Every length read from the file is checked against
//! the bytes that remain *before* anything is allocated or copied, so a
//! corrupted length is an error, never an allocation.

/// A cursor over a byte slice; every read is bounds-checked.
#[derive(Clone)]
pub struct Stream<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Stream<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }

    /// The offset of the next byte.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// The whole file's length.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// Bytes left after the cursor.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// Moves the cursor to `pos`, which must lie within the file.
    pub fn seek(&mut self, pos: u64) -> Result<(), String> {
        match usize::try_from(pos) {
            Ok(p) if p <= self.data.len() => {
                self.pos = p;
                Ok(())
            }
            _ => Err(format!(
                "offset {pos} lies beyond the end of the file ({} bytes)",
                self.data.len()
            )),
        }
    }

    /// The next `n` bytes, if that many remain.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        if n > self.remaining() {
            return Err(format!(
                "the file is truncated: {n} bytes needed at offset {}, {} left",
                self.pos,
                self.remaining()
            ));
        }
        let bytes = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(bytes)
    }

    /// The next `N` bytes as an array.
    pub fn array<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    pub fn u8(&mut self) -> Result<u8, String> {
        Ok(self.array::<1>()?[0])
    }

    pub fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    pub fn i32(&mut self) -> Result<i32, String> {
        Ok(i32::from_le_bytes(self.array()?))
    }

    pub fn i64(&mut self) -> Result<i64, String> {
        Ok(i64::from_le_bytes(self.array()?))
    }

    pub fn f32(&mut self) -> Result<f32, String> {
        Ok(f32::from_le_bytes(self.array()?))
    }

    pub fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array()?))
    }

    /// Three `i32`s: an OpenVDB `Coord`.
    pub fn coord(&mut self) -> Result<[i32; 3], String> {
        Ok([self.i32()?, self.i32()?, self.i32()?])
    }

    /// A string as OpenVDB writes names (io/io.h `readString`): a `u32`
    /// length, then that many bytes, no terminator. The length is checked
    /// against the bytes left before anything is copied.
    pub fn string(&mut self) -> Result<String, String> {
        let n = self.u32()? as usize;
        let bytes = self
            .take(n)
            .map_err(|e| format!("a string of {n} bytes: {e}"))?;
        Ok(String::from_utf8_lossy(bytes).into_owned())
    }

    /// `n` 64-bit words (a node mask, util/NodeMasks.h `load`).
    pub fn words(&mut self, n: usize) -> Result<Vec<u64>, String> {
        let bytes = self.take(n.checked_mul(8).ok_or("a mask too large")?)?;
        Ok(bytes
            .chunks_exact(8)
            .map(|c| {
                let mut w = [0u8; 8];
                w.copy_from_slice(c);
                u64::from_le_bytes(w)
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_beyond_the_end_are_errors_not_allocations() {
        // A string claiming 0xFFFFFFFF bytes in a 6-byte buffer.
        let data = [0xFF, 0xFF, 0xFF, 0xFF, b'a', b'b'];
        let mut s = Stream::new(&data);
        let e = s.string().unwrap_err();
        assert!(e.contains("truncated") && e.contains("4294967295"), "{e}");
        let mut s = Stream::new(&data);
        assert!(s.seek(7).is_err());
        assert!(s.seek(6).is_ok());
        assert!(s.u8().is_err());
    }

    #[test]
    fn little_endian_numbers() {
        let data = [1, 0, 0, 0, 0xFE, 0xFF, 0xFF, 0xFF];
        let mut s = Stream::new(&data);
        assert_eq!(s.u32(), Ok(1));
        assert_eq!(s.i32(), Ok(-2));
        assert_eq!(s.remaining(), 0);
    }
}
