//! Geometric shapes: spheres, parallelogram quads and triangles.
//!
//! Shapes answer two questions: where does a ray first meet me within
//! `(t_min, t_max)`, and what is my geometric normal at a point. Boxes and
//! meshes are built from quads and triangles by the scene loaders.

use crate::ray::Ray;
use glam::{Vec2, Vec3};

/// Smallest ray parameter accepted as a hit. Zero: secondary rays start
/// from origins already moved off their surface
/// ([`crate::ray::offset_origin`]).
pub const T_MIN: f32 = 0.0;

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    /// The empty box (the identity of [`Bounds::union`]).
    pub const EMPTY: Bounds = Bounds {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn new(a: Vec3, b: Vec3) -> Self {
        Self {
            min: a.min(b),
            max: a.max(b),
        }
    }

    pub fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    pub fn include(self, p: Vec3) -> Bounds {
        Bounds {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Whether `p` lies in the closed box.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// The parameter interval where `ray` is inside the box, clipped to
    /// `[t0, t1]` (slab test); `None` if it does not enter it there.
    pub fn clip_ray(&self, ray: &Ray, t0: f32, t1: f32) -> Option<(f32, f32)> {
        let inv = ray.direction.recip();
        let a = (self.min - ray.origin) * inv;
        let b = (self.max - ray.origin) * inv;
        // NaN (0·∞ on a slab boundary) is discarded by min/max ordering.
        let near = a.min(b).max_element().max(t0);
        let far = a.max(b).min_element().min(t1);
        (near <= far).then_some((near, far))
    }
}

/// A sphere, closed and hit from either side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        // |o + t d − c|² = r² with |d| = 1: t² + 2 b t + c = 0.
        let oc = ray.origin - self.center;
        let b = oc.dot(ray.direction);
        let c = oc.length_squared() - self.radius * self.radius;
        // Numerically stable discriminant (Hearn & Baker; pbrt-v4 §6.8.1):
        // b² − c computed as r² − |oc − b d|².
        let perp = oc - b * ray.direction;
        let disc = self.radius * self.radius - perp.length_squared();
        if disc < 0.0 {
            return None;
        }
        let sq = disc.sqrt();
        let q = if b > 0.0 { -b - sq } else { -b + sq };
        let (mut t0, mut t1) = (q, c / q);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        if t0 > T_MIN && t0 < t_max {
            Some(t0)
        } else if t1 > T_MIN && t1 < t_max {
            Some(t1)
        } else {
            None
        }
    }

    pub fn normal(&self, p: Vec3) -> Vec3 {
        (p - self.center).normalize()
    }

    pub fn bounds(&self) -> Bounds {
        Bounds::new(
            self.center - Vec3::splat(self.radius),
            self.center + Vec3::splat(self.radius),
        )
    }
}

/// A parallelogram `origin + u·edge_u + v·edge_v`, `u, v ∈ [0, 1]`.
///
/// Its normal is `normalize(edge_u × edge_v)`. A one-sided quad is hit
/// only by rays that meet its front (`direction · normal < 0`); the course
/// code base the paper extends made quads one-sided (docs/scene-format.md, legacy format).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    pub origin: Vec3,
    pub edge_u: Vec3,
    pub edge_v: Vec3,
    pub normal: Vec3,
    pub one_sided: bool,
    /// `n / |n|²` for the unnormalised normal `n = edge_u × edge_v`, used
    /// to find the hit's (u, v) coordinates.
    w: Vec3,
}

/// Relative tolerance for four corners to form a parallelogram.
const PARALLELOGRAM_TOLERANCE: f32 = 1e-4;

impl Quad {
    /// A quad from four corners listed around a parallelogram; the error
    /// says why they do not form one.
    pub fn from_corners(c: [Vec3; 4], one_sided: bool) -> Result<Quad, String> {
        let scale = c
            .iter()
            .map(|p| p.abs().max_element())
            .fold(1.0f32, f32::max);
        let expected = c[1] + c[3] - c[0];
        if (expected - c[2]).length() > PARALLELOGRAM_TOLERANCE * scale {
            return Err(format!(
                "the corners must form a parallelogram listed in order around it (the third corner should be {:?})",
                expected.to_array()
            ));
        }
        Self::new(c[0], c[1] - c[0], c[3] - c[0], one_sided)
            .ok_or_else(|| "the corners must span a parallelogram of non-zero area".to_string())
    }

