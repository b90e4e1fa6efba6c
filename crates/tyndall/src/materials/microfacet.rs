//! The glossy layers' lobe: the GGX (Trowbridge–Reitz) microfacet
//! distribution of roughness α (Walter et al. 2007, "Microfacet Models
//! for Refraction through Rough Surfaces"), with the height-correlated
//! Smith masking-shadowing term (Heitz 2014, "Understanding the
//! Masking-Shadowing Function in Microfacet-Based BRDFs"), sampled by its
//! visible normals drawn from spherical caps (Dupuy & Benyoub 2023,
//! "Sampling Visible GGX Normals with Spherical Caps"). The energy single
//! scattering between microfacets loses is restored by albedo scaling
//! (Turquin 2019, "Practical multiple scattering compensation for
//! microfacet models"), as Cycles' multiscatter GGX does since 4.0: a
//! layer of reflectance F reflects `F·(1 + F·(1 − E)/E)` times the
//! single-scattering lobe, E its directional albedo (F = 1) towards the
//! viewer, so a white layer reflects all it receives.
//!
//! Vectors are world-space and unit; `outgoing` points from the surface
//! towards the viewer, `incident` towards the light, `normal` to their
//! side.

use crate::color::Rgb;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Cosines of the viewing angle at which the directional albedo is
/// tabulated: `(k + 1)/ALBEDO_COSINES`, k = 0 … 15 (1/16 to 1).
pub const ALBEDO_COSINES: usize = 16;

/// Roughnesses at which it is tabulated: `j/(ALBEDO_ROUGHNESSES − 1)`.
pub const ALBEDO_ROUGHNESSES: usize = 32;

/// A GGX lobe of roughness `alpha` in (0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    alpha: f32,
}

impl Ggx {
    /// The lobe of roughness `alpha`; `None` for a mirror (α ≤ 0), whose
    /// lobe is a delta.
    #[inline]
    pub fn new(alpha: f32) -> Option<Self> {
        (alpha > 0.0).then(|| Self {
            alpha: alpha.min(1.0),
        })
    }

    /// The microfacet distribution at a microfacet normal of cosine
    /// `cos_h` to the surface normal:
    /// `α²/(π·(cos²θ_h·(α² − 1) + 1)²)`.
    #[inline]
    fn distribution(&self, cos_h: f32) -> f32 {
        let a2 = self.alpha * self.alpha;
        let d = cos_h * cos_h * (a2 - 1.0) + 1.0;
        a2 / (PI * d * d)
    }

