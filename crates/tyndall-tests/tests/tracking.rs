//! Delta (spectral) tracking and ratio tracking against independent
//! computation: the closed form in a homogeneous voxel grid and in a
//! mesh-bounded medium, Simpson quadrature of the optical depth in
//! procedural smoke, and the free-flight distance distribution.
//!
//! Every estimate is a mean of N independent one-sample estimates and is
//! compared within 5 of its own standard errors (plus a small absolute
//! slack for f32 rounding): a correct estimator fails with probability
//! below 1e-6 per comparison.
mod common;

use common::simpson;
use glam::{UVec3, Vec3};
use tyndall::Rgb;
use tyndall::media::grid::VoxelGrid;
use tyndall::media::noise::SmokeNoise;
use tyndall::media::tracking::{Collision, FlightOptions, VolumeTracker};
use tyndall::media::volume::{Density, MeshRegion, Volume, VolumeRegion};
use tyndall::phase::PhaseFunction;
use tyndall::ray::Ray;
use tyndall::shapes::{Bounds, Triangle};
use tyndall::testing::RandomStream;

const N: usize = 100_000;

fn unit_box() -> Bounds {
    Bounds::new(Vec3::splat(-1.0), Vec3::splat(1.0))
}

fn volume(sigma_t: Rgb, albedo: f32, density: Density, region: VolumeRegion) -> Volume {
    Volume::new(
        sigma_t,
        Rgb::splat(albedo),
        PhaseFunction::Isotropic,
        density,
        region,
    )
    .expect("volume")
}

