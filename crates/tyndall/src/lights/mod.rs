//! Light sources: point, spot (the paper's §3.2), directional, area
//! lights (quads, spheres and triangle meshes; any number of each), and
//! one environment (a uniform or mapped sky).
//!
//! A light owns its physics, pbrt-style, behind one enum ([`Light`]):
//! integrators call its methods and name no kind.
//!
//! - Towards a receiving point `x` (next event estimation):
//!   [`Light::sample_point`] picks the emitting point `y` (the light's
//!   position, or a uniformly chosen point of an area light, with its
//!   surface normal: a [`LightPoint`]),
//!   [`Light::incident`] gives the light arriving at `x` from `y` before
//!   occlusion, glass and fog are applied, and [`Light::sample_li`] /
//!   [`Light::pdf_li`] sample and weigh that point in solid angle
//!   (spherical rectangles and cones where possible).
//! - Away from the light (paths traced from it): [`Light::sample_le`] and
//!   [`Light::pdf_le`]; [`Light::power`] is the total flux.
//! - Choosing among many lights: [`Light::bounds`] bounds a point or
//!   spot light's emission ([`LightBounds`]); the [`LightTree`] over them
//!   and the [`LightSampler`] that visits the rest choose the lights an
//!   estimate connects to.
//! - Capabilities integrators choose strategies by: [`Light::is_delta`],
//!   [`Light::position`], [`Light::origin`], [`Light::is_flat_emitter`], [`Light::area`].
//!
//! Spotlights also clip a ray to the part inside their cone
//! ([`Light::reach`]), which the integrators use so that no march step or
//! distance sample is spent outside the beam.

//!
//! Each kind's physics is in its own module (`point`, `spot`,
//! `directional`, `area` for quads and spheres, `mesh`, `environment`; measured
//! luminaire profiles on point and spot lights in `photometric`); this module
//! holds the enum, the types of the interface, and the dispatch.

mod area;
pub mod bounds;
mod directional;
pub mod environment;
pub mod gobo;
pub mod light_sampler;
mod mesh;
pub mod photometric;
mod point;
mod spot;
pub mod tree;

pub use area::{QuadLight, SOLID_ANGLE_REACH, SphereLight, SphericalRectangle};
pub use bounds::LightBounds;
pub use directional::DirectionalLight;
pub use environment::{EnvironmentLight, EnvironmentMap};
pub use gobo::Gobo;
pub use light_sampler::{Chosen, LightSampler, LightSampling};
pub use mesh::{EmissionTexture, MeshLight};
pub use photometric::{Luminaire, PhotometricProfile};
pub use point::PointLight;
pub use spot::{SpotLight, SpotProfile};
pub use tree::LightTree;

use crate::color::Rgb;
use crate::ray::Ray;
use glam::{Vec2, Vec3};

/// The closed set of light kinds.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Directional(DirectionalLight),
    Quad(QuadLight),
    Sphere(SphereLight),
    Mesh(MeshLight),
    Environment(EnvironmentLight),
}

/// A point light leaves from: the position of a point or spot light, or a
/// point of an area light's surface with the unit normal there (the side
/// a one-sided emitter emits from). A mesh light's normal depends on the
/// triangle the point lies on, so the point carries it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPoint {
    pub position: Vec3,
    /// The emitting surface's unit normal at `position`; `None` for point
    /// and spot lights.
    pub normal: Option<Vec3>,
    /// The radiance leaving the point where it varies over the light's
    /// surface (a mesh light with an emission texture, set by its
    /// [`Light::sample_point`]); `None` where the light's radiance is
    /// uniform, or where the point was not sampled from the light (a
    /// ray's hit, whose density alone is asked for).
    pub radiance: Option<Rgb>,
}

impl LightPoint {
    /// The point of a point or spot light.
    pub fn delta(position: Vec3) -> Self {
        Self {
            position,
            normal: None,
            radiance: None,
        }
    }

    /// A point of an emitting surface whose unit normal there is `normal`
    /// (for example where a ray hit an emitter).
    pub fn on_surface(position: Vec3, normal: Vec3) -> Self {
        Self {
            position,
            normal: Some(normal),
            radiance: None,
        }
    }
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
    /// The emitting surface's unit normal at the light's point (area
    /// lights); `None` for point, spot and directional lights.
    pub light_normal: Option<Vec3>,
}

