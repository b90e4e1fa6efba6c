//! How much of a surface one sample stands for, so that textures are
//! filtered over it instead of aliasing: ray cones (Akenine-Möller et al.
//! 2019, "Texture Level of Detail Strategies for Real-Time Ray Tracing",
//! Ray Tracing Gems ch. 20: a cone's width over the surface, in texels of
//! the triangle's mapping, gives the level of detail of one trilinear
//! lookup), with the camera's spread scaled by
//! the samples per pixel as pbrt-v4 scales its ray differentials
//! (`max(1/8, 1/√spp)`, pbrt-v4 `CameraBase::GenerateRayDifferential`'s
//! callers): at one sample a pixel's texels are averaged by the filter,
//! at many by the samples themselves.
//!
//! A camera ray's cone goes on through mirrors, glossy layers, panes and
//! refraction (planar: its spread is kept) and ends at the first diffuse
//! or volume scattering event: beyond, textures are read at full
//! resolution, as light sampling reads them, so that every strategy that
//! finds one path vertex weighs the same texel (MIS needs the integrand
//! they share).

use crate::shapes::Triangle;
use glam::Vec2;

/// A cone of rays about a ray: its `width` (scene units) where it starts
/// and its `spread` (radians: the growth of its width per unit distance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayCone {
    pub width: f32,
    pub spread: f32,
}

impl RayCone {
    /// The cone's width at distance `t` along it.
    #[inline]
    pub fn width_at(&self, t: f32) -> f32 {
        self.width + self.spread * t
    }

    /// The cone of the ray that goes on from a specular event at distance
    /// `t`: as wide as this one there, spreading as it did (a planar
    /// mirror or interface; the surface's curvature is not followed).
    #[inline]
    pub fn advanced(&self, t: f32) -> Self {
        Self {
            width: self.width_at(t),
            spread: self.spread,
        }
    }

    /// The footprint on a surface met at distance `t` at `cos` (the
    /// cosine between the ray and the surface's normal): the cone's width
    /// over `|cos|`, its longer extent across a slanted surface, as the
    /// ray-cone chapter measures it (`|cos|` kept above 1/64, a footprint
    /// 64 times the cone's width, at grazing incidence).
    #[inline]
    pub fn footprint(&self, t: f32, cos: f32) -> Footprint {
        Footprint(self.width_at(t) / cos.abs().max(1.0 / 64.0))
    }
}

/// The share of a pixel a camera ray's cone spreads over at `spp`
/// samples per pixel: `max(1/8, 1/√spp)`, pbrt-v4's scale of its camera
/// ray differentials. One sample's cone covers the pixel; many samples
/// average the pixel themselves, and a narrower cone keeps the texture
/// from being blurred twice.
pub fn camera_spread_scale(spp: u32) -> f32 {
    (1.0 / (spp.max(1) as f32).sqrt()).max(0.125)
}

/// The width, in scene units, of the patch of surface one sample stands
/// for ([`RayCone::footprint`]); 0 for a point, which textures read at
/// full resolution.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Footprint(pub f32);

impl Footprint {
    /// A point: textures at full resolution.
    pub const POINT: Self = Self(0.0);

    /// The level of detail of this footprint in a `width × height`
    /// texture mapped onto `triangle` by its corners' coordinates `uvs`:
    /// log₂ of its width in texels, the texels per scene unit being
    /// `√(texel area / surface area)` of the triangle (the ray-cone
    /// chapter's Δ). −∞ for a point, or a triangle whose
    /// coordinates or surface span no area.
    #[inline]
    pub fn level_of_detail(
        &self,
        (width, height): (u32, u32),
        triangle: &Triangle,
        uvs: [Vec2; 3],
    ) -> f32 {
        if self.0.is_nan() || self.0 <= 0.0 {
            return f32::NEG_INFINITY;
        }
        let uv_area = (uvs[1] - uvs[0]).perp_dot(uvs[2] - uvs[0]).abs();
        let surface_area = triangle.e1.cross(triangle.e2).length();
        let texels_per_unit = (width as f32 * height as f32 * uv_area / surface_area).sqrt();
        let lod = (self.0 * texels_per_unit).log2();
        if lod.is_nan() { f32::NEG_INFINITY } else { lod }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A 2 × 2 scene-unit square mapped once by a 256² texture has 128
    /// texels a unit: a footprint of 1/128 is one texel (lod 0), of 1/32
    /// four (lod 2); the cone widens by its spread and slants by 1/cos.
    #[test]
    fn footprints_count_texels() {
        let triangle = Triangle::new(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
        )
        .unwrap();
        let uvs = [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)];
        let lod = |w: f32| Footprint(w).level_of_detail((256, 256), &triangle, uvs);
        assert!(lod(1.0 / 128.0).abs() < 1e-5);
        assert!((lod(1.0 / 32.0) - 2.0).abs() < 1e-5);
        assert_eq!(
            Footprint::POINT.level_of_detail((256, 256), &triangle, uvs),
            f32::NEG_INFINITY
        );
        let flat = [Vec2::ZERO; 3];
        assert_eq!(
            Footprint(1.0).level_of_detail((256, 256), &triangle, flat),
            f32::NEG_INFINITY
        );
        let cone = RayCone {
            width: 0.0,
            spread: 0.01,
        };
        assert!((cone.footprint(3.0, 0.5).0 - 0.06).abs() < 1e-7);
        assert!((cone.advanced(3.0).width_at(1.0) - 0.04).abs() < 1e-7);
        assert_eq!(cone.footprint(1.0, 0.0).0, 0.64);
    }
}
