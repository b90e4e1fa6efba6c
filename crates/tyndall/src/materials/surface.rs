//! The opaque surface: a Lambertian lobe, a specular layer and an
//! optional clear coat, the choice between them, and each reflective
//! layer's lobe.

use super::microfacet::{Ggx, compensated};
use crate::color::{Rgb, luminance};
use crate::sampling::cosine_hemisphere;
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Lambertian diffuse reflectance `diffuse` (BRDF `diffuse/π`) plus a
/// specular layer of reflectance `specular`: a perfect mirror when
/// `roughness` (α) is 0, otherwise a glossy GGX lobe ([`Ggx`]); and over
/// both, optionally, a clear `coat`.
///
/// The reflective layers are followed by tracing one reflected ray (the
/// course code base's model, which the paper's scenes use): they reflect
/// what that ray sees (emitters, lit surfaces, fog); a glossy layer
/// reflects delta lights by next event estimation too
/// ([`Surface::glossy_toward`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub diffuse: Rgb,
    pub specular: Rgb,
    pub roughness: f32,
    pub coat: Coat,
}

/// A clear coat: a colourless dielectric layer over a surface (glTF's
/// `KHR_materials_clearcoat`, the Coat of Blender's Principled BSDF),
/// which reflects `reflectance` of the light at normal incidence — its
/// weight times the layer's `((n − 1)/(n + 1))²` — by a lobe of its own
/// `roughness` (α, as [`Surface::roughness`]: a mirror at 0), followed
/// as the specular layer is. What it does not reflect reaches the layers
/// beneath; whoever makes the surface scales them by `1 − reflectance`
/// ([`super::MetallicRoughness::surface`]), at normal incidence as the rest of
/// the model is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coat {
    pub reflectance: f32,
    pub roughness: f32,
}

impl Coat {
    /// No coat.
    pub const NONE: Self = Self {
        reflectance: 0.0,
        roughness: 0.0,
    };
}

impl Surface {
    /// A surface that reflects nothing.
    pub const BLACK: Self = Self {
        diffuse: Rgb::ZERO,
        specular: Rgb::ZERO,
        roughness: 0.0,
        coat: Coat::NONE,
    };

    /// A purely diffuse surface.
    pub fn diffuse(reflectance: Rgb) -> Self {
        Self {
            diffuse: reflectance,
            ..Self::BLACK
        }
    }

    /// A surface of Lambertian reflectance `diffuse` and a specular layer
    /// of reflectance `specular` and roughness `roughness`, uncoated.
    pub fn layered(diffuse: Rgb, specular: Rgb, roughness: f32) -> Self {
        Self {
            diffuse,
            specular,
            roughness,
            coat: Coat::NONE,
        }
    }

    /// Lambert BRDF value `ρ/π` (sr⁻¹).
    #[inline]
    pub fn diffuse_brdf(&self) -> Rgb {
        self.diffuse / PI
    }

    /// Whether a reflective layer (the specular layer or the coat)
    /// reflects any light.
    pub fn has_specular(&self) -> bool {
        self.specular.max_element() > 0.0 || self.coat.reflectance > 0.0
    }

    /// Whether the surface reflects any light (by any lobe).
    pub fn reflects(&self) -> bool {
        self.diffuse.max_element() > 0.0 || self.has_specular()
    }

    /// All the light the surface reflects at normal incidence, every
    /// layer's reflectance summed (the albedo a denoiser's guide holds).
    pub fn albedo(&self) -> Rgb {
        self.diffuse + self.specular + Rgb::splat(self.coat.reflectance)
    }

    /// Direction of the specular layer's reflected ray for a ray
    /// travelling along `incoming` ([`reflect_layer`]).
    pub fn reflect(&self, incoming: Vec3, normal: Vec3, u: Vec2) -> Option<Vec3> {
        reflect_layer((self.specular, self.roughness), incoming, normal, u).map(|(d, _)| d)
    }

