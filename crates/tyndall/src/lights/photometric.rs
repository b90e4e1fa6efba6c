//! Measured luminaire intensity distributions (goniophotometry): the
//! candela tables of IES LM-63 files, which every fixture maker publishes,
//! and their orientation on a point or spot light.
//!
//! The table is in Type C photometry (IES LM-63-2019, §5; IES LM-75-19):
//! vertical angles θ from the nadir (0°, straight down the luminaire's
//! axis) to the zenith (180°), horizontal angles φ about that axis from the
//! luminaire's 0° plane (its length axis), counter-clockwise seen from
//! above. A file lists only the horizontal angles its symmetry needs:
//! one (rotationally symmetric), 0–90° (the same in each quadrant), 0–180°
//! (mirrored about the 0–180° plane), 90–270° (mirrored about the
//! 90–270° plane) or 0–360° (none). Beyond the listed vertical angles the
//! luminaire emits nothing.
//!
//! LM-63 leaves interpolation between the tabulated angles to the
//! application. Tyndall interpolates linearly in θ and in φ (bilinear on
//! the angle grid), which keeps the profile non-negative, reproduces every
//! tabulated value, and integrates in closed form. Its total flux for four
//! manufacturers' files is within 0.015–0.08 % of Photometric Toolbox's
//! figures, inside linear interpolation's error bound
//! (crates/tyndall-tests/tests/photometry.rs).
//!
//! Normalisation: the profile is divided by its largest value, so the
//! light's `intensity` is the luminaire's peak intensity (W/sr) and the
//! profile only shapes it; [`PhotometricProfile::mean`] converts between
//! the peak and the total power (`Φ = 4π·I_peak·mean`).

use glam::Vec3;
use std::f64::consts::PI;

/// Horizontal angles a table lists, and how the others follow from them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HorizontalSymmetry {
    /// One angle: the same in every vertical plane.
    Rotational,
    /// 0–90°: each quadrant mirrors the first.
    Quadrants,
    /// 0–180°: mirrored about the 0–180° plane.
    Bilateral0To180,
    /// 90–270°: mirrored about the 90–270° plane.
    Bilateral90To270,
    /// 0–360°: every plane measured.
    Full,
}

/// A luminaire's relative intensity `P(θ, φ) ∈ [0, 1]` on a Type C grid,
/// 1 at its peak (see the module's documentation for the conventions).
#[derive(Clone, Debug, PartialEq)]
pub struct PhotometricProfile {
    /// Vertical angles θ in degrees, increasing, within [0, 180].
    vertical: Vec<f32>,
    /// Horizontal angles φ in degrees, increasing, as the file lists them.
    horizontal: Vec<f32>,
    symmetry: HorizontalSymmetry,
    /// `values[h·V + v]`: the relative intensity at `horizontal[h]`,
    /// `vertical[v]`.
    values: Vec<f32>,
    /// `(1/4π)·∫ P dω` over the sphere.
    mean: f32,
}

