//! Light sources: point, spot (the paper's §3.2), directional and quad
//! area lights. Any number of each.
//!
//! Every light answers two questions for a receiving point `x`:
//! [`Light::sample_point`] picks the emitting point `y` (the light's
//! position, or a uniformly chosen point of an area light), and
//! [`Light::incident`] gives the light arriving at `x` from `y` before
//! occlusion, glass and fog are applied. Spotlights also clip a ray to the
//! part inside their cone ([`Light::reach`]), which both integrators use so
//! that no march step or distance sample is spent outside the beam.

use crate::color::Rgb;
use crate::ray::{Ray, offset_origin};
use crate::sampling::{cosine_hemisphere, uniform_cone, uniform_cone_pdf};
use crate::shapes::{Quad, Sphere};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// How a spotlight's intensity falls off from its axis to its cutoff.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpotProfile {
    /// The paper's eq. 5: `i = 1 − (1 − cos θ)/(1 − cos θc)`.
    Linear,
    /// Full intensity inside `cos_inner`, a smoothstep (in cos θ) down to
    /// zero at the cutoff, as glTF's KHR_lights_punctual spot cone.
    Smooth { cos_inner: f32 },
    /// 1 inside the cone, 0 outside.
    Hard,
}

/// Point light of radiant intensity `intensity` (W/sr) in all directions.
/// The paper writes `Φ/(4π)` for a light of power Φ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Rgb,
}

/// Spotlight: intensity `intensity` (W/sr) on its axis, shaped by
/// `profile`, zero outside the cone `cos θ ≤ cos_cutoff`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    /// Unit axis of the cone, the direction light leaves along.
    pub direction: Vec3,
    /// Cosine of the cutoff half-angle θc ∈ (0°, 90°].
    pub cos_cutoff: f32,
    pub profile: SpotProfile,
    pub intensity: Rgb,
}

impl SpotLight {
    /// The profile factor for a direction at angle θ off the axis, given
    /// as `cos θ`: 0 outside the cone (the paper's eq. 4), else eq. 5 or
    /// its alternatives.
    #[inline]
    pub fn falloff(&self, cos_theta: f32) -> f32 {
        if cos_theta <= self.cos_cutoff {
            return 0.0;
        }
        match self.profile {
            SpotProfile::Linear => 1.0 - (1.0 - cos_theta) / (1.0 - self.cos_cutoff),
            SpotProfile::Hard => 1.0,
            SpotProfile::Smooth { cos_inner } => {
                if cos_theta >= cos_inner {
                    1.0
                } else {
                    let x = (cos_theta - self.cos_cutoff) / (cos_inner - self.cos_cutoff);
                    x * x * (3.0 - 2.0 * x)
                }
            }
        }
    }

    /// The interval of `[t0, t1]` along `ray` inside the cone. The cone is
    /// convex (θc ≤ 90°), so the set is one interval.
    pub fn clip_ray(&self, ray: &Ray, t0: f32, t1: f32) -> Option<(f32, f32)> {
        // Inside ⇔ g(t) = (v·d + t ω·d) − |v + t ω| cos θc > 0, v = o − apex.
        // Its boundary is where (v·d + t ω·d)² = cos²θc |v + t ω|² (a
        // quadratic) with v·d + t ω·d ≥ 0, or where the axis plane is
        // crossed (v·d + t ω·d = 0, the whole boundary when θc = 90°).
        let v = ray.origin - self.position;
        let (vd, wd) = (v.dot(self.direction), ray.direction.dot(self.direction));
        let c2 = self.cos_cutoff * self.cos_cutoff;
        let a = wd * wd - c2;
        let b = 2.0 * (vd * wd - c2 * v.dot(ray.direction));
        let c = vd * vd - c2 * v.length_squared();
        let mut cuts = [t0, t1, f32::NAN, f32::NAN, f32::NAN];
        if a.abs() > 1e-12 {
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                let sq = disc.sqrt();
                let q = -0.5 * (b + b.signum() * sq);
                cuts[2] = q / a;
                cuts[3] = if q != 0.0 { c / q } else { f32::NAN };
            }
        } else if b != 0.0 {
            cuts[2] = -c / b;
        }
        if wd != 0.0 {
            cuts[4] = -vd / wd;
        }
        // Candidate boundaries in [t0, t1], ascending; NaN (no root) and
        // out-of-range roots are pushed past the end and ignored.
        for t in &mut cuts {
            if !(*t >= t0 && *t <= t1) {
                *t = f32::NAN;
            }
        }
        cuts.sort_unstable_by(f32::total_cmp);
        let count = cuts.iter().take_while(|t| !t.is_nan()).count();
        let ts = &cuts[..count];
        let inside = |t: f32| {
            let p = ray.at(t) - self.position;
            p.dot(self.direction) > p.length() * self.cos_cutoff
        };
        let mut result: Option<(f32, f32)> = None;
        for w in ts.windows(2) {
            let (lo, hi) = (w[0], w[1]);
            if hi <= lo {
                continue;
            }
            let mid = if hi.is_infinite() {
                lo + 1.0 + lo.abs()
            } else {
                0.5 * (lo + hi)
            };
            if inside(mid) {
                result = Some(match result {
                    None => (lo, hi),
                    Some((s, _)) => (s, hi),
                });
            }
        }
        result
    }
}

