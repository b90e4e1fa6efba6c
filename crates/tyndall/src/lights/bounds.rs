//! Bounds on the emission of a cluster of point and spot lights, and the
//! importance that bounds a cluster's light at a receiving point or along
//! a ray segment in fog: the `LightBounds` of pbrt-v4's BVH light sampler
//! (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed.,
//! §12.6.3, after Conty Estevez & Kulla 2018, "Importance Sampling of
//! Many Lights with Adaptive Tree Splitting"), with the segment
//! importance that Cycles' light tree gives volume segments.
//!
//! An importance is a heuristic for how much light a cluster sends to a
//! receiver, used only to choose among clusters. It must be exactly zero
//! only where every light of the cluster sends nothing (outside every
//! cone): anywhere else a light with a zero chance of being chosen would
//! bias the image. Every zero below is a proof by angles that all the
//! cluster's directions towards the receiver lie outside its cones.

use crate::ray::Ray;
use crate::sampling::inverse_square_integral;
use crate::shapes::Bounds;
use glam::Vec3;
use std::f32::consts::PI;

/// Margin (radians) by which a receiver must lie outside a cluster's
/// cones before its importance is 0: float rounding in the angles here
/// must never cull a light whose own cone test passes.
const CONE_SLACK: f32 = 1e-3;

/// How near, as a share of a cluster's bounding radius, its light is taken
/// to be to a receiver inside its bounding sphere. The distance a
/// cluster's importance uses is the nearest its bounding sphere comes (not
/// its centre's, as pbrt-v4's): a light of the cluster may lie there, and
/// a cluster weighed as if all its light came from its centre is chosen
/// too rarely where one of its lights is close, which an estimate divided
/// by that small probability pays for in fireflies.
const NEAREST_SHARE: f32 = 0.05;

/// What bounds the emission of a cluster of point and spot lights: where
/// the lights are, their summed peak intensity, and a cone of directions
/// holding every light's emission.
///
/// The emission cone is pbrt-v4's pair of angles: every light's axis lies
/// within `theta_o` of `axis`, and every light emits only within
/// `theta_e` of its own axis. A point light has `theta_o = π` (any axis)
/// and `theta_e = π/2`; a spot of cutoff θc has `theta_o = 0` and
/// `theta_e = θc`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// The lights' positions.
    pub bounds: Bounds,
    /// The sum of the lights' peak radiant intensities (W/sr, the mean
    /// of the channels).
    pub intensity: f32,
    cone: EmissionCone,
}

/// The cone of a cluster's emission, with the cosines and sines its
/// importance reads (the angles' trigonometry done once, at the build).
#[derive(Clone, Copy, Debug, PartialEq)]
struct EmissionCone {
    /// The unit axis of the cone of the lights' axes.
    axis: Vec3,
    /// Half-angle (radians) of the cone around `axis` holding every
    /// light's own axis.
    theta_o: f32,
    /// Half-angle (radians) around its own axis beyond which no light
    /// emits.
    theta_e: f32,
    cos_o: f32,
    sin_o: f32,
    /// cos(θ_e + [`CONE_SLACK`]): a receiver whose cos θ' is no more
    /// than this lies outside every cone.
    cos_e: f32,
}

impl EmissionCone {
    fn new(axis: Vec3, theta_o: f32, theta_e: f32) -> Self {
        let (sin_o, cos_o) = theta_o.sin_cos();
        Self {
            axis,
            theta_o,
            theta_e,
            cos_o,
            sin_o,
            cos_e: (theta_e + CONE_SLACK).min(PI).cos(),
        }
    }

    /// `cos θ'` for a receiver whose directions from the cluster's centre
    /// come no nearer to `axis` than an angle of cosine `cos_w`, the
    /// cluster's box seen from it within an angle of sine `sin_b` (≥ 1:
    /// the receiver is inside its bounding sphere), where
    /// `θ' = max(0, θ_w − θ_o − θ_b)` (pbrt-v4's `LightBounds::Importance`,
    /// in cosines and sines); `None` past the cutoff, where no light of
    /// the cluster reaches the receiver.
    fn cos_theta_past(&self, cos_w: f32, sin_b: f32) -> Option<f32> {
        if sin_b >= 1.0 {
            return Some(1.0);
        }
        let cos_w = cos_w.clamp(-1.0, 1.0);
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        // θ_x = max(0, θ_w − θ_o).
        let (cos_x, sin_x) = if cos_w >= self.cos_o {
            (1.0, 0.0)
        } else {
            (
                cos_w * self.cos_o + sin_w * self.sin_o,
                sin_w * self.cos_o - cos_w * self.sin_o,
            )
        };
        // θ' = max(0, θ_x − θ_b).
        let cos_b = (1.0 - sin_b * sin_b).max(0.0).sqrt();
        let cos_past = if cos_x >= cos_b {
            1.0
        } else {
            cos_x * cos_b + sin_x * sin_b
        };
        (cos_past > self.cos_e).then_some(cos_past)
    }
}

