//! A scattering vertex that a connection joins to another vertex.

use super::surfaces::SurfaceNormals;
use crate::color::Rgb;
use crate::materials::Surface;
use crate::phase::PhaseFunction;
use crate::ray::offset_origin;
use glam::Vec3;

/// A scattering vertex that a connection joins to another vertex (a
/// light vertex in `volpath`, the camera in the light tracer): how it
/// turns light towards the connection, and where a ray leaving it starts.
pub(crate) enum Scatterer<'a> {
    /// A real scattering event in a medium, reached by a path travelling
    /// along unit `arriving`.
    Medium {
        phase: &'a PhaseFunction,
        arriving: Vec3,
    },
    /// An opaque surface with its normals facing the side the path
    /// arrived from; connections join its Lambertian lobe.
    Surface {
        surface: Surface,
        normals: SurfaceNormals,
    },
}

impl Scatterer<'_> {
    /// For a connection leaving along unit `omega`: the scattering
    /// `p(θ)` (cos θ = arriving·omega) or the surface's Lambertian
    /// `ρ/π·cos θ` ([`Surface::eval`]), and the density with which
    /// continuing the path picks `omega` (phase sampling, or
    /// [`Surface::pdf`]). `None` if a surface does not scatter that way.
    pub fn scatter(&self, omega: Vec3) -> Option<(Rgb, f32)> {
        match *self {
            Scatterer::Medium { phase, arriving } => {
                let p = phase.eval(omega.dot(arriving));
                Some((Rgb::splat(p), p))
            }
            Scatterer::Surface { surface, normals } => normals.reflects(omega).then(|| {
                (
                    surface.eval(normals.shading, omega),
                    surface.pdf(normals.shading, omega),
                )
            }),
        }
    }

    /// Where a ray from `x` along `omega` starts: just off a surface.
    pub fn origin(&self, x: Vec3, omega: Vec3) -> Vec3 {
        match *self {
            Scatterer::Medium { .. } => x,
            Scatterer::Surface { normals, .. } => offset_origin(x, normals.geometric, omega),
        }
    }
}
