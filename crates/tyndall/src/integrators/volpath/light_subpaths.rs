//! The light subpaths one pass of `volpath` connects camera vertices to:
//! a pool shared by every pixel of the pass (a light vertex cache, as in
//! Davidovič et al. 2014, "Progressive Light Transport Simulation on the
//! GPU: Survey and Improvements", §4.2).
//!
//! Each camera-path vertex that connects picks one subpath of the pool
//! uniformly. The pool is a sample of independent subpaths, so the pick
//! is a subpath distributed as a freshly traced one, and every connection
//! stays unbiased; but tracing it costs the pass a few hundred light
//! flights instead of two per camera vertex, which had been a third of a
//! multiple-scattering render's time. Two vertices of one camera path
//! pick the same subpath with probability 1/M, so their connections stay
//! nearly independent (one subpath per camera path, shared by all its
//! vertices, measured 20 % more error at equal samples on
//! `fog-room-multi`). Within a pass all pixels draw from the same M
//! subpaths — the pass's image is correlated across pixels, each pixel's
//! error is not — and each pass has its own pool.

use super::mis::LightVertexDensity;
use crate::accel::Hit;
use crate::color::Rgb;
use crate::integrators::{MAX_GLASS_CROSSINGS, TRACKING_STREAM};
use crate::light_groups::LightGroup;
use crate::lights::{LeSample, Light, LightPoint};
use crate::materials::SurfaceEvent;
use crate::media::Fog;
use crate::media::tracking::{Collision, FlightOptions, VolumeTracker};
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::{IntegratorKind, RenderSettings};
use crate::visibility::RayCounts;
use glam::Vec3;
use rayon::prelude::*;

/// Seeds the pool's sequences apart from the pixels' and the caustic
/// light paths'.
const SUBPATH_SEED: u64 = 0x11c4_7ca5_e5ee_d5a1;

/// Subpaths in a pass's pool (fewer only if the pass has fewer camera
/// samples). What the pool adds to the variance of any mean over n
/// pixels of a pass is at most 1/M of a pixel's variance (the law of
/// total variance: the pool's part of a pixel's value varies less than
/// the pixel), against 1/n for independent pixels; with M = 1024 a pixel
/// is not affected and a 10×10 region by at most 10 %. Tracing them is
/// about 1 % of a 320×240 pass.
pub const POOL_SIZE: u64 = 1024;

/// A light subpath: started on a quad light (chosen uniformly, a point
/// uniform on it, a cosine-distributed direction, through thin glass) to
/// its first free-flight event y1 in the fog, and turned there by the
/// phase function to a second event y2; or, in uniform volumes, to its
/// first collision y1 there ([`LightSubpath::sample_in_volumes`]).
#[derive(Clone, Copy)]
pub(super) struct LightSubpath<'a> {
    pub(super) light: &'a Light,
    /// The light's group.
    pub(super) group: LightGroup,
    pub(super) y0: LightPoint,
    /// The light's direction y0 → y1.
    pub(super) direction: Vec3,
    pub(super) y1: Vec3,
    /// β·n_q·tint: Le·cos θ₀·n_q/(p_pos·p_dir) through the glass crossed;
    /// the light vertex's density cancels T(y0, y1), cos θ₀ and
    /// 1/|y1 − y0|² of the path's contribution. In volumes it also holds
    /// the flight's weight `σs·T/p` at y1.
    pub(super) emitted: Rgb,
    /// The solid-angle density with which NEE at y1 finds y0.
    pub(super) p_omega: f32,
    /// y1 as the light-vertex strategies see it.
    pub(super) at_y1: Option<LightVertexDensity>,
    /// The volume that scatters at y1, if y1 is a collision in the
    /// volumes (`None`: a fog event).
    pub(super) volume: Option<usize>,
    /// y2 and the turn's direction y1 → y2 (no surface between: y2 → y1 is
    /// a camera segment); `None` if the second flight left the fog.
    pub(super) second: Option<(Vec3, Vec3)>,
}

/// The pool of one pass: M independent light subpaths, `None` where a
/// subpath's first flight left the fog (such a pick connects to nothing,
/// as a fresh subpath would).
pub struct LightSubpaths<'a> {
    subpaths: Vec<Option<LightSubpath<'a>>>,
}

impl<'a> LightSubpaths<'a> {
    /// No pool: `volpath` makes no light-vertex connections (and the
    /// other integrators need none).
    pub fn none() -> Self {
        Self {
            subpaths: Vec::new(),
        }
    }