/// Directional light (a sun): parallel light travelling along `direction`
/// with irradiance `irradiance` (W/m²) on a surface facing it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    pub direction: Vec3,
    pub irradiance: Rgb,
}

/// A parallelogram area light of constant radiance `radiance`
/// (W·sr⁻¹·m⁻²), emitting from the front of `quad` (both sides if
/// `two_sided`). Its geometry is also in the scene, so it is seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadLight {
    pub quad: Quad,
    pub radiance: Rgb,
    pub two_sided: bool,
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
    fn area(&self) -> f32 {
        4.0 * PI * self.sphere.radius * self.sphere.radius
    }

    /// A point uniform over the surface (density 1/A) from `u ∈ [0,1)²`:
    /// the full sphere of directions is the cone with cos θmax = −1.
    fn point(&self, u: Vec2) -> Vec3 {
        self.sphere.center + self.sphere.radius * uniform_cone(Vec3::Z, -1.0, u)
    }

    /// `cos θmax` of the cone the sphere subtends from `x`, if `x` is
    /// outside it.
    fn cone(&self, x: Vec3) -> Option<f32> {
        let d2 = (self.sphere.center - x).length_squared();
        let r2 = self.sphere.radius * self.sphere.radius;
        (d2 > r2 * (1.0 + 1e-4)).then(|| (1.0 - r2 / d2).max(0.0).sqrt())
    }

    /// Light from a point of the sphere chosen for the receiver `x`
    /// (uniform in the subtended cone from outside, uniform in area from
    /// inside), divided by the point's density, and that density per unit
    /// solid angle seen from `x`.
    pub fn sample_incident(&self, x: Vec3, u: Vec2) -> Option<(Incident, f32)> {
        let Some(cos_max) = self.cone(x) else {
            let y = self.point(u);
            let incident = Light::Sphere(*self).incident(x, Some(y))?;
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
        let pdf = uniform_cone_pdf(cos_max);
        Some((
            Incident {
                direction,
                distance,
                irradiance: self.radiance / pdf,
            },
            pdf,
        ))
    }

    /// Density per unit solid angle, seen from `x`, with which
    /// [`SphereLight::sample_incident`] picks the point `y` in direction
    /// `direction` (unit, from `x`).
    pub fn pdf(&self, x: Vec3, y: Vec3, direction: Vec3) -> f32 {
        if let Some(cos_max) = self.cone(x) {
            return uniform_cone_pdf(cos_max);
        }
        let normal = (y - self.sphere.center) / self.sphere.radius;
        let cos = normal.dot(direction).abs();
        let d2 = (y - x).length_squared();
        if cos > 0.0 {
            d2 / (self.area() * cos)
        } else {
            0.0
        }
    }
}

/// The closed set of light kinds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Directional(DirectionalLight),
    Quad(QuadLight),
    Sphere(SphereLight),
}

/// Light arriving at a point from one emitting point, before occlusion,
/// glass and fog transmittance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// Unit direction from the receiving point towards the light.
    pub direction: Vec3,
    /// Distance to the emitting point (∞ for a directional light).
    pub distance: f32,
    /// Irradiance on a surface facing the light (W/m²), divided by the
    /// probability density of the emitting point chosen by
    /// [`Light::sample_point`]: `I(dir)/d²` for point and spot lights,
    /// `L·cos θ_y·A/d²` for an area light of area A, `E` for a sun.
    pub irradiance: Rgb,
}