    /// Continues a path by the reflective layers: the specular layer or
    /// the coat, chosen by `choice` with probability proportional to the
    /// luminance of each one's reflectance, its direction by
    /// [`reflect_layer`] from `u`. The weight is the chosen layer's
    /// ([`reflect_layer`]'s) over its probability, so that its expectation
    /// is the layers' sum. `None` if neither reflects or the direction falls
    /// below the surface. Without a coat the specular layer is chosen
    /// whatever `choice` is.
    #[inline]
    pub fn reflect_layers(
        &self,
        incoming: Vec3,
        normal: Vec3,
        choice: f32,
        u: Vec2,
    ) -> Option<SurfaceSample> {
        let specular = luminance(self.specular);
        let total = specular + self.coat.reflectance;
        if total <= 0.0 {
            return None;
        }
        let p_specular = specular / total;
        self.reflection_by(
            incoming,
            normal,
            (choice < p_specular).then_some(p_specular),
            (1.0 - p_specular, u),
        )
    }

    /// The reflected ray of the specular layer if `specular` holds the
    /// probability it was chosen with, else of the coat, chosen with
    /// probability `coat.0`; the weight is the layer's reflectance over
    /// its probability.
    #[inline]
    fn reflection_by(
        &self,
        incoming: Vec3,
        normal: Vec3,
        specular: Option<f32>,
        (p_coat, u): (f32, Vec2),
    ) -> Option<SurfaceSample> {
        let (layer, p, lobe) = match specular {
            Some(p) => ((self.specular, self.roughness), p, Lobe::Specular),
            None => (
                (Rgb::splat(self.coat.reflectance), self.coat.roughness),
                p_coat,
                Lobe::Coat,
            ),
        };
        let (direction, weight) = reflect_layer(layer, incoming, normal, u)?;
        Some(SurfaceSample {
            direction,
            weight: weight / p,
            pdf: 0.0,
            lobe,
        })
    }

    /// Whether a reflective layer is rough (glossy): the only kind whose
    /// light from a delta light can be evaluated ([`Surface::glossy_toward`]).
    #[inline]
    pub fn has_glossy_layer(&self) -> bool {
        (self.roughness > 0.0 && self.specular.max_element() > 0.0)
            || (self.coat.roughness > 0.0 && self.coat.reflectance > 0.0)
    }

    /// The glossy layers (specular, coat) as a point seen by a ray
    /// travelling along `incoming`, with unit `normal` facing it, sees
    /// them: their `f·cos θ` ([`GlossyLayer::eval`], summed), which next
    /// event estimation adds for delta lights, that the layers' reflected
    /// rays can never reach; other lights the reflected ray finds, so
    /// they are left to it. Mirrors (a delta lobe) are `None`.
    #[inline]
    pub fn glossy_toward(&self, incoming: Vec3, normal: Vec3) -> [Option<GlossyLayer>; 2] {
        let coat = (Rgb::splat(self.coat.reflectance), self.coat.roughness);
        [
            GlossyLayer::toward((self.specular, self.roughness), incoming, normal),
            GlossyLayer::toward(coat, incoming, normal),
        ]
    }

    /// The roughness of the layer `lobe` samples (0 for the Lambertian
    /// lobe, which is not a reflection).
    #[inline]
    pub fn roughness_of(&self, lobe: Lobe) -> f32 {
        match lobe {
            Lobe::Diffuse => 0.0,
            Lobe::Specular => self.roughness,
            Lobe::Coat => self.coat.roughness,
        }
    }
}

/// A reflective layer of reflectance `reflectance` and roughness
/// `roughness` (α) continuing a ray travelling along `incoming` at a
/// surface with unit `normal` facing it, for `u` ∈ [0, 1)²: the reflected
/// direction and its weight `f·cos θ/pdf`. At roughness 0 a mirror: the
/// mirror direction, weight `reflectance`. Otherwise a GGX lobe
/// ([`Ggx`]): a direction drawn from its visible normals, weight the
/// multiple-scattering-compensated reflectance ([`compensated`], at the
/// lobe's albedo towards the viewer) times `G₂/G₁`. `None` where the
/// drawn direction falls below the surface.
#[inline]
pub fn reflect_layer(
    (reflectance, roughness): (Rgb, f32),
    incoming: Vec3,
    normal: Vec3,
    u: Vec2,
) -> Option<(Vec3, Rgb)> {
    let Some(lobe) = Ggx::new(roughness) else {
        return Some((incoming - 2.0 * incoming.dot(normal) * normal, reflectance));
    };
    let outgoing = -incoming;
    let direction = lobe.sample(outgoing, normal, u)?;
    let f = compensated(reflectance, lobe.albedo(outgoing.dot(normal)));
    Some((direction, f * lobe.weight(outgoing, normal, direction)))
}