    /// A quad from a corner and two edges; `None` if the edges are
    /// parallel or zero (a degenerate quad has no area and no normal).
    pub fn new(origin: Vec3, edge_u: Vec3, edge_v: Vec3, one_sided: bool) -> Option<Self> {
        let n = edge_u.cross(edge_v);
        let n2 = n.length_squared();
        let has_area = n2 > 0.0 && n2.is_finite();
        if !has_area {
            return None;
        }
        Some(Self {
            origin,
            edge_u,
            edge_v,
            normal: n / n2.sqrt(),
            one_sided,
            w: n / n2,
        })
    }

    /// Area in square scene units.
    pub fn area(&self) -> f32 {
        self.edge_u.cross(self.edge_v).length()
    }

    pub fn centroid(&self) -> Vec3 {
        self.origin + 0.5 * (self.edge_u + self.edge_v)
    }

    /// The point at parametric coordinates `(u, v) ∈ [0,1]²`.
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        self.origin + u * self.edge_u + v * self.edge_v
    }

    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let denom = self.normal.dot(ray.direction);
        if denom == 0.0 || (self.one_sided && denom > 0.0) {
            return None;
        }
        let t = self.normal.dot(self.origin - ray.origin) / denom;
        if !(t > T_MIN && t < t_max) {
            return None;
        }
        let p = ray.at(t) - self.origin;
        let u = self.w.dot(p.cross(self.edge_v));
        let v = self.w.dot(self.edge_u.cross(p));
        ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some(t)
    }

    pub fn bounds(&self) -> Bounds {
        Bounds::new(self.origin, self.origin)
            .include(self.origin + self.edge_u)
            .include(self.origin + self.edge_v)
            .include(self.origin + self.edge_u + self.edge_v)
    }
}

/// A triangle with normal `normalize((b − a) × (c − a))`; one-sided
/// triangles are hit only from the front, like one-sided quads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub v0: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
    pub normal: Vec3,
    pub one_sided: bool,
}

impl Triangle {
    /// `None` for a degenerate (zero-area) triangle.
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Option<Self> {
        let (e1, e2) = (b - a, c - a);
        let n = e1.cross(e2);
        let len = n.length();
        (len > 0.0 && len.is_finite()).then(|| Self {
            v0: a,
            e1,
            e2,
            normal: n / len,
            one_sided: false,
        })
    }

    /// A triangle hit only by rays meeting its front face.
    pub fn new_one_sided(a: Vec3, b: Vec3, c: Vec3) -> Option<Self> {
        Self::new(a, b, c).map(|t| Self {
            one_sided: true,
            ..t
        })
    }

    /// Area (m²): half the length of `e1 × e2`.
    pub fn area(&self) -> f32 {
        0.5 * self.e1.cross(self.e2).length()
    }

    /// A point uniformly distributed over the triangle's area (density
    /// `1/A`) from `u ∈ [0,1)²`, by the square-root warp
    /// `P = v0 + √u₁(1 − u₂)·e1 + √u₁·u₂·e2` (Shirley 1992; pbrt-v4
    /// §A.5.5 "Sampling a triangle" gives the same density).
    pub fn point(&self, u: glam::Vec2) -> Vec3 {
        let s = u.x.sqrt();
        self.v0 + self.e1 * (s * (1.0 - u.y)) + self.e2 * (s * u.y)
    }

    /// The barycentric weights `(b1, b2)` of the corners `v0 + e1` and
    /// `v0 + e2` at the point `p` of the triangle's plane (`v0` weighs
    /// `1 − b1 − b2`), from the normal equations of `p − v0 = b1·e1 + b2·e2`.
    pub fn barycentric(&self, p: Vec3) -> (f32, f32) {
        let d = p - self.v0;
        let (e11, e12, e22) = (
            self.e1.dot(self.e1),
            self.e1.dot(self.e2),
            self.e2.dot(self.e2),
        );
        let (d1, d2) = (d.dot(self.e1), d.dot(self.e2));
        let det = e11 * e22 - e12 * e12;
        ((e22 * d1 - e12 * d2) / det, (e11 * d2 - e12 * d1) / det)
    }

