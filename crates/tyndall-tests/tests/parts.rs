//! Splitting a render (issue 13): tiles, sample ranges and checkpoints
//! reassemble into the single render — tiles and resumed renders bit for
//! bit, sample ranges to f64 rounding — and the light-tracing pass splits
//! the same way.

mod common;

use common::Loaded;
use common::repo;
use std::ops::ControlFlow;
use std::path::PathBuf;
use tyndall::parts::{self, Part, PartIdentity};
use tyndall::region::{PixelRect, RenderRegion};
use tyndall::render::{Accumulation, render_region, traces_light_paths};
use tyndall::settings::VisibilityMode;
use tyndall::{Image, IntegratorKind, RenderSettings};
use tyndall_image::parts::{PartCompression, read_part, write_part};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tyndall-parts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// The glass-sphere scene (caustic light paths) at a tiny size.
fn focus() -> (Loaded, RenderSettings) {
    let desc = common::load_native(&repo().join("scenes/glass-sphere-focus.toml")).expect("scene");
    let settings = RenderSettings {
        width: 36,
        height: 28,
        spp: 5,
        threads: Some(2),
        ..desc.settings
    };
    assert!(traces_light_paths(&desc.scene, &settings));
    (desc, settings)
}

/// The demo under `march` with shadow maps.
fn demo_march() -> (Loaded, RenderSettings) {
    let desc = common::demo().expect("demo");
    let settings = RenderSettings {
        width: 40,
        height: 22,
        spp: 4,
        integrator: IntegratorKind::March,
        step: 0.25,
        visibility: VisibilityMode::Maps { resolution: 64 },
        threads: Some(2),
        ..desc.settings
    };
    (desc, settings)
}

fn part(desc: &Loaded, settings: &RenderSettings, region: RenderRegion) -> Part {
    let (accumulation, _) = render_region(
        &desc.scene,
        settings,
        &region,
        None,
        &|_| {},
        &mut |_, _| ControlFlow::Continue(()),
    )
    .expect("render");
    Part {
        identity: PartIdentity::new(&desc.scene, settings),
        accumulation,
    }
}

/// Writes each part to a file and reads it back, as a farm would.
fn through_files(parts: Vec<Part>, tag: &str) -> Vec<(PathBuf, Part)> {
    parts
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            let path = scratch(&format!("{tag}-{i}.exr"));
            write_part(&path, &p, PartCompression::Rle).expect("write part");
            let back = read_part(&path).expect("read part");
            assert_eq!(back, p, "the file holds the sums exactly");
            (path, back)
        })
        .collect()
}

