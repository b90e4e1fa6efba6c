//! Area lights: parallelograms and spheres of constant radiance, and
//! how next event estimation picks their points (by solid angle near a
//! rectangle and outside a sphere, by area elsewhere).

use super::{Incident, LeSample, LightPoint, towards};
use crate::color::Rgb;
use crate::ray::{Ray, offset_origin};
use crate::sampling::{cosine_hemisphere, uniform_cone, uniform_cone_pdf_from_gap};
use crate::shapes::{Quad, Sphere};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A parallelogram area light of constant radiance `radiance`
/// (W·sr⁻¹·m⁻²), emitting from the front of `quad` (both sides if
/// `two_sided`). Its geometry is also in the scene, so it is seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadLight {
    pub quad: Quad,
    pub radiance: Rgb,
    pub two_sided: bool,
    /// The quad's frame for solid-angle sampling if it is a rectangle
    /// (set by [`QuadLight::new`], computed once rather than per sample).
    pub(super) rectangle: Option<RectangleFrame>,
}

/// A rectangle's edges as an orthonormal frame (x and y along the edges,
/// z their normal) and lengths, for [`SphericalRectangle`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct RectangleFrame {
    corner: Vec3,
    x: Vec3,
    y: Vec3,
    z: Vec3,
    width: f32,
    height: f32,
    /// The rectangle's centre.
    centre: Vec3,
    /// The squared distance from the centre within which NEE samples by
    /// solid angle ([`SOLID_ANGLE_REACH`] diagonals).
    solid_angle_reach2: f32,
}

/// How far from a rectangular light's centre, in diagonals, next event
/// estimation samples it by solid angle; beyond, uniformly by area. Out
/// there every point of the light lies between `(R − ½)` and `(R + ½)`
/// diagonals away (R = 2), so area sampling's estimate
/// `L·cos θ_y·A/d² = L·h·A/d³` (h the receiver's height over the
/// light's plane) varies over the light by at most `(5/3)³ ≈ 4.6`,
/// and by less where the light is seen face on, while a solid-angle
/// sample costs four arc cosines, a sine, a cosine and about ten
/// square roots more. Measured on cornell-fog-multi (160×120, 32 spp,
/// seeds 7 and 8): the same relMSE within 0.2 %, 16 % less CPU time
/// (docs/benchmarks.md).
pub const SOLID_ANGLE_REACH: f32 = 2.0;

impl RectangleFrame {
    /// The frame of `quad` if its edges are orthogonal (solid-angle
    /// sampling needs a rectangle).
    fn new(quad: &Quad) -> Option<Self> {
        let (ex, ey) = (quad.edge_u, quad.edge_v);
        let (width, height) = (ex.length(), ey.length());
        if ex.dot(ey).abs() > 1e-5 * width * height {
            return None;
        }
        let (x, y) = (ex / width, ey / height);
        Some(Self {
            corner: quad.origin,
            x,
            y,
            z: x.cross(y),
            width,
            height,
            centre: quad.origin + 0.5 * (ex + ey),
            solid_angle_reach2: SOLID_ANGLE_REACH * SOLID_ANGLE_REACH * (ex + ey).length_squared(),
        })
    }

    /// The spherical rectangle to sample from `x` if it lies within
    /// [`SOLID_ANGLE_REACH`] of the light; `None` beyond, or where the
    /// rectangle subtends no solid angle.
    fn seen_from(&self, x: Vec3) -> Option<SphericalRectangle> {
        if (x - self.centre).length_squared() >= self.solid_angle_reach2 {
            return None;
        }
        SphericalRectangle::new(self, x)
    }
}

/// An emissive sphere: constant radiance `radiance` (W·sr⁻¹·m⁻²) from
/// its outside (and its inside if `two_sided`). Its geometry is in the
/// scene, so it is seen and occludes.
///
/// From outside, NEE samples the cone the sphere subtends uniformly in
/// solid angle (pbrt-v4 §6.2.4, "Sampling spheres"): density 1/Ω with
/// `Ω = 2π(1 − cos θmax)`, `sin θmax = r/d`, so the estimate `L·Ω·cos θ`
/// stays bounded near the sphere. From inside, it samples the surface
/// uniformly by area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereLight {
    pub sphere: Sphere,
    pub radiance: Rgb,
    pub two_sided: bool,
}