impl LightBounds {
    /// The bounds of one light at `position` of peak `intensity` (W/sr)
    /// that emits only within `theta_e` of the unit `axis`.
    pub fn cone(position: Vec3, intensity: f32, axis: Vec3, theta_e: f32) -> Self {
        Self {
            bounds: Bounds::new(position, position),
            intensity,
            cone: EmissionCone::new(axis, 0.0, theta_e),
        }
    }

    /// The bounds of one light at `position` of peak `intensity` (W/sr)
    /// that may emit in every direction.
    pub fn sphere(position: Vec3, intensity: f32) -> Self {
        Self {
            bounds: Bounds::new(position, position),
            intensity,
            cone: EmissionCone::new(Vec3::Z, PI, PI / 2.0),
        }
    }

    /// The bounds of both clusters: the union of the boxes, the summed
    /// intensities, and the smallest cone holding both cones of axes
    /// (pbrt-v4's `DirectionCone::Union`).
    pub fn union(&self, other: &LightBounds) -> LightBounds {
        let (a, b) = (&self.cone, &other.cone);
        let (axis, theta_o) = cone_union((a.axis, a.theta_o), (b.axis, b.theta_o));
        LightBounds {
            bounds: self.bounds.union(other.bounds),
            intensity: self.intensity + other.intensity,
            cone: EmissionCone::new(axis, theta_o, a.theta_e.max(b.theta_e)),
        }
    }

    /// The radius of the bounding sphere around the box's centre.
    fn radius(&self) -> f32 {
        0.5 * self.bounds.extent().length()
    }

    /// Importance of the cluster to a receiver at `x`, after pbrt-v4's
    /// `LightBounds::Importance`: `I·cos θ'/d²`, with `d` the distance
    /// from the bounding sphere (at least [`NEAREST_SHARE`] of its
    /// radius) and θ' the angle left between the receiver and the cones
    /// ([`LightBounds`]); 0 only where `x` lies outside every light's
    /// cone.
    pub fn importance_at(&self, x: Vec3) -> f32 {
        let centre = self.bounds.center();
        let radius = self.radius();
        let to_x = x - centre;
        let d2 = to_x.length_squared();
        let d = d2.sqrt();
        let cos_w = if d > 0.0 {
            self.cone.axis.dot(to_x) / d
        } else {
            1.0
        };
        let sin_b = if d > radius { radius / d } else { 1.0 };
        match self.cone.cos_theta_past(cos_w, sin_b) {
            Some(cos) => {
                let nearest = (d - radius).max(NEAREST_SHARE * radius);
                positive(self.intensity * cos / (nearest * nearest).max(1e-12))
            }
            None => 0.0,
        }
    }

    /// Importance of the cluster to the segment `[a, b]` of `ray` (unit
    /// direction; `b` may be infinite) in fog: `I·cos θ'·∫ ds/d(s)²`,
    /// the in-scattering of a point light at the box's centre along the
    /// segment ([`inverse_square_integral`], at the distance from the line
    /// to the bounding sphere, at least [`NEAREST_SHARE`] of its radius), times the
    /// cone factor of [`LightBounds::importance_at`] with θ_w the least
    /// angle between the cone's axis and the directions from the centre
    /// to the segment; 0 only where every point of the segment lies
    /// outside every light's cone.
    pub fn importance_along(&self, ray: &Ray, a: f32, b: f32) -> f32 {
        // An empty (or NaN) segment receives nothing.
        if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) {
            return 0.0;
        }
        let centre = self.bounds.center();
        let radius = self.radius();
        let along = (centre - ray.origin).dot(ray.direction);
        let gap = (ray.at(along.clamp(a, b)) - centre).length();
        let sin_b = if gap > radius { radius / gap } else { 1.0 };
        let end = |t: f32| {
            if t.is_finite() {
                (ray.at(t) - centre).normalize_or_zero()
            } else {
                ray.direction
            }
        };
        let cos_w = cos_to_arc(self.cone.axis, end(a), end(b));
        let Some(cos) = self.cone.cos_theta_past(cos_w, sin_b) else {
            return 0.0;
        };
        let line_distance =
            ((ray.at(along) - centre).length() - radius).max(NEAREST_SHARE * radius);
        let line = inverse_square_integral(line_distance, a - along, b - along);
        positive(self.intensity * cos * line)
    }
}

