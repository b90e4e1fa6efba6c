//! Spotlights (the paper's §3.2): the cone, its intensity profile
//! (eq. 4 and 5) and the part of a ray inside it.

use super::bounds::LightBounds;
use super::gobo::Gobo;
use super::photometric::Luminaire;
use super::{Incident, LeSample, LightPoint, mean_channel, towards};
use crate::color::Rgb;
use crate::ray::Ray;
use crate::sampling::uniform_cone;
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

/// Spotlight: intensity `intensity` (W/sr) on its axis, shaped by
/// `profile`, zero outside the cone `cos θ ≤ cos_cutoff`; with a measured
/// `luminaire` profile (its nadir the cone's axis) also times `P(ω)`, and
/// with a `gobo` filtered by its image's colour `G(ω)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    /// Unit axis of the cone, the direction light leaves along.
    pub direction: Vec3,
    /// Cosine of the cutoff half-angle θc ∈ (0°, 90°].
    pub cos_cutoff: f32,
    pub profile: SpotProfile,
    pub intensity: Rgb,
    pub luminaire: Option<Luminaire>,
    pub gobo: Option<Gobo>,
}

impl SpotLight {
    /// Light reaching `x`: `I·falloff/d²`; `None` outside the cone (the
    /// paper's cone test before the shadow ray) and at the position.
    #[inline]
    pub(super) fn incident(&self, x: Vec3) -> Option<Incident> {
        let (direction, d2) = towards(x, self.position)?;
        let falloff = self.falloff(-direction.dot(self.direction)) * self.measured(-direction);
        if falloff <= 0.0 {
            return None;
        }
        let filtered = self.filtered(-direction);
        (filtered != Rgb::ZERO).then(|| Incident {
            direction,
            distance: d2.sqrt(),
            irradiance: filtered * (falloff / d2),
            light_normal: None,
        })
    }

    /// A ray leaving the light uniformly over its cone (from
    /// `u_direction`), carrying `I·falloff·Ω_cone`; `None` where the
    /// profile is 0 (at the cut).
    pub(super) fn sample_le(&self, u_direction: Vec2) -> Option<LeSample> {
        let direction = uniform_cone(self.direction, self.cos_cutoff, u_direction);
        let falloff = self.falloff(direction.dot(self.direction)) * self.measured(direction);
        if falloff <= 0.0 {
            return None;
        }
        let solid_angle = 2.0 * PI * (1.0 - self.cos_cutoff);
        Some(LeSample {
            point: LightPoint::delta(self.position),
            ray: Ray {
                origin: self.position,
                direction,
            },
            beta: self.filtered(direction) * (falloff * solid_angle),
        })
    }

    /// The measured profile's relative intensity towards the unit
    /// direction `emitted` (1 without one).
    #[inline]
    fn measured(&self, emitted: Vec3) -> f32 {
        self.luminaire.as_ref().map_or(1.0, |l| l.factor(emitted))
    }

    /// The intensity's colour towards the unit direction `emitted`
    /// through the gobo, if any: `I·G(ω)`.
    #[inline]
    fn filtered(&self, emitted: Vec3) -> Rgb {
        match &self.gobo {
            Some(g) => self.intensity * g.colour(emitted),
            None => self.intensity,
        }
    }

    /// Its emission's bounds: nothing outside the cone, peak `I` inside
    /// (profiles and measured tables are at most 1; the intensity only
    /// weighs the light's chance of being chosen, so a gobo's colour
    /// need not be bounded by it).
    pub(super) fn bounds(&self) -> LightBounds {
        let theta_c = self.cos_cutoff.clamp(-1.0, 1.0).acos();
        LightBounds::cone(
            self.position,
            mean_channel(self.intensity),
            self.direction,
            theta_c,
        )
    }