impl Light {
    /// The emitting point for receivers to connect to: the position of a
    /// point or spot light, a uniformly distributed point (density 1/A) on
    /// an area light from `u ∈ [0,1)²`, `None` for a directional light.
    #[inline]
    pub fn sample_point(&self, u: Vec2) -> Option<Vec3> {
        match self {
            Light::Point(p) => Some(p.position),
            Light::Spot(s) => Some(s.position),
            Light::Directional(_) => None,
            Light::Quad(q) => Some(q.quad.point(u.x, u.y)),
            Light::Sphere(s) => Some(s.point(u)),
        }
    }

    /// Light reaching `x` from the emitting point `y` (from
    /// [`Light::sample_point`]); `None` where it is zero (outside a
    /// spotlight's cone, behind a one-sided emitter), so callers skip the
    /// shadow ray — the paper's cone test before the shadow ray.
    #[inline]
    pub fn incident(&self, x: Vec3, y: Option<Vec3>) -> Option<Incident> {
        match (self, y) {
            (Light::Directional(d), _) => Some(Incident {
                direction: -d.direction,
                distance: f32::INFINITY,
                irradiance: d.irradiance,
            }),
            (Light::Point(p), _) => {
                let (direction, d2) = towards(x, p.position)?;
                Some(Incident {
                    direction,
                    distance: d2.sqrt(),
                    irradiance: p.intensity / d2,
                })
            }
            (Light::Spot(s), _) => {
                let (direction, d2) = towards(x, s.position)?;
                let falloff = s.falloff(-direction.dot(s.direction));
                (falloff > 0.0).then(|| Incident {
                    direction,
                    distance: d2.sqrt(),
                    irradiance: s.intensity * (falloff / d2),
                })
            }
            (Light::Quad(q), Some(y)) => {
                let (direction, d2) = towards(x, y)?;
                let cos_y = -direction.dot(q.quad.normal);
                let cos_y = if q.two_sided { cos_y.abs() } else { cos_y };
                (cos_y > 0.0).then(|| Incident {
                    direction,
                    distance: d2.sqrt(),
                    irradiance: q.radiance * (cos_y * q.quad.area() / d2),
                })
            }
            (Light::Sphere(s), Some(y)) => {
                let (direction, d2) = towards(x, y)?;
                let normal = (y - s.sphere.center) / s.sphere.radius;
                let cos_y = -direction.dot(normal);
                let cos_y = if s.two_sided { cos_y.abs() } else { cos_y };
                (cos_y > 0.0).then(|| Incident {
                    direction,
                    distance: d2.sqrt(),
                    irradiance: s.radiance * (cos_y * s.area() / d2),
                })
            }
            (Light::Quad(_) | Light::Sphere(_), None) => None,
        }
    }

    /// The part of `[t0, t1]` along `ray` that this light can reach: the
    /// cone for a spotlight, everything for other lights.
    #[inline]
    pub fn reach(&self, ray: &Ray, t0: f32, t1: f32) -> Option<(f32, f32)> {
        match self {
            Light::Spot(s) => s.clip_ray(ray, t0, t1),
            _ => (t0 < t1).then_some((t0, t1)),
        }
    }
}

/// An emitted ray chosen by [`Light::sample_le`], for paths traced from
/// the light (the light tracer, `volpath`'s light subpaths).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeSample {
    /// The emitting point y₀: the light's position, or a point of an area
    /// light's surface.
    pub point: Vec3,
    /// The emitted ray along the sampled direction, from y₀ (moved just
    /// off an area light's surface).
    pub ray: Ray,
    /// The light subpath's initial throughput
    /// `Le(y₀, ω)·|cos θ₀| / (p_pos(y₀)·p_dir(ω))` (Veach 1997 §10.2):
    /// `I(ω)/p_dir` (W) for point and spot lights, `L·A·π·s` for a
    /// Lambertian quad of area A emitting from s sides.
    pub beta: Rgb,
}