impl Incident {
    /// The light's point this light comes from, seen from the receiver
    /// `x` (for its density: the point's radiance is not kept);
    /// meaningless for a directional light (infinitely far).
    #[inline]
    pub fn light_point(&self, x: Vec3) -> LightPoint {
        LightPoint {
            position: x + self.direction * self.distance,
            normal: self.light_normal,
            radiance: None,
        }
    }
}

impl Light {
    /// The emitting point for receivers to connect to: the position of a
    /// point or spot light, a uniformly distributed point (density 1/A) on
    /// an area light from `u ∈ [0,1)²`, `None` for a directional light.
    #[inline]
    pub fn sample_point(&self, u: Vec2) -> Option<LightPoint> {
        match self {
            Light::Point(p) => Some(LightPoint::delta(p.position)),
            Light::Spot(s) => Some(LightPoint::delta(s.position)),
            Light::Directional(_) | Light::Environment(_) => None,
            Light::Quad(q) => Some(q.sample_point(u)),
            Light::Sphere(s) => Some(s.sample_point(u)),
            Light::Mesh(m) => Some(m.sample_point(u)),
        }
    }

    /// Light reaching `x` from the emitting point `y` (from
    /// [`Light::sample_point`]); `None` where it is zero (outside a
    /// spotlight's cone, behind a one-sided emitter), so callers skip the
    /// shadow ray — the paper's cone test before the shadow ray.
    #[inline]
    pub fn incident(&self, x: Vec3, y: Option<LightPoint>) -> Option<Incident> {
        match (self, y) {
            (Light::Directional(d), _) => Some(d.incident()),
            (Light::Point(p), _) => p.incident(x),
            (Light::Spot(s), _) => s.incident(x),
            (Light::Quad(q), Some(y)) => q.incident(x, y.position),
            (Light::Sphere(s), Some(y)) => s.incident(x, y.position),
            (Light::Mesh(m), Some(y)) => m.incident(x, y),
            (Light::Quad(_) | Light::Sphere(_) | Light::Mesh(_), None) => None,
            // Its light comes from a sampled direction ([`Light::sample_li`]).
            (Light::Environment(_), _) => None,
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

/// Where a light's light comes from, for methods that look out from the
/// light (shadow maps): one point in all directions, one point through a
/// cone, parallel from infinity, or an extended surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightOrigin {
    /// From `position` in all directions (a point light).
    Point { position: Vec3 },
    /// From `apex` within the cone around the unit `axis` whose half-angle
    /// has cosine `cos_cutoff` (a spotlight).
    Cone {
        apex: Vec3,
        axis: Vec3,
        cos_cutoff: f32,
    },
    /// Parallel light travelling along the unit `direction` (a sun).
    Parallel { direction: Vec3 },
    /// From infinitely far in every direction (an environment): no
    /// centre of projection.
    Surrounding,
    /// From every point of a surface (area lights): no single centre of
    /// projection.
    Surface,
}

/// An emitted ray chosen by [`Light::sample_le`], for paths traced from
/// the light (the light tracer, `volpath`'s light subpaths).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeSample {
    /// The emitting point y₀: the light's position, or a point of an area
    /// light's surface with its normal.
    pub point: LightPoint,
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

    /// What shapes this light's emission beyond its kind's own law, named
    /// for messages: a measured (IES) profile on a point or spot light, a
    /// gobo on a spot, an emission texture on a mesh; `None` for plain
    /// lights.
    #[inline]
    pub fn emission_pattern(&self) -> Option<&'static str> {
        match self {
            Light::Point(p) => p.luminaire.as_ref().map(|_| "a measured (`ies`) profile"),
            Light::Spot(s) => match (&s.luminaire, &s.gobo) {
                (Some(_), _) => Some("a measured (`ies`) profile"),
                (None, Some(_)) => Some("a gobo"),
                (None, None) => None,
            },
            Light::Mesh(m) => m.emission_texture().map(|_| "an emission texture"),
            Light::Directional(_) | Light::Quad(_) | Light::Sphere(_) | Light::Environment(_) => {
                None
            }
        }
    }

