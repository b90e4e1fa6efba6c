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
//! * blackbody emission from a temperature field,
//!   `T = temperature_scale·value + temperature_offset` kelvin from the
//!   `temperature_grid`, by one of two laws ([`BlackbodyLaw`]):
//!   - Kirchhoff's (the default): `j = blackbody_intensity · σa(x) ·
//!     B(T(x))`, with `σa = σt·(1 − albedo)` the medium's absorption and
//!     `B` the Planck radiance of [`crate::color::blackbody::rgb`];
//!     `blackbody_intensity = 1` is a physical emitter (pbrt-v4's σa·Le
//!     with Le the blackbody);
//!   - Cycles' Principled Volume's: `j = tint · (σ_SB·10⁻⁶/π) ·
//!     ((1 − b) + b·T⁴) · ĉ(T)`, with b the `blackbody_intensity`, σ_SB
//!     the Stefan–Boltzmann constant and ĉ the blackbody's colour at
//!     luminance 1 ([`crate::color::blackbody::unit_luminance_rgb`]):
//!     independent of density and absorption, as Cycles' kernel computes
//!     it (docs/physics.md §2.5, where it is derived).
//!
//! Each is positive only where the tracking majorant is: Kirchhoff's term
//! by σa ≤ σt, the colour term on the density by its density; an emission
//! grid, and a temperature field under Cycles' law, by a majorant floor
//! the volume adds where they are positive
//! ([`super::volume::Volume::with_emission`]).

use super::density::Density;
use crate::color::Rgb;
use crate::color::blackbody::{self, BlackbodyTable};
use glam::Vec3;

/// How a temperature becomes an emission coefficient (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BlackbodyLaw {
    /// `j = intensity · σa · B(T)`: thermal emission by Kirchhoff's law.
    Kirchhoff,
    /// `j = tint · (σ_SB·10⁻⁶/π) · ((1 − intensity) + intensity·T⁴) ·
    /// ĉ(T)`: Cycles' Principled Volume, `intensity` its "Blackbody
    /// Intensity" (0 to 1) and `tint` its "Blackbody Tint".
    Cycles { tint: Rgb },
}

impl BlackbodyLaw {
    /// The law's function of temperature alone, W·sr⁻¹·m⁻² per unit
    /// length per unit of what multiplies it (σa·intensity for
    /// Kirchhoff's, the tint for Cycles').
    fn of_temperature(self, intensity: f32) -> impl Fn(f64) -> Rgb {
        let b = intensity as f64;
        let cycles_scale = blackbody::stefan_boltzmann() * 1e-6 / std::f64::consts::PI;
        move |kelvin| match self {
            Self::Kirchhoff => blackbody::rgb(kelvin),
            Self::Cycles { .. } => {
                let power = cycles_scale * ((1.0 - b) + b * kelvin.powi(4));
                blackbody::unit_luminance_rgb(kelvin) * power as f32
            }
        }
    }
}

/// Blackbody emission from a temperature field.
#[derive(Clone, Debug, PartialEq)]
pub struct Blackbody {
    /// The temperature field (in the medium's unit cube), in grid units.
    pub temperature: Density,
    /// Kelvin per grid unit.
    pub scale: f32,
    /// Kelvin added: `T = scale·value + offset`.
    pub offset: f32,
    /// Dimensionless; 1 is Kirchhoff's physical emitter, and Cycles'
    /// T⁴ law without its constant term.
    pub intensity: f32,
    pub law: BlackbodyLaw,
}

/// Where a blackbody emits regardless of absorption.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EmitsUnabsorbed {
    /// Nowhere (Kirchhoff's law: only where it absorbs).
    Nowhere,
    /// Where the temperature field is positive.
    WhereHot,
    /// Everywhere in the volume (Cycles' law below intensity 1, or with a
    /// temperature offset).
    Everywhere,
}

impl Blackbody {
    /// Where the emission may be positive without absorption.
    pub(crate) fn emits_unabsorbed(&self) -> EmitsUnabsorbed {
        match self.law {
            BlackbodyLaw::Kirchhoff => EmitsUnabsorbed::Nowhere,
            BlackbodyLaw::Cycles { tint } if tint == Rgb::ZERO => EmitsUnabsorbed::Nowhere,
            BlackbodyLaw::Cycles { .. } if self.intensity < 1.0 || self.offset > 0.0 => {
                EmitsUnabsorbed::Everywhere
            }
            BlackbodyLaw::Cycles { .. } => EmitsUnabsorbed::WhereHot,
        }
    }
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
            BlackbodyTable::of(b.scale * peak + b.offset, b.law.of_temperature(b.intensity))
        });
        Self { desc, table }
    }

    /// A bound of the largest channel of `j` over the unit-cube box
    /// `[lo, hi]`, for choosing where to sample emission: the fields'
    /// bounds there, `sigma_a_max` the largest absorption where the
    /// density is 1, and the blackbody law's largest value up to the
    /// hottest temperature.
    pub(crate) fn bound(&self, lo: Vec3, hi: Vec3, density: &Density, sigma_a_max: f32) -> f32 {
        let d = &self.desc;
        let field = d.field.as_ref().unwrap_or(density);
        let mut bound = d.color.max_element() * field.max_in(lo, hi);
        if let (Some(b), Some(table)) = (&d.blackbody, &self.table) {
            let hottest = b.scale * b.temperature.max_in(lo, hi) + b.offset;
            let law = table.max_up_to(hottest);
            bound += match b.law {
                BlackbodyLaw::Kirchhoff => b.intensity * sigma_a_max * density.max_in(lo, hi) * law,
                BlackbodyLaw::Cycles { tint } => tint.max_element() * law,
            };
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
        if let (Some(b), Some(table)) = (&d.blackbody, &self.table) {
            let kelvin = || b.scale * b.temperature.eval(u) + b.offset;
            match b.law {
                BlackbodyLaw::Kirchhoff if sigma_a != Rgb::ZERO => {
                    j += sigma_a * table.eval(kelvin()) * b.intensity;
                }
                BlackbodyLaw::Kirchhoff => {}
                // Cycles reads voxels by stochastic one-tap interpolation
                // (kernel/util/texture_3d.h): its mean is the law at the
                // voxels, interpolated.
                BlackbodyLaw::Cycles { tint } => {
                    j += tint
                        * b.temperature
                            .eval_mapped(u, |v| table.eval(b.scale * v + b.offset));
                }
            }
        }
        j
    }
}