impl SphereLight {
    /// The emitting point for receivers to connect to: uniform over the
    /// surface (density 1/A) from `u ∈ [0,1)²`, with its normal.
    #[inline]
    pub(super) fn sample_point(&self, u: Vec2) -> LightPoint {
        let y = self.point(u);
        LightPoint::on_surface(y, self.normal(y))
    }

    /// Total emitted power, `L·π·A` per emitting side.
    pub(super) fn power(&self) -> Rgb {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance * (PI * self.area() * sides)
    }

    pub(super) fn area(&self) -> f32 {
        4.0 * PI * self.sphere.radius * self.sphere.radius
    }

    /// A point uniform over the surface (density 1/A) from `u ∈ [0,1)²`:
    /// the full sphere of directions is the cone with cos θmax = −1.
    pub(super) fn point(&self, u: Vec2) -> Vec3 {
        self.sphere.center + self.sphere.radius * uniform_cone(Vec3::Z, -1.0, u)
    }

    /// Unit outward normal at the surface point `y`.
    pub(super) fn normal(&self, y: Vec3) -> Vec3 {
        (y - self.sphere.center) / self.sphere.radius
    }

    /// Light reaching `x` from the surface point `y`: `L·cos θ_y·A/d²`,
    /// the radiance over the point's density when chosen uniformly by
    /// area; `None` from inside a one-sided sphere.
    pub(super) fn incident(&self, x: Vec3, y: Vec3) -> Option<Incident> {
        let (direction, d2) = towards(x, y)?;
        let normal = self.normal(y);
        let cos_y = -direction.dot(normal);
        let cos_y = if self.two_sided { cos_y.abs() } else { cos_y };
        (cos_y > 0.0).then(|| Incident {
            direction,
            distance: d2.sqrt(),
            irradiance: self.radiance * (cos_y * self.area() / d2),
            light_normal: Some(normal),
        })
    }

    /// The cone the sphere subtends from `x`, if `x` is outside it:
    /// `cos θmax = √(1 − sin²θmax)` with `sin θmax = r/d`, and the density
    /// of uniform directions in it. The density takes
    /// `1 − cos θmax = sin²θmax/(1 + cos θmax)`, exact where `cos θmax`
    /// rounds to 1: a sphere 10⁴ radii away gave an infinite density, and
    /// volpath's MIS weights ∞/∞ = NaN for every sample.
    fn cone(&self, x: Vec3) -> Option<(f32, f32)> {
        let d2 = (self.sphere.center - x).length_squared();
        let r2 = self.sphere.radius * self.sphere.radius;
        (d2 > r2 * (1.0 + 1e-4)).then(|| {
            let sin2_max = r2 / d2;
            let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
            let pdf = uniform_cone_pdf_from_gap(sin2_max / (1.0 + cos_max));
            (cos_max, pdf.min(f32::MAX))
        })
    }

    /// Light from a point of the sphere chosen for the receiver `x`
    /// (uniform in the subtended cone from outside, uniform in area from
    /// inside), divided by the point's density, and that density per unit
    /// solid angle seen from `x`.
    pub fn sample_incident(&self, x: Vec3, u: Vec2) -> Option<(Incident, f32)> {
        let Some((cos_max, pdf)) = self.cone(x) else {
            let y = self.point(u);
            let incident = self.incident(x, y)?;
            let pdf = self.pdf(x, y, incident.direction);
            return Some((incident, pdf));
        };
        let to_center = self.sphere.center - x;
        let d = to_center.length();
        let axis = to_center / d;
        let direction = uniform_cone(axis, cos_max, u);
        // The nearer intersection with the sphere along `direction`
        // (pbrt-v4: from the triangle x, centre, point, not a ray test,
        // which misses at the silhouette in f32).
        let cos = direction.dot(axis).min(1.0);
        let sin2 = (1.0 - cos * cos).max(0.0);
        let r = self.sphere.radius;
        let distance = d * cos - (r * r - d * d * sin2).max(0.0).sqrt();
        Some((
            Incident {
                direction,
                distance,
                irradiance: self.radiance / pdf,
                light_normal: Some(self.normal(x + direction * distance)),
            },
            pdf,
        ))
    }