    /// The position of a light that emits from one point (point and spot
    /// lights); `None` for distant and area lights.
    #[inline]
    pub fn position(&self) -> Option<Vec3> {
        match self {
            Light::Point(p) => Some(p.position),
            Light::Spot(s) => Some(s.position),
            Light::Directional(_)
            | Light::Quad(_)
            | Light::Sphere(_)
            | Light::Mesh(_)
            | Light::Environment(_) => None,
        }
    }

    /// Bounds on the emission of a light that emits from one point (point
    /// and spot lights), for the light tree ([`LightTree`]); `None` for
    /// distant and area lights, which every estimate visits.
    #[inline]
    pub fn bounds(&self) -> Option<LightBounds> {
        match self {
            Light::Point(p) => Some(p.bounds()),
            Light::Spot(s) => Some(s.bounds()),
            Light::Directional(_)
            | Light::Quad(_)
            | Light::Sphere(_)
            | Light::Mesh(_)
            | Light::Environment(_) => None,
        }
    }

    /// Where the light's light comes from (see [`LightOrigin`]).
    #[inline]
    pub fn origin(&self) -> LightOrigin {
        match self {
            Light::Point(p) => LightOrigin::Point {
                position: p.position,
            },
            Light::Spot(s) => LightOrigin::Cone {
                apex: s.position,
                axis: s.direction,
                cos_cutoff: s.cos_cutoff,
            },
            Light::Directional(d) => LightOrigin::Parallel {
                direction: d.direction,
            },
            Light::Quad(_) | Light::Sphere(_) | Light::Mesh(_) => LightOrigin::Surface,
            Light::Environment(_) => LightOrigin::Surrounding,
        }
    }

    /// Whether the light is an area light with a flat emitting surface (a
    /// quad): [`Light::sample_le`] starts rays on it, and its geometry
    /// term has one normal. A triangle mesh is not: its normal varies
    /// from triangle to triangle.
    #[inline]
    pub fn is_flat_emitter(&self) -> bool {
        matches!(self, Light::Quad(_))
    }

    /// Surface area (m²) of an area light's emitting surface; 0 for delta
    /// lights and the environment.
    #[inline]
    pub fn area(&self) -> f32 {
        match self {
            Light::Quad(q) => q.quad.area(),
            Light::Sphere(s) => s.area(),
            Light::Mesh(m) => m.area(),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Environment(_) => 0.0,
        }
    }

