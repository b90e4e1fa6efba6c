//! Shadow maps and coloured transmittance maps: the fast visibility path
//! the paper could not finish (its §4.3, §5.1).
//!
//! For every point, spot and directional light, a map is rendered from the
//! light once per frame by casting one ray per texel through the BVH. A
//! texel stores the distance to the first opaque surface and, before it,
//! the glass panes the ray crossed as *layers*: each layer's depth and the
//! cumulative tint of the light after crossing it, under the scene's glass
//! model. It is a coloured deep shadow map: a fog point between the light
//! and a pane is untinted, one behind the pane is tinted, one behind the
//! opaque surface is dark — what a shadow ray would say, at the map's
//! resolution. Map rays leave the light while shadow rays head for it, so
//! map rays meet one-sided quads from the other side
//! ([`crate::accel::Geometry::for_each_hit_from_light`]): both find the
//! same occluders between a point and the light. A lookup then costs a projection and four texel reads
//! instead of a BVH traversal, independent of the march step.
//!
//! Projections: a spotlight of cutoff θc ≤ 60° uses one perspective map
//! over its cone (half-angle θc); point lights and wider spots use a cube
//! map (six 90° faces); a directional light uses an orthographic map over
//! the scene's bounding sphere. Quad area lights have no single centre of
//! projection: they keep exact shadow rays.
//!
//! Filtering is percentage-closer (bilinear over the four nearest texels),
//! which turns a one-texel staircase into a one-texel ramp.
//!
//! Depth bias: a texel's depth is measured along the ray through its
//! centre, so a lit surface seen at angle θ from the light differs from a
//! neighbouring texel's depth by up to `w·tan θ` for a texel footprint `w`
//! at that distance. For surface points the comparison allows
//! `w·(1.5 + min(tan θ, 8))`: lit planes never shadow themselves (no acne),
//! and light leaks at most that distance past an occluder's edge or
//! contact point — about one texel plus the slope term. Fog points cannot
//! shadow themselves and get no bias, so no light leaks through thin
//! walls into the fog behind them.
//!
//! Memory: a texel is one f32, the depth of the first opaque surface,
//! negated when glass lies in front of it; only those texels have layers,
//! found through a per-face offset table. A 512² face is 1 MiB and stays
//! in cache, so a lookup is cheaper than a shadow ray.

use crate::accel::Geometry;
use crate::color::Rgb;
use crate::glass::{Glass, GlassModel};
use crate::lights::{Light, LightOrigin};
use crate::materials::Material;
use crate::ray::Ray;
use crate::shapes::Bounds;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Distance from a light, relative to its coordinates' magnitude, within
/// which map rays ignore what they meet (see `render_face`).
const LIGHT_CLEARANCE: f32 = 1e-4;
/// Bias in texel footprints for fog points (no surface normal).
const BIAS_TEXELS: f32 = 1.5;
/// Largest slope (tan θ) the surface bias follows; grazing surfaces
/// beyond it may show acne rather than leak ever more light.
const MAX_BIAS_SLOPE: f32 = 8.0;
/// Spot cutoffs above this use a cube map (a single perspective map's
/// texels grow without bound as the half-angle approaches 90°).
const MAX_PERSPECTIVE_CUTOFF_DEG: f32 = 60.0;

/// One layer of glass in a texel: the depth of the pane and the light's
/// tint after crossing it (and every pane before it).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Layer {
    depth: f32,
    tint: Rgb,
}

/// How world points map to a face's texels: a frame at the light and a
/// perspective or parallel projection along its `forward` axis.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Projection {
    origin: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    kind: ProjectionKind,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum ProjectionKind {
    /// Rays from `origin` through a square of half-extent `tan_half` at
    /// distance 1. Depth is the distance from `origin`.
    Perspective { tan_half: f32 },
    /// Parallel rays from the plane through `origin`, covering
    /// `±half_extent` along `right` and `up`. Depth is the distance from
    /// that plane.
    Orthographic { half_extent: f32 },
}

impl Projection {
    /// Face coordinates in [−1, 1]² (outside: off the face) and the depth
    /// of `x`; `None` behind a perspective face.
    #[inline]
    fn project(&self, x: Vec3) -> Option<(Vec2, f32)> {
        let d = x - self.origin;
        let lateral = Vec2::new(d.dot(self.right), d.dot(self.up));
        let z = d.dot(self.forward);
        match self.kind {
            ProjectionKind::Perspective { tan_half } => {
                (z > 0.0).then(|| (lateral / (z * tan_half), d.length()))
            }
            ProjectionKind::Orthographic { half_extent } => Some((lateral / half_extent, z)),
        }
    }

