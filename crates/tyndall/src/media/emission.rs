//! Emission of a [`super::volume::Volume`]: light a medium gives off per
//! unit length (docs/physics.md §2.5), the source term of the radiative
//! transfer equation with emission (pbrt-v4 §11.1.3 and §14.1, Novák et
//! al. 2018 §3):
//!
//! ```text
//! dL/ds = −σt·L + σs·∫p·L dω + j,   L = ∫ T(t)·j(t) dt + …
//! ```
//!
//! Tyndall's emission coefficient `j(x)` (W·sr⁻¹·m⁻² per scene unit of
//! length, per channel) is the sum of two terms:
//!
//! * a colour times a field: `j = emission · e(x)` with `e` the medium's
//!   `emission_grid` (another grid of its VDB file) or, without one, the
//!   medium's density: `emission` is radiance per unit length per unit
//!   density — Cycles' "Emission Strength × Emission Color", not
//!   multiplied by σa;
//! * blackbody emission by Kirchhoff's law: `j = blackbody_intensity ·
//!   σa(x) · B(T(x))`, with `σa = σt·(1 − albedo)` the medium's absorption,
//!   `B` the Planck radiance of [`crate::color::blackbody::rgb`] and
//!   `T = temperature_scale·value + temperature_offset` kelvin from the
//!   `temperature_grid`; `blackbody_intensity = 1` is a physical emitter
//!   (pbrt-v4's σa·Le with Le the blackbody).
//!
//! Both are positive only where the tracking majorant is: the blackbody
//! term by σa ≤ σt, the colour term on the density by its density, and an
//! emission grid by a majorant floor the volume adds where the grid is
//! positive ([`super::volume::Volume::with_emission`]).

use super::density::Density;
use crate::color::Rgb;
use crate::color::blackbody::BlackbodyTable;
use glam::Vec3;

/// Blackbody emission from a temperature field.
#[derive(Clone, Debug, PartialEq)]
pub struct Blackbody {
    /// The temperature field (in the medium's unit cube), in grid units.
    pub temperature: Density,
    /// Kelvin per grid unit.
    pub scale: f32,
    /// Kelvin added: `T = scale·value + offset`.
    pub offset: f32,
    /// Dimensionless; 1 is Kirchhoff's physical emitter.
    pub intensity: f32,
}

/// What a medium emits (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Emission {
    /// Emission coefficient per unit of `field`, W·sr⁻¹·m⁻² per unit
    /// length (linear RGB); 0 for blackbody emission alone.
    pub color: Rgb,
    /// The field `color` is multiplied by; `None`: the medium's density.
    pub field: Option<Density>,
    pub blackbody: Option<Blackbody>,
}

/// An [`Emission`] ready to evaluate: the blackbody tabulated up to the
/// field's hottest point.
#[derive(Clone, Debug)]
pub(crate) struct EmissionEval {
    pub(crate) desc: Emission,
    table: Option<BlackbodyTable>,
}

impl EmissionEval {
    pub(crate) fn new(desc: Emission) -> Self {
        let table = desc.blackbody.as_ref().map(|b| {
            let peak = b.temperature.max_in(Vec3::ZERO, Vec3::ONE);
            BlackbodyTable::new(b.scale * peak + b.offset)
        });
        Self { desc, table }
    }

    /// A bound of the largest channel of `j` over the unit-cube box
    /// `[lo, hi]`, for choosing where to sample emission: the fields'
    /// bounds there, `sigma_a_max` the largest absorption where the
    /// density is 1, and Planck's radiance at the hottest temperature
    /// (it grows with temperature at every wavelength).
    pub(crate) fn bound(&self, lo: Vec3, hi: Vec3, density: &Density, sigma_a_max: f32) -> f32 {
        let d = &self.desc;
        let field = d.field.as_ref().unwrap_or(density);
        let mut bound = d.color.max_element() * field.max_in(lo, hi);
        if let (Some(b), Some(table)) = (&d.blackbody, &self.table) {
            let hottest = b.scale * b.temperature.max_in(lo, hi) + b.offset;
            bound += b.intensity
                * sigma_a_max
                * density.max_in(lo, hi)
                * table.eval(hottest).max_element();
        }
        bound
    }

    /// `j(x)` at `u` in the unit cube, given the density there and the
    /// medium's absorption σa(x) (module doc).
    #[inline]
    pub(crate) fn eval(&self, u: Vec3, density: f32, sigma_a: Rgb) -> Rgb {
        let d = &self.desc;
        let mut j = Rgb::ZERO;
        if d.color != Rgb::ZERO {
            let e = d.field.as_ref().map_or(density, |f| f.eval(u));
            j += d.color * e;
        }
        if let (Some(b), Some(table)) = (&d.blackbody, &self.table)
            && sigma_a != Rgb::ZERO
        {
            let kelvin = b.scale * b.temperature.eval(u) + b.offset;
            j += sigma_a * table.eval(kelvin) * b.intensity;
        }
        j
    }
}