    /// Light reaching the receiver `x` from a point of this light chosen
    /// for it (next event estimation), divided by the point's density:
    /// uniform in solid angle for a rectangle and from outside a sphere,
    /// uniform in area otherwise (a mesh: a triangle chosen by its power,
    /// see [`MeshLight`]); a direction drawn by the map's brightness from
    /// an environment ([`EnvironmentLight`]) (`u ∈ [0,1)²`; delta lights use their
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
            Light::Mesh(m) => m
                .sample_incident(x, u)
                .map(|(incident, pdf)| (incident, Some(pdf))),
            Light::Environment(e) => e
                .sample_incident(u)
                .map(|(incident, pdf)| (incident, Some(pdf))),
            Light::Point(p) => p.incident(x).map(|i| (i, None)),
            Light::Spot(s) => s.incident(x).map(|i| (i, None)),
            Light::Directional(d) => Some((d.incident(), None)),
        }
    }

    /// Density per unit solid angle, seen from `x`, with which
    /// [`Light::sample_li`] picks the point `y` of an area light (with its
    /// surface normal) in the unit direction `direction` from `x`, or the
    /// direction itself from an environment (`y` unused); 0 for delta
    /// lights.
    #[inline]
    pub fn pdf_li(&self, x: Vec3, y: LightPoint, direction: Vec3) -> f32 {
        match self {
            Light::Quad(q) => q.pdf(x, y.position, direction),
            Light::Sphere(s) => s.pdf(x, y.position, direction),
            Light::Mesh(m) => m.pdf(x, y, direction),
            Light::Environment(e) => e.pdf(direction),
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
    /// emissive spheres and meshes).
    pub fn sample_le(&self, u_point: Vec2, u_direction: Vec2, u_side: f32) -> Option<LeSample> {
        match self {
            Light::Point(p) => Some(p.sample_le(u_direction)),
            Light::Spot(s) => s.sample_le(u_direction),
            Light::Quad(q) => Some(q.sample_le(u_point, u_direction, u_side)),
            Light::Directional(_) | Light::Sphere(_) | Light::Mesh(_) | Light::Environment(_) => {
                None
            }
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
            Light::Quad(q) => q.pdf_le(direction),
            Light::Point(_)
            | Light::Spot(_)
            | Light::Directional(_)
            | Light::Sphere(_)
            | Light::Mesh(_)
            | Light::Environment(_) => 0.0,
        }
    }

    /// Total emitted power Φ (W). A directional light's is the flux
    /// through a disk of radius `scene_radius` (the scene's bounding
    /// sphere) facing it, `E·π·r²`, as pbrt-v4's `DistantLight` (an
    /// environment's `π r² ∫ L dω`, as its infinite lights); emitters
    /// count `L·π·A` per emitting side (pbrt-v4's `DiffuseAreaLight::Phi`).
    pub fn power(&self, scene_radius: f32) -> Rgb {
        match self {
            Light::Point(p) => p.power(),
            Light::Spot(s) => s.power(),
            Light::Directional(d) => d.power(scene_radius),
            Light::Quad(q) => q.power(),
            Light::Sphere(s) => s.power(),
            Light::Mesh(m) => m.power(),
            Light::Environment(e) => e.power(scene_radius),
        }
    }
}

/// The mean of a colour's channels: the grey intensity light choices
/// weigh lights by.
#[inline]
pub(super) fn mean_channel(c: Rgb) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Unit direction and squared distance from `x` to `y`; `None` if they
/// coincide.
#[inline]
pub(super) fn towards(x: Vec3, y: Vec3) -> Option<(Vec3, f32)> {
    let d = y - x;
    let d2 = d.length_squared();
    (d2 > 0.0).then(|| (d / d2.sqrt(), d2))
}

#[cfg(test)]
mod tests {
    use super::spot::tests::spot;
    use super::*;
    use crate::shapes::Quad;
    use std::f32::consts::PI;

    /// The emitted rays' mean throughput is the light's power,
    /// `E[β] = ∫∫ Le·cos θ₀ dA dω = Φ`: checks `sample_le`'s weights
    /// against `power`'s closed forms (spot profiles included).
    #[test]
    fn emitted_throughput_averages_to_power() {
        // A bilateral table, uneven in θ and φ, lit above the horizon too.
        let measured = |nadir: Vec3| {
            let rows = vec![
                vec![5.0, 4.0, 2.5, 1.0, 0.5, 0.0],
                vec![5.0, 4.5, 3.5, 1.5, 0.2, 0.0],
                vec![5.0, 3.0, 1.0, 0.2, 0.1, 0.0],
            ];
            let table = PhotometricProfile::new(
                vec![0.0, 20.0, 45.0, 80.0, 120.0, 180.0],
                vec![0.0, 60.0, 180.0],
                &rows,
            )
            .unwrap();
            Luminaire::new(std::sync::Arc::new(table), nadir, 25.0)
        };
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
                luminaire: None,
                position: Vec3::ONE,
                intensity: Rgb::new(1.0, 2.0, 3.0),
            }),
            Light::Spot(spot(SpotProfile::Linear, 35.0)),
            Light::Spot(spot(SpotProfile::Hard, 35.0)),
            Light::Spot(spot(SpotProfile::Smooth { cos_inner: inner }, 35.0)),
            Light::Quad(QuadLight::new(quad, Rgb::splat(2.0), true)),
            Light::Point(PointLight {
                luminaire: Some(measured(Vec3::new(0.3, -1.0, 0.2))),
                position: Vec3::ONE,
                intensity: Rgb::new(1.0, 2.0, 3.0),
            }),
            Light::Spot(SpotLight {
                luminaire: Some(measured(-Vec3::Y)),
                ..spot(SpotProfile::Smooth { cos_inner: inner }, 35.0)
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
        let front = QuadLight::new(quad, Rgb::ONE, false);
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
