//! Which part of a render to compute: a rectangle of pixels and a range of
//! each pixel's sample indices — how a render is split over machines
//! (`--tile`, `--samples`) and resumed from a checkpoint.
//!
//! Every sample is identified globally by (seed, pixel, sample index), and
//! each light-tracing path by its global path index (see
//! [`crate::render`](mod@crate::render)), so any part computes exactly the samples the whole
//! render would compute for its pixels and indices.

use crate::settings::MAX_SPP;
use std::ops::Range;

/// The pixels `[x0, x1) × [y0, y1)` of an image, in full-image
/// coordinates (rows top to bottom).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PixelRect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

/// Why a tile could not be chosen.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RegionError {
    #[error("tile {index}/{count}: the index must be below the count (tiles are numbered from 0)")]
    TileIndex { index: u32, count: u32 },
    #[error("{count} tiles: an image {height} rows high splits into at most {height} tiles")]
    TooManyTiles { count: u32, height: u32 },
    #[error("sample range {start}..{end} is empty: the end must be above the start")]
    EmptySamples { start: u32, end: u32 },
    #[error(
        "sample range {start}..{end} reaches past sample index {max}: sample indices are bounded as `spp` is (at most {max} per pixel)"
    )]
    SamplesBeyondLimit { start: u32, end: u32, max: u32 },
    #[error("pixel rectangle {0} is empty or outside the {1}×{2} image")]
    Rect(PixelRect, u32, u32),
    #[error(
        "pixel rectangle {0} is not a band of whole rows, which renders that trace light paths need"
    )]
    NotBand(PixelRect),
}

impl PixelRect {
    /// The whole `width`×`height` image.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Tile `index` of `count` of a `width`×`height` image: horizontal
    /// bands of whole rows, band `i` holding rows
    /// `⌊i·height/count⌋ .. ⌊(i+1)·height/count⌋`. The bands cover the
    /// image without gaps or overlaps, and differ in height by at most one
    /// row.
    pub fn tile(index: u32, count: u32, width: u32, height: u32) -> Result<Self, RegionError> {
        if index >= count {
            return Err(RegionError::TileIndex { index, count });
        }
        if count > height {
            return Err(RegionError::TooManyTiles { count, height });
        }
        let row = |i: u32| (i as u64 * height as u64 / count as u64) as u32;
        Ok(Self {
            x0: 0,
            y0: row(index),
            x1: width,
            y1: row(index + 1),
        })
    }

    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Number of pixels.
    pub fn area(&self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// Whether the rectangle is non-empty and inside a `width`×`height`
    /// image.
    pub fn check(&self, width: u32, height: u32) -> Result<(), RegionError> {
        if self.x0 < self.x1 && self.y0 < self.y1 && self.x1 <= width && self.y1 <= height {
            Ok(())
        } else {
            Err(RegionError::Rect(*self, width, height))
        }
    }

    pub fn contains(&self, x: u32, y: u32) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }

    /// Whether the two rectangles share a pixel.
    pub fn overlaps(&self, other: &PixelRect) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }

    /// Index of full-image pixel (x, y) in the rectangle's row-major
    /// storage; `None` outside it.
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        self.contains(x, y)
            .then(|| (y - self.y0) as usize * self.width() as usize + (x - self.x0) as usize)
    }
}

impl std::fmt::Display for PixelRect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "x {}..{}, y {}..{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// A part of a render: the pixels of `rect`, samples `samples` of each.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderRegion {
    pub rect: PixelRect,
    pub samples: Range<u32>,
}

impl RenderRegion {
    /// The whole image, samples `0..spp`.
    pub fn full(width: u32, height: u32, spp: u32) -> Self {
        Self {
            rect: PixelRect::full(width, height),
            samples: 0..spp,
        }
    }

    /// Checks the region against a `width`×`height` image, and its
    /// sample indices against [`MAX_SPP`]: a range may start anywhere
    /// below it (parts of one render, or samples added to it later) but
    /// never reaches past it, so a part's work is bounded as a whole
    /// render's is (`--samples 0..4294967295` ran until killed).
    pub fn check(&self, width: u32, height: u32) -> Result<(), RegionError> {
        if self.samples.start >= self.samples.end {
            return Err(RegionError::EmptySamples {
                start: self.samples.start,
                end: self.samples.end,
            });
        }
        if self.samples.end > MAX_SPP {
            return Err(RegionError::SamplesBeyondLimit {
                start: self.samples.start,
                end: self.samples.end,
                max: MAX_SPP,
            });
        }
        self.rect.check(width, height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_image_without_overlap() {
        for (count, height) in [(1, 1), (3, 10), (7, 7), (4, 1000), (5, 13)] {
            let tiles: Vec<PixelRect> = (0..count)
                .map(|i| PixelRect::tile(i, count, 9, height).expect("tile"))
                .collect();
            let mut covered = vec![0u32; height as usize];
            for t in &tiles {
                assert!(t.height() >= height / count && t.height() <= height / count + 1);
                assert_eq!((t.x0, t.x1), (0, 9));
                for y in t.y0..t.y1 {
                    covered[y as usize] += 1;
                }
            }
            assert!(covered.iter().all(|&c| c == 1), "{count} tiles of {height}");
        }
        assert!(PixelRect::tile(3, 3, 9, 9).is_err());
        assert!(PixelRect::tile(0, 10, 9, 9).is_err());
    }
}