    /// Density per unit solid angle, seen from `x`, with which
    /// [`SphereLight::sample_incident`] picks the point `y` in direction
    /// `direction` (unit, from `x`).
    pub fn pdf(&self, x: Vec3, y: Vec3, direction: Vec3) -> f32 {
        if let Some((_, pdf)) = self.cone(x) {
            return pdf;
        }
        let cos = self.normal(y).dot(direction).abs();
        let d2 = (y - x).length_squared();
        if cos > 0.0 {
            d2 / (self.area() * cos)
        } else {
            0.0
        }
    }
}

/// A rectangle seen from a point as a spherical rectangle, for sampling
/// directions uniformly in its solid angle (Ureña, Fajardo & King 2013,
/// "An Area-Preserving Parametrization for Spherical Rectangles"). Uniform
/// area sampling has density ∝ d²/cos, unbounded for receivers close to the
/// light; solid-angle sampling has density 1/Ω, so the estimate of the
/// irradiance `L·Ω·cos` of a small neighbourhood stays bounded.
#[derive(Clone, Copy, Debug)]
pub struct SphericalRectangle {
    origin: Vec3,
    x: Vec3,
    y: Vec3,
    z: Vec3,
    z0: f32,
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    b0: f32,
    b1: f32,
    k: f32,
    /// Solid angle (sr).
    pub solid_angle: f32,
}

impl SphericalRectangle {
    /// The rectangle `frame` seen from `o`; `None` if `o` lies in its
    /// plane or it subtends no solid angle.
    pub(super) fn new(frame: &RectangleFrame, o: Vec3) -> Option<Self> {
        let (x, y) = (frame.x, frame.y);
        let (exl, eyl) = (frame.width, frame.height);
        let mut z = frame.z;
        let d = frame.corner - o;
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        if z0 > -1e-7 * (1.0 + d.length()) {
            return None;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + exl, y0 + eyl);
        // Normals of the four great-circle edges, in the local frame.
        let n0 = Vec3::new(0.0, z0, -y0).normalize();
        let n1 = Vec3::new(-z0, 0.0, x1).normalize();
        let n2 = Vec3::new(0.0, -z0, y1).normalize();
        let n3 = Vec3::new(z0, 0.0, -x0).normalize();
        let angle = |a: Vec3, b: Vec3| arc_cosine(-a.dot(b));
        let (g0, g1, g2, g3) = (angle(n0, n1), angle(n1, n2), angle(n2, n3), angle(n3, n0));
        let k = std::f32::consts::TAU - g2 - g3;
        let solid_angle = g0 + g1 - k;
        (solid_angle > 0.0 && solid_angle.is_finite()).then_some(Self {
            origin: o,
            x,
            y,
            z,
            z0,
            x0,
            x1,
            y0,
            y1,
            b0: n0.z,
            b1: n2.z,
            k,
            solid_angle,
        })
    }

    /// A point on the rectangle, uniformly distributed in solid angle from
    /// the origin, for `u ∈ [0, 1)²`.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let au = u.x * self.solid_angle + self.k;
        let fu = (au.cos() * self.b0 - self.b1) / au.sin();
        let cu = (1.0 / (fu * fu + self.b0 * self.b0).sqrt())
            .copysign(fu)
            .clamp(-1.0, 1.0);
        let xu = (-(cu * self.z0) / (1.0 - cu * cu).max(1e-12).sqrt()).clamp(self.x0, self.x1);
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + u.y * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-6 {
            hv * d / (1.0 - hv2).sqrt()
        } else {
            self.y1
        };
        self.origin + self.x * xu + self.y * yv.clamp(self.y0, self.y1) + self.z * self.z0
    }
}

/// acos(x) in radians for x ∈ [−1, 1] (clamped), to f32 precision:
/// Abramowitz & Stegun (1964) 4.4.46, `acos x = √(1 − x)·Σ aᵢxⁱ` on
/// [0, 1] with |error| ≤ 2·10⁻⁸, and `acos(−x) = π − acos x`. Next
/// event estimation builds a spherical rectangle, four arc cosines, at
/// every vertex; libm's `acosf` (with its errno wrapper) was 4.4 % of a
/// multiple-scattering render's instructions (callgrind, fog-room-multi),
/// this about a third of that.
fn arc_cosine(x: f32) -> f32 {
    const A: [f32; 8] = [
        // a₀ = 1.5707963050 rounds to π/2 in f32.
        std::f32::consts::FRAC_PI_2,
        -0.214_598_8,
        0.088_978_99,
        -0.050_174_303,
        0.030_891_88,
        -0.017_088_126,
        0.006_670_09,
        -0.001_262_491_1,
    ];
    let x = x.clamp(-1.0, 1.0);
    let a = x.abs();
    let poly = A.iter().rev().fold(0.0, |sum, &c| sum * a + c);
    let acos_a = (1.0 - a).sqrt() * poly;
    if x < 0.0 { PI - acos_a } else { acos_a }
}

