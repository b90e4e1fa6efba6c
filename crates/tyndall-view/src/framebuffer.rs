//! Tone mapping into the window's CPU framebuffer: `2^exposure`, clamp,
//! sRGB, 8 bits — the bytes `tyndall_image::to_srgb8` gives the PNG
//! writer — packed as softbuffer's `0x00RRGGBB` words.

use tyndall::Image;

/// The framebuffer words of `image` after `exposure` stops, row-major.
pub fn tone_map(image: &Image, exposure: f32) -> Vec<u32> {
    tyndall_image::format::to_srgb8(image, exposure)
        .chunks_exact(3)
        .map(|c| (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32)
        .collect()
}

/// Copies `pixels` (`width × height`) into `target` (`target_width` wide,
/// `target.len() / target_width` high) at the top-left corner; what lies
/// outside the image is black.
pub fn blit(pixels: &[u32], width: u32, target: &mut [u32], target_width: u32) {
    target.fill(0);
    if width == 0 || target_width == 0 {
        return;
    }
    let copy = width.min(target_width) as usize;
    for (src, dst) in pixels
        .chunks_exact(width as usize)
        .zip(target.chunks_exact_mut(target_width as usize))
    {
        dst[..copy].copy_from_slice(&src[..copy]);
    }
}

/// Composites `overlay` — premultiplied RGBA bytes in sRGB encoding, as
/// egui draws them, one pixel per word of `target`, row-major — over
/// `target`'s words: `out = overlay + (1 − α)·target` per channel, in the
/// encoded values (egui's blending in a non-sRGB framebuffer).
pub fn composite_over(overlay: &[u8], target: &mut [u32]) {
    for (word, px) in target.iter_mut().zip(overlay.chunks_exact(4)) {
        let alpha = px[3] as u32;
        if alpha == 0 {
            continue;
        }
        let under = word.to_be_bytes();
        let channel = |i: usize| {
            let blended = px[i] as u32 + (under[i + 1] as u32 * (255 - alpha) + 127) / 255;
            blended.min(255)
        };
        *word = channel(0) << 16 | channel(1) << 8 | channel(2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tyndall::Rgb;

    #[test]
    fn tone_map_packs_the_png_bytes() {
        let image = Image::from_pixels(2, 1, vec![Rgb::new(1.0, 0.5, 0.0), Rgb::splat(0.25)]);
        let bytes = tyndall_image::format::to_srgb8(&image, 1.0);
        let words = tone_map(&image, 1.0);
        assert_eq!(words[0], 0xFFFF00);
        for (w, c) in words.iter().zip(bytes.chunks_exact(3)) {
            assert_eq!(w.to_be_bytes(), [0, c[0], c[1], c[2]]);
        }
    }

    #[test]
    fn composite_over_blends_premultiplied() {
        let mut target = vec![0x00_80_40_20, 0x00_10_20_30, 0x00_FF_FF_FF];
        // Transparent, opaque red, half-transparent white (premultiplied).
        let overlay = [0, 0, 0, 0, 255, 0, 0, 255, 128, 128, 128, 128];
        composite_over(&overlay, &mut target);
        assert_eq!(target[0], 0x00_80_40_20);
        assert_eq!(target[1], 0x00_FF_00_00);
        // 128 + 255·127/255 = 255 per channel.
        assert_eq!(target[2], 0x00_FF_FF_FF);
    }

    #[test]
    fn blit_crops_and_pads() {
        let mut target = vec![7; 3 * 2];
        blit(&[1, 2, 3, 4], 2, &mut target, 3);
        assert_eq!(target, [1, 2, 0, 3, 4, 0]);
    }
}