    /// The pool of sample index `sample_index` of a render with
    /// `settings`, whose passes have `samples_per_pass` camera samples
    /// (its full image's pixel count, whatever part of it is rendered:
    /// the pool must not depend on the split). Subpath `j` is the
    /// `sample_index`-th sample of its own Owen-scrambled Sobol sequence,
    /// so each subpath is stratified across passes; traced in parallel
    /// on the current rayon pool. Empty unless
    /// `volpath` with light-vertex connections applies to `scene`.
    pub fn for_pass(
        scene: &'a Scene,
        settings: &RenderSettings,
        samples_per_pass: u64,
        sample_index: u32,
        counts: &mut RayCounts,
    ) -> Self {
        if !Self::apply(scene, settings) {
            return Self::none();
        }
        let seed = settings.seed ^ SUBPATH_SEED;
        let (subpaths, flights): (Vec<_>, Vec<u64>) = (0..Self::pool_size(samples_per_pass))
            .into_par_iter()
            .map(|j| {
                let mut sampler = PixelSampler::new(seed, j, sample_index);
                let mut own = RayCounts::default();
                let subpath = match &scene.fog {
                    Some(fog) => LightSubpath::sample(scene, fog, &mut sampler, &mut own),
                    None => LightSubpath::sample_in_volumes(scene, &mut sampler, &mut own),
                };
                (subpath, own.camera)
            })
            .unzip();
        counts.camera += flights.iter().sum::<u64>();
        Self { subpaths }
    }

    /// Whether a render of `scene` with `settings` connects camera
    /// vertices to light subpaths (and so correlates the pixels of a
    /// pass): `volpath` with the strategy on, a quad light, a depth that
    /// allows a connection (x at event 1 joined to y1 makes two events),
    /// and either fog without volumes or uniform volumes without fog
    /// ([`connects_in_volumes`]; where both are, which medium a light
    /// subpath's first event lies in would need both flights' densities).
    pub fn apply(scene: &Scene, settings: &RenderSettings) -> bool {
        settings.integrator == IntegratorKind::Volpath
            && settings.strategies.connections
            && settings.max_depth >= 2
            && (scene.fog.is_some() && scene.volumes.is_empty() || connects_in_volumes(scene))
            && scene.flat_emitter_count() > 0
    }

    /// Subpaths in the pool of a pass of `samples_per_pass` camera
    /// samples: [`POOL_SIZE`], or one per sample if there are fewer.
    pub fn pool_size(samples_per_pass: u64) -> u64 {
        samples_per_pass.clamp(1, POOL_SIZE)
    }

    /// Whether camera vertices connect to light subpaths.
    pub(super) fn connect(&self) -> bool {
        !self.subpaths.is_empty()
    }

    /// The subpath `u ∈ [0, 1)` picks, each with probability 1/M.
    pub(super) fn choose(&self, u: f32) -> Option<&LightSubpath<'a>> {
        let m = self.subpaths.len();
        let j = ((u * m as f32) as usize).min(m.checked_sub(1)?);
        self.subpaths[j].as_ref()
    }
}