impl QuadLight {
    /// The emitting point for receivers to connect to: uniform over the
    /// quad (density 1/A) from `u ∈ [0,1)²`, with its normal.
    #[inline]
    pub(super) fn sample_point(&self, u: Vec2) -> LightPoint {
        LightPoint::on_surface(self.quad.point(u.x, u.y), self.quad.normal)
    }

    /// A ray leaving the quad from a point uniform in area (`u_point`)
    /// with a cosine-distributed direction (`u_direction`), on its back
    /// side if it is two-sided and `u_side ≥ ½`.
    pub(super) fn sample_le(&self, u_point: Vec2, u_direction: Vec2, u_side: f32) -> LeSample {
        let (normal, sides) = if self.two_sided {
            let back = u_side >= 0.5;
            (
                if back {
                    -self.quad.normal
                } else {
                    self.quad.normal
                },
                2.0,
            )
        } else {
            (self.quad.normal, 1.0)
        };
        let point = self.quad.point(u_point.x, u_point.y);
        let direction = cosine_hemisphere(normal, u_direction);
        LeSample {
            point: LightPoint::on_surface(point, self.quad.normal),
            ray: Ray {
                origin: offset_origin(point, normal, direction),
                direction,
            },
            // L·cos θ₀ / ((1/A)·(cos θ₀/(π·s))).
            beta: self.radiance * (self.quad.area() * PI * sides),
        }
    }

    /// The density of [`QuadLight::sample_le`]'s rays along the unit
    /// `direction`, per unit area and projected solid angle: `1/(A·π·s)`
    /// from `s` emitting sides, 0 behind a one-sided quad.
    pub(super) fn pdf_le(&self, direction: Vec3) -> f32 {
        if !(self.two_sided || direction.dot(self.quad.normal) > 0.0) {
            return 0.0;
        }
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        1.0 / (self.quad.area() * PI * sides)
    }

    /// Total emitted power, `L·π·A` per emitting side.
    pub(super) fn power(&self) -> Rgb {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance * (PI * self.quad.area() * sides)
    }

    /// A light of radiance `radiance` on `quad`.
    pub fn new(quad: Quad, radiance: Rgb, two_sided: bool) -> Self {
        Self {
            quad,
            radiance,
            two_sided,
            rectangle: RectangleFrame::new(&quad),
        }
    }

    /// Whether the quad is a rectangle, which next event estimation
    /// samples uniformly in solid angle from receivers near it
    /// ([`QuadLight::sample_incident`]); other parallelograms are sampled
    /// uniformly by area.
    pub fn is_rectangle(&self) -> bool {
        self.rectangle.is_some()
    }

    /// Light reaching `x` from the point `y` of the quad: `L·cos θ_y·A/d²`,
    /// the radiance over the point's density when chosen uniformly by
    /// area; `None` behind a one-sided quad.
    pub(super) fn incident(&self, x: Vec3, y: Vec3) -> Option<Incident> {
        let (direction, d2) = towards(x, y)?;
        let cos_y = -direction.dot(self.quad.normal);
        let cos_y = if self.two_sided { cos_y.abs() } else { cos_y };
        (cos_y > 0.0).then(|| Incident {
            direction,
            distance: d2.sqrt(),
            irradiance: self.radiance * (cos_y * self.quad.area() / d2),
            light_normal: Some(self.quad.normal),
        })
    }