    /// The corners' weights `[b0, b1, b2]` at the point `p` of the
    /// triangle (corners `v0`, `v0 + e1`, `v0 + e2`), for interpolating
    /// per-corner values: [`Triangle::barycentric`] clamped to the
    /// triangle, against rounding at its edges.
    #[inline]
    pub fn corner_weights(&self, p: Vec3) -> [f32; 3] {
        let (b1, b2) = self.barycentric(p);
        let (b1, b2) = (b1.clamp(0.0, 1.0), b2.clamp(0.0, 1.0));
        [(1.0 - b1 - b2).max(0.0), b1, b2]
    }

    /// Texture coordinates at the point `p` of the triangle, interpolated
    /// from its corners' `uvs` (in the order of its corners) by
    /// [`Triangle::corner_weights`].
    #[inline]
    pub fn uv_at(&self, [t0, t1, t2]: [Vec2; 3], p: Vec3) -> Vec2 {
        let [b0, b1, b2] = self.corner_weights(p);
        t0 * b0 + t1 * b1 + t2 * b2
    }

    /// Möller–Trumbore ray/triangle intersection.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let p = ray.direction.cross(self.e2);
        // det = −direction·(e1 × e2): positive for a front-face hit.
        let det = self.e1.dot(p);
        if det == 0.0 || (self.one_sided && det < 0.0) {
            return None;
        }
        let inv = 1.0 / det;
        let s = ray.origin - self.v0;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = ray.direction.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        (t > T_MIN && t < t_max).then_some(t)
    }

    pub fn bounds(&self) -> Bounds {
        Bounds::new(self.v0, self.v0)
            .include(self.v0 + self.e1)
            .include(self.v0 + self.e2)
    }
}

/// The closed set of shapes; an enum so the BVH's leaf test is a `match`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Sphere(Sphere),
    Quad(Quad),
    Triangle(Triangle),
}

impl Shape {
    /// Distance to the first intersection in `(0, t_max)`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Quad(q) => q.intersect(ray, t_max),
            Shape::Triangle(t) => t.intersect(ray, t_max),
        }
    }

    /// Distance to the first intersection in `(0, t_max)` of a ray traced
    /// along the light's flow (from a light, as shadow maps are). A
    /// one-sided shape is seen from the side opposite to [`Shape::intersect`]'s:
    /// a ray from the light meets its back where the reverse ray, traced
    /// towards the light, meets its front. Both directions then find the
    /// same occluders between two points, so shadow maps agree with
    /// shadow rays.
    pub fn intersect_from_light(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        match self {
            // Flipping the normal flips only the culling: t does not depend
            // on its sign, and (u, v) come from `w`, which is unchanged.
            Shape::Quad(q) if q.one_sided => Quad {
                normal: -q.normal,
                ..*q
            }
            .intersect(ray, t_max),
            // Swapping the edges describes the same triangle with the
            // opposite winding, so the determinant's sign flips.
            Shape::Triangle(t) if t.one_sided => Triangle {
                e1: t.e2,
                e2: t.e1,
                normal: -t.normal,
                ..*t
            }
            .intersect(ray, t_max),
            _ => self.intersect(ray, t_max),
        }
    }

    /// Outward (sphere) or front-face (quad, triangle) unit normal at `p`.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Quad(q) => q.normal,
            Shape::Triangle(t) => t.normal,
        }
    }

    /// The same shape hit from both sides (spheres already are).
    pub fn two_sided(self) -> Shape {
        match self {
            Shape::Sphere(s) => Shape::Sphere(s),
            Shape::Quad(q) => Shape::Quad(Quad {
                one_sided: false,
                ..q
            }),
            Shape::Triangle(t) => Shape::Triangle(Triangle {
                one_sided: false,
                ..t
            }),
        }
    }

    pub fn bounds(&self) -> Bounds {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Quad(q) => q.bounds(),
            Shape::Triangle(t) => t.bounds(),
        }
    }
}

