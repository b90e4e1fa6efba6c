//! Emissive triangle meshes as area lights: one light per emissive mesh,
//! which picks one of its triangles in proportion to its area and then a
//! point of that triangle uniformly by area; an emission texture scales
//! the radiance point by point.

use super::{Incident, LightPoint, towards};
use crate::color::Rgb;
use crate::footprint::Footprint;
use crate::shapes::Triangle;
use crate::texture::Texture;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

/// A colour texture over a mesh light (glTF's `emissiveTexture`): its
/// colour at a point (sRGB-decoded, bilinear) multiplies the mesh's
/// radiance there. The coordinates are one per corner of each of the
/// mesh's triangles, in its triangles' order, interpolated across each.
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionTexture {
    pub texture: Arc<Texture>,
    pub uvs: Vec<[Vec2; 3]>,
}

/// A triangle mesh of radiance `radiance` (W·sr⁻¹·m⁻²), times its
/// emission texture's colour where it has one, emitting from the front of
/// each triangle (the side its normal faces; both sides if `two_sided`).
/// Its triangles are also in the scene, so they are seen and occlude.
///
/// **Light selection.** Next event estimation must not visit every
/// triangle of a mesh of thousands. Every triangle has the same radiance,
/// so a triangle's power is proportional to its area: the mesh picks
/// triangle k with probability `A_k/A` (a cumulative table, binary
/// search) and a point uniform on it (density `1/A_k`), so the emitting
/// point is uniform over the whole surface with density `1/A` whichever
/// triangle it lies on — pbrt-v4's power light sampler restricted to one
/// mesh, whose density needs no triangle index to evaluate (pbrt-v4
/// §12.6.3, "Power Light Sampler"; Shirley, Wang & Zimmerman 1996,
/// "Monte Carlo techniques for direct lighting calculations"). With an
/// emission texture the choice stays uniform in area, so its density is
/// unchanged and the texture's colour at the chosen point weighs it: the
/// estimate stays unbiased wherever the texture glows, and spends samples
/// on its dark parts too.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshLight {
    triangles: Vec<Triangle>,
    /// `cdf[k]`: the summed areas of triangles `0..=k` over the total.
    cdf: Vec<f64>,
    area: f32,
    pub radiance: Rgb,
    pub two_sided: bool,
    texture: Option<EmissionTexture>,
}

impl MeshLight {
    /// The emitter made of `triangles`; `None` if they have no area.
    pub fn new(triangles: Vec<Triangle>, radiance: Rgb, two_sided: bool) -> Option<Self> {
        let mut cdf = Vec::with_capacity(triangles.len());
        let mut sum = 0.0f64;
        for triangle in &triangles {
            sum += f64::from(triangle.area());
            cdf.push(sum);
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return None;
        }
        for c in &mut cdf {
            *c /= sum;
        }
        Some(Self {
            triangles,
            cdf,
            area: sum as f32,
            radiance,
            two_sided,
            texture: None,
        })
    }

    /// The mesh with its radiance scaled by `texture` (whose coordinates
    /// are one set per triangle: `texture.uvs.len()` must be the
    /// triangles' count, as the scene description's validation ensures).
    pub fn with_texture(self, texture: EmissionTexture) -> Self {
        debug_assert_eq!(texture.uvs.len(), self.triangles.len());
        Self {
            texture: Some(texture),
            ..self
        }
    }

    /// The emission texture, if the radiance varies over the mesh.
    pub fn emission_texture(&self) -> Option<&EmissionTexture> {
        self.texture.as_ref()
    }

    /// The radiance leaving the point `p` of triangle `k`: `radiance`
    /// times the emission texture's colour there, if it has one (at full
    /// resolution: what light sampling finds).
    #[inline]
    pub fn radiance_at(&self, k: usize, p: Vec3) -> Rgb {
        self.radiance_over(k, p, Footprint::POINT)
    }