    /// Light from a point of this light chosen for the receiver `x`:
    /// uniformly in solid angle for a rectangle when `x` lies within
    /// [`SOLID_ANGLE_REACH`] diagonals of its centre, uniformly in area
    /// otherwise. Returns the incident light divided by the point's
    /// density, and that density per unit solid angle seen from `x`.
    pub fn sample_incident(&self, x: Vec3, u: Vec2) -> Option<(Incident, f32)> {
        if let Some(rect) = self.rectangle.as_ref().and_then(|frame| frame.seen_from(x)) {
            let y = rect.sample(u);
            let (direction, d2) = towards(x, y)?;
            let cos_y = -direction.dot(self.quad.normal);
            let cos_y = if self.two_sided { cos_y.abs() } else { cos_y };
            if cos_y <= 0.0 {
                return None;
            }
            let pdf = 1.0 / rect.solid_angle;
            return Some((
                Incident {
                    direction,
                    distance: d2.sqrt(),
                    irradiance: self.radiance * rect.solid_angle,
                    light_normal: Some(self.quad.normal),
                },
                pdf,
            ));
        }
        let y = self.quad.point(u.x, u.y);
        let incident = self.incident(x, y)?;
        let pdf = self.pdf(x, y, incident.direction);
        Some((incident, pdf))
    }