    /// Total emitted power: `I·∫ falloff dω` over the cone, in closed form
    /// per profile; with a measured profile or a gobo `∫ I·falloff·P·G dω`
    /// by the midpoint rule on a 256 × 512 grid in (cos θ, φ) about the
    /// axis. No renderer reads it; the emitted throughput's mean is tested
    /// against it (within 10⁻³ for a measured table, lights/mod.rs).
    pub(super) fn power(&self) -> Rgb {
        if self.luminaire.is_some() || self.gobo.is_some() {
            let (n_cos, n_phi) = (256, 512);
            let d_cos = (1.0 - self.cos_cutoff) / n_cos as f32;
            let d_phi = 2.0 * PI / n_phi as f32;
            let (t, b) = self.direction.any_orthonormal_pair();
            let mut sum = glam::DVec3::ZERO;
            for i in 0..n_cos {
                let c = self.cos_cutoff + (i as f32 + 0.5) * d_cos;
                let s = (1.0 - c * c).max(0.0).sqrt();
                let falloff = self.falloff(c);
                for j in 0..n_phi {
                    let (sp, cp) = ((j as f32 + 0.5) * d_phi).sin_cos();
                    let omega = self.direction * c + (t * cp + b * sp) * s;
                    let weight = falloff * self.measured(omega);
                    sum += (self.filtered(omega) * weight).as_dvec3();
                }
            }
            return (sum * f64::from(d_cos * d_phi)).as_vec3();
        }
        let cos_c = self.cos_cutoff;
        let integral = match self.profile {
            // 2π ∫ (1 − (1 − c)/(1 − c_c)) dc over [c_c, 1].
            SpotProfile::Linear => PI * (1.0 - cos_c),
            SpotProfile::Hard => 2.0 * PI * (1.0 - cos_c),
            // The smoothstep averages ½ over [c_c, c_i].
            SpotProfile::Smooth { cos_inner } => {
                2.0 * PI * ((1.0 - cos_inner) + 0.5 * (cos_inner - cos_c))
            }
        };
        self.intensity * integral
    }

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
        //
        // Solved about `t_c`, where the ray passes nearest the apex (its
        // direction is unit), so that `v` is that small offset: from a
        // ray's origin far away, the two crossings of a thin beam near its
        // apex lie a chord `≈ 2·D·tan θc` apart at `t ≈ |v|`, and `b² − 4ac`,
        // each term `∝ |v|²`, cancelled in f32 to below its rounding (a
        // camera ray passing a head of the stage rig 3.5 cm from the apex
        // at 22 m lost its crossing: no equiangular sample, and NEE from
        // fog events there went unweighted, a firefly).
        let t_c = -(ray.origin - self.position).dot(ray.direction);
        let v = ray.origin + t_c * ray.direction - self.position;
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
                cuts[2] = t_c + q / a;
                cuts[3] = if q != 0.0 { t_c + c / q } else { f32::NAN };
            }
        } else if b != 0.0 {
            cuts[2] = t_c - c / b;
        }
        if wd != 0.0 {
            cuts[4] = t_c - vd / wd;
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

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A spot at (0, 3, 0) pointing down, of unit intensity.
    pub(in crate::lights) fn spot(profile: SpotProfile, cutoff_deg: f32) -> SpotLight {
        SpotLight {
            gobo: None,
            luminaire: None,
            position: Vec3::new(0.0, 3.0, 0.0),
            direction: -Vec3::Y,
            cos_cutoff: cutoff_deg.to_radians().cos(),
            profile,
            intensity: Rgb::ONE,
        }
    }

    /// Eq. 5 at its defining points, and one value computed by hand:
    /// θ = 15°, θc = 30°: 1 − (1 − 0.9659258)/(1 − 0.8660254) = 0.7456669.
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

    /// A ray from far away passing just below the apex, across the cone:
    /// its crossing is found, where the inside test (in f64, by
    /// bisection from the point under the apex) puts it, for passes from
    /// 1 mm to 10 cm at 30 m. (Solved about the ray's origin, the
    /// quadratic's discriminant cancelled to nothing in f32 at these
    /// distances.)
    #[test]
    fn cone_clip_finds_a_thin_beam_far_from_the_ray_origin() {
        let s = spot(SpotProfile::Hard, 12.0);
        for pass in [1e-3f64, 1e-2, 3.5e-2, 1e-1] {
            for (k, sideways) in [0.0f64, 0.3, -0.45].into_iter().enumerate() {
                // Nearly horizontal, through (0, 3 − pass, 0).
                let under = [0.0, 3.0 - pass, 0.0];
                let dir = {
                    let d = [1.0, 0.02 * k as f64, sideways];
                    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    [d[0] / n, d[1] / n, d[2] / n]
                };
                let origin = [
                    under[0] - 30.0 * dir[0],
                    under[1] - 30.0 * dir[1],
                    under[2] - 30.0 * dir[2],
                ];
                let inside = |t: f64| {
                    let p = [
                        origin[0] + t * dir[0],
                        origin[1] + t * dir[1] - 3.0,
                        origin[2] + t * dir[2],
                    ];
                    let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                    -p[1] > len * 12f64.to_radians().cos()
                };
                assert!(inside(30.0), "the pass at 30 m is inside the cone");
                let edge = |outward: f64| {
                    let (mut lo, mut hi) = (30.0, 30.0 + outward);
                    for _ in 0..80 {
                        let mid = 0.5 * (lo + hi);
                        if inside(mid) { lo = mid } else { hi = mid }
                    }
                    lo
                };
                let (enter, leave) = (edge(-1.0), edge(1.0));
                let ray = Ray::new(
                    Vec3::new(origin[0] as f32, origin[1] as f32, origin[2] as f32),
                    Vec3::new(dir[0] as f32, dir[1] as f32, dir[2] as f32),
                );
                let clip = s.clip_ray(&ray, 0.0, 60.0);
                let Some((a, b)) = clip else {
                    panic!("pass {pass}, ray {k}: no crossing; expected {enter}..{leave}")
                };
                // f32 positions 30 m out are good to about 4·10⁻⁶ m.
                let tolerance = 1e-5 + 1e-3 * (leave - enter);
                assert!(
                    (f64::from(a) - enter).abs() < tolerance
                        && (f64::from(b) - leave).abs() < tolerance,
                    "pass {pass}, ray {k}: {a}..{b} against {enter}..{leave}"
                );
            }
        }
    }
}
