//! Environment light: radiance arriving from infinitely far in every
//! direction — a uniform sky, or an equirectangular (latitude–longitude)
//! map of one, importance-sampled by its brightness (pbrt-v4's
//! `UniformInfiniteLight` and `ImageInfiniteLight`, Pharr, Jakob &
//! Humphreys 2023, §12.5; Mitsuba 3's `constant` and `envmap`).
//!
//! A map is oriented as Mitsuba 3's `envmap`: y is up; the direction ω
//! has the map coordinates `u = atan2(ω_x, −ω_z)/2π` (wrapped into
//! `[0, 1)`) and `v = acos(ω_y)/π`, the top row (`v = 0`) is straight up
//! and the middle of the map (`u = ½`) looks along +z. Texel centres are
//! at `((i + ½)/W, (j + ½)/H)`, as Cycles and image tools place them
//! (Mitsuba puts its rows at `v = j/(H − 1)`, the poles included); the
//! radiance between them is bilinear, wrapping in `u` and clamped in `v`.
//!
//! Sampling draws `(u, v)` from a piecewise-constant density over the
//! texels ([`PiecewiseConstant2D`]) whose weight is the brightest
//! channel mean within the texel's bilinear support (the texel and its
//! eight neighbours), times `sin θ` at the texel's row: every direction
//! with radiance has density > 0, so light sampling alone (the
//! single-scattering integrators) is unbiased. The density per unit
//! solid angle is `p(u, v)/(2π² sin θ)`, the Jacobian of the
//! latitude–longitude map.

use super::{Incident, mean_channel};
use crate::color::Rgb;
use crate::distribution::PiecewiseConstant2D;
use crate::sampling::{uniform_cone, uniform_cone_pdf};
use crate::texture::{Wrap, bilinear_corners};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::{PI, TAU};
use std::sync::Arc;

/// Radiance from infinitely far: `scale` times the map's radiance in each
/// direction, or `scale` alone in every direction without a map (W/(m²·sr)).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLight {
    pub scale: Rgb,
    pub map: Option<Arc<EnvironmentMap>>,
    /// The rotation from world directions into the map's frame (identity:
    /// the map as the module's text orients it).
    pub to_map: Mat3,
}

/// An equirectangular map of radiance (linear RGB, row-major, the top row
/// first) with its sampling density (see the module's text).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    width: u32,
    height: u32,
    texels: Vec<Rgb>,
    distribution: PiecewiseConstant2D,
    /// `∫ L dω` over the sphere, per channel, by the midpoint rule over
    /// the texels.
    integral: Rgb,
}

impl EnvironmentMap {
    /// The map of `width × height` texels of radiance. Every channel must
    /// be finite and ≥ 0; the error names the first texel that is not.
    pub fn new(width: u32, height: u32, texels: Vec<Rgb>) -> Result<Self, String> {
        let (w, h) = (width as usize, height as usize);
        if w == 0 || h == 0 {
            return Err(format!("the map is {width}×{height}: it has no texels"));
        }
        if texels.len() != w * h {
            return Err(format!(
                "{} texels for a {width}×{height} map",
                texels.len()
            ));
        }
        if let Some(i) = texels
            .iter()
            .position(|t| !(t.is_finite() && t.min_element() >= 0.0))
        {
            return Err(format!(
                "texel ({}, {}) (column, row from the top) is {}: radiance must be finite and ≥ 0",
                i % w,
                i / w,
                texels[i]
            ));
        }
        let brightness: Vec<f32> = texels.iter().map(|&t| mean_channel(t)).collect();
        let mut weights = vec![0.0f32; w * h];
        let mut integral = Rgb::ZERO;
        let cell = (TAU / w as f32) * (PI / h as f32);
        for j in 0..h {
            let sin_theta = (PI * (j as f32 + 0.5) / h as f32).sin();
            for i in 0..w {
                let mut brightest = 0.0f32;
                for dj in [-1i64, 0, 1] {
                    let row = (j as i64 + dj).clamp(0, h as i64 - 1) as usize;
                    for di in [-1i64, 0, 1] {
                        let column = (i as i64 + di).rem_euclid(w as i64) as usize;
                        brightest = brightest.max(brightness[row * w + column]);
                    }
                }
                weights[j * w + i] = brightest * sin_theta;
                integral += texels[j * w + i] * (sin_theta * cell);
            }
        }
        Ok(Self {
            width,
            height,
            distribution: PiecewiseConstant2D::new(&weights, w, h),
            texels,
            integral,
        })
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The radiance at map coordinates `uv` (bilinear between texel
    /// centres, as textures are filtered, wrapping in `u`, clamped in `v`);
    /// 0 at non-finite coordinates.
    pub fn lookup(&self, uv: Vec2) -> Rgb {
        let Some(corners) = bilinear_corners(uv, self.width, self.height) else {
            return Rgb::ZERO;
        };
        corners
            .into_iter()
            .map(|(i, j, weight)| {
                let column = Wrap::Repeat.index(i, self.width);
                let row = Wrap::Clamp.index(j, self.height);
                self.texels[row * self.width as usize + column] * weight
            })
            .sum()
    }
}

/// The map coordinates of the unit direction `d` (see the module's text).
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let u = d.x.atan2(-d.z) / TAU;
    let u = u - u.floor();
    Vec2::new(
        u.min(crate::sampler::ONE_MINUS_EPSILON),
        d.y.clamp(-1.0, 1.0).acos() / PI,
    )
}

/// The unit direction at map coordinates `uv`, with `sin θ` there.
pub fn uv_to_direction(uv: Vec2) -> (Vec3, f32) {
    let (sin_theta, cos_theta) = (PI * uv.y).sin_cos();
    let (sin_phi, cos_phi) = (TAU * uv.x).sin_cos();
    (
        Vec3::new(sin_theta * sin_phi, cos_theta, -sin_theta * cos_phi),
        sin_theta,
    )
}

impl EnvironmentLight {
    /// A uniform environment of `radiance`.
    pub fn uniform(radiance: Rgb) -> Self {
        Self {
            scale: radiance,
            map: None,
            to_map: Mat3::IDENTITY,
        }
    }