    /// Density per unit solid angle, seen from `x`, with which
    /// [`QuadLight::sample_incident`] picks the point `y` of this light
    /// in direction `direction` (unit, from `x`).
    pub fn pdf(&self, x: Vec3, y: Vec3, direction: Vec3) -> f32 {
        if let Some(rect) = self.rectangle.as_ref().and_then(|frame| frame.seen_from(x)) {
            return 1.0 / rect.solid_angle;
        }
        let cos = self.quad.normal.dot(direction).abs();
        let d2 = (y - x).length_squared();
        if cos > 0.0 {
            d2 / (self.quad.area() * cos)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn arc_cosine_is_acos_to_f32_precision() {
        // Against f64's acos on a fine grid and at the ends: within the
        // polynomial's 2e-8 plus a few f32 roundings of values up to π.
        let mut worst = 0.0f64;
        for i in 0..=200_000 {
            let x = -1.0 + 2.0 * f64::from(i) / 200_000.0;
            let error = (f64::from(super::arc_cosine(x as f32)) - (x as f32 as f64).acos()).abs();
            worst = worst.max(error);
        }
        assert!(
            worst < 2e-8 + 4.0 * f64::from(f32::EPSILON) * std::f64::consts::PI,
            "{worst}"
        );
        assert_eq!(super::arc_cosine(1.0), 0.0);
        assert!((super::arc_cosine(-1.0) - PI).abs() <= f32::EPSILON * PI);
        assert_eq!(super::arc_cosine(2.0), 0.0, "clamped");
    }

    use super::*;

    /// The 1.2 × 0.8 rectangle facing down at height 2 that these tests
    /// light and sample.
    fn test_rectangle() -> Quad {
        Quad::new(
            Vec3::new(-0.5, 2.0, -0.3),
            Vec3::new(1.2, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.8),
            false,
        )
        .unwrap()
    }

    /// The solid angle `quad` subtends from `x`, `∫ |cos θ_y|/d² dA`, by
    /// the midpoint rule on an n × n grid, in f64.
    fn solid_angle_by_quadrature(quad: &Quad, x: Vec3, n: u32) -> f64 {
        let mut omega = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let y = quad.point((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = y - x;
                let cos = f64::from((quad.normal.dot(d) / d.length()).abs());
                omega +=
                    cos / f64::from(d.length_squared()) * f64::from(quad.area()) / f64::from(n * n);
            }
        }
        omega
    }

    /// Solid-angle sampling: points lie on the rectangle, and the solid
    /// angle equals the integral of cos/d² over its area (midpoint rule).
    #[test]
    fn spherical_rectangle_sampling() {
        let quad = test_rectangle();
        for o in [
            Vec3::ZERO,
            Vec3::new(0.4, 1.5, 0.2),
            Vec3::new(3.0, 0.5, -2.0),
        ] {
            let frame = RectangleFrame::new(&quad).unwrap();
            let rect = SphericalRectangle::new(&frame, o).unwrap();
            let omega = solid_angle_by_quadrature(&quad, o, 400);
            assert!(
                (rect.solid_angle as f64 - omega).abs() < 1e-3 * omega,
                "{o}: {} vs {omega}",
                rect.solid_angle
            );
            for k in 0..64 {
                let u = Vec2::new((k % 8) as f32 / 8.0 + 0.06, (k / 8) as f32 / 8.0 + 0.06);
                let p = rect.sample(u) - quad.origin;
                let (a, b) = (
                    p.dot(quad.edge_u) / quad.edge_u.length_squared(),
                    p.dot(quad.edge_v) / quad.edge_v.length_squared(),
                );
                assert!(
                    (-1e-4..=1.0001).contains(&a)
                        && (-1e-4..=1.0001).contains(&b)
                        && p.dot(quad.normal).abs() < 1e-4
                );
            }
        }
    }

    /// Next event estimation's light from a rectangle, `L/p` averaged over
    /// a 256² grid of `u`, is `L·Ω` near the light (solid-angle sampling)
    /// and beyond [`SOLID_ANGLE_REACH`] (area sampling), with Ω the
    /// test's own midpoint quadrature of `cos θ_y/d²`; and `pdf` gives
    /// each sample's density.
    #[test]
    fn rectangle_light_is_unbiased_near_and_far() {
        let quad = test_rectangle();
        let light = QuadLight::new(quad, Rgb::splat(3.0), false);
        let centre = quad.origin + 0.5 * (quad.edge_u + quad.edge_v);
        let diagonal = (quad.edge_u + quad.edge_v).length();
        let below = Vec3::new(0.3, -1.0, 0.2).normalize();
        for reach in [0.3, 1.0, 1.9, 2.1, 4.0, 12.0] {
            let x = centre + below * (reach * diagonal);
            let omega = solid_angle_by_quadrature(&quad, x, 512);
            let m = 256;
            let mut sum = 0.0f64;
            for i in 0..m {
                for j in 0..m {
                    let u = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                    let (incident, pdf) = light.sample_incident(x, u).expect("in front");
                    let y = x + incident.direction * incident.distance;
                    let again = light.pdf(x, y, incident.direction);
                    assert!(
                        (again - pdf).abs() <= 1e-4 * pdf,
                        "{reach}: pdf {again} vs {pdf}"
                    );
                    sum += f64::from(incident.irradiance.x);
                }
            }
            let mean = sum / (m * m) as f64;
            assert!(
                (mean - 3.0 * omega).abs() < 1e-3 * 3.0 * omega,
                "{reach} diagonals: {mean} vs L·Ω = {}",
                3.0 * omega
            );
        }
    }

    /// A sphere far away (issue 28: 10⁴ radii, where `cos θmax` rounds to
    /// 1 in f32 and the cone's density was infinite, so every volpath
    /// sample was NaN) has a finite density, and its sampled irradiance
    /// `L·Ω` matches the closed form `Ω = 2π(1 − √(1 − (r/d)²))`,
    /// evaluated in f64, to f32 rounding.
    #[test]
    fn far_spheres_have_finite_cone_densities() {
        use super::SphereLight;
        use crate::color::Rgb;
        use crate::shapes::Sphere;
        use glam::{Vec2, Vec3};
        for d in [10.0f32, 1e3, 1e4, 1e5, 3e6] {
            let light = SphereLight {
                sphere: Sphere {
                    center: Vec3::new(0.0, 0.0, -d),
                    radius: 1.0,
                },
                radiance: Rgb::splat(2.0),
                two_sided: false,
            };
            let (incident, pdf) = light
                .sample_incident(Vec3::ZERO, Vec2::new(0.3, 0.7))
                .expect("outside the sphere");
            let d = d as f64;
            let omega =
                std::f64::consts::TAU * (1.0 / (d * d)) / (1.0 + (1.0 - 1.0 / (d * d)).sqrt());
            assert!(pdf.is_finite() && pdf > 0.0, "d {d}: pdf {pdf}");
            let relative = |x: f64, want: f64| ((x - want) / want).abs();
            assert!(
                relative(1.0 / pdf as f64, omega) < 1e-5,
                "d {d}: Ω {} vs {omega}",
                1.0 / pdf
            );
            assert!(
                relative(incident.irradiance.x as f64, 2.0 * omega) < 1e-5,
                "d {d}: {:?}",
                incident.irradiance
            );
            assert!(incident.distance.is_finite() && incident.direction.is_finite());
            let y = Vec3::ZERO + incident.direction * incident.distance;
            assert_eq!(light.pdf(Vec3::ZERO, y, incident.direction), pdf);
        }
    }
}