impl<'a> LightSubpath<'a> {
    fn sample(
        scene: &'a Scene,
        fog: &Fog,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> Option<Self> {
        let lights = scene.flat_emitter_count();
        let choice = sampler.next_1d() * lights as f32;
        let (u_point, u_direction, u_flight) =
            (sampler.next_2d(), sampler.next_2d(), sampler.next_1d());
        let (u_turn, u_flight2) = (sampler.next_2d(), sampler.next_1d());
        let (index, light, emission) = emit(scene, choice, u_point, u_direction)?;
        let (y0, direction) = (emission.point, emission.ray.direction);
        // The first flight may cross thin glass (it is not a camera segment).
        let (y1, tint) = light_flight(scene, fog, emission.ray, u_flight, true, counts)?;
        let (turn, _) = fog.phase.sample(direction, u_turn);
        let turned = Ray {
            origin: y1,
            direction: turn,
        };
        let second =
            light_flight(scene, fog, turned, u_flight2, false, counts).map(|(y2, _)| (y2, turn));
        Some(Self {
            light,
            group: scene.light_group(index),
            y0,
            direction,
            y1,
            emitted: emission.beta * tint * lights as f32,
            p_omega: light.pdf_li(y1, y0, -direction),
            at_y1: LightVertexDensity::new(scene, fog, light, y0.position, y1),
            volume: None,
            second,
        })
    }

    /// A subpath whose first event y1 is a collision in the scene's
    /// uniform volumes ([`connects_in_volumes`]): the flight is drawn by
    /// one-sample spectral MIS with the emitted light's channels as its
    /// weights, so `emitted` carries `σs·T/p` of the collision; y1's
    /// density for the balance heuristic is the flight's with even
    /// channel weights ([`LightVertexDensity::in_volumes`]). No second
    /// vertex: camera vertices in volumes connect to first ones only.
    fn sample_in_volumes(
        scene: &'a Scene,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> Option<Self> {
        let lights = scene.flat_emitter_count();
        let choice = sampler.next_1d() * lights as f32;
        let (u_point, u_direction) = (sampler.next_2d(), sampler.next_2d());
        let mut tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
        let (index, light, emission) = emit(scene, choice, u_point, u_direction)?;
        let (y0, mut ray) = (emission.point, emission.ray);
        let mut beta = emission.beta * lights as f32;
        let mut crossings = 0u32;
        // Across thin glass (it is not a camera segment), as in the fog.
        let (y1, volume) = loop {
            counts.camera += 1;
            let hit = scene.intersect(&ray, f32::INFINITY);
            let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
            let flight = tracker.sample_collision(
                &scene.volumes,
                &ray,
                0.0,
                t_hit,
                &mut beta,
                FlightOptions::default(),
            );
            match flight {
                Collision::Scatter { t, volume } => break (ray.at(t), volume),
                Collision::Absorbed => return None,
                Collision::Escaped => {}
            }
            if !pass_pane(scene, &hit?, &mut ray, &mut beta, &mut crossings) {
                return None;
            }
        };
        let direction = emission.ray.direction;
        Some(Self {
            light,
            group: scene.light_group(index),
            y0,
            direction,
            y1,
            emitted: beta,
            p_omega: light.pdf_li(y1, y0, -direction),
            at_y1: LightVertexDensity::in_volumes(scene, &mut tracker, light, y0.position, y1),
            volume: Some(volume),
            second: None,
        })
    }
}

/// Whether camera vertices in `scene`'s volumes connect to light
/// subpaths: every volume is uniform and quiet, so that the flights'
/// densities, which the balance heuristic weighs the connections by, are
/// closed-form ([`crate::media::tracking::UniformFlight`]), and there is
/// no fog.
pub(super) fn connects_in_volumes(scene: &Scene) -> bool {
    scene.fog.is_none()
        && !scene.volumes.is_empty()
        && scene
            .volumes
            .iter()
            .all(|v| v.uniform_extinction().is_some())
}

/// A light subpath's free flight along `ray` to its first fog event, with
/// one optical depth `−ln(1 − u)` spent piece by piece; across thin glass
/// panes (multiplying the tint) if `through_glass`, else stopping at any
/// surface. The event and the tint, or `None` if the flight ends on a
/// surface or leaves the scene.
fn light_flight(
    scene: &Scene,
    fog: &Fog,
    mut ray: Ray,
    u: f32,
    through_glass: bool,
    counts: &mut RayCounts,
) -> Option<(Vec3, Rgb)> {
    let mut depth_left = -(1.0 - u).ln();
    let mut tint = Rgb::ONE;
    let mut crossings = 0u32;
    loop {
        counts.camera += 1;
        let hit = scene.intersect(&ray, f32::INFINITY);
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        if let Some((a, b)) = fog.interval(&ray, 0.0, t_hit) {
            let depth = fog.sigma_t * (b - a);
            if depth_left < depth {
                return Some((ray.at(a + depth_left / fog.sigma_t), tint));
            }
            depth_left -= depth;
        }
        if !(through_glass && pass_pane(scene, &hit?, &mut ray, &mut tint, &mut crossings)) {
            return None;
        }
    }
}

/// The quad light a subpath starts on, chosen uniformly by `choice ∈
/// [0, n_q)` (n_q the scene's quad lights), and its emitted ray from
/// `u_point` and `u_direction`; a two-sided light picks its side with
/// the choice's fraction. The light's index, the light, the emission.
fn emit(
    scene: &Scene,
    choice: f32,
    u_point: glam::Vec2,
    u_direction: glam::Vec2,
) -> Option<(usize, &Light, LeSample)> {
    let lights = scene.flat_emitter_count();
    let (index, light) = scene
        .lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.is_flat_emitter())
        .nth((choice as usize).min(lights.checked_sub(1)?))?;
    let emission = light.sample_le(u_point, u_direction, choice.fract())?;
    Some((index, light, emission))
}