    /// Smith's Λ for a direction of cosine `cos` (> 0) to the normal:
    /// `(√(1 + α²·tan²θ) − 1)/2`.
    #[inline]
    fn lambda(&self, cos: f32) -> f32 {
        let tan2 = (1.0 - cos * cos).max(0.0) / (cos * cos);
        0.5 * ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0)
    }

    /// A direction towards the light for light leaving towards
    /// `outgoing` at `normal`, for `u` ∈ [0, 1)²: a visible microfacet
    /// normal drawn from its spherical cap, and `outgoing` reflected
    /// about it; `None` where that falls below the surface.
    #[inline]
    pub fn sample(&self, outgoing: Vec3, normal: Vec3, u: Vec2) -> Option<Vec3> {
        let (t, b) = normal.any_orthonormal_pair();
        let o = Vec3::new(outgoing.dot(t), outgoing.dot(b), outgoing.dot(normal));
        // The view in the hemisphere configuration (α = 1).
        let o_std = Vec3::new(self.alpha * o.x, self.alpha * o.y, o.z).normalize();
        let phi = 2.0 * PI * u.x;
        let z = (1.0 - u.y) * (1.0 + o_std.z) - o_std.z;
        let sin_t = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
        let h_std = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), z) + o_std;
        let h = Vec3::new(self.alpha * h_std.x, self.alpha * h_std.y, h_std.z.max(0.0))
            .try_normalize()?;
        let h = t * h.x + b * h.y + normal * h.z;
        let incident = 2.0 * outgoing.dot(h) * h - outgoing;
        (incident.dot(normal) > 0.0).then_some(incident)
    }

    /// The single-scattering lobe's `f·cos θ_i` for a layer of
    /// reflectance 1: `D(h)·G₂/(4·cos θ_o)`, h the half vector; 0 where
    /// either direction is below the surface.
    #[inline]
    pub fn eval(&self, outgoing: Vec3, normal: Vec3, incident: Vec3) -> f32 {
        let Some((cos_o, cos_i, cos_h)) = pair_cosines(outgoing, normal, incident) else {
            return 0.0;
        };
        let g2 = 1.0 / (1.0 + self.lambda(cos_o) + self.lambda(cos_i));
        self.distribution(cos_h) * g2 / (4.0 * cos_o)
    }

    /// The solid-angle density with which [`Ggx::sample`] draws
    /// `incident`: `G₁(o)·D(h)/(4·cos θ_o)`.
    #[inline]
    pub fn pdf(&self, outgoing: Vec3, normal: Vec3, incident: Vec3) -> f32 {
        let Some((cos_o, _, cos_h)) = pair_cosines(outgoing, normal, incident) else {
            return 0.0;
        };
        let g1 = 1.0 / (1.0 + self.lambda(cos_o));
        g1 * self.distribution(cos_h) / (4.0 * cos_o)
    }

    /// A sample's weight for a layer of reflectance 1, `f·cos/pdf` =
    /// `G₂/G₁(o)` = `(1 + Λ(o))/(1 + Λ(o) + Λ(i))`.
    #[inline]
    pub fn weight(&self, outgoing: Vec3, normal: Vec3, incident: Vec3) -> f32 {
        let lo = self.lambda(outgoing.dot(normal).max(1e-7));
        let li = self.lambda(incident.dot(normal).max(1e-7));
        (1.0 + lo) / (1.0 + lo + li)
    }

    /// The single-scattering lobe's directional albedo `E(cos θ_o)` for a
    /// layer of reflectance 1, from the tabulated rows
    /// ([`albedo_row_at`]): bilinear in the cosine (held at the first and
    /// last node beyond them) and the roughness.
    #[inline]
    pub fn albedo(&self, cos_o: f32) -> f32 {
        let (j, fj) = self.roughness_node();
        let row = |j: usize| albedo_in_row(albedo_row_at(j), cos_o);
        row(j) * (1.0 - fj) + row(j + 1) * fj
    }

    /// The roughness node below this lobe's α and the fraction of the way
    /// to the next.
    #[inline]
    fn roughness_node(&self) -> (usize, f32) {
        let x = (self.alpha * (ALBEDO_ROUGHNESSES - 1) as f32)
            .clamp(0.0, (ALBEDO_ROUGHNESSES - 1) as f32);
        let j = (x as usize).min(ALBEDO_ROUGHNESSES - 2);
        (j, x - j as f32)
    }

    /// The single-scattering albedo at this roughness at each tabulated
    /// cosine (interpolated between the roughness nodes as
    /// [`Ggx::albedo`] does), for renderers that interpolate in the
    /// cosine alone (the GPU's materials).
    pub fn albedo_row(&self) -> [f32; ALBEDO_COSINES] {
        let (j, fj) = self.roughness_node();
        let (a, b) = (albedo_row_at(j), albedo_row_at(j + 1));
        std::array::from_fn(|k| a[k] * (1.0 - fj) + b[k] * fj)
    }
}

/// The cosines to `normal` of `outgoing`, `incident` and their half
/// vector; `None` where either direction is below the surface (or they
/// are opposite).
#[inline]
fn pair_cosines(outgoing: Vec3, normal: Vec3, incident: Vec3) -> Option<(f32, f32, f32)> {
    let (cos_o, cos_i) = (outgoing.dot(normal), incident.dot(normal));
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return None;
    }
    let h = (outgoing + incident).try_normalize()?;
    Some((cos_o, cos_i, h.dot(normal)))
}