/// A glossy layer as a point seen by a ray travelling along `incoming`
/// sees it: its GGX lobe ([`reflect_layer`]'s) and its reflectance
/// compensated at the lobe's albedo towards that viewer — what every
/// light's evaluation at the point shares, made once.
#[derive(Clone, Copy, Debug)]
pub struct GlossyLayer {
    lobe: Ggx,
    reflectance: Rgb,
    outgoing: Vec3,
    normal: Vec3,
}

impl GlossyLayer {
    /// The layer `(reflectance, roughness)` at unit `normal` seen along
    /// `incoming`; `None` for a mirror, whose lobe is a delta.
    #[inline]
    pub fn toward(
        (reflectance, roughness): (Rgb, f32),
        incoming: Vec3,
        normal: Vec3,
    ) -> Option<Self> {
        let lobe = Ggx::new(roughness)?;
        let outgoing = -incoming;
        Some(Self {
            lobe,
            reflectance: compensated(reflectance, lobe.albedo(outgoing.dot(normal))),
            outgoing,
            normal,
        })
    }

    /// Its `f·cos θ` for light arriving from unit `omega`: the compensated
    /// reflectance times [`Ggx::eval`].
    #[inline]
    pub fn eval(&self, omega: Vec3) -> Rgb {
        self.reflectance * self.lobe.eval(self.outgoing, self.normal, omega)
    }
}

/// A glossy layer's `f·cos θ` for light arriving from unit `omega` at a
/// point seen by a ray travelling along `incoming` ([`GlossyLayer::eval`]);
/// 0 for a mirror.
#[inline]
pub fn layer_eval(layer: (Rgb, f32), incoming: Vec3, normal: Vec3, omega: Vec3) -> Rgb {
    GlossyLayer::toward(layer, incoming, normal).map_or(Rgb::ZERO, |l| l.eval(omega))
}

/// The lobe of a [`Surface`] a sampled direction came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// The Lambertian lobe, cosine-sampled: its direction can also be
    /// reached by light sampling, so its density takes part in MIS.
    Diffuse,
    /// The specular layer (mirror or glossy), followed by its one
    /// reflected ray: no other strategy produces it.
    Specular,
    /// The clear coat, followed as the specular layer is.
    Coat,
}

/// A direction drawn by [`Surface::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// Unit direction of the continuing ray.
    pub direction: Vec3,
    /// `f·cos θ / p` with the lobe's choice probability in `p`: `ρ/P_d`
    /// for the Lambertian lobe, a reflective layer's reflectance over its
    /// probability for that layer (whose lobe is sampled exactly).
    pub weight: Rgb,
    /// Solid-angle density of the direction for the Lambertian lobe,
    /// `P_d·cos θ/π` ([`Surface::pdf`]); not meaningful for the
    /// reflective layer.
    pub pdf: f32,
    pub lobe: Lobe,
}

impl Surface {
    /// The probabilities of continuing a path by the Lambertian lobe, the
    /// specular layer and the coat: proportional to the luminance of each
    /// one's reflectance. `None` if the surface reflects nothing.
    #[inline]
    fn lobe_probabilities(&self) -> Option<[f32; 3]> {
        let (diffuse, specular) = (luminance(self.diffuse), luminance(self.specular));
        let total = diffuse + specular + self.coat.reflectance;
        if total <= 0.0 {
            return None;
        }
        Some([diffuse, specular, self.coat.reflectance].map(|l| l / total))
    }

    /// The probability `P_d` of continuing a path by the Lambertian lobe
    /// rather than a reflective layer (see [`Surface::sample`]). `None` if
    /// the surface reflects nothing.
    #[inline]
    pub fn diffuse_probability(&self) -> Option<f32> {
        self.lobe_probabilities().map(|[p_diffuse, ..]| p_diffuse)
    }