/// The six outward-facing, two-sided quads of an axis-aligned box; `None`
/// if the box is too thin for its faces to have an area in f32.
pub fn box_faces(b: Bounds) -> Option<[Quad; 6]> {
    let (lo, hi) = (b.min, b.max);
    let d = hi - lo;
    let (dx, dy, dz) = (Vec3::X * d.x, Vec3::Y * d.y, Vec3::Z * d.z);
    Some([
        Quad::new(lo, dz, dy, false)?,      // −x
        Quad::new(lo + dx, dy, dz, false)?, // +x
        Quad::new(lo, dx, dz, false)?,      // −y
        Quad::new(lo + dy, dz, dx, false)?, // +y
        Quad::new(lo, dy, dx, false)?,      // −z
        Quad::new(lo + dz, dx, dy, false)?, // +z
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_hit_from_outside_and_inside() {
        let s = Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
        assert!((s.intersect(&r, f32::INFINITY).unwrap() - 4.0).abs() < 1e-5);
        let inside = Ray::new(Vec3::ZERO, Vec3::X);
        assert!((s.intersect(&inside, f32::INFINITY).unwrap() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn one_sided_quad_is_invisible_from_behind() {
        let q = Quad::new(
            Vec3::new(-1.0, -1.0, 0.0),
            2.0 * Vec3::X,
            2.0 * Vec3::Y,
            true,
        )
        .unwrap();
        assert_eq!(q.normal, Vec3::Z);
        let front = Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z);
        let back = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z);
        assert!(q.intersect(&front, f32::INFINITY).is_some());
        assert!(q.intersect(&back, f32::INFINITY).is_none());
        let two_sided = Quad::new(q.origin, q.edge_u, q.edge_v, false).unwrap();
        assert!(two_sided.intersect(&back, f32::INFINITY).is_some());
    }

    /// A ray from the light sees a one-sided quad or triangle exactly when
    /// the reverse ray, towards the light, does.
    #[test]
    fn rays_from_light_see_the_reverse_side() {
        let quad = Shape::Quad(
            Quad::new(
                Vec3::new(-1.0, -1.0, 0.0),
                2.0 * Vec3::X,
                2.0 * Vec3::Y,
                true,
            )
            .unwrap(),
        );
        let triangle = Shape::Triangle(
            Triangle::new_one_sided(
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(2.0, -1.0, 0.0),
                Vec3::new(-1.0, 2.0, 0.0),
            )
            .unwrap(),
        );
        for shape in [quad, triangle] {
            for (a, b) in [
                (Vec3::new(0.1, 0.2, 1.0), Vec3::new(0.1, 0.2, -1.0)),
                (Vec3::new(0.1, 0.2, -1.0), Vec3::new(0.3, 0.0, 2.0)),
            ] {
                let towards = Ray::new(a, (b - a).normalize());
                let from = Ray::new(b, (a - b).normalize());
                let d = (b - a).length();
                let seen_towards = shape.intersect(&towards, d).is_some();
                let seen_from = shape.intersect_from_light(&from, d).is_some();
                assert_eq!(seen_towards, seen_from, "{shape:?} {a} {b}");
                if let (Some(t0), Some(t1)) = (
                    shape.intersect(&towards, d),
                    shape.intersect_from_light(&from, d),
                ) {
                    assert!((t0 + t1 - d).abs() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn box_faces_point_outward() {
        let b = Bounds::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        for f in box_faces(b).unwrap() {
            let out = f.centroid() - b.center();
            assert!(f.normal.dot(out) > 0.0, "{f:?}");
        }
    }

    #[test]
    fn triangle_hit() {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y).unwrap();
        let r = Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z);
        assert!((t.intersect(&r, 10.0).unwrap() - 1.0).abs() < 1e-6);
        let miss = Ray::new(Vec3::new(0.8, 0.8, 1.0), -Vec3::Z);
        assert!(t.intersect(&miss, 10.0).is_none());
    }

    #[test]
    fn bounds_clip() {
        let b = Bounds::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
        let (a, c) = b.clip_ray(&r, 0.0, f32::INFINITY).unwrap();
        assert!((a - 4.0).abs() < 1e-6 && (c - 6.0).abs() < 1e-6);
        assert!(b.clip_ray(&r, 0.0, 3.0).is_none());
    }
}