/// Mean and standard error per channel of `N` draws of `estimate`.
fn mean_and_stderr(mut estimate: impl FnMut() -> Rgb) -> (Rgb, Rgb) {
    let (mut sum, mut sum2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..N {
        let e = estimate().as_dvec3();
        sum += e;
        sum2 += e * e;
    }
    let n = N as f64;
    let mean = sum / n;
    let var = (sum2 / n - mean * mean).max(glam::DVec3::ZERO) * (n / (n - 1.0));
    (mean.as_vec3(), (var / n).map(f64::sqrt).as_vec3())
}

fn assert_close(what: &str, (mean, stderr): (Rgb, Rgb), exact: Rgb) {
    for c in 0..3 {
        assert!(
            (mean[c] - exact[c]).abs() <= 5.0 * stderr[c] + 1e-4,
            "{what}, channel {c}: {mean} ± {stderr}, exact {exact}"
        );
    }
}

/// Ratio tracking's transmittance and spectral tracking's escape weight
/// (in an absorbing medium the throughput of an escaped flight) both
/// estimate `T` per channel.
fn check_estimators(what: &str, volumes: &[Volume], ray: &Ray, t1: f32, exact: Rgb) {
    let mut tracker = VolumeTracker::new(RandomStream::new(42));
    let ratio = mean_and_stderr(|| tracker.transmittance(volumes, ray, 0.0, t1));
    assert_close(&format!("{what}: ratio tracking"), ratio, exact);
    let delta = mean_and_stderr(|| {
        let mut throughput = Rgb::ONE;
        match tracker.sample_collision(
            volumes,
            ray,
            0.0,
            t1,
            &mut throughput,
            FlightOptions::default(),
        ) {
            Collision::Escaped => throughput,
            _ => Rgb::ZERO,
        }
    });
    assert_close(&format!("{what}: spectral tracking"), delta, exact);
}

/// A grid of constant density 0.7 with RGB extinction: `T = exp(−σt·0.7·L)`
/// per channel, L the chord through the box.
#[test]
fn homogeneous_grid_matches_closed_form() {
    let size = UVec3::new(5, 6, 7);
    let grid = VoxelGrid::new(size, vec![0.7; 210]).unwrap();
    let sigma_t = Rgb::new(0.4, 0.9, 1.6);
    let v = volume(
        sigma_t,
        0.0,
        Density::Grid(grid),
        VolumeRegion::Box(unit_box()),
    );
    let ray = Ray::new(Vec3::new(-3.0, 0.2, -0.1), Vec3::new(1.0, 0.1, 0.05));
    let (a, b) = unit_box().clip_ray(&ray, 0.0, 10.0).unwrap();
    let exact = (-sigma_t * 0.7 * (b - a)).exp();
    check_estimators("homogeneous grid", &[v], &ray, 10.0, exact);
}

/// Procedural smoke: the exact transmittance is `exp(−∫σt)`, the optical
/// depth integrated by Simpson's rule with 4096 intervals along the chord
/// (the density is smooth, so the quadrature error is far below the
/// statistical tolerance).
#[test]
fn smoke_matches_quadrature() {
    let noise = SmokeNoise {
        frequency: 3.0,
        octaves: 4,
        bias: 0.25,
        seed: 3,
    };
    let sigma_t = Rgb::new(2.0, 3.0, 4.5);
    let v = volume(
        sigma_t,
        0.0,
        Density::Noise(noise),
        VolumeRegion::Box(unit_box()),
    );
    for dir in [Vec3::new(1.0, 0.1, 0.05), Vec3::new(1.0, -0.2, 0.15)] {
        let ray = Ray::new(Vec3::new(-2.5, 0.3, -0.2), dir);
        let (a, b) = unit_box().clip_ray(&ray, 0.0, 10.0).unwrap();
        let depth = |c: usize| {
            simpson(
                |t| v.extinction_at(ray.at(t as f32))[c] as f64,
                a as f64,
                b as f64,
                4096,
            )
        };
        let exact = Rgb::new(
            (-depth(0)).exp() as f32,
            (-depth(1)).exp() as f32,
            (-depth(2)).exp() as f32,
        );
        assert!(
            exact.min_element() > 0.05 && exact.max_element() < 0.95,
            "the test ray should cross real smoke: {exact}"
        );
        check_estimators("smoke", std::slice::from_ref(&v), &ray, 10.0, exact);
    }
}

/// Two overlapping volumes add: the transmittance is the product.
#[test]
fn overlapping_volumes_multiply_transmittance() {
    let a = volume(
        Rgb::new(0.5, 0.6, 0.7),
        0.0,
        Density::Uniform,
        VolumeRegion::Box(unit_box()),
    );
    let inner = Bounds::new(Vec3::splat(-0.5), Vec3::splat(0.5));
    let b = volume(
        Rgb::new(1.5, 0.2, 0.9),
        0.0,
        Density::Uniform,
        VolumeRegion::Box(inner),
    );
    let ray = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
    let exact = (-Rgb::new(0.5, 0.6, 0.7) * 2.0 - Rgb::new(1.5, 0.2, 0.9)).exp();
    check_estimators("overlap", &[a, b], &ray, 10.0, exact);
}

/// A medium bounded by a closed mesh (an octahedron |x|+|y|+|z| ≤ 1):
/// along the x axis the chord is 2.
#[test]
fn mesh_bounded_medium_matches_closed_form() {
    let p = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let mut triangles = Vec::new();
    for &x in &p[0..2] {
        for &y in &p[2..4] {
            for &z in &p[4..6] {
                triangles.push(Triangle::new(x, y, z).unwrap());
            }
        }
    }
    let sigma_t = Rgb::new(0.3, 0.5, 0.8);
    let v = volume(
        sigma_t,
        0.0,
        Density::Uniform,
        VolumeRegion::Mesh(MeshRegion::new(triangles)),
    );
    // Slightly off the axis so the ray meets faces, not the vertex:
    // at y = z = 0.05 the chord is 2·(1 − 0.1).
    let ray = Ray::new(Vec3::new(-4.0, 0.05, 0.05), Vec3::X);
    let exact = (-sigma_t * 1.8).exp();
    check_estimators("octahedron", &[v], &ray, 10.0, exact);
}

/// Delta tracking's collision distances in a grey, non-absorbing
/// homogeneous grid follow `P(t < s) = 1 − exp(−σt·(s − a))`: a
/// histogram of 8 bins over the chord against the exact probabilities,
/// each within 5 binomial standard errors.
#[test]
fn free_flight_distances_follow_beer_lambert() {
    let grid = VoxelGrid::new(UVec3::splat(4), vec![1.0; 64]).unwrap();
    let sigma = 0.6;
    let v = volume(
        Rgb::splat(sigma),
        1.0,
        Density::Grid(grid),
        VolumeRegion::Box(unit_box()),
    );
    let ray = Ray::new(Vec3::new(-2.0, 0.1, 0.2), Vec3::X);
    let (a, b) = (1.0f32, 3.0f32);
    let mut tracker = VolumeTracker::new(RandomStream::new(7));
    let mut bins = [0u32; 9];
    for _ in 0..N {
        let mut throughput = Rgb::ONE;
        match tracker.sample_collision(
            std::slice::from_ref(&v),
            &ray,
            0.0,
            10.0,
            &mut throughput,
            FlightOptions::default(),
        ) {
            Collision::Scatter { t, .. } => {
                assert_eq!(throughput, Rgb::ONE, "grey tracking never reweights");
                let bin = (((t - a) / (b - a)) * 8.0).clamp(0.0, 7.0) as usize;
                bins[bin] += 1;
            }
            Collision::Escaped => bins[8] += 1,
            Collision::Absorbed => panic!("albedo 1 never absorbs"),
        }
    }
    let cdf = |s: f32| 1.0 - (-sigma * (s - a)).exp();
    for (i, &count) in bins.iter().enumerate() {
        let p = if i < 8 {
            let w = (b - a) / 8.0;
            cdf(a + w * (i + 1) as f32) - cdf(a + w * i as f32)
        } else {
            1.0 - cdf(b)
        } as f64;
        let expected = p * N as f64;
        let sd = (N as f64 * p * (1.0 - p)).sqrt();
        assert!(
            (count as f64 - expected).abs() <= 5.0 * sd,
            "bin {i}: {count} vs {expected:.0} ± {sd:.0}"
        );
    }
}

/// Where a flight scatters, weighted, against the closed form: in a
/// medium of constant extinction σt the expected weighted throughput of
/// the flights that scatter in volume i between s0 and s1 along the chord
/// is `β·σs_i·(e^{−σt·s0} − e^{−σt·s1})/σt` per channel (β the incoming
/// throughput), and that of the flights that escape is `β·e^{−σt·ℓ}`.
/// Two overlapping chromatic volumes (a box inside one filling all space)
/// with unequal albedos and an uneven incoming throughput; the same
/// volumes drawn as uniform (closed-form flights by spectral MIS), as
/// uniform with the flights also aimed at a point beside the box
/// (equiangular sampling mixed in), and with the box a constant voxel
/// grid (spectral tracking there) must all match. Eight bins along the
/// box's chord, per volume, within 5 standard errors.
#[test]
fn scattering_in_uniform_media_matches_closed_form() {
    let outer_sigma = Rgb::new(0.45, 0.3, 0.15);
    let outer_albedo = Rgb::new(0.8, 0.9, 0.97);
    let inner_sigma = Rgb::new(0.2, 1.1, 0.6);
    let inner_albedo = Rgb::new(0.5, 0.95, 0.3);
    let beta = Rgb::new(0.2, 1.0, 0.5);
    let (a, b) = (2.0f32, 4.0f32);
    let ray = Ray::new(Vec3::new(-3.0, 0.1, -0.2), Vec3::X);
    let make = |grid: bool| -> [Volume; 2] {
        let inner_density = if grid {
            Density::Grid(VoxelGrid::new(UVec3::splat(3), vec![1.0; 27]).unwrap())
        } else {
            Density::Uniform
        };
        let outer = Volume::new(
            outer_sigma,
            outer_albedo,
            PhaseFunction::Isotropic,
            Density::Uniform,
            VolumeRegion::Everywhere,
        )
        .unwrap();
        let inner = Volume::new(
            inner_sigma,
            inner_albedo,
            PhaseFunction::Isotropic,
            inner_density,
            VolumeRegion::Box(unit_box()),
        )
        .unwrap();
        [outer, inner]
    };
    // The box spans t ∈ [a, b] of the ray; the flight ends at t = 6.
    let end = 6.0f32;
    let bins = 8;
    let width = (b - a) / bins as f32;
    // Optical depth at t per channel, and the expected weighted share
    // of each (volume, bin), then of the outer volume before and after
    // the box, then the escape.
    let depth = |t: f32| outer_sigma * t + inner_sigma * (t.clamp(a, b) - a);
    let between = |t0: f32, t1: f32, sigma_s: Rgb, sigma_t: Rgb| {
        beta * sigma_s * ((-depth(t0)).exp() - (-depth(t1)).exp()) / sigma_t
    };
    let inside = outer_sigma + inner_sigma;
    let mut exact = Vec::new();
    for k in 0..bins {
        let (t0, t1) = (a + width * k as f32, a + width * (k + 1) as f32);
        exact.push(between(t0, t1, outer_sigma * outer_albedo, inside));
        exact.push(between(t0, t1, inner_sigma * inner_albedo, inside));
    }
    exact.push(between(0.0, a, outer_sigma * outer_albedo, outer_sigma));
    exact.push(between(b, end, outer_sigma * outer_albedo, outer_sigma));
    exact.push(beta * (-depth(end)).exp());
    let aim = Vec3::new(0.4, 0.9, 0.1);
    for (label, grid, aim) in [
        ("closed-form flights", false, None),
        ("closed-form flights aimed at a point", false, Some(aim)),
        ("tracking", true, None),
    ] {
        let volumes = make(grid);
        let mut tracker = VolumeTracker::new(RandomStream::new(5 + grid as u64));
        let mut sums = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO); exact.len()];
        for _ in 0..N {
            let mut throughput = beta;
            let options = FlightOptions { emitted: None, aim };
            let slot = match tracker.sample_collision(
                &volumes,
                &ray,
                0.0,
                end,
                &mut throughput,
                options,
            ) {
                Collision::Scatter { t, volume } if t < a => {
                    assert_eq!(volume, 0, "only the outer volume is before the box");
                    2 * bins
                }
                Collision::Scatter { t, volume } if t >= b => {
                    assert_eq!(volume, 0, "only the outer volume is past the box");
                    2 * bins + 1
                }
                Collision::Scatter { t, volume } => {
                    2 * (((t - a) / width) as usize).min(bins - 1) + volume
                }
                Collision::Escaped => 2 * bins + 2,
                Collision::Absorbed => continue,
            };
            let e = throughput.as_dvec3();
            sums[slot].0 += e;
            sums[slot].1 += e * e;
        }
        let n = N as f64;
        for (slot, (&(sum, sum2), &expected)) in sums.iter().zip(&exact).enumerate() {
            let mean = sum / n;
            let stderr =
                ((sum2 / n - mean * mean).max(glam::DVec3::ZERO) / (n - 1.0)).map(f64::sqrt);
            assert_close(
                &format!("{label}, slot {slot}"),
                (mean.as_vec3(), stderr.as_vec3()),
                expected,
            );
        }
    }
}