    /// The ray through face coordinates `s ∈ [−1, 1]²`.
    fn ray(&self, s: Vec2) -> Ray {
        let lateral = self.right * s.x + self.up * s.y;
        match self.kind {
            ProjectionKind::Perspective { tan_half } => {
                Ray::new(self.origin, self.forward + lateral * tan_half)
            }
            ProjectionKind::Orthographic { half_extent } => Ray {
                origin: self.origin + lateral * half_extent,
                direction: self.forward,
            },
        }
    }

    /// World size of one texel at depth `depth` for a face of `resolution`.
    #[inline]
    fn footprint(&self, depth: f32, resolution: u32) -> f32 {
        match self.kind {
            ProjectionKind::Perspective { tan_half } => depth * 2.0 * tan_half / resolution as f32,
            ProjectionKind::Orthographic { half_extent } => 2.0 * half_extent / resolution as f32,
        }
    }
}

/// One rendered face of a light's map.
#[derive(Clone, Debug)]
struct Face {
    projection: Projection,
    /// Per texel, the distance to the first opaque surface (∞ if none),
    /// negated when the texel has glass layers.
    depths: Vec<f32>,
    /// Per texel with layers, `layers[layer_offsets[i]..layer_offsets[i + 1]]`
    /// are its panes in increasing depth; `layer_offsets` has one entry per
    /// texel plus one.
    layer_offsets: Vec<u32>,
    layers: Vec<Layer>,
}

/// What the map of a light says about a point.
#[derive(Clone, Debug)]
enum LightMap {
    /// A single face (spot, directional).
    Single(Face),
    /// Six faces around a point: +x, −x, +y, −y, +z, −z.
    Cube(Box<[Face; 6]>),
    /// No map (area lights): use a shadow ray.
    None,
}

/// The maps of every light of a scene, in the scene's light order.
#[derive(Clone, Debug)]
pub struct ShadowMaps {
    resolution: u32,
    maps: Vec<LightMap>,
}

/// What a shadow map needs to know about the scene to render itself.
pub struct MapScene<'a> {
    pub geometry: &'a Geometry,
    pub materials: &'a [Material],
    pub model: GlassModel,
}

/// Whether a spotlight of cutoff cosine `cos_cutoff` is narrow enough
/// for one perspective map over its cone (θc ≤ 60°); a wider one gets a
/// cube map of [`CUBE_FACES`].
pub fn is_narrow(cos_cutoff: f32) -> bool {
    cos_cutoff >= MAX_PERSPECTIVE_CUTOFF_DEG.to_radians().cos()
}

/// How many map faces [`ShadowMaps::build`] renders for `light`: six for
/// a point light or a wide spot, one for a narrow spot or a directional
/// light, none for an area light or the environment (they keep shadow
/// rays).
pub(crate) fn face_count(light: &Light) -> u64 {
    match light.origin() {
        LightOrigin::Cone { cos_cutoff, .. } if is_narrow(cos_cutoff) => 1,
        LightOrigin::Cone { .. } | LightOrigin::Point { .. } => 6,
        LightOrigin::Parallel { .. } => 1,
        LightOrigin::Surface | LightOrigin::Surrounding => 0,
    }
}

impl ShadowMaps {
    /// Renders the maps of all lights at `resolution`² texels per face.
    pub fn build(scene: &MapScene, lights: &[Light], resolution: u32) -> Self {
        let maps = lights
            .iter()
            .map(|light| match light.origin() {
                LightOrigin::Cone {
                    apex,
                    axis,
                    cos_cutoff,
                } if is_narrow(cos_cutoff) => {
                    let (right, up) = axis.any_orthonormal_pair();
                    let tan_half = cos_cutoff.acos().tan();
                    let projection = Projection {
                        origin: apex,
                        right,
                        up,
                        forward: axis,
                        kind: ProjectionKind::Perspective { tan_half },
                    };
                    LightMap::Single(render_face(scene, projection, resolution))
                }
                LightOrigin::Cone { apex: position, .. } | LightOrigin::Point { position } => {
                    cube(scene, position, resolution)
                }
                LightOrigin::Parallel { direction } => {
                    let bounds = scene.geometry.bounds();
                    let (center, radius) = bounding_sphere(bounds);
                    let (right, up) = direction.any_orthonormal_pair();
                    // Start a little outside the sphere so nothing is clipped.
                    let origin = center - direction * (radius * 1.01 + 1e-3);
                    let projection = Projection {
                        origin,
                        right,
                        up,
                        forward: direction,
                        kind: ProjectionKind::Orthographic {
                            half_extent: radius * 1.01 + 1e-3,
                        },
                    };
                    LightMap::Single(render_face(scene, projection, resolution))
                }
                LightOrigin::Surface | LightOrigin::Surrounding => LightMap::None,
            })
            .collect();
        Self { resolution, maps }
    }