    /// The map times `scale`, turned by `rotate_deg` about +y
    /// (counter-clockwise seen from above: a feature of the map at +z
    /// moves towards +x for 90°).
    pub fn mapped(map: Arc<EnvironmentMap>, scale: Rgb, rotate_deg: f32) -> Self {
        Self {
            scale,
            map: Some(map),
            to_map: Mat3::from_rotation_y(-rotate_deg.to_radians()),
        }
    }

    /// Radiance arriving from the unit direction `towards` (the direction
    /// a ray leaving the scene travels in).
    #[inline]
    pub fn radiance(&self, towards: Vec3) -> Rgb {
        match &self.map {
            None => self.scale,
            Some(map) => self.scale * map.lookup(direction_to_uv(self.to_map * towards)),
        }
    }

    /// A direction towards the environment from `u ∈ [0, 1)²`: uniform
    /// over the sphere without a map, by the map's density with one.
    /// The incident light is `L(ω)/p(ω)` (irradiance over the density),
    /// with `p(ω)` per unit solid angle; `None` where the sample carries
    /// nothing.
    pub(super) fn sample_incident(&self, u: Vec2) -> Option<(Incident, f32)> {
        let (direction, pdf) = match &self.map {
            None => (uniform_cone(Vec3::Z, -1.0, u), uniform_cone_pdf(-1.0)),
            Some(map) => {
                let (uv, p_uv) = map.distribution.sample(u);
                let (in_map, sin_theta) = uv_to_direction(uv);
                if !(p_uv > 0.0 && sin_theta > 0.0) {
                    return None;
                }
                // A rotation's inverse is its transpose.
                let direction = self.to_map.transpose() * in_map;
                (direction, p_uv / (2.0 * PI * PI * sin_theta))
            }
        };
        let radiance = self.radiance(direction);
        if radiance == Rgb::ZERO {
            return None;
        }
        Some((
            Incident {
                direction,
                distance: f32::INFINITY,
                irradiance: radiance / pdf,
                light_normal: None,
            },
            pdf,
        ))
    }