/// `row` (the albedo at the tabulated cosines) linearly interpolated at
/// `cos`, held at the first and last node beyond them.
#[inline]
pub fn albedo_in_row(row: &[f32; ALBEDO_COSINES], cos: f32) -> f32 {
    let x = (cos * ALBEDO_COSINES as f32 - 1.0).clamp(0.0, (ALBEDO_COSINES - 1) as f32);
    let k = (x as usize).min(ALBEDO_COSINES - 2);
    let fk = x - k as f32;
    row[k] * (1.0 - fk) + row[k + 1] * fk
}

/// The reflectance a layer of normal-incidence reflectance `f` has with
/// its multiple scattering restored, where its single-scattering lobe's
/// albedo is `e`: `f·(1 + f·(1 − e)/e)` per channel (Turquin 2019): a
/// white layer (f = 1) reflects `1/e` times its single-scattering lobe,
/// all the light it receives.
#[inline]
pub fn compensated(f: Rgb, e: f32) -> Rgb {
    f * (Rgb::ONE + f * ((1.0 - e) / e))
}

/// The directional albedo `E(cos θ_o, α)` of the single-scattering GGX
/// lobe of reflectance 1 at roughness node `j` (α = j/31), at each cosine
/// node ((k + 1)/16): each the mean sample weight `G₂/G₁` over a 16 × 512
/// midpoint grid of [`Ggx::sample`]'s numbers (0 where the direction
/// falls below the surface, a cut across the second number, which the
/// grid resolves to 1/1024) — the estimator of ∫f·cos dω with the lobe's
/// own sampling. Each row is computed once, on first use (a few
/// milliseconds: a scene of one roughness needs two rows).
pub fn albedo_row_at(j: usize) -> &'static [f32; ALBEDO_COSINES] {
    static ROWS: [OnceLock<[f32; ALBEDO_COSINES]>; ALBEDO_ROUGHNESSES] =
        [const { OnceLock::new() }; ALBEDO_ROUGHNESSES];
    ROWS[j].get_or_init(|| {
        let alpha = j as f32 / (ALBEDO_ROUGHNESSES - 1) as f32;
        std::array::from_fn(|k| match Ggx::new(alpha) {
            None => 1.0,
            Some(lobe) => {
                let cos = (k as f32 + 1.0) / ALBEDO_COSINES as f32;
                let outgoing = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                // The weight is smooth in u but for the cut at the
                // horizon, across u.y: fine in u.y, coarse in φ.
                const NX: usize = 16;
                const NY: usize = 512;
                let mut sum = 0.0f64;
                for a in 0..NX {
                    for c in 0..NY {
                        let u =
                            Vec2::new((a as f32 + 0.5) / NX as f32, (c as f32 + 0.5) / NY as f32);
                        if let Some(incident) = lobe.sample(outgoing, Vec3::Z, u) {
                            sum += f64::from(lobe.weight(outgoing, Vec3::Z, incident));
                        }
                    }
                }
                (sum / (NX * NY) as f64) as f32
            }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::r2_point;

    /// The lobe's sampling and density agree, and its value is its
    /// density times its weight: for several roughnesses and views, 16384
    /// draws of a low-discrepancy sequence fall into each of 8 rings of
    /// polar angle about the normal as a midpoint quadrature of `pdf`
    /// over the ring says (within 5σ of the binomial plus the
    /// quadrature's error), `pdf` integrates over the hemisphere to the
    /// share of draws above the surface, and `eval = pdf·weight`.
    #[test]
    fn sample_pdf_and_eval_agree() {
        for alpha in [0.1f32, 0.4, 1.0] {
            let lobe = Ggx::new(alpha).unwrap();
            for view in [0.0f32, 50.0, 80.0] {
                let t = view.to_radians();
                let outgoing = Vec3::new(t.sin(), 0.0, t.cos());
                // The R₂ sequence (Roberts 2018): a grid's rows would
                // fall together on the lobe's long tail.
                let n = 128;
                let mut rings = [0u32; 8];
                let mut drawn = 0u32;
                for i in 0..n * n {
                    let u = r2_point(i);
                    if let Some(d) = lobe.sample(outgoing, Vec3::Z, u) {
                        drawn += 1;
                        rings[((d.z * 8.0) as usize).min(7)] += 1;
                        let (pdf, w) = (
                            lobe.pdf(outgoing, Vec3::Z, d),
                            lobe.weight(outgoing, Vec3::Z, d),
                        );
                        let eval = lobe.eval(outgoing, Vec3::Z, d);
                        assert!(
                            (eval - pdf * w).abs() <= 1e-4 * eval.max(1.0),
                            "α {alpha}, view {view}°: eval {eval} vs {pdf}·{w}"
                        );
                    }
                }
                // ∫ pdf over each ring of cos θ ∈ [r/8, (r + 1)/8).
                let (m, p) = (256, 256);
                let mut total = 0.0f64;
                for (r, &count) in rings.iter().enumerate() {
                    let mut ring = 0.0f64;
                    for a in 0..m {
                        let cos = (r as f64 + (a as f64 + 0.5) / m as f64) / 8.0;
                        let sin = (1.0 - cos * cos).sqrt();
                        for b in 0..p {
                            let phi = 2.0 * std::f64::consts::PI * (b as f64 + 0.5) / p as f64;
                            let d = Vec3::new(
                                (sin * phi.cos()) as f32,
                                (sin * phi.sin()) as f32,
                                cos as f32,
                            );
                            ring += f64::from(lobe.pdf(outgoing, Vec3::Z, d));
                        }
                    }
                    ring *= (1.0 / 8.0 / m as f64) * (2.0 * std::f64::consts::PI / p as f64);
                    total += ring;
                    let expected = ring * (n * n) as f64;
                    let sigma = (expected * (1.0 - ring)).max(1.0).sqrt();
                    assert!(
                        (f64::from(count) - expected).abs() < 5.0 * sigma + 0.01 * expected,
                        "α {alpha}, view {view}°, ring {r}: {count} vs {expected:.1}"
                    );
                }
                let share = f64::from(drawn) / (n * n) as f64;
                assert!(
                    (total - share).abs() < 0.01,
                    "α {alpha}, view {view}°: {total} vs {share}"
                );
            }
        }
    }

    /// The albedo table: 1 for a mirror; a smooth lobe loses little seen
    /// head-on (α = 0.1: above 0.98), the roughest more than half; every
    /// entry in (0, 1]; the compensated reflectance of a white layer times
    /// the albedo is 1. (Its values against a quadrature of the lobe:
    /// `surface.rs`'s furnace test.)
    #[test]
    fn albedo_table_is_an_albedo() {
        assert!(albedo_row_at(0).iter().all(|&e| e == 1.0));
        for row in (0..ALBEDO_ROUGHNESSES).map(albedo_row_at) {
            assert!(row.iter().all(|&e| e > 0.0 && e <= 1.0 + 1e-3), "{row:?}");
        }
        let smooth = Ggx::new(0.1).unwrap();
        assert!(smooth.albedo(1.0) > 0.98, "{}", smooth.albedo(1.0));
        let rough = Ggx::new(1.0).unwrap();
        assert!(rough.albedo(1.0) < 0.5, "{}", rough.albedo(1.0));
        let e = rough.albedo(0.6);
        assert!(
            (compensated(Rgb::ONE, e) * e - Rgb::ONE)
                .abs()
                .max_element()
                < 1e-6
        );
        let row = rough.albedo_row();
        assert!((albedo_in_row(&row, 0.6) - e).abs() < 1e-6);
    }
}