    /// [`MeshLight::radiance_at`] with the texture filtered over
    /// `footprint` (a camera ray's, [`crate::footprint`]).
    #[inline]
    pub fn radiance_over(&self, k: usize, p: Vec3, footprint: Footprint) -> Rgb {
        match &self.texture {
            Some(t) => {
                let triangle = &self.triangles[k];
                let size = (t.texture.width(), t.texture.height());
                let lod = footprint.level_of_detail(size, triangle, t.uvs[k]);
                self.radiance * t.texture.lookup_lod(triangle.uv_at(t.uvs[k], p), lod)
            }
            None => self.radiance,
        }
    }

    /// Total emitting area (m²), one side.
    pub fn area(&self) -> f32 {
        self.area
    }

    /// The triangles that emit.
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// The cumulative selection table: entry `k` is the summed areas of
    /// triangles `0..=k` over the total (the last is 1), so triangle `k`
    /// is picked with probability `cdf[k] − cdf[k−1]`.
    pub fn selection_cdf(&self) -> &[f64] {
        &self.cdf
    }

    /// A point uniform over the mesh's surface (density `1/A`) from
    /// `u ∈ [0,1)²`: `u.x` picks the triangle through the cumulative
    /// table and, rescaled within the triangle's share, places the point
    /// on it with `u.y`.
    pub fn sample_point(&self, u: Vec2) -> LightPoint {
        let x = f64::from(u.x);
        let k = self
            .cdf
            .partition_point(|&c| c <= x)
            .min(self.triangles.len() - 1);
        let low = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        let share = self.cdf[k] - low;
        let within = if share > 0.0 {
            (((x - low) / share) as f32).clamp(0.0, crate::sampler::ONE_MINUS_EPSILON)
        } else {
            0.5
        };
        let triangle = &self.triangles[k];
        let position = triangle.point(Vec2::new(within, u.y));
        LightPoint {
            position,
            normal: Some(triangle.normal),
            radiance: self
                .texture
                .is_some()
                .then(|| self.radiance_at(k, position)),
        }
    }

    /// Light reaching `x` from the mesh's point `y` (from
    /// [`MeshLight::sample_point`], which gives a textured mesh's point
    /// its radiance): `L·cos θ_y·A/d²`, the radiance over the point's
    /// density in solid angle; `None` behind a one-sided emitter.
    pub fn incident(&self, x: Vec3, y: LightPoint) -> Option<Incident> {
        let radiance = y.radiance.unwrap_or(self.radiance);
        let normal = y.normal?;
        let (direction, d2) = towards(x, y.position)?;
        let cos_y = -direction.dot(normal);
        let cos_y = if self.two_sided { cos_y.abs() } else { cos_y };
        (cos_y > 0.0).then(|| Incident {
            direction,
            distance: d2.sqrt(),
            irradiance: radiance * (cos_y * self.area / d2),
            light_normal: Some(normal),
        })
    }

    /// Light reaching `x` from a point of the mesh chosen for it (a
    /// triangle by its share of the area, then a point uniform on it,
    /// from `u ∈ [0,1)²`), with the choice's solid-angle density.
    #[inline]
    pub(super) fn sample_incident(&self, x: Vec3, u: Vec2) -> Option<(Incident, f32)> {
        let y = self.sample_point(u);
        let incident = self.incident(x, y)?;
        let pdf = self.pdf(x, y, incident.direction);
        Some((incident, pdf))
    }

    /// Total emitted power, `L·π·A` per emitting side; with an emission
    /// texture `L` is scaled by the texture's mean colour over its image
    /// (the part the mesh's coordinates cover may differ: the power only
    /// weighs this light among others, which any positive weight keeps
    /// unbiased).
    pub(super) fn power(&self) -> Rgb {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        let scale = self.texture.as_ref().map_or(Rgb::ONE, |t| t.texture.mean());
        self.radiance * scale * (PI * self.area() * sides)
    }