impl PhotometricProfile {
    /// A profile from a Type C table: `vertical` and `horizontal` angles
    /// in degrees, `candela[h][v]` (any positive scale: the profile is
    /// normalised to its peak). Errors name what is wrong: angle counts
    /// and ranges, angles that do not increase, a horizontal set that is
    /// none of LM-63's symmetries, negative or non-finite values, a table
    /// that is zero everywhere.
    pub fn new(
        vertical: Vec<f32>,
        horizontal: Vec<f32>,
        candela: &[Vec<f32>],
    ) -> Result<Self, String> {
        if vertical.len() < 2 || horizontal.is_empty() {
            return Err(
                "a photometric table needs at least two vertical angles and one horizontal angle"
                    .into(),
            );
        }
        for (name, angles) in [("vertical", &vertical), ("horizontal", &horizontal)] {
            if let Some(a) = angles.iter().find(|a| !a.is_finite()) {
                return Err(format!("{name} angle {a} is not a finite number"));
            }
            if let Some(w) = angles.windows(2).find(|w| w[1] <= w[0]) {
                return Err(format!(
                    "{name} angles must increase, but {} follows {}",
                    w[1], w[0]
                ));
            }
        }
        let (v0, v1) = (vertical[0], vertical[vertical.len() - 1]);
        if v0 < 0.0 || v1 > 180.0 {
            return Err(format!(
                "vertical angles must lie in [0°, 180°] (Type C photometry), not [{v0}°, {v1}°]"
            ));
        }
        let (h0, h1) = (horizontal[0], horizontal[horizontal.len() - 1]);
        let symmetry = if horizontal.len() == 1 {
            HorizontalSymmetry::Rotational
        } else if (h0, h1) == (0.0, 90.0) {
            HorizontalSymmetry::Quadrants
        } else if (h0, h1) == (0.0, 180.0) {
            HorizontalSymmetry::Bilateral0To180
        } else if (h0, h1) == (90.0, 270.0) {
            HorizontalSymmetry::Bilateral90To270
        } else if (h0, h1) == (0.0, 360.0) {
            HorizontalSymmetry::Full
        } else {
            return Err(format!(
                "horizontal angles from {h0}° to {h1}° are none of LM-63's sets \
                 (one angle, 0–90°, 0–180°, 90–270° or 0–360°)"
            ));
        };
        if candela.len() != horizontal.len() {
            return Err(format!(
                "the table has {} rows of candela values for {} horizontal angles",
                candela.len(),
                horizontal.len()
            ));
        }
        let mut values = Vec::with_capacity(vertical.len() * horizontal.len());
        for (h, row) in candela.iter().enumerate() {
            if row.len() != vertical.len() {
                return Err(format!(
                    "horizontal angle {}° has {} candela values for {} vertical angles",
                    horizontal[h],
                    row.len(),
                    vertical.len()
                ));
            }
            if let Some((v, c)) = row
                .iter()
                .enumerate()
                .find(|(_, c)| !(c.is_finite() && **c >= 0.0))
            {
                return Err(format!(
                    "the candela value at horizontal {}°, vertical {}° is {c}: values must be finite and ≥ 0",
                    horizontal[h], vertical[v]
                ));
            }
            values.extend_from_slice(row);
        }
        let peak = values.iter().copied().fold(0.0f32, f32::max);
        if peak <= 0.0 {
            return Err("every candela value is 0: the luminaire emits nothing".into());
        }
        values.iter_mut().for_each(|c| *c /= peak);
        let mut profile = Self {
            vertical,
            horizontal,
            symmetry,
            values,
            mean: 0.0,
        };
        profile.mean = (profile.integral() / (4.0 * PI)) as f32;
        Ok(profile)
    }

    /// `(1/4π)·∫ P dω`: the total power of a light of peak intensity 1
    /// W/sr is `4π·mean` W.
    pub fn mean(&self) -> f32 {
        self.mean
    }

    /// The symmetry the table's horizontal angles imply.
    pub fn symmetry(&self) -> HorizontalSymmetry {
        self.symmetry
    }

    /// `P(θ, φ)`, angles in degrees (φ any real: it is reduced to the
    /// table's range by the symmetry): bilinear in the angles, 0 beyond
    /// the tabulated vertical range.
    pub fn eval(&self, theta_deg: f32, phi_deg: f32) -> f32 {
        let Some((v, tv)) = bracket(&self.vertical, theta_deg) else {
            return 0.0;
        };
        let nv = self.vertical.len();
        let at = |h: usize| {
            let row = &self.values[h * nv..(h + 1) * nv];
            match v {
                Bracket::One(i) => row[i],
                Bracket::Two(i) => row[i] + (row[i + 1] - row[i]) * tv,
            }
        };
        if self.horizontal.len() == 1 {
            return at(0);
        }
        let phi = self.fold(phi_deg);
        match bracket(&self.horizontal, phi) {
            Some((Bracket::One(h), _)) => at(h),
            Some((Bracket::Two(h), th)) => at(h) + (at(h + 1) - at(h)) * th,
            // The fold keeps φ in the listed range; rounding at its ends
            // takes the nearer end.
            None if phi < self.horizontal[0] => at(0),
            None => at(self.horizontal.len() - 1),
        }
    }

    /// φ (degrees) reduced into the listed horizontal range by the
    /// table's symmetry.
    fn fold(&self, phi_deg: f32) -> f32 {
        let phi = phi_deg.rem_euclid(360.0);
        match self.symmetry {
            HorizontalSymmetry::Rotational | HorizontalSymmetry::Full => phi,
            HorizontalSymmetry::Quadrants => {
                let p = phi % 180.0;
                if p > 90.0 { 180.0 - p } else { p }
            }
            HorizontalSymmetry::Bilateral0To180 => {
                if phi > 180.0 {
                    360.0 - phi
                } else {
                    phi
                }
            }
            HorizontalSymmetry::Bilateral90To270 => {
                if phi < 90.0 {
                    180.0 - phi
                } else if phi > 270.0 {
                    540.0 - phi
                } else {
                    phi
                }
            }
        }
    }