impl LightBounds {
    /// Whether the cluster's bounding sphere, seen from `x`, subtends a
    /// half-angle of sine above `sine` (or holds `x`): its lights lie in
    /// directions and at distances too different for one importance.
    pub fn looms_at(&self, x: Vec3, sine: f32) -> bool {
        self.radius() > sine * (x - self.bounds.center()).length()
    }

    /// [`LightBounds::looms_at`] for the nearest point of the segment
    /// `[a, b]` of `ray`.
    pub fn looms_along(&self, ray: &Ray, a: f32, b: f32, sine: f32) -> bool {
        let centre = self.bounds.center();
        let along = (centre - ray.origin).dot(ray.direction).clamp(a, b);
        self.radius() > sine * (ray.at(along) - centre).length()
    }
}

/// A receiver the cones do not exclude keeps a chance of being lit,
/// however small its importance rounds to (a light with no chance where
/// it shines would bias the estimate): the smallest normal float.
#[inline]
fn positive(importance: f32) -> f32 {
    importance.max(f32::MIN_POSITIVE)
}

/// The cosine of the least angle between the unit `w` and the shorter
/// great-circle arc from unit `u0` to unit `u1` (the directions from a
/// point to the points of a segment that misses it): of the angle to the
/// arc's plane if `w`'s projection on it falls within the arc, else to
/// the nearer end.
fn cos_to_arc(w: Vec3, u0: Vec3, u1: Vec3) -> f32 {
    let ends = w.dot(u0).max(w.dot(u1));
    let Some(n) = u0.cross(u1).try_normalize() else {
        return ends;
    };
    let in_plane = w - n * w.dot(n);
    let within = u0.cross(in_plane).dot(n) >= 0.0 && in_plane.cross(u1).dot(n) >= 0.0;
    if within {
        in_plane.length().max(ends)
    } else {
        ends
    }
}

/// The angle (radians) between unit vectors.
#[inline]
fn angle_between(u: Vec3, v: Vec3) -> f32 {
    u.dot(v).clamp(-1.0, 1.0).acos()
}