fn bits(image: &Image) -> Vec<[u32; 3]> {
    image
        .pixels()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// Asserts two images are identical bit for bit (reporting how many
/// pixels differ rather than printing them).
fn assert_same_bits(a: &Image, b: &Image, what: &str) {
    let (a, b) = (bits(a), bits(b));
    assert_eq!(a.len(), b.len(), "{what}: sizes differ");
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert!(differ == 0, "{what}: {differ} of {} pixels differ", a.len());
}

#[test]
fn merged_tiles_are_bit_identical_to_the_single_render() {
    for (name, (desc, settings)) in [("focus", focus()), ("demo", demo_march())] {
        let single = tyndall::render(&desc.scene, &settings, &|_| {}).expect("render");
        let n = 3;
        let tiles = (0..n)
            .map(|i| {
                let rect = PixelRect::tile(i, n, settings.width, settings.height).expect("tile");
                part(
                    &desc,
                    &settings,
                    RenderRegion {
                        rect,
                        samples: 0..settings.spp,
                    },
                )
            })
            .collect();
        // In a shuffled order: merging does not depend on it.
        let mut files = through_files(tiles, name);
        files.reverse();
        let merged = parts::merge(files).expect("merge");
        assert_same_bits(&merged.accumulation.resolve(), &single.image, name);
    }
}

#[test]
fn merged_sample_ranges_equal_the_single_render_to_rounding() {
    for (name, (desc, settings)) in [("focus", focus()), ("demo", demo_march())] {
        let single = tyndall::render(&desc.scene, &settings, &|_| {}).expect("render");
        let full = PixelRect::full(settings.width, settings.height);
        let ranges = [0..2, 2..3, 3..settings.spp];
        let pieces = ranges
            .iter()
            .map(|r| {
                part(
                    &desc,
                    &settings,
                    RenderRegion {
                        rect: full,
                        samples: r.clone(),
                    },
                )
            })
            .collect();
        let merged = parts::merge(through_files(pieces, &format!("{name}-s"))).expect("merge");
        assert_eq!(merged.accumulation.region.samples, 0..settings.spp);
        let e = tyndall_image::metrics::relative_mse(&merged.accumulation.resolve(), &single.image);
        assert!(e <= 1e-12, "{name}: relMSE {e:e}");
        // And the merged image is not trivially anything: each range alone
        // is a different (noisier) estimate.
        let alone = part(
            &desc,
            &settings,
            RenderRegion {
                rect: full,
                samples: 0..2,
            },
        );
        assert!(
            tyndall_image::metrics::relative_mse(&alone.accumulation.resolve(), &single.image)
                > 1e-6
        );
    }
}

#[test]
fn a_resumed_render_is_bit_identical_to_an_uninterrupted_one() {
    for (name, (desc, settings)) in [("focus", focus()), ("demo", demo_march())] {
        let single = tyndall::render(&desc.scene, &settings, &|_| {}).expect("render");
        let region = RenderRegion::full(settings.width, settings.height, settings.spp);
        // Stop after two passes, as a killed render's last checkpoint.
        let (stopped, _) = render_region(
            &desc.scene,
            &settings,
            &region,
            None,
            &|_| {},
            &mut |a: &Accumulation, _| {
                if a.passes() == 2 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .expect("render");
        assert_eq!(stopped.region.samples, 0..2);
        let path = scratch(&format!("{name}-checkpoint.exr"));
        let checkpoint = Part {
            identity: PartIdentity::new(&desc.scene, &settings),
            accumulation: stopped,
        };
        write_part(&path, &checkpoint, PartCompression::None).expect("write");
        let resume = read_part(&path).expect("read").accumulation;
        let (resumed, stats) = render_region(
            &desc.scene,
            &settings,
            &region,
            Some(resume),
            &|_| {},
            &mut |_, _| ControlFlow::Continue(()),
        )
        .expect("resume");
        assert_eq!(
            stats.samples,
            (settings.spp - 2) as u64 * (settings.width * settings.height) as u64,
            "only the missing passes are rendered"
        );
        assert_same_bits(&resumed.resolve(), &single.image, name);
    }
}

#[test]
fn merge_rejects_parts_that_do_not_fit() {
    let (desc, settings) = demo_march();
    let full = PixelRect::full(settings.width, settings.height);
    let tile = |i| PixelRect::tile(i, 2, settings.width, settings.height).expect("tile");
    let p = |rect, samples| part(&desc, &settings, RenderRegion { rect, samples });
    let expect_error = |parts: Vec<Part>, what: &str| {
        let files = through_files(parts, "bad");
        match parts::merge(files) {
            Err(e) => assert!(e.to_string().contains(what), "{e} should say {what}"),
            Ok(_) => panic!("merged parts that do not fit ({what})"),
        }
    };
    expect_error(vec![p(full, 0..2), p(full, 3..4)], "gap");
    expect_error(vec![p(full, 0..2), p(full, 1..4)], "overlap");
    expect_error(vec![p(tile(0), 0..2), p(full, 2..3)], "overlap");
    expect_error(vec![p(tile(0), 0..2), p(tile(1), 0..3)], "same samples");
    // A different seed is a different render.
    let other = RenderSettings {
        seed: 9,
        ..settings
    };
    let foreign = part(
        &desc,
        &other,
        RenderRegion {
            rect: tile(1),
            samples: 0..2,
        },
    );
    expect_error(vec![p(tile(0), 0..2), foreign], "different scenes");
}

#[test]
fn a_lone_tile_is_not_a_whole_image_but_two_are() {
    let (desc, settings) = demo_march();
    let tile = |i| PixelRect::tile(i, 2, settings.width, settings.height).expect("tile");
    let p = |rect| {
        part(
            &desc,
            &settings,
            RenderRegion {
                rect,
                samples: 0..1,
            },
        )
    };
    // One tile alone merges to itself (a rectangle, not the image).
    let one = parts::merge(through_files(vec![p(tile(0))], "lone")).expect("one");
    assert_eq!(one.accumulation.region.rect, tile(0));
    let both = parts::merge(through_files(vec![p(tile(0)), p(tile(1))], "two")).expect("two");
    assert_eq!(
        both.accumulation.region.rect,
        PixelRect::full(settings.width, settings.height)
    );
}

#[test]
fn scene_hash_follows_what_changes_the_samples() {
    let (desc, settings) = demo_march();
    let h = |s: &RenderSettings| parts::scene_hash(&desc.scene, s);
    let base = h(&settings);
    assert_eq!(
        base,
        h(&RenderSettings {
            spp: 99,
            threads: Some(1),
            exposure: 2.0,
            ..settings
        })
    );
    for changed in [
        RenderSettings {
            seed: 1,
            ..settings
        },
        RenderSettings {
            width: 41,
            ..settings
        },
        RenderSettings {
            step: 0.2,
            ..settings
        },
        RenderSettings {
            visibility: VisibilityMode::ShadowRays,
            ..settings
        },
        RenderSettings {
            integrator: IntegratorKind::Single,
            ..settings
        },
    ] {
        assert_ne!(base, h(&changed));
    }
    let (focus, _) = focus();
    assert_ne!(parts::scene_hash(&focus.scene, &settings), base);
}

/// Two loads of one OpenVDB scene are one scene to its parts (and
/// checkpoints): the hash reads a sparse grid's contents in a canonical
/// order. It followed the brick map's iteration order, which the standard
/// hasher's random keys made differ from one load (and one process) to
/// the next, so the parts of a VDB scene rendered apart never merged.
/// The same grid under another extinction is another scene.
#[test]
fn scene_hash_of_a_vdb_scene_is_the_same_on_every_load() {
    let path = repo().join("scenes/reference/smoke-grid/smoke-grid.toml");
    let load = || common::load_native(&path).expect("scene");
    let (a, b) = (load(), load());
    let settings = RenderSettings {
        width: 8,
        height: 6,
        spp: 2,
        ..a.settings
    };
    let base = parts::scene_hash(&a.scene, &settings);
    assert_eq!(base, parts::scene_hash(&b.scene, &settings));
    // What the hash is for: sample ranges rendered from the two loads merge.
    let full = PixelRect::full(settings.width, settings.height);
    let range = |desc: &Loaded, samples| {
        part(
            desc,
            &settings,
            RenderRegion {
                rect: full,
                samples,
            },
        )
    };
    let pieces = vec![range(&a, 0..1), range(&b, 1..2)];
    parts::merge(through_files(pieces, "vdb-loads")).expect("parts of two loads merge");
    let denser = std::fs::read_to_string(&path)
        .expect("scene text")
        .replace(
            "sigma_t = [12.0, 12.0, 12.0]",
            "sigma_t = [12.0, 12.0, 12.5]",
        )
        .replace(
            "file = \"smoke-grid.vdb\"",
            &format!("file = {:?}", path.with_file_name("smoke-grid.vdb")),
        );
    let denser = common::scene(&denser);
    assert_ne!(base, parts::scene_hash(&denser.scene, &settings));
}

/// Tiles divide the light-tracing work, not just its output: their rays
/// add up to the single render's exactly (tracing every light path in
/// every tile would count the light paths' rays once per tile).
#[test]
fn tiles_share_the_light_paths() {
    let (desc, settings) = focus();
    let region = |rect| RenderRegion {
        rect,
        samples: 0..settings.spp,
    };
    let rays = |rect| {
        let (_, stats) = render_region(
            &desc.scene,
            &settings,
            &region(rect),
            None,
            &|_| {},
            &mut |_, _| ControlFlow::Continue(()),
        )
        .expect("render");
        stats.rays
    };
    let full = rays(PixelRect::full(settings.width, settings.height));
    let tiles: Vec<_> = (0..4)
        .map(|i| rays(PixelRect::tile(i, 4, settings.width, settings.height).expect("tile")))
        .collect();
    assert_eq!(tiles.iter().map(|r| r.camera).sum::<u64>(), full.camera);
    assert_eq!(tiles.iter().map(|r| r.shadow).sum::<u64>(), full.shadow);
    // Light paths were traced at all: more rays than camera samples.
    assert!(full.camera > (settings.width * settings.height * settings.spp) as u64);
}

/// Damage (issue 28): `tyndall merge` took a part with four flipped bits
/// in its pixel data and wrote NaN, infinite and negative pixels with
/// exit 0, and a damaged checkpoint was resumed silently. Now every part
/// carries a checksum of its header and sums. Four bits are flipped at
/// each of a spread of offsets through an uncompressed part file (the
/// focus scene's, with both layers), every one of them in the pixel data
/// of a camera or light sum, the derived image channels, or the header;
/// reading must either refuse the file or give back exactly the part
/// written — a derived image channel is not read, so damage there changes
/// nothing — never a different part.
#[test]
fn damaged_parts_are_refused_never_read_as_other_sums() {
    let (desc, settings) = focus();
    let written = part(&desc, &settings, RenderRegion::full(36, 28, 2));
    let path = scratch("damage-original.exr");
    write_part(&path, &written, PartCompression::None).expect("write part");
    let bytes = std::fs::read(&path).expect("read back");
    let damaged = scratch("damage.exr");
    let (mut refused, mut harmless) = (0, 0);
    for offset in (0..bytes.len() - 1).step_by(bytes.len() / 397) {
        let mut copy = bytes.clone();
        copy[offset] ^= 0x81;
        copy[offset + 1] ^= 0x18;
        std::fs::write(&damaged, &copy).expect("write damaged copy");
        match read_part(&damaged) {
            Err(_) => refused += 1,
            Ok(back) => {
                assert_eq!(
                    back, written,
                    "bits flipped at byte {offset} changed the sums read"
                );
                harmless += 1;
            }
        }
    }
    // The sums outnumber the image channels and header: most flips are
    // refused.
    assert!(
        refused > 2 * harmless,
        "{refused} refused, {harmless} harmless"
    );
    // The message says what is wrong, naming the file.
    let sums_at = bytes.len() - 64;
    let mut copy = bytes.clone();
    copy[sums_at] ^= 0x0f;
    std::fs::write(&damaged, &copy).expect("write damaged copy");
    let e = read_part(&damaged).expect_err("a flipped sum").to_string();
    assert!(
        e.starts_with(&damaged.display().to_string()) && e.contains("checksum"),
        "{e}"
    );
}

/// The AOVs (first-surface guides and radiance components) split and
/// merge as the radiance does: merged tiles and a resumed render hold the
/// single render's sums bit for bit, merged sample ranges to f64
/// rounding, and a part without them does not merge with parts that have
/// them.
#[test]
fn parts_carry_the_aovs() {
    let (desc, plain) = demo_march();
    let settings = RenderSettings {
        guides: true,
        components: true,
        ..plain
    };
    let full = PixelRect::full(settings.width, settings.height);
    let whole = |samples| {
        part(
            &desc,
            &settings,
            RenderRegion {
                rect: full,
                samples,
            },
        )
    };
    let single = whole(0..settings.spp).accumulation;
    let single_guides = single.guides.clone().expect("guides kept");
    assert!(
        single_guides
            .iter()
            .any(|g| g.hits > 0 && g.albedo != glam::DVec3::ZERO)
    );

    let tiles = (0..3)
        .map(|i| {
            let rect = PixelRect::tile(i, 3, settings.width, settings.height).expect("tile");
            part(
                &desc,
                &settings,
                RenderRegion {
                    rect,
                    samples: 0..settings.spp,
                },
            )
        })
        .collect();
    let merged = parts::merge(through_files(tiles, "guides-t")).expect("merge");
    assert_eq!(
        merged.accumulation.guides.as_ref(),
        Some(&single_guides),
        "tiles"
    );
    assert_eq!(merged.accumulation.components, single.components, "tiles");
    assert!(
        single
            .components
            .iter()
            .flatten()
            .any(|c| c[1] != glam::DVec3::ZERO)
    );

    let ranges = vec![whole(0..1), whole(1..settings.spp)];
    let merged = parts::merge(through_files(ranges, "guides-s")).expect("merge");
    let resolved = merged.accumulation.resolve_guides().expect("guides");
    let expected = single.resolve_guides().expect("guides");
    for aov in tyndall::aov::Aov::ALL.into_iter().filter(|a| a.is_guide()) {
        let (a, b) = (
            resolved.get(aov).expect("a guide"),
            expected.get(aov).expect("a guide"),
        );
        for (p, q) in a.pixels().iter().zip(b.pixels()) {
            let close = |u: f32, v: f32| u == v || (u - v).abs() <= 1e-6 * v.abs().max(1.0);
            assert!((0..3).all(|c| close(p[c], q[c])), "{aov:?}: {p} vs {q}");
        }
    }

    let region = RenderRegion::full(settings.width, settings.height, settings.spp);
    let (stopped, _) = render_region(
        &desc.scene,
        &settings,
        &region,
        None,
        &|_| {},
        &mut |a: &Accumulation, _| {
            if a.passes() == 1 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .expect("render");
    let checkpoint = through_files(
        vec![Part {
            identity: PartIdentity::new(&desc.scene, &settings),
            accumulation: stopped,
        }],
        "guides-c",
    );
    let resume = checkpoint.into_iter().next().expect("one").1.accumulation;
    // Resumed without guides, the checkpoint does not fit.
    let refused = render_region(
        &desc.scene,
        &plain,
        &region,
        Some(resume.clone()),
        &|_| {},
        &mut |_, _| ControlFlow::Continue(()),
    );
    match refused {
        Err(e) => assert!(e.to_string().contains("guides"), "{e}"),
        Ok(_) => panic!("a checkpoint with guides resumed a render without"),
    }
    let (resumed, _) = render_region(
        &desc.scene,
        &settings,
        &region,
        Some(resume),
        &|_| {},
        &mut |_, _| ControlFlow::Continue(()),
    )
    .expect("resume");
    assert_eq!(resumed.guides.as_ref(), Some(&single_guides), "resumed");
    assert_eq!(resumed.components, single.components, "resumed");

    let without = part(
        &desc,
        &plain,
        RenderRegion {
            rect: PixelRect::tile(1, 2, settings.width, settings.height).expect("tile"),
            samples: 0..settings.spp,
        },
    );
    let with = part(
        &desc,
        &settings,
        RenderRegion {
            rect: PixelRect::tile(0, 2, settings.width, settings.height).expect("tile"),
            samples: 0..settings.spp,
        },
    );
    match parts::merge(through_files(vec![with, without], "guides-mixed")) {
        Err(e) => assert!(e.to_string().contains("guides"), "{e}"),
        Ok(_) => panic!("merged parts with and without guides"),
    }
}