    pub fn resolution(&self) -> u32 {
        self.resolution
    }

    /// Light from light `index` reaching `x` past geometry: 0 behind an
    /// opaque surface, the glass tint in front of one, filtered over the
    /// four nearest texels. `normal` is the surface normal at `x` (for the
    /// slope-scaled bias), `None` in fog; `to_light` the unit direction
    /// from `x` towards the light. `None` if the light has no map.
    pub fn transmittance(
        &self,
        index: usize,
        x: Vec3,
        normal: Option<Vec3>,
        to_light: Vec3,
    ) -> Option<Rgb> {
        let face = match &self.maps[index] {
            LightMap::Single(face) => face,
            LightMap::Cube(faces) => {
                // The face is chosen by the direction from the light.
                let d = -to_light;
                let a = d.abs();
                let i = if a.x >= a.y && a.x >= a.z {
                    if d.x > 0.0 { 0 } else { 1 }
                } else if a.y >= a.z {
                    if d.y > 0.0 { 2 } else { 3 }
                } else if d.z > 0.0 {
                    4
                } else {
                    5
                };
                &faces[i]
            }
            LightMap::None => return None,
        };
        let Some((s, depth)) = face.projection.project(x) else {
            return Some(Rgb::ONE);
        };
        if s.x.abs() > 1.0 || s.y.abs() > 1.0 {
            // Off the map: outside a spot's cone (already dark) or outside
            // the scene's bounds (nothing there to occlude).
            return Some(Rgb::ONE);
        }
        let bias = normal.map_or(0.0, |n| {
            let cos = n.dot(to_light).abs().max(1e-3);
            let slope = ((1.0 - cos * cos).sqrt() / cos).min(MAX_BIAS_SLOPE);
            face.projection.footprint(depth, self.resolution) * (BIAS_TEXELS + slope)
        });
        Some(face.filtered(s, depth, bias, self.resolution))
    }
}

impl Face {
    /// Percentage-closer filtering: the bilinear blend of the four
    /// nearest texels' answers for a point at `depth`. Texels without
    /// glass answer 0 or 1, so the common case blends scalars only.
    #[inline]
    fn filtered(&self, s: Vec2, depth: f32, bias: f32, resolution: u32) -> Rgb {
        let r = resolution as f32;
        // Texel centres sit at integer coordinates p = (s + 1)/2·R − ½.
        let p = (s + Vec2::ONE) * 0.5 * r - Vec2::splat(0.5);
        // p ≥ −½ on the face, so truncating p + 1 floors it (without a
        // libm call on this hot path).
        let (x0, y0) = ((p.x + 1.0) as i32 - 1, (p.y + 1.0) as i32 - 1);
        let f = p - Vec2::new(x0 as f32, y0 as f32);
        let max = resolution as i32 - 1;
        let column = |dx: i32| (x0 + dx).clamp(0, max) as usize;
        let row = |dy: i32| (y0 + dy).clamp(0, max) as usize * resolution as usize;
        let texels = [
            row(0) + column(0),
            row(0) + column(1),
            row(1) + column(0),
            row(1) + column(1),
        ];
        let weights = [
            (1.0 - f.x) * (1.0 - f.y),
            f.x * (1.0 - f.y),
            (1.0 - f.x) * f.y,
            f.x * f.y,
        ];
        if texels.iter().all(|&i| self.depths[i] >= 0.0) {
            let lit: f32 = texels
                .iter()
                .zip(weights)
                .map(|(&i, w)| {
                    if depth > self.depths[i] + bias {
                        0.0
                    } else {
                        w
                    }
                })
                .sum();
            return Rgb::splat(lit);
        }
        texels
            .iter()
            .zip(weights)
            .map(|(&i, w)| self.lookup(i, depth, bias) * w)
            .sum()
    }