impl Light {
    /// Whether the light is a Dirac delta in position or direction (point,
    /// spot, directional): no sampled direction can hit it, so only light
    /// sampling ([`Light::sample_li`]) reaches it, and choosing its
    /// emitting point takes no random numbers.
    #[inline]
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point(_) | Light::Spot(_) | Light::Directional(_)
        )
    }

    /// The position of a light that emits from one point (point and spot
    /// lights); `None` for distant and area lights.
    #[inline]
    pub fn position(&self) -> Option<Vec3> {
        match self {
            Light::Point(p) => Some(p.position),
            Light::Spot(s) => Some(s.position),
            Light::Directional(_) | Light::Quad(_) | Light::Sphere(_) => None,
        }
    }

    /// Whether the light is an area light with a flat emitting surface (a
    /// quad): [`Light::sample_le`] starts rays on it, and its geometry
    /// term has one normal.
    #[inline]
    pub fn is_flat_emitter(&self) -> bool {
        matches!(self, Light::Quad(_))
    }

    /// Surface area (m²) of an area light's emitting surface; 0 for delta
    /// lights.
    #[inline]
    pub fn area(&self) -> f32 {
        match self {
            Light::Quad(q) => q.quad.area(),
            Light::Sphere(s) => s.area(),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => 0.0,
        }
    }

    /// Unit normal of an area light's surface at its point `y` (the side
    /// a one-sided light emits from); `None` for delta lights.
    #[inline]
    pub fn normal(&self, y: Vec3) -> Option<Vec3> {
        match self {
            Light::Quad(q) => Some(q.quad.normal),
            Light::Sphere(s) => Some((y - s.sphere.center) / s.sphere.radius),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => None,
        }
    }

    /// Light reaching the receiver `x` from a point of this light chosen
    /// for it (next event estimation), divided by the point's density:
    /// uniform in solid angle for a rectangle and from outside a sphere,
    /// uniform in area otherwise (`u ∈ [0,1)²`; delta lights use their
    /// fixed point and ignore `u`). Also returns the choice's solid-angle
    /// density for MIS ([`Light::pdf_li`]), `None` for delta lights, which
    /// no sampled direction can hit.
    #[inline]
    pub fn sample_li(&self, x: Vec3, u: Vec2) -> Option<(Incident, Option<f32>)> {
        match self {
            Light::Quad(q) => q
                .sample_incident(x, u)
                .map(|(incident, pdf)| (incident, Some(pdf))),
            Light::Sphere(s) => s
                .sample_incident(x, u)
                .map(|(incident, pdf)| (incident, Some(pdf))),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => self
                .incident(x, self.sample_point(Vec2::ZERO))
                .map(|i| (i, None)),
        }
    }

    /// Density per unit solid angle, seen from `x`, with which
    /// [`Light::sample_li`] picks the point `y` of an area light in the
    /// unit direction `direction` from `x`; 0 for delta lights.
    #[inline]
    pub fn pdf_li(&self, x: Vec3, y: Vec3, direction: Vec3) -> f32 {
        match self {
            Light::Quad(q) => q.pdf(x, y, direction),
            Light::Sphere(s) => s.pdf(x, y, direction),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => 0.0,
        }
    }

    /// A ray leaving the light, for paths traced from it: a point light
    /// emits uniformly over the sphere and a spot uniformly over its cone
    /// (both from `u_direction`); a quad from a point uniform in area
    /// (`u_point`) with a cosine-distributed direction (`u_direction`),
    /// on its back side if it is two-sided and `u_side ≥ ½`. `None` where
    /// the sampled ray carries nothing (a spot's profile is 0 at its cut)
    /// and for lights whose emission is not sampled (directional lights,
    /// emissive spheres).
    pub fn sample_le(&self, u_point: Vec2, u_direction: Vec2, u_side: f32) -> Option<LeSample> {
        match self {
            Light::Point(p) => {
                let direction = uniform_cone(Vec3::Z, -1.0, u_direction);
                Some(LeSample {
                    point: p.position,
                    ray: Ray {
                        origin: p.position,
                        direction,
                    },
                    beta: p.intensity * (4.0 * PI),
                })
            }
            Light::Spot(s) => {
                let direction = uniform_cone(s.direction, s.cos_cutoff, u_direction);
                let falloff = s.falloff(direction.dot(s.direction));
                if falloff <= 0.0 {
                    return None;
                }
                let solid_angle = 2.0 * PI * (1.0 - s.cos_cutoff);
                Some(LeSample {
                    point: s.position,
                    ray: Ray {
                        origin: s.position,
                        direction,
                    },
                    beta: s.intensity * (falloff * solid_angle),
                })
            }
            Light::Quad(q) => {
                let (normal, sides) = if q.two_sided {
                    let back = u_side >= 0.5;
                    (if back { -q.quad.normal } else { q.quad.normal }, 2.0)
                } else {
                    (q.quad.normal, 1.0)
                };
                let point = q.quad.point(u_point.x, u_point.y);
                let direction = cosine_hemisphere(normal, u_direction);
                Some(LeSample {
                    point,
                    ray: Ray {
                        origin: offset_origin(point, normal, direction),
                        direction,
                    },
                    // L·cos θ₀ / ((1/A)·(cos θ₀/(π·s))).
                    beta: q.radiance * (q.quad.area() * PI * sides),
                })
            }
            Light::Directional(_) | Light::Sphere(_) => None,
        }
    }

    /// The density with which [`Light::sample_le`] emits a ray along the
    /// unit `direction`, per unit area at its emitting point and per unit
    /// projected solid angle of the direction (`p_pos·p_dir/|cos θ₀|`,
    /// Veach 1997 §4.1): `1/(A·π·s)` for a quad of area A emitting from s
    /// sides (uniform over its surface, so the point does not matter), 0
    /// behind a one-sided quad. 0 for lights that no other strategy meets
    /// at a sampled point (point and spot lights, whose p_pos is a Dirac
    /// delta) and for lights whose emission is not sampled.
    pub fn pdf_le(&self, direction: Vec3) -> f32 {
        match self {
            Light::Quad(q) => {
                if !(q.two_sided || direction.dot(q.quad.normal) > 0.0) {
                    return 0.0;
                }
                let sides = if q.two_sided { 2.0 } else { 1.0 };
                1.0 / (q.quad.area() * PI * sides)
            }
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Sphere(_) => 0.0,
        }
    }

    /// Total emitted power Φ (W). A directional light's is the flux
    /// through a disk of radius `scene_radius` (the scene's bounding
    /// sphere) facing it, `E·π·r²`, as pbrt-v4's `DistantLight`; emitters
    /// count `L·π·A` per emitting side (pbrt-v4's `DiffuseAreaLight::Phi`).
    pub fn power(&self, scene_radius: f32) -> Rgb {
        match self {
            Light::Point(p) => p.intensity * (4.0 * PI),
            // ∫ falloff dω over the cone, in closed form per profile.
            Light::Spot(s) => {
                let cos_c = s.cos_cutoff;
                let integral = match s.profile {
                    // 2π ∫ (1 − (1 − c)/(1 − c_c)) dc over [c_c, 1].
                    SpotProfile::Linear => PI * (1.0 - cos_c),
                    SpotProfile::Hard => 2.0 * PI * (1.0 - cos_c),
                    // The smoothstep averages ½ over [c_c, c_i].
                    SpotProfile::Smooth { cos_inner } => {
                        2.0 * PI * ((1.0 - cos_inner) + 0.5 * (cos_inner - cos_c))
                    }
                };
                s.intensity * integral
            }
            Light::Directional(d) => d.irradiance * (PI * scene_radius * scene_radius),
            Light::Quad(q) => {
                let sides = if q.two_sided { 2.0 } else { 1.0 };
                q.radiance * (PI * q.quad.area() * sides)
            }
            Light::Sphere(s) => {
                let sides = if s.two_sided { 2.0 } else { 1.0 };
                s.radiance * (PI * s.area() * sides)
            }
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
    /// The rectangle `quad` (its edges must be orthogonal) seen from `o`;
    /// `None` if `o` lies in its plane or it subtends no solid angle.
    pub fn new(quad: &Quad, o: Vec3) -> Option<Self> {
        let (ex, ey) = (quad.edge_u, quad.edge_v);
        let (exl, eyl) = (ex.length(), ey.length());
        let (x, y) = (ex / exl, ey / eyl);
        let mut z = x.cross(y);
        let d = quad.origin - o;
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
        let angle = |a: Vec3, b: Vec3| (-a.dot(b)).clamp(-1.0, 1.0).acos();
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

/// Whether solid-angle sampling applies: a rectangle (orthogonal edges).
fn is_rectangle(quad: &Quad) -> bool {
    quad.edge_u.dot(quad.edge_v).abs() <= 1e-5 * quad.edge_u.length() * quad.edge_v.length()
}

impl QuadLight {
    /// Light from a point of this light chosen for the receiver `x`:
    /// uniformly in solid angle for a rectangle, uniformly in area
    /// otherwise. Returns the incident light divided by the point's
    /// density, and that density per unit solid angle seen from `x`.
    pub fn sample_incident(&self, x: Vec3, u: Vec2) -> Option<(Incident, f32)> {
        if is_rectangle(&self.quad)
            && let Some(rect) = SphericalRectangle::new(&self.quad, x)
        {
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
                },
                pdf,
            ));
        }
        let y = self.quad.point(u.x, u.y);
        let incident = Light::Quad(*self).incident(x, Some(y))?;
        let pdf = self.pdf(x, y, incident.direction);
        Some((incident, pdf))
    }

    /// Density per unit solid angle, seen from `x`, with which
    /// [`QuadLight::sample_incident`] picks the point `y` of this light
    /// in direction `direction` (unit, from `x`).
    pub fn pdf(&self, x: Vec3, y: Vec3, direction: Vec3) -> f32 {
        if is_rectangle(&self.quad)
            && let Some(rect) = SphericalRectangle::new(&self.quad, x)
        {
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

/// Unit direction and squared distance from `x` to `y`; `None` if they
/// coincide.
#[inline]
fn towards(x: Vec3, y: Vec3) -> Option<(Vec3, f32)> {
    let d = y - x;
    let d2 = d.length_squared();
    (d2 > 0.0).then(|| (d / d2.sqrt(), d2))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot(profile: SpotProfile, cutoff_deg: f32) -> SpotLight {
        SpotLight {
            position: Vec3::new(0.0, 3.0, 0.0),
            direction: -Vec3::Y,
            cos_cutoff: cutoff_deg.to_radians().cos(),
            profile,
            intensity: Rgb::ONE,
        }
    }

    /// Eq. 5 at its defining points, and one value computed by hand:
    /// θ = 15°, θc = 30°: 1 − (1 − 0.9659258)/(1 − 0.8660254) = 0.7456669.
    /// Solid-angle sampling: points lie on the rectangle, and the solid
    /// angle equals the integral of cos/d² over its area (midpoint rule).
    #[test]
    fn spherical_rectangle_sampling() {
        let quad = Quad::new(
            Vec3::new(-0.5, 2.0, -0.3),
            Vec3::new(1.2, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.8),
            false,
        )
        .unwrap();
        for o in [
            Vec3::ZERO,
            Vec3::new(0.4, 1.5, 0.2),
            Vec3::new(3.0, 0.5, -2.0),
        ] {
            let rect = SphericalRectangle::new(&quad, o).unwrap();
            let n = 400;
            let mut omega = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let p = quad.point((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let d = p - o;
                    let cos = (quad.normal.dot(d) / d.length()).abs() as f64;
                    omega +=
                        cos / d.length_squared() as f64 * (quad.area() as f64 / (n * n) as f64);
                }
            }
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

    #[test]
    fn linear_profile_is_paper_eq5() {
        let s = spot(SpotProfile::Linear, 30.0);
        assert!((s.falloff(1.0) - 1.0).abs() < 1e-6);
        assert_eq!(s.falloff(30f32.to_radians().cos()), 0.0);
        assert_eq!(s.falloff(40f32.to_radians().cos()), 0.0);
        assert!((s.falloff(15f32.to_radians().cos()) - 0.745_666_9).abs() < 1e-5);
    }

    #[test]
    fn smooth_and_hard_profiles() {
        let inner = 10f32.to_radians().cos();
        let s = spot(SpotProfile::Smooth { cos_inner: inner }, 30.0);
        assert_eq!(s.falloff(5f32.to_radians().cos()), 1.0);
        let mid = s.falloff(20f32.to_radians().cos());
        assert!(mid > 0.0 && mid < 1.0);
        assert_eq!(s.falloff(31f32.to_radians().cos()), 0.0);
        let h = spot(SpotProfile::Hard, 30.0);
        assert_eq!(h.falloff(29.9f32.to_radians().cos()), 1.0);
        assert_eq!(h.falloff(30.1f32.to_radians().cos()), 0.0);
    }

    /// The cone interval agrees with a brute-force scan of the inside test.
    #[test]
    fn cone_clip_matches_scan() {
        for cutoff in [10.0, 25.0, 60.0, 90.0] {
            let s = spot(SpotProfile::Hard, cutoff);
            for k in 0..40 {
                let a = k as f32 * 0.37;
                let o = Vec3::new(3.0 * a.cos(), 1.0 + (a * 1.7).sin(), 3.0 * a.sin());
                let target = Vec3::new(0.3 * (a * 2.3).cos(), 0.5 * (a * 0.7).sin(), 0.2);
                let ray = Ray::new(o, target - o);
                let (t0, t1) = (0.0, 12.0);
                let inside = |t: f32| {
                    let p = ray.at(t) - s.position;
                    p.dot(s.direction) > p.length() * s.cos_cutoff
                };
                let n = 4000;
                let mut scan: Option<(f32, f32)> = None;
                for i in 0..=n {
                    let t = t0 + (t1 - t0) * i as f32 / n as f32;
                    if inside(t) {
                        scan = Some(scan.map_or((t, t), |(lo, _)| (lo, t)));
                    }
                }
                let clip = s.clip_ray(&ray, t0, t1);
                match (scan, clip) {
                    (None, None) => {}
                    (Some((lo, hi)), Some((clo, chi))) => {
                        let h = (t1 - t0) / n as f32;
                        assert!((lo - clo).abs() <= 2.0 * h, "{cutoff} {k}: {lo} vs {clo}");
                        assert!((hi - chi).abs() <= 2.0 * h, "{cutoff} {k}: {hi} vs {chi}");
                    }
                    (scan, clip) => {
                        // A sliver thinner than the scan step may be missed.
                        let width = clip.map_or(0.0, |(a, b)| b - a);
                        assert!(
                            scan.is_none() && width < 0.01,
                            "{cutoff} {k}: {scan:?} vs {clip:?}"
                        );
                    }
                }
            }
        }
    }

    /// The emitted rays' mean throughput is the light's power,
    /// `E[β] = ∫∫ Le·cos θ₀ dA dω = Φ`: checks `sample_le`'s weights
    /// against `power`'s closed forms (spot profiles included).
    #[test]
    fn emitted_throughput_averages_to_power() {
        let inner = 20f32.to_radians().cos();
        let quad = Quad::new(
            Vec3::new(-0.5, 2.0, -0.3),
            Vec3::new(1.2, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.8),
            false,
        )
        .unwrap();
        let lights = [
            Light::Point(PointLight {
                position: Vec3::ONE,
                intensity: Rgb::new(1.0, 2.0, 3.0),
            }),
            Light::Spot(spot(SpotProfile::Linear, 35.0)),
            Light::Spot(spot(SpotProfile::Hard, 35.0)),
            Light::Spot(spot(SpotProfile::Smooth { cos_inner: inner }, 35.0)),
            Light::Quad(QuadLight {
                quad,
                radiance: Rgb::splat(2.0),
                two_sided: true,
            }),
        ];
        for light in lights {
            let n = 256;
            let mut sum = Rgb::ZERO;
            for i in 0..n {
                for j in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    if let Some(sample) = light.sample_le(u, Vec2::new(u.y, u.x), u.x) {
                        sum += sample.beta;
                    }
                }
            }
            let mean = sum / (n * n) as f32;
            let power = light.power(1.0);
            assert!(
                (mean - power).abs().max_element() < 1e-3 * power.max_element(),
                "{light:?}: {mean} vs {power}"
            );
        }
    }

    /// A quad's emission density is `1/(A·π·s)` on its emitting sides and
    /// 0 behind a one-sided quad; its emitted rays leave from the front.
    #[test]
    fn quad_emission_density() {
        let quad = Quad::new(Vec3::ZERO, Vec3::X * 2.0, Vec3::Z, false).unwrap();
        let front = QuadLight {
            quad,
            radiance: Rgb::ONE,
            two_sided: false,
        };
        let one_sided = Light::Quad(front);
        let n = quad.normal;
        let area = quad.area();
        assert!((one_sided.pdf_le(n) - 1.0 / (area * PI)).abs() < 1e-7);
        assert_eq!(one_sided.pdf_le(-n), 0.0);
        let sample = one_sided
            .sample_le(Vec2::splat(0.3), Vec2::new(0.2, 0.7), 0.9)
            .unwrap();
        assert!(sample.ray.direction.dot(n) > 0.0);
        assert!(sample.ray.origin.dot(n) > 0.0);
        let two_sided = Light::Quad(QuadLight {
            two_sided: true,
            ..front
        });
        assert!((two_sided.pdf_le(-n) - 1.0 / (area * PI * 2.0)).abs() < 1e-7);
        let back = two_sided
            .sample_le(Vec2::splat(0.3), Vec2::new(0.2, 0.7), 0.9)
            .unwrap();
        assert!(back.ray.direction.dot(n) < 0.0);
    }
}