    /// Continues a path that arrived along `incoming` at a point with unit
    /// normal `normal` (facing the path): the lobe — Lambertian, specular
    /// layer or coat — is chosen by `choice` with probability proportional
    /// to the luminance of its reflectance ([`Surface::diffuse_probability`]
    /// for the first), the direction from `u` (cosine-distributed, or by
    /// [`reflect_layer`] of the layer's roughness). `None` if the surface
    /// reflects nothing or the reflected direction falls below it.
    #[inline]
    pub fn sample(
        &self,
        incoming: Vec3,
        normal: Vec3,
        choice: f32,
        u: Vec2,
    ) -> Option<SurfaceSample> {
        let [p_diffuse, p_specular, p_coat] = self.lobe_probabilities()?;
        if choice < p_diffuse {
            let direction = cosine_hemisphere(normal, u);
            // f·cos/pdf = (ρ/π)·cos / (P_d·cos/π) = ρ/P_d.
            return Some(SurfaceSample {
                direction,
                weight: self.diffuse / p_diffuse,
                pdf: p_diffuse * normal.dot(direction).max(0.0) * FRAC_1_PI,
                lobe: Lobe::Diffuse,
            });
        }
        let specular = (choice < p_diffuse + p_specular || p_coat <= 0.0).then_some(p_specular);
        self.reflection_by(incoming, normal, specular, (p_coat, u))
    }

    /// The Lambertian lobe's `f·cos θ` for light leaving along unit
    /// `omega` at a point with unit normal `normal` (the cosine included,
    /// as Mitsuba 3's `BSDF::eval`): `ρ/π·cos θ`, 0 below the surface.
    /// The reflective layer is not evaluated: it is only followed by its
    /// reflected ray.
    #[inline]
    pub fn eval(&self, normal: Vec3, omega: Vec3) -> Rgb {
        let cos = normal.dot(omega);
        if cos > 0.0 {
            self.diffuse * (FRAC_1_PI * cos)
        } else {
            Rgb::ZERO
        }
    }

