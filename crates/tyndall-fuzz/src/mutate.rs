//! Mutations: bit flips, byte and range edits, splices with other seeds,
//! numbers replaced by hostile values and hostile little-endian words
//! (lengths, counts and floats of binary formats).

/// SplitMix64: a small, fixed, seedable generator.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Values that broke or nearly broke the loaders before (issue 11).
const HOSTILE_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "1e-45",
    "3e-7",
    "1e15",
    "1e16",
    "1e20",
    "3e38",
    "-1.5e38",
    "1e39",
    "nan",
    "inf",
    "-inf",
    "255",
    "256",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "1024",
    "16384",
    "32768",
    "0.5",
    "[1, 1e9, 1]",
    "[0, -1, -1.5e38]",
];

/// Tokens spliced into text: statements and keys of both formats.
const TOKENS: &[&str] = &[
    "\n",
    " ",
    "[",
    "]",
    "=",
    ",",
    "\"",
    "{",
    "}",
    "<",
    ">",
    "#",
    "[[shapes]]\n",
    "[[lights]]\n",
    "[[media]]\n",
    "[render]\n",
    "type = \"mesh\"\n",
    "density = \"noise\"\n",
    "density = \"grid\"\n",
    "integrator = \"march\"\n",
    "integrator = \"volpath\"\n",
    "visibility = \"maps\"\n",
    "mtllib /dev/zero\n",
    "v ",
    "f 1 2 3 4\n",
    "s 0 0 0 1\n",
    "m 0\n",
    "material\n",
    "emitted 1 1 1\n",
    "c 30\n",
    "PerspectiveCamera {",
];

pub fn mutate(rng: &mut Rng, input: &mut Vec<u8>, seeds: &[Vec<u8>]) {
    let rounds = 1 + rng.below(8);
    for _ in 0..rounds {
        let len = input.len();
        match rng.below(9) {
            0 if len > 0 => {
                let i = rng.below(len);
                input[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                input[i] = rng.next() as u8;
            }
            2 if len > 0 => {
                let start = rng.below(len);
                let end = (start + 1 + rng.below(64)).min(len);
                input.drain(start..end);
            }
            3 if len > 0 => {
                // Duplicate a range.
                let start = rng.below(len);
                let end = (start + 1 + rng.below(256)).min(len);
                let chunk = input[start..end].to_vec();
                let at = rng.below(len + 1);
                input.splice(at..at, chunk);
            }
            4 => {
                // Splice in part of another seed.
                let other = &seeds[rng.below(seeds.len())];
                if !other.is_empty() {
                    let start = rng.below(other.len());
                    let end = (start + 1 + rng.below(512)).min(other.len());
                    let at = rng.below(len + 1);
                    input.splice(at..at, other[start..end].iter().copied());
                }
            }
            5 | 6 => replace_number(rng, input),
            7 => {
                let token = TOKENS[rng.below(TOKENS.len())].as_bytes();
                let at = rng.below(len + 1);
                input.splice(at..at, token.iter().copied());
            }
            _ => {
                // Overwrite four bytes with a hostile little-endian value
                // (grid sizes and densities).
                if len >= 4 {
                    let values: [u32; 6] =
                        [0, u32::MAX, 0x7f80_0000, 0xff80_0000, 0x7fc0_0000, 1 << 31];
                    let at = rng.below(len - 3);
                    let v = values[rng.below(values.len())].to_le_bytes();
                    input[at..at + 4].copy_from_slice(&v);
                }
            }
        }
    }
    input.truncate(1 << 20);
}

/// Replaces a run of digits (with sign, point and exponent) by a hostile
/// number.
fn replace_number(rng: &mut Rng, input: &mut Vec<u8>) {
    if input.is_empty() {
        return;
    }
    let from = rng.below(input.len());
    let Some(start) = (from..input.len()).find(|&i| input[i].is_ascii_digit()) else {
        return;
    };
    let start = if start > 0 && input[start - 1] == b'-' {
        start - 1
    } else {
        start
    };
    let end = (start + 1..input.len())
        .find(|&i| !(input[i].is_ascii_digit() || b".eE+-".contains(&input[i])))
        .unwrap_or(input.len());
    let number = HOSTILE_NUMBERS[rng.below(HOSTILE_NUMBERS.len())].as_bytes();
    input.splice(start..end, number.iter().copied());
}
