//! Writes the voxel smoke plume of `scenes/smoke.toml`:
//!
//! ```text
//! cargo run --release -p tyndall-load --example smoke_plume -- scenes/smoke/plume.tgrid
//! ```
//!
//! A rising column of smoke: a widening, drifting cone whose density is
//! broken up by fractal noise advected with height, fading in at the
//! source and out at the top. Deterministic: the file in the repository
//! is this program's output.

use glam::{UVec3, Vec3};
use tyndall::media::grid::VoxelGrid;
use tyndall::media::noise::SmokeNoise;

/// Voxels along x, y (up) and z.
const SIZE: UVec3 = UVec3::new(48, 80, 48);

fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Plume density at `u` in the unit cube (y up).
fn plume(u: Vec3, turbulence: &SmokeNoise, wisps: &SmokeNoise) -> f32 {
    let h = u.y;
    // The column drifts sideways and widens as it rises.
    let centre = Vec3::new(
        0.5 + 0.12 * (3.0 * h).sin() * h,
        h,
        0.5 + 0.08 * (2.0 * h + 1.0).cos() * h,
    );
    let radius = 0.06 + 0.34 * h;
    let d = Vec3::new(u.x - centre.x, 0.0, u.z - centre.z).length();
    // Coarse turbulence bends the edge; fine wisps carve the inside.
    let rise = Vec3::new(0.0, -1.5 * h, 0.0);
    let edge = radius * (1.0 + 0.5 * turbulence.fbm(u * 0.5 + rise));
    let body = 1.0 - smoothstep(0.5 * edge, edge, d);
    let detail = (0.55 + 0.9 * wisps.fbm(u + rise)).clamp(0.0, 1.0);
    let ends = smoothstep(0.0, 0.06, h) * (1.0 - smoothstep(0.75, 1.0, h));
    // Denser near the source, thinning as it spreads.
    body * detail * ends * (1.2 - 0.7 * h)
}

fn main() -> Result<(), String> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: smoke_plume OUTPUT.tgrid")?;
    let turbulence = SmokeNoise {
        frequency: 4.0,
        octaves: 3,
        bias: 0.0,
        seed: 11,
    };
    let wisps = SmokeNoise {
        frequency: 7.0,
        octaves: 5,
        bias: 0.0,
        seed: 5,
    };
    let mut values = Vec::with_capacity(SIZE.element_product() as usize);
    for z in 0..SIZE.z {
        for y in 0..SIZE.y {
            for x in 0..SIZE.x {
                let u = (UVec3::new(x, y, z).as_vec3() + 0.5) / SIZE.as_vec3();
                values.push(plume(u, &turbulence, &wisps).max(0.0));
            }
        }
    }
    let grid = VoxelGrid::new(SIZE, values).ok_or("the plume produced an invalid grid")?;
    std::fs::write(&path, tyndall_load::tgrid::to_bytes(&grid))
        .map_err(|e| format!("cannot write `{path}`: {e}"))?;
    eprintln!("wrote {path}: {} voxels", SIZE.element_product());
    Ok(())
}