    /// Texel `i`'s answer for a point at `depth`.
    #[inline]
    fn lookup(&self, i: usize, depth: f32, bias: f32) -> Rgb {
        let stored = self.depths[i];
        if depth > stored.abs() + bias {
            return Rgb::ZERO;
        }
        if stored >= 0.0 {
            return Rgb::ONE;
        }
        let layers =
            &self.layers[self.layer_offsets[i] as usize..self.layer_offsets[i + 1] as usize];
        // The last pane in front of the point sets the tint.
        layers
            .iter()
            .rev()
            .find(|l| l.depth + bias < depth)
            .map_or(Rgb::ONE, |l| l.tint)
    }
}

/// A cube map's faces in order: (forward, right, up) for +x, −x, +y, −y,
/// +z, −z, right-handed (right × up = forward).
pub const CUBE_FACES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::NEG_Z, Vec3::Y),
    (Vec3::NEG_X, Vec3::Z, Vec3::Y),
    (Vec3::Y, Vec3::X, Vec3::NEG_Z),
    (Vec3::NEG_Y, Vec3::X, Vec3::Z),
    (Vec3::Z, Vec3::X, Vec3::Y),
    (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
];

fn cube(scene: &MapScene, origin: Vec3, resolution: u32) -> LightMap {
    let faces = CUBE_FACES.map(|(forward, right, up)| {
        render_face(
            scene,
            Projection {
                origin,
                right,
                up,
                forward,
                kind: ProjectionKind::Perspective { tan_half: 1.0 },
            },
            resolution,
        )
    });
    LightMap::Cube(Box::new(faces))
}

fn bounding_sphere(b: Bounds) -> (Vec3, f32) {
    if b.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        (b.center(), (0.5 * b.extent().length()).max(1e-3))
    }
}

/// Casts one ray per texel centre, in parallel over rows.
fn render_face(scene: &MapScene, projection: Projection, resolution: u32) -> Face {
    let r = resolution as usize;
    // Per row: the depths, each texel's layer count, and the layers.
    let rows: Vec<(Vec<f32>, Vec<u32>, Vec<Layer>)> = (0..r)
        .into_par_iter()
        .map(|y| {
            let (mut depths, mut counts, mut layers) =
                (Vec::with_capacity(r), Vec::with_capacity(r), Vec::new());
            let mut hits: Vec<(f32, Glass)> = Vec::new();
            for x in 0..r {
                let s = Vec2::new(
                    (x as f32 + 0.5) / resolution as f32 * 2.0 - 1.0,
                    (y as f32 + 0.5) / resolution as f32 * 2.0 - 1.0,
                );
                let ray = projection.ray(s);
                // One traversal: every hit, then the panes before the
                // first opaque surface.
                hits.clear();
                let mut opaque = f32::INFINITY;
                // Shadow rays end just short of the light
                // (`ray::shadow_ray_end`): a surface through the light's
                // own position — a legacy spot's lamp quad — does not
                // shadow it, however rounding places its hit.
                let clearance = LIGHT_CLEARANCE * (1.0 + ray.origin.abs().max_element());
                scene
                    .geometry
                    .for_each_hit_from_light(&ray, f32::INFINITY, |t, index| {
                        if t <= clearance {
                            return std::ops::ControlFlow::Continue(());
                        }
                        match scene.materials[scene.geometry.primitive(index).material as usize] {
                            Material::Glass(g) => hits.push((t, g)),
                            _ => opaque = opaque.min(t),
                        }
                        std::ops::ControlFlow::Continue(())
                    });
                hits.retain(|(t, _)| *t < opaque);
                hits.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                let mut tint = Rgb::ONE;
                for (t, glass) in &hits {
                    tint = scene.model.tint_after(tint, glass);
                    // Texel rays start at the light (or the orthographic
                    // plane) with unit direction: depth is ray distance.
                    layers.push(Layer { depth: *t, tint });
                }
                depths.push(if hits.is_empty() { opaque } else { -opaque });
                counts.push(hits.len() as u32);
            }
            (depths, counts, layers)
        })
        .collect();
    let mut depths = Vec::with_capacity(r * r);
    let mut layer_offsets = Vec::with_capacity(r * r + 1);
    let mut layers = Vec::new();
    layer_offsets.push(0);
    for (row_depths, row_counts, row_layers) in rows {
        depths.extend(row_depths);
        for count in row_counts {
            let last = *layer_offsets.last().expect("starts with 0");
            layer_offsets.push(last + count);
        }
        layers.extend(row_layers);
    }
    Face {
        projection,
        depths,
        layer_offsets,
        layers,
    }
}