    /// Solid-angle density with which [`Surface::sample`] picks `omega`
    /// by the Lambertian lobe, `P_d·cos θ/π` (0 below the surface or if
    /// the surface reflects nothing).
    #[inline]
    pub fn pdf(&self, normal: Vec3, omega: Vec3) -> f32 {
        self.diffuse_probability().map_or(0.0, |p_diffuse| {
            p_diffuse * normal.dot(omega).max(0.0) * FRAC_1_PI
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{hemisphere_integral, r2_point};

    #[test]
    fn mirror_reflects_about_normal() {
        let s = Surface::layered(Rgb::ZERO, Rgb::ONE, 0.0);
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = s.reflect(d, Vec3::Y, Vec2::ZERO).unwrap();
        assert!((r - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    /// A smooth GGX layer (α = 0.05) reflects most draws within a few
    /// degrees of the mirror direction: its microfacets' tangents have
    /// `P(tan²θ_h < t) = t/(α² + t)`, so 90 % lie within tan θ_h = 3α, the
    /// reflection within 2θ_h ≈ 17°.
    #[test]
    fn rough_reflection_stays_near_mirror() {
        let s = Surface::layered(Rgb::ZERO, Rgb::ONE, 0.05);
        let mirror = Vec3::Y;
        let n = 4096;
        let near = (0..n)
            .filter_map(|i| s.reflect(-Vec3::Y, Vec3::Y, r2_point(i)))
            .filter(|r| r.dot(mirror) > 17f32.to_radians().cos())
            .count();
        assert!(near as f64 > 0.89 * n as f64, "{near} of {n}");
    }

    /// A white glossy layer (reflectance 1) reflects all the light it
    /// receives, its multiple scattering restored: over the hemisphere,
    /// `∫ layer_eval dω` (midpoint rule in cos θ and φ) is 1, and so is the
    /// mean weight of [`reflect_layer`]'s draws over a stratified grid —
    /// within the albedo table's error (10⁻³) and the rules' (a few 10⁻³
    /// where the lobe is sharp) — for roughness 0.3 and 1, seen head-on
    /// and at 60°; a grey layer of reflectance ρ reflects `ρ·(E + ρ(1 −
    /// E))`, less than ρ. A mirror evaluates to 0 (a delta lobe).
    #[test]
    fn a_white_glossy_layer_keeps_the_furnace_white() {
        let normal = Vec3::Y;
        for roughness in [0.3f32, 1.0] {
            for view in [0.0f32, 60.0] {
                let v = view.to_radians();
                let incoming = Vec3::new(v.sin(), -v.cos(), 0.0);
                let total = hemisphere_integral(500, |omega| {
                    f64::from(layer_eval((Rgb::ONE, roughness), incoming, normal, omega).x)
                });
                assert!(
                    (total - 1.0).abs() < 5e-3,
                    "α {roughness}, {view}°: ∫ = {total}"
                );
                let n = 128;
                let mut mean = 0.0f64;
                for i in 0..n * n {
                    let u = Vec2::new(
                        ((i % n) as f32 + 0.5) / n as f32,
                        ((i / n) as f32 + 0.5) / n as f32,
                    );
                    if let Some((_, w)) = reflect_layer((Rgb::ONE, roughness), incoming, normal, u)
                    {
                        mean += f64::from(w.x) / (n * n) as f64;
                    }
                }
                assert!(
                    (mean - 1.0).abs() < 5e-3,
                    "α {roughness}, {view}°: mean weight {mean}"
                );
                let grey = layer_eval((Rgb::splat(0.5), roughness), incoming, normal, Vec3::Y);
                let white = layer_eval((Rgb::ONE, roughness), incoming, normal, Vec3::Y);
                assert!(grey.x < 0.5 * white.x + 1e-6 || white.x == 0.0);
            }
        }
        assert_eq!(
            layer_eval((Rgb::ONE, 0.0), -Vec3::Y, normal, Vec3::Y),
            Rgb::ZERO
        );
    }

    /// `sample`, `eval` and `pdf` agree: a Lambertian sample's weight is
    /// `eval/pdf`, the lobe follows `choice` against `P_d` (luminance
    /// ratio), and `pdf` integrates to `P_d` over the hemisphere.
    #[test]
    fn surface_sample_eval_pdf_agree() {
        let s = Surface::layered(Rgb::new(0.6, 0.5, 0.4), Rgb::splat(0.3), 0.0);
        let n = Vec3::Y;
        let incoming = Vec3::new(0.3, -1.0, 0.2).normalize();
        let p_d = s.diffuse_probability().unwrap();
        let expected = luminance(s.diffuse) / (luminance(s.diffuse) + luminance(s.specular));
        assert!((p_d - expected).abs() < 1e-6);
        let diffuse = s
            .sample(incoming, n, 0.5 * p_d, Vec2::new(0.3, 0.8))
            .unwrap();
        assert_eq!(diffuse.lobe, Lobe::Diffuse);
        assert!((diffuse.pdf - s.pdf(n, diffuse.direction)).abs() < 1e-6);
        let ratio = s.eval(n, diffuse.direction) / diffuse.pdf;
        assert!((ratio - diffuse.weight).abs().max_element() < 1e-5);
        let specular = s.sample(incoming, n, 0.5 + 0.5 * p_d, Vec2::ZERO).unwrap();
        assert_eq!(specular.lobe, Lobe::Specular);
        assert!((specular.direction - s.reflect(incoming, n, Vec2::ZERO).unwrap()).length() < 1e-6);
        assert!(
            (specular.weight - s.specular / (1.0 - p_d))
                .abs()
                .max_element()
                < 1e-6
        );
        // ∫ pdf dω over the hemisphere (midpoint rule in cos θ and φ).
        let total = hemisphere_integral(200, |omega| f64::from(s.pdf(n, omega)));
        assert!((total - f64::from(p_d)).abs() < 1e-3, "{total} vs {p_d}");
        assert_eq!(s.eval(n, -Vec3::Y), Rgb::ZERO);
        assert_eq!(Surface::diffuse(Rgb::ZERO).diffuse_probability(), None);
    }
}