/// `UniformFlight` describes the flights `sample_collision` draws: with
/// albedo 1 every collision scatters, so the share of unaimed flights
/// whose collision falls in a bin is the integral of
/// `UniformFlight::density` over it (16-point midpoint quadrature here),
/// within 5 binomial standard errors, for an uneven incoming throughput
/// across three uniform pieces (a box inside a haze filling all space,
/// so the density jumps and the channel weights change at each piece).
/// Its transmittance is the closed form `exp(−∫σt)`, and its
/// in-scattering the two volumes' `σs·p(θ)` inside the box and the
/// haze's alone outside.
#[test]
fn uniform_flight_density_is_the_collision_density() {
    let outer_sigma = Rgb::new(0.9, 0.3, 0.1);
    let inner_sigma = Rgb::new(0.2, 1.1, 0.6);
    let outer_phase = PhaseFunction::from_asymmetry(0.4);
    let inner_phase = PhaseFunction::Isotropic;
    let inner_albedo = Rgb::new(1.0, 0.5, 0.25);
    // A white haze filling all space and a box of albedo `box_albedo`.
    let haze_and_box = |box_albedo: Rgb| {
        [
            Volume::new(
                outer_sigma,
                Rgb::ONE,
                outer_phase,
                Density::Uniform,
                VolumeRegion::Everywhere,
            )
            .expect("haze"),
            Volume::new(
                inner_sigma,
                box_albedo,
                inner_phase,
                Density::Uniform,
                VolumeRegion::Box(unit_box()),
            )
            .expect("box"),
        ]
    };
    let volumes = haze_and_box(inner_albedo);
    let beta = Rgb::new(1.0, 0.05, 0.3);
    let (a, b, end) = (2.0f32, 4.0f32, 6.0f32);
    let ray = Ray::new(Vec3::new(-3.0, 0.1, -0.2), Vec3::X);
    let mut tracker = VolumeTracker::new(RandomStream::new(9));
    let mut flight = tyndall::media::tracking::UniformFlight::default();
    assert!(tracker.describe_uniform_flight(&volumes, &ray, 0.0, end, beta, &mut flight));

    let depth = |t: f32| outer_sigma * t + inner_sigma * (t.clamp(a, b) - a);
    for t in [0.5f32, 2.5, 3.9, 5.5] {
        let exact = (-depth(t)).exp();
        let got = flight.transmittance(t);
        assert!(
            (got - exact).abs().max_element() < 1e-5,
            "T({t}): {got} vs {exact}"
        );
        let cos = 0.3;
        let inside = (a..b).contains(&t);
        let mut sigma_p = outer_sigma * outer_phase.eval(cos);
        if inside {
            sigma_p += inner_sigma * inner_albedo * inner_phase.eval(cos);
        }
        let got = flight.in_scattering(&volumes, t, cos);
        assert!(
            (got - sigma_p).abs().max_element() < 1e-5,
            "σs·p at {t}: {got} vs {sigma_p}"
        );
    }

    // An absorbed flight reports no distance: the density is checked
    // with both volumes at albedo 1, where every collision scatters.
    let white = haze_and_box(Rgb::ONE);
    assert!(tracker.describe_uniform_flight(&white, &ray, 0.0, end, beta, &mut flight));
    let bins = 24usize;
    let width = end / bins as f32;
    let mut counts = vec![0u32; bins];
    for _ in 0..N {
        let mut throughput = beta;
        let options = FlightOptions::default();
        if let Collision::Scatter { t, .. } =
            tracker.sample_collision(&white, &ray, 0.0, end, &mut throughput, options)
        {
            counts[((t / width) as usize).min(bins - 1)] += 1;
        }
    }
    for (k, &count) in counts.iter().enumerate() {
        let t0 = width * k as f32;
        let p: f32 = (0..16)
            .map(|j| flight.density(t0 + width * (j as f32 + 0.5) / 16.0) * width / 16.0)
            .sum();
        let share = count as f32 / N as f32;
        let stderr = (p * (1.0 - p) / N as f32).sqrt();
        assert!(
            (share - p).abs() <= 5.0 * stderr + 2e-4,
            "bin {k} at t = {t0}: share {share} vs ∫density {p} (σ {stderr:.2e})"
        );
    }
}
