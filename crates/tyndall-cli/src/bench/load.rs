//! `tyndall bench --only load`: how long big scenes take to load, the
//! targets of issue 12 — a glTF of about a million triangles (written
//! here: a wavy grid with vertex normals and texture coordinates, as an
//! exporter writes a dense scan) under 3 s, and a sparse OpenVDB cloud of
//! 512³ bounds (`--vdb FILE`, made by scenes/smoke/make_sparse_cloud.py
//! with the real OpenVDB library) under 5 s, in memory proportional to
//! its active voxels — and of issue 21: a half-float cloud of 100 M
//! active voxels (the script's `--big`) under 5 s, held in at most 1.2×
//! its voxel bytes.

use super::{BenchArgs, median};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use tyndall::Scene;
use tyndall::media::sparse::Precision;

/// Quads along each side of the grid: 2·708² = 1,002,528 triangles.
const GRID: u32 = 708;

pub fn run(args: &BenchArgs) -> Result<()> {
    let grid = if args.quick { 64 } else { GRID };
    println!("## Loading big scenes\n");
    let path = args.cache.join(format!("grid-{grid}.glb"));
    if !path.exists() {
        std::fs::create_dir_all(&args.cache)?;
        write_grid_glb(&path, grid)?;
    }
    let (mut loads, mut builds) = (Vec::new(), Vec::new());
    let mut triangles = 0;
    for _ in 0..args.runs {
        let start = Instant::now();
        let desc = tyndall_load::load(&path, Default::default())?;
        loads.push(start.elapsed());
        let start = Instant::now();
        let scene = Scene::from_desc(desc)?;
        builds.push(start.elapsed());
        triangles = scene.geometry().primitives().len();
    }
    let (load, build) = (median(&mut loads), median(&mut builds));
    println!(
        "glTF, {triangles} triangles with NORMAL and TEXCOORD_0 ({}, {:.1} MB): read and \
         converted in {:.2} s, BVH and scene built in {:.2} s, {:.2} s in all (median of {}).\n",
        path.display(),
        std::fs::metadata(&path)?.len() as f64 / 1e6,
        load.as_secs_f64(),
        build.as_secs_f64(),
        (load + build).as_secs_f64(),
        args.runs
    );
    match &args.vdb {
        Some(vdb) => vdb_load(args, vdb)?,
        None => println!(
            "OpenVDB: pass `--vdb FILE` (a sparse cloud written by \
             `/usr/bin/python3 scenes/smoke/make_sparse_cloud.py [--big] FILE`).\n"
        ),
    }
    Ok(())
}

/// Times reading grid "density" of `path` and reports its storage.
fn vdb_load(args: &BenchArgs, path: &Path) -> Result<()> {
    let mut times: Vec<Duration> = Vec::new();
    let mut report = String::new();
    for _ in 0..args.runs {
        let start = Instant::now();
        let grid = tyndall_load::vdb::read_grid(path, "density")
            .map_err(anyhow::Error::msg)
            .with_context(|| path.display().to_string())?;
        times.push(start.elapsed());
        let (voxel_bricks, tiles) = grid.brick_counts();
        let (lo, hi) = grid.active_bounds().unwrap_or_default();
        let extent = (hi - lo + 1).as_dvec3();
        let value_bytes = match grid.precision() {
            Precision::Full => 4.0,
            Precision::Half => 2.0,
        };
        let held = grid.storage_bytes() as f64;
        let nonzero = grid.nonzero_voxels();
        let dense = value_bytes * extent.element_product();
        report = format!(
            "{precision} voxels, index bounds {}×{}×{}, {voxel_bricks} voxel bricks of 8³ and \
             {tiles} constant tiles: {nonzero} voxels of non-zero density, held in {:.1} MB \
             (bricks, their maxima and the brick map), {:.3}× their {:.1} MB of voxel values \
             ({:.1} % of the dense grid's {:.0} MB)",
            extent.x,
            extent.y,
            extent.z,
            held / 1e6,
            held / (value_bytes * nonzero as f64),
            value_bytes * nonzero as f64 / 1e6,
            100.0 * held / dense,
            dense / 1e6,
            precision = match grid.precision() {
                Precision::Full => "full-precision (f32)",
                Precision::Half => "half-float",
            },
        );
    }
    println!(
        "OpenVDB {}: read in {:.2} s (median of {}); {report}.\n",
        path.display(),
        median(&mut times).as_secs_f64(),
        args.runs
    );
    Ok(())
}

/// Writes a binary glTF of an `n × n` quad grid over [−1, 1]² in the
/// x–z plane, heights `0.1·sin(6x)·cos(5z)`, with the surface's normals
/// and texture coordinates, two triangles per quad.
fn write_grid_glb(path: &PathBuf, n: u32) -> Result<()> {
    let side = n + 1;
    let mut bin: Vec<u8> = Vec::new();
    let put = |bin: &mut Vec<u8>, v: f32| bin.extend_from_slice(&v.to_le_bytes());
    let at = |i: u32| -1.0 + 2.0 * i as f32 / n as f32;
    for j in 0..side {
        for i in 0..side {
            let (x, z) = (at(i), at(j));
            for v in [x, 0.1 * (6.0 * x).sin() * (5.0 * z).cos(), z] {
                put(&mut bin, v);
            }
        }
    }
    let normals_offset = bin.len();
    for j in 0..side {
        for i in 0..side {
            let (x, z) = (at(i), at(j));
            // −∂h/∂x, 1, −∂h/∂z, normalised.
            let (dx, dz) = (
                0.6 * (6.0 * x).cos() * (5.0 * z).cos(),
                -0.5 * (6.0 * x).sin() * (5.0 * z).sin(),
            );
            let len = (dx * dx + 1.0 + dz * dz).sqrt();
            for v in [-dx / len, 1.0 / len, -dz / len] {
                put(&mut bin, v);
            }
        }
    }
    let uvs_offset = bin.len();
    for j in 0..side {
        for i in 0..side {
            put(&mut bin, i as f32 / n as f32);
            put(&mut bin, j as f32 / n as f32);
        }
    }
    let indices_offset = bin.len();
    for j in 0..n {
        for i in 0..n {
            let v = |di: u32, dj: u32| (j + dj) * side + i + di;
            for index in [v(0, 0), v(0, 1), v(1, 0), v(1, 0), v(0, 1), v(1, 1)] {
                bin.extend_from_slice(&index.to_le_bytes());
            }
        }
    }
    let vertices = side * side;
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3}}]}}],
"buffers":[{{"byteLength":{len}}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{normals_offset}}},
{{"buffer":0,"byteOffset":{normals_offset},"byteLength":{nl}}},
{{"buffer":0,"byteOffset":{uvs_offset},"byteLength":{ul}}},
{{"buffer":0,"byteOffset":{indices_offset},"byteLength":{il}}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":{vertices},"type":"VEC3","min":[-1,-0.1,-1],"max":[1,0.1,1]}},
{{"bufferView":1,"componentType":5126,"count":{vertices},"type":"VEC3"}},
{{"bufferView":2,"componentType":5126,"count":{vertices},"type":"VEC2"}},
{{"bufferView":3,"componentType":5125,"count":{count},"type":"SCALAR"}}]}}"#,
        len = bin.len(),
        nl = uvs_offset - normals_offset,
        ul = indices_offset - uvs_offset,
        il = bin.len() - indices_offset,
        count = 6 * n * n,
    );
    let glb = tyndall_load::gltf::glb_bytes(json.as_bytes(), &bin);
    std::fs::write(path, glb).with_context(|| path.display().to_string())
}