    /// `∫ P dω` over the sphere, exact for the bilinear interpolant: per
    /// vertical interval, `∫ (a + (b − a)·s) sin θ dθ` in closed form
    /// (s the interval's fraction); per horizontal interval the
    /// trapezoid rule (exact for linear in φ), over the whole circle the
    /// listed range stands for.
    fn integral(&self) -> f64 {
        let nv = self.vertical.len();
        // ∫ P(θ, φ_h) sin θ dθ for row h.
        let row_integral = |h: usize| -> f64 {
            let row = &self.values[h * nv..(h + 1) * nv];
            (0..nv.saturating_sub(1))
                .map(|i| {
                    let (t0, t1) = (
                        f64::from(self.vertical[i]).to_radians(),
                        f64::from(self.vertical[i + 1]).to_radians(),
                    );
                    let (a, b) = (f64::from(row[i]), f64::from(row[i + 1]));
                    // ∫ sin = cos t0 − cos t1; ∫ s sin with s = (θ − t0)/Δ:
                    // [sin θ − θ cos θ + t0 cos θ]/Δ from t0 to t1.
                    let delta = t1 - t0;
                    let i0 = t0.cos() - t1.cos();
                    let i1 = (t1.sin() - t0.sin() - delta * t1.cos()) / delta;
                    a * i0 + (b - a) * i1
                })
                .sum()
        };
        let nh = self.horizontal.len();
        if nh == 1 {
            return 2.0 * PI * row_integral(0);
        }
        let listed: f64 = (0..nh - 1)
            .map(|h| {
                let dphi = f64::from(self.horizontal[h + 1] - self.horizontal[h]).to_radians();
                0.5 * dphi * (row_integral(h) + row_integral(h + 1))
            })
            .sum();
        // The listed range covers 90°, 180° or 360° of the circle.
        let span = f64::from(self.horizontal[nh - 1] - self.horizontal[0]);
        listed * 360.0 / span
    }
}

/// Where a value lies in an increasing list of angles: on one entry
/// (also for a one-entry list), or between entries i and i + 1.
#[derive(Clone, Copy, Debug)]
enum Bracket {
    One(usize),
    Two(usize),
}

/// The bracket of `x` in `angles` and its fraction of the way from entry
/// i to i + 1; `None` outside `[first, last]`.
fn bracket(angles: &[f32], x: f32) -> Option<(Bracket, f32)> {
    let (first, last) = (angles[0], angles[angles.len() - 1]);
    if !(x >= first && x <= last) {
        return None;
    }
    if angles.len() == 1 || x == last {
        return Some((Bracket::One(angles.len() - 1), 0.0));
    }
    // The last i with angles[i] ≤ x (i < len − 1 as x < last).
    let i = angles.partition_point(|&a| a <= x) - 1;
    let t = (x - angles[i]) / (angles[i + 1] - angles[i]);
    Some((Bracket::Two(i), t))
}

/// A [`PhotometricProfile`] placed on a light: `nadir` the unit direction
/// of θ = 0 and `zero` the unit direction of φ = 0 (perpendicular to
/// `nadir`); φ = 90° lies along `zero × nadir` (counter-clockwise seen
/// from above, looking along the nadir).
#[derive(Clone, Debug, PartialEq)]
pub struct Luminaire {
    pub profile: std::sync::Arc<PhotometricProfile>,
    nadir: Vec3,
    zero: Vec3,
    ninety: Vec3,
}

impl Luminaire {
    /// The profile with its nadir along the unit `nadir` and its 0° plane
    /// turned `rotate_deg` counter-clockwise (seen from above) from the
    /// reference direction: world +X projected perpendicular to the nadir,
    /// or world +Z where the nadir is within 25° of ±X.
    pub fn new(profile: std::sync::Arc<PhotometricProfile>, nadir: Vec3, rotate_deg: f32) -> Self {
        let nadir = nadir.normalize();
        let reference = if nadir.x.abs() > 0.9 {
            Vec3::Z
        } else {
            Vec3::X
        };
        let zero0 = (reference - reference.dot(nadir) * nadir).normalize();
        let ninety0 = zero0.cross(nadir);
        let (s, c) = rotate_deg.to_radians().sin_cos();
        let zero = zero0 * c + ninety0 * s;
        Self {
            profile,
            nadir,
            zero,
            ninety: zero.cross(nadir),
        }
    }

    /// The relative intensity `P(θ, φ)` towards the unit direction
    /// `emitted` (the direction light leaves the luminaire along).
    #[inline]
    pub fn factor(&self, emitted: Vec3) -> f32 {
        let cos_theta = emitted.dot(self.nadir).clamp(-1.0, 1.0);
        let theta = cos_theta.acos().to_degrees();
        let phi = emitted
            .dot(self.ninety)
            .atan2(emitted.dot(self.zero))
            .to_degrees();
        self.profile.eval(theta, phi)
    }
}