    /// The density per unit solid angle with which
    /// [`EnvironmentLight::sample_incident`] draws the unit `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        match &self.map {
            None => uniform_cone_pdf(-1.0),
            Some(map) => {
                let in_map = self.to_map * direction;
                let sin_theta = (1.0 - in_map.y * in_map.y).max(0.0).sqrt();
                if sin_theta == 0.0 {
                    return 0.0;
                }
                map.distribution.pdf(direction_to_uv(in_map)) / (2.0 * PI * PI * sin_theta)
            }
        }
    }

    /// The flux through a disk of radius `scene_radius` (the scene's
    /// bounding sphere), `π r² ∫ L dω`, as pbrt-v4's infinite lights.
    pub(super) fn power(&self, scene_radius: f32) -> Rgb {
        let integral = match &self.map {
            None => Rgb::splat(4.0 * PI),
            Some(map) => map.integral,
        };
        self.scale * integral * (PI * scene_radius * scene_radius)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map brighter towards +x and the top, with a hot spot.
    fn sky() -> EnvironmentLight {
        let (w, h) = (32u32, 16u32);
        let texels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                let hot = if (i, j) == (9, 4) { 200.0 } else { 0.0 };
                Rgb::new(
                    1.0 + i as f32 * 0.1 + hot,
                    0.5 + (h - j) as f32 * 0.2,
                    if j > 12 { 0.0 } else { 0.3 },
                )
            })
            .collect();
        EnvironmentLight::mapped(
            Arc::new(EnvironmentMap::new(w, h, texels).unwrap()),
            Rgb::new(1.0, 2.0, 0.5),
            0.0,
        )
    }

    /// The midpoint rule over the sphere in `n` polar by `2n` azimuthal
    /// cells (angles about +y, apart from the map's): `f(ω, dω)` per cell.
    fn over_the_sphere(n: usize, mut f: impl FnMut(Vec3, f32)) {
        for a in 0..n {
            let theta = PI * (a as f32 + 0.5) / n as f32;
            for b in 0..2 * n {
                let phi = TAU * (b as f32 + 0.5) / (2 * n) as f32;
                let (sin, cos) = theta.sin_cos();
                let d = Vec3::new(sin * phi.cos(), cos, sin * phi.sin());
                f(d, sin * (PI / n as f32) * (TAU / (2 * n) as f32));
            }
        }
    }

    /// The map's coordinates and directions invert each other, and follow
    /// Mitsuba's `envmap`: the top row is +y, the middle column +z.
    #[test]
    fn coordinates_follow_mitsuba() {
        assert!((uv_to_direction(Vec2::new(0.5, 0.5)).0 - Vec3::Z).length() < 1e-6);
        assert!((uv_to_direction(Vec2::new(0.25, 0.5)).0 - Vec3::X).length() < 1e-6);
        assert!((uv_to_direction(Vec2::new(0.3, 0.0)).0 - Vec3::Y).length() < 1e-6);
        for uv in [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.7, 0.9),
            Vec2::new(0.999, 0.5),
        ] {
            let back = direction_to_uv(uv_to_direction(uv).0);
            assert!((back - uv).length() < 1e-5, "{uv} → {back}");
        }
    }

    /// Light sampling integrates the environment: the mean of `L cos θ / p`
    /// over samples is the irradiance on a plane, checked against a
    /// quadrature of the radiance over the hemisphere written here, and
    /// each sample's density is the one `pdf` gives its direction.
    #[test]
    fn sampled_irradiance_matches_quadrature() {
        let turned = EnvironmentLight {
            to_map: Mat3::from_rotation_y(-0.7),
            ..sky()
        };
        for light in [
            sky(),
            turned,
            EnvironmentLight::uniform(Rgb::new(0.2, 0.4, 0.8)),
        ] {
            let normal = Vec3::new(0.3, 0.8, -0.2).normalize();
            let mut quadrature = Rgb::ZERO;
            over_the_sphere(1024, |d, dw| {
                let cos = d.dot(normal);
                if cos > 0.0 {
                    quadrature += light.radiance(d) * (cos * dw);
                }
            });
            let m = 512;
            let mut sampled = Rgb::ZERO;
            for i in 0..m {
                for j in 0..m {
                    let u = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                    let Some((incident, pdf)) = light.sample_incident(u) else {
                        continue;
                    };
                    let p = light.pdf(incident.direction);
                    assert!((p - pdf).abs() <= 1e-3 * pdf, "{pdf} vs {p}");
                    let cos = incident.direction.dot(normal);
                    if cos > 0.0 {
                        sampled += incident.irradiance * cos;
                    }
                }
            }
            sampled /= (m * m) as f32;
            // Both are deterministic rules: their discretisations (the
            // midpoint rule's, and the sample grid's across the map's
            // cells) stay below 5·10⁻³, where a density off by a factor
            // or a sample turned the wrong way is off by far more.
            let error = (sampled - quadrature).abs() / quadrature;
            assert!(error.max_element() < 5e-3, "{sampled} vs {quadrature}");
        }
    }

    /// The density integrates to one over the sphere, and no direction
    /// with radiance has density 0.
    #[test]
    fn density_covers_the_radiance() {
        let light = sky();
        let mut integral = 0.0f64;
        over_the_sphere(512, |d, dw| {
            let p = light.pdf(d);
            assert!(light.radiance(d) == Rgb::ZERO || p > 0.0, "{d}");
            integral += f64::from(p * dw);
        });
        assert!((integral - 1.0).abs() < 2e-3, "{integral}");
    }

    /// A turn about +y moves the map's features with it: 90° takes what
    /// was seen along +z to +x.
    #[test]
    fn rotation_turns_the_map() {
        let plain = sky();
        let turned = EnvironmentLight {
            to_map: EnvironmentLight::mapped(plain.map.clone().unwrap(), Rgb::ONE, 90.0).to_map,
            ..sky()
        };
        for d in [Vec3::Z, Vec3::new(0.3, 0.5, 0.8).normalize(), Vec3::NEG_X] {
            let moved = Vec3::new(d.z, d.y, -d.x);
            let (a, b) = (plain.radiance(d), turned.radiance(moved));
            assert!(
                (a - b).abs().max_element() < 1e-4 * a.max_element(),
                "{d}: {a} vs {b}"
            );
        }
    }

    /// Non-finite or negative radiance is refused, naming the texel.
    #[test]
    fn bad_texels_are_named() {
        let mut texels = vec![Rgb::ONE; 8];
        texels[5] = Rgb::new(1.0, f32::NAN, 1.0);
        let e = EnvironmentMap::new(4, 2, texels).unwrap_err();
        assert!(e.contains("texel (1, 1)"), "{e}");
        assert!(EnvironmentMap::new(4, 2, vec![Rgb::ONE; 7]).is_err());
        assert!(EnvironmentMap::new(0, 2, vec![]).is_err());
    }
}