/// The smallest cone holding the cones `(axis, half-angle)` `a` and `b`
/// (pbrt-v4's `DirectionCone::Union`).
fn cone_union(a: (Vec3, f32), b: (Vec3, f32)) -> (Vec3, f32) {
    let theta_d = angle_between(a.0, b.0);
    if (theta_d + b.1).min(PI) <= a.1 {
        return a;
    }
    if (theta_d + a.1).min(PI) <= b.1 {
        return b;
    }
    let theta_o = 0.5 * (a.1 + theta_d + b.1);
    if theta_o >= PI {
        return (a.0, PI);
    }
    // Turn a's axis towards b's by the half-angle a's cone must grow.
    let Some(about) = a.0.cross(b.0).try_normalize() else {
        return (a.0, PI);
    };
    let axis = glam::Quat::from_axis_angle(about, theta_o - a.1) * a.0;
    (axis.normalize(), theta_o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb;
    use crate::lights::{Light, SpotLight, SpotProfile};

    fn spot_at(position: Vec3, direction: Vec3, cutoff_deg: f32) -> SpotLight {
        SpotLight {
            position,
            direction: direction.normalize(),
            cos_cutoff: cutoff_deg.to_radians().cos(),
            profile: SpotProfile::Hard,
            intensity: Rgb::ONE,
            luminaire: None,
            gobo: None,
        }
    }

    /// A deterministic spread of unit vectors.
    fn directions(n: usize) -> impl Iterator<Item = Vec3> {
        (0..n).map(move |i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let phi = i as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
    }

    /// The union's cone holds both cones: every direction within either
    /// lies within the union.
    #[test]
    fn cone_union_holds_both() {
        let cones: Vec<(Vec3, f32)> = directions(12)
            .zip([0.0, 0.1, 0.5, 1.0, 2.0, 0.3].iter().cycle())
            .map(|(d, &t)| (d, t))
            .collect();
        for &a in &cones {
            for &b in &cones {
                let (axis, theta) = cone_union(a, b);
                for cone in [a, b] {
                    for d in directions(200) {
                        if angle_between(d, cone.0) <= cone.1 {
                            assert!(angle_between(d, axis) <= theta + 1e-4, "{a:?} ∪ {b:?}");
                        }
                    }
                }
            }
        }
    }

    /// A cluster's importance is 0 only where no light of it reaches: at
    /// points and along segments, a cluster of spots each lighting the
    /// receiver has importance > 0, and a receiver outside all cones
    /// mostly has 0 (the bounds are not loose everywhere).
    #[test]
    fn importance_is_zero_only_outside_every_cone() {
        let spots: Vec<SpotLight> = directions(16)
            .enumerate()
            .map(|(i, d)| {
                let position = Vec3::new((i % 4) as f32, 3.0, (i / 4) as f32) * 0.5;
                spot_at(position, -Vec3::Y + 0.6 * d, 10.0 + 2.0 * i as f32)
            })
            .collect();
        let bounds: Vec<LightBounds> = spots
            .iter()
            .map(|s| Light::Spot(s.clone()).bounds().unwrap())
            .collect();
        let cluster = bounds[1..].iter().fold(bounds[0], |acc, b| acc.union(b));
        let (mut points_culled, mut points) = (0, 0);
        for (i, d) in directions(400).enumerate() {
            let x = Vec3::new(1.0, 1.5, 1.0) + d * (0.5 + (i % 7) as f32);
            let lit = spots.iter().any(|s| s.incident(x).is_some());
            let importance = cluster.importance_at(x);
            if lit {
                assert!(importance > 0.0, "{x} is lit but has importance 0");
            }
            for (s, b) in spots.iter().zip(&bounds) {
                if s.incident(x).is_some() {
                    assert!(b.importance_at(x) > 0.0);
                }
            }
            points += 1;
            points_culled += usize::from(importance == 0.0);
            let ray = Ray {
                origin: x,
                direction: directions(7).nth(i % 7).unwrap(),
            };
            for b_end in [0.5, 3.0, f32::INFINITY] {
                let reached = spots.iter().any(|s| s.clip_ray(&ray, 0.0, b_end).is_some());
                if reached {
                    assert!(cluster.importance_along(&ray, 0.0, b_end) > 0.0);
                }
                for (s, b) in spots.iter().zip(&bounds) {
                    if s.clip_ray(&ray, 0.0, b_end).is_some() {
                        assert!(b.importance_along(&ray, 0.0, b_end) > 0.0);
                    }
                }
            }
        }
        // Some points below and beside the rig lie outside every cone.
        assert!(
            points_culled > 0 && points_culled < points,
            "{points_culled}/{points}"
        );
    }

    /// Along a segment far from a point light the importance is the
    /// light's in-scattering integral `I·∫ds/d²`, here by the midpoint
    /// rule.
    #[test]
    fn segment_importance_of_a_point_light_is_its_line_integral() {
        let light = LightBounds::sphere(Vec3::new(0.3, 2.0, -0.4), 2.5);
        let ray = Ray {
            origin: Vec3::new(-3.0, 0.0, 0.0),
            direction: Vec3::new(1.0, 0.1, 0.05).normalize(),
        };
        let (a, b) = (0.5f32, 7.0f32);
        let n = 100_000;
        let h = f64::from(b - a) / n as f64;
        let sum: f64 = (0..n)
            .map(|i| {
                let t = f64::from(a) + (i as f64 + 0.5) * h;
                let d2 = (ray.at(t as f32) - light.bounds.min).length_squared() as f64;
                2.5 / d2 * h
            })
            .sum();
        let importance = light.importance_along(&ray, a, b) as f64;
        assert!(
            (importance - sum).abs() < 1e-4 * sum,
            "{importance} vs {sum}"
        );
    }
}