/// A light subpath's flight meeting the surface `hit` along `ray`: if it
/// is a thin pane, the flight passes it (`tint` takes its transmittance,
/// `ray` starts again just beyond it) and true, unless that makes more
/// than [`MAX_GLASS_CROSSINGS`]; false at any other surface.
fn pass_pane(scene: &Scene, hit: &Hit, ray: &mut Ray, tint: &mut Rgb, crossings: &mut u32) -> bool {
    let SurfaceEvent::Pane { transmittance } = scene.material(hit.primitive).event(true, false)
    else {
        return false;
    };
    *tint *= transmittance;
    *crossings += 1;
    if *crossings > MAX_GLASS_CROSSINGS {
        return false;
    }
    let p = ray.at(hit.t);
    let n = scene.geometry.normal(hit.primitive, p);
    ray.origin = offset_origin(p, n, ray.direction);
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraSpec;
    use crate::description::{Origin, SceneDesc, Sourced};
    use crate::materials::Material;
    use crate::phase::PhaseFunction;
    use crate::shapes::{Quad, Shape};

    const SIGMA_T: f32 = 0.5;

    /// A downward-facing 1 × 1 quad light in fog filling all space.
    fn lamp_in_fog() -> Scene {
        let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
        let mut desc = SceneDesc::new(Sourced::code(camera));
        let lamp = desc.add_material(Material::emitter(Rgb::splat(5.0), false), Origin::Code);
        let quad = Quad::new(Vec3::new(-0.5, 2.0, -0.5), Vec3::X, Vec3::Z, true).expect("quad");
        desc.add_shapes(vec![Shape::Quad(quad)], lamp, Origin::Code);
        desc.fog = Some(Sourced::code(Fog {
            sigma_t: SIGMA_T,
            albedo: Rgb::splat(0.9),
            phase: PhaseFunction::from_asymmetry(0.3),
            bounds: None,
        }));
        Scene::build(&desc).expect("scene")
    }

    fn settings() -> RenderSettings {
        RenderSettings {
            integrator: IntegratorKind::Volpath,
            ..RenderSettings::default()
        }
    }

    /// The pool is a function of (seed, sample index) alone, each pass's
    /// its own: a pool reused across passes would leave its sampling error
    /// in the image however many samples it took.
    #[test]
    fn each_pass_has_its_own_pool() {
        let scene = lamp_in_fog();
        let first_events = |seed: u64, pass: u32, pixels: u64| -> Vec<Vec3> {
            let settings = RenderSettings { seed, ..settings() };
            let pool =
                LightSubpaths::for_pass(&scene, &settings, pixels, pass, &mut RayCounts::default());
            pool.subpaths
                .iter()
                .map(|p| p.expect("no surface to end on").y1)
                .collect()
        };
        assert_eq!(first_events(1, 3, 1 << 20), first_events(1, 3, 1 << 20));
        assert_eq!(first_events(1, 3, 1 << 20).len(), POOL_SIZE as usize);
        assert_eq!(first_events(1, 3, 10).len(), 10);
        let (a, b, c) = (
            first_events(1, 3, 64),
            first_events(1, 4, 64),
            first_events(2, 3, 64),
        );
        assert!(
            a.iter().zip(&b).all(|(a, b)| a != b),
            "passes share subpaths"
        );
        assert!(
            a.iter().zip(&c).all(|(a, c)| a != c),
            "seeds share subpaths"
        );
    }

    /// Every subpath starts on the lamp's emitting side and flies an
    /// exponential distance: the mean of |y1 − y0| over the pool is 1/σt
    /// within 5 standard errors (1/(σt·√M)); y2, unless the turn flew
    /// back into the lamp, lies along the turn from y1.
    #[test]
    fn subpaths_fly_exponential_distances_from_the_light() {
        let scene = lamp_in_fog();
        let pool =
            LightSubpaths::for_pass(&scene, &settings(), 1 << 20, 0, &mut RayCounts::default());
        let m = pool.subpaths.len() as f32;
        let mut first = 0.0;
        for subpath in &pool.subpaths {
            let s = subpath.expect("unbounded fog keeps every flight");
            assert!(s.y1.y < 2.0 && s.direction.y < 0.0, "below the lamp");
            assert!((s.y0.position.y - 2.0).abs() < 1e-6);
            first += (s.y1 - s.y0.position).length();
            if let Some((y2, turn)) = s.second {
                assert!(((y2 - s.y1).normalize() - turn).length() < 1e-3);
            }
        }
        let (mean, bound) = (first / m, 5.0 / (SIGMA_T * m.sqrt()));
        assert!(
            (mean - 1.0 / SIGMA_T).abs() < bound,
            "{mean} vs {}",
            1.0 / SIGMA_T
        );
    }

    /// Without a quad light, without fog, or with the strategy off there
    /// is no pool.
    #[test]
    fn no_pool_where_nothing_connects() {
        let scene = lamp_in_fog();
        assert!(LightSubpaths::apply(&scene, &settings()));
        let off = |change: fn(&mut RenderSettings)| {
            let mut s = settings();
            change(&mut s);
            LightSubpaths::for_pass(&scene, &s, 100, 0, &mut RayCounts::default()).connect()
        };
        assert!(off(|_| {}));
        assert!(!off(|s| s.strategies.connections = false));
        assert!(!off(|s| s.max_depth = 1));
        assert!(!off(|s| s.integrator = IntegratorKind::Single));
    }
}