    /// Density per unit solid angle, seen from `x`, of the point `y`
    /// (with its triangle's normal) reached in the unit `direction`:
    /// `d²/(A·|cos θ_y|)`.
    pub fn pdf(&self, x: Vec3, y: LightPoint, direction: Vec3) -> f32 {
        let Some(normal) = y.normal else {
            return 0.0;
        };
        let cos = normal.dot(direction).abs();
        let d2 = (y.position - x).length_squared();
        if cos > 0.0 {
            d2 / (self.area * cos)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::Light;
    use std::f64::consts::PI;

    /// A pyramid of four triangles of different sizes over a square
    /// hole: a non-planar mesh whose triangles face the origin, below it.
    fn pyramid(two_sided: bool) -> MeshLight {
        let apex = Vec3::new(0.3, 2.5, -0.2);
        let base = [
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.5, 1.0, -1.0),
            Vec3::new(1.6, 1.05, -0.7),
            Vec3::new(-0.7, 0.9, 1.1),
        ];
        let triangles = (0..4)
            .map(|i| {
                let (a, b) = (base[i], base[(i + 1) % 4]);
                // Wound so that the normal faces down, towards the origin.
                let t = Triangle::new(a, apex, b).unwrap();
                if t.normal.y < 0.0 {
                    t
                } else {
                    Triangle::new(b, apex, a).unwrap()
                }
            })
            .collect();
        MeshLight::new(triangles, Rgb::new(1.0, 2.0, 0.5), two_sided).unwrap()
    }

    /// Whether `p` lies on `t`, by its barycentric coordinates.
    fn on_triangle(t: &Triangle, p: Vec3) -> bool {
        let d = p - t.v0;
        if d.dot(t.normal).abs() > 1e-4 {
            return false;
        }
        let (e11, e12, e22) = (t.e1.dot(t.e1), t.e1.dot(t.e2), t.e2.dot(t.e2));
        let (d1, d2) = (d.dot(t.e1), d.dot(t.e2));
        let det = e11 * e22 - e12 * e12;
        let b1 = (e22 * d1 - e12 * d2) / det;
        let b2 = (e11 * d2 - e12 * d1) / det;
        b1 >= -1e-4 && b2 >= -1e-4 && b1 + b2 <= 1.0 + 1e-4
    }

    /// Irradiance at `x` (normal `n`) from a uniformly emitting polygon
    /// of radiance 1 seen from its emitting side, by Lambert's closed
    /// form: `E = ½ Σ_edges γ_i (n · (r_i × r_{i+1})/|r_i × r_{i+1}|)`,
    /// with `r_i` the unit directions to the vertices and `γ_i` the angle
    /// between consecutive ones (Arvo 1995, "Applications of irradiance
    /// tensors to the simulation of non-Lambertian phenomena", eq. 1).
    fn polygon_irradiance(x: Vec3, n: Vec3, vertices: &[Vec3]) -> f64 {
        let mut sum = 0.0f64;
        for i in 0..vertices.len() {
            let a = (vertices[i] - x).normalize().as_dvec3();
            let b = (vertices[(i + 1) % vertices.len()] - x)
                .normalize()
                .as_dvec3();
            let gamma = a.dot(b).clamp(-1.0, 1.0).acos();
            let cross = a.cross(b).normalize();
            sum += gamma * cross.dot(n.as_dvec3());
        }
        0.5 * sum.abs()
    }

    /// NEE from the mesh estimates the closed-form irradiance of every
    /// triangle summed, at receivers facing the mesh; the tolerance is
    /// five standard errors of the estimate, measured from its samples.
    #[test]
    fn irradiance_matches_lamberts_polygon_formula() {
        let mesh = pyramid(false);
        let light = Light::Mesh(mesh.clone());
        for (x, n) in [
            (Vec3::ZERO, Vec3::Y),
            (
                Vec3::new(0.5, -0.5, 0.3),
                Vec3::new(0.2, 1.0, -0.1).normalize(),
            ),
        ] {
            for t in mesh.triangles() {
                assert!((x - t.v0).dot(t.normal) > 0.0, "every triangle faces {x}");
            }
            let exact: f64 = mesh
                .triangles()
                .iter()
                .map(|t| polygon_irradiance(x, n, &[t.v0, t.v0 + t.e1, t.v0 + t.e2]))
                .sum();
            let k = 256usize;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for i in 0..k {
                for j in 0..k {
                    let u = Vec2::new(
                        (i as f32 + 0.5) / k as f32,
                        ((j * 7 + i * 3) % k) as f32 / k as f32 + 0.5 / k as f32,
                    );
                    let e = light.sample_li(x, u).map_or(0.0, |(incident, _)| {
                        f64::from(incident.irradiance.y / 2.0)
                            * f64::from(incident.direction.dot(n).max(0.0))
                    });
                    sum += e;
                    sum2 += e * e;
                }
            }
            let count = (k * k) as f64;
            let mean = sum / count;
            let std_error = ((sum2 / count - mean * mean) / count).sqrt();
            assert!(
                (mean - exact).abs() < 5.0 * std_error + 1e-6 * exact,
                "{x}: {mean} vs {exact} (σ {std_error})"
            );
            assert!(exact > 0.01 && exact < PI);
        }
    }

    /// The sampled point's density, recovered from its irradiance
    /// (`E = L/p_Ω` for area sampling), is the density `pdf_li` gives for
    /// the same point; and every triangle is chosen in proportion to its
    /// area (a binomial bound of five standard deviations).
    #[test]
    fn density_agrees_with_sampling_and_selection_follows_area() {
        let mesh = pyramid(true);
        let light = Light::Mesh(mesh.clone());
        let x = Vec3::new(0.2, -0.3, 0.1);
        let n = 4096usize;
        let mut chosen = [0usize; 4];
        for i in 0..n {
            let u = Vec2::new(
                (i as f32 + 0.5) / n as f32,
                ((i * 37) % n) as f32 / n as f32,
            );
            let point = mesh.sample_point(u);
            let k = mesh
                .triangles()
                .iter()
                .position(|t| Some(t.normal) == point.normal && on_triangle(t, point.position))
                .expect("the point lies on its own triangle");
            chosen[k] += 1;
            let (incident, pdf) = light.sample_li(x, u).unwrap();
            let pdf = pdf.unwrap();
            let from_point = light.pdf_li(x, point, incident.direction);
            assert!(
                (pdf - from_point).abs() <= 1e-4 * pdf,
                "{pdf} vs {from_point}"
            );
            let recovered = mesh.radiance.y / incident.irradiance.y;
            assert!((recovered - pdf).abs() <= 1e-4 * pdf);
        }
        for (k, t) in mesh.triangles().iter().enumerate() {
            let p = f64::from(t.area() / mesh.area());
            let expected = p * n as f64;
            let sigma = (n as f64 * p * (1.0 - p)).sqrt();
            assert!(
                (chosen[k] as f64 - expected).abs() < 5.0 * sigma,
                "triangle {k}: {} vs {expected}",
                chosen[k]
            );
        }
    }

    /// Power is `L·π·A` per emitting side, `A` the summed triangle areas
    /// (each computed here from its vertices).
    #[test]
    fn power_counts_every_triangle_and_side() {
        let one = pyramid(false);
        let area: f32 = one
            .triangles()
            .iter()
            .map(|t| 0.5 * t.e1.cross(t.e2).length())
            .sum();
        let power = Light::Mesh(one).power(1.0);
        assert!((power.x - std::f32::consts::PI * area).abs() < 1e-5 * power.x);
        let both = Light::Mesh(pyramid(true)).power(1.0);
        assert!((both.x - 2.0 * power.x).abs() < 1e-5 * power.x);
    }

    /// A 2 × 2 square at height 1 facing down, of radiance 1 times a
    /// two-texel texture, white then black along x (clamped): bilinear
    /// between the texel centres, so the emission is 1 for u ≤ ¼, 0 for
    /// u ≥ ¾ and linear between, with u = (x + 1)/2.
    fn ramped_square() -> MeshLight {
        use crate::texture::Wrap;
        let corners = [
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(-1.0, 1.0, 1.0),
        ];
        let triangles: Vec<Triangle> = [[0, 1, 2], [0, 2, 3]]
            .into_iter()
            .map(|[a, b, c]| {
                let t = Triangle::new(corners[a], corners[b], corners[c]).unwrap();
                if t.normal.y < 0.0 {
                    t
                } else {
                    Triangle::new(corners[a], corners[c], corners[b]).unwrap()
                }
            })
            .collect();
        let uv = |p: Vec3| Vec2::new((p.x + 1.0) / 2.0, 0.5);
        let uvs = triangles
            .iter()
            .map(|t| [t.v0, t.v0 + t.e1, t.v0 + t.e2].map(uv))
            .collect();
        let ramp = Texture::new(2, 1, vec![[255; 3], [0; 3]], [Wrap::Clamp; 2]).unwrap();
        MeshLight::new(triangles, Rgb::ONE, false)
            .unwrap()
            .with_texture(EmissionTexture {
                texture: Arc::new(ramp),
                uvs,
            })
    }

    /// The ramp's emission at x, written here from the texel centres.
    fn ramp(x: f64) -> f64 {
        let u = (x + 1.0) / 2.0;
        ((0.75 - u) / 0.5).clamp(0.0, 1.0)
    }

    /// Irradiance at `x` (normal up) from the ramped square, by midpoint
    /// quadrature over an `n × n` grid of its surface.
    fn ramped_irradiance(x: Vec3, n: usize) -> f64 {
        let x = x.as_dvec3();
        let h = 2.0 / n as f64;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let y = glam::DVec3::new(
                    -1.0 + (i as f64 + 0.5) * h,
                    1.0,
                    -1.0 + (j as f64 + 0.5) * h,
                );
                let d = y - x;
                let d2 = d.length_squared();
                // cos at the receiver (normal +y) and at the emitter
                // (normal −y) are both d.y/|d|.
                sum += ramp(y.x) * (d.y * d.y / d2) / d2 * h * h;
            }
        }
        sum
    }

    /// NEE from a textured mesh weighs each point by the texture where it
    /// lies: beneath the square's centre, where the ramp's two halves are
    /// symmetric about ½, the irradiance is half that of the uniform
    /// square (Lambert's formula); off centre it is the quadrature above
    /// (its error bounded by its change from n to 2n). The texture's mean
    /// halves the power. Tolerances: five standard errors of the estimate.
    #[test]
    fn textured_irradiance_matches_quadrature() {
        let mesh = ramped_square();
        let light = Light::Mesh(mesh.clone());
        let square = [
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(-1.0, 1.0, 1.0),
        ];
        let centre = 0.5 * polygon_irradiance(Vec3::ZERO, Vec3::Y, &square);
        assert!((ramped_irradiance(Vec3::ZERO, 400) - centre).abs() < 1e-3 * centre);
        let off = Vec3::new(0.6, 0.0, 0.2);
        let (coarse, fine) = (ramped_irradiance(off, 200), ramped_irradiance(off, 400));
        for (x, exact, quadrature_error) in [
            (Vec3::ZERO, centre, 0.0),
            (off, fine, (fine - coarse).abs()),
        ] {
            let k = 256usize;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for i in 0..k {
                for j in 0..k {
                    let u = Vec2::new(
                        (i as f32 + 0.5) / k as f32,
                        ((j * 7 + i * 3) % k) as f32 / k as f32 + 0.5 / k as f32,
                    );
                    let e = light.sample_li(x, u).map_or(0.0, |(incident, _)| {
                        f64::from(incident.irradiance.x) * f64::from(incident.direction.y.max(0.0))
                    });
                    sum += e;
                    sum2 += e * e;
                }
            }
            let count = (k * k) as f64;
            let mean = sum / count;
            let std_error = ((sum2 / count - mean * mean) / count).sqrt();
            assert!(
                (mean - exact).abs() < 5.0 * std_error + quadrature_error + 1e-6,
                "{x}: {mean} vs {exact} (σ {std_error})"
            );
        }
        let uniform = MeshLight::new(mesh.triangles().to_vec(), Rgb::ONE, false).unwrap();
        let (textured, plain) = (
            Light::Mesh(mesh).power(1.0),
            Light::Mesh(uniform).power(1.0),
        );
        assert!((textured.x - 0.5 * plain.x).abs() < 1e-6 * plain.x);
    }
}
