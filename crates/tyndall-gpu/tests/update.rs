//! `GpuMarch::update` (the live viewer's in-place updates) against a fresh
//! `GpuMarch::new` of the same scene: after each change of a sequence —
//! a turned spot, fog and camera and an intensity, the glass model, a
//! spot widened past 60° (one map face to a cube), a new image size, a
//! moved point light, an emissive mesh added (a new light, its triangles
//! in a buffer of their own) — the updated march's frames must equal a new
//! march's frames of the final state exactly.
//!
//! Why exact, not within a tolerance: an update is meant to leave every
//! buffer holding what `new` would write (uniforms with frame 0, the
//! scene's arrays, the map faces, every texel's depth and glass layers —
//! their place in the layer array may differ, which no lookup sees — and
//! zeroed sums); the same kernels then run the same
//! dispatches on the same device, and each pixel's sum is written by its
//! one invocation without atomics, so there is no reordering of f32 sums
//! that could differ by round-off. Any difference is a stale or missing
//! write — a light's map not rendered again after it turned, the sum not
//! cleared (frames already summed before the update would be added in),
//! a stale uniform — which this test exists to catch. Each step also
//! checks which maps the update says it rendered again, so a change that
//! silently rebuilds everything (correct but slow) fails too.

mod support;

use glam::Vec3;
use tyndall::description::LightDesc;
use tyndall::glass::GlassModel;
use tyndall::settings::VisibilityMode;
use tyndall::{Image, IntegratorKind, Scene, SceneDesc};
use tyndall_gpu::{Gpu, GpuMarch, InScattering, MapsRebuilt, MarchSettings};

/// Frames rendered after each update (and before the first, so the sum
/// an update must clear is not empty).
const FRAMES: u32 = 2;

fn scene_and_settings(desc: &SceneDesc) -> (Scene, MarchSettings) {
    let scene = Scene::build(desc).expect("scene");
    (scene, MarchSettings::from(&desc.settings))
}

/// The demo at `width × height`, rendered with the march (as the viewer
/// starts; its description names `single`) on the viewer's 4×4
/// interleaving tile.
fn demo(width: u32, height: u32) -> SceneDesc {
    let mut desc = tyndall_load::demo::load().expect("demo");
    (desc.settings.width, desc.settings.height) = (width, height);
    desc.settings.integrator = IntegratorKind::March;
    desc.settings.interleave = 4;
    desc
}

/// The image the viewer shows after `FRAMES` frames: for the march, the
/// young image's filtered display, which reads both the sums and their
/// in-scattered part (so a part not cleared by an update shows).
fn frames(gpu: &Gpu, march: &mut GpuMarch) -> Image {
    march.submit_frames(gpu, FRAMES);
    march.wait(gpu).expect("wait");
    march.display_image(gpu).expect("image")
}

/// The index of the first pixel where the images differ, if any.
fn first_difference(a: &Image, b: &Image) -> Option<usize> {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()), "size");
    a.pixels()
        .iter()
        .zip(b.pixels())
        .position(|(p, q)| p.to_array().map(f32::to_bits) != q.to_array().map(f32::to_bits))
}

fn spot(desc: &mut SceneDesc) -> &mut tyndall::lights::SpotLight {
    match &mut desc.lights[0].value {
        LightDesc::Spot(s) => s,
        other => panic!("the demo's first light is a spot, not {other:?}"),
    }
}

fn point(desc: &mut SceneDesc) -> &mut tyndall::lights::PointLight {
    match &mut desc.lights[1].value {
        LightDesc::Point(p) => p,
        other => panic!("the demo's second light is a point, not {other:?}"),
    }
}

#[test]
fn updates_equal_a_fresh_march_of_the_final_state() {
    const TEST: &str = "updates_equal_a_fresh_march_of_the_final_state";
    let Some(gpu) = support::gpu_or_skip(TEST) else {
        return;
    };
    let mut desc = demo(48, 32);
    desc.settings.visibility = VisibilityMode::Maps { resolution: 64 };
    let (scene, settings) = scene_and_settings(&desc);
    let mut march = GpuMarch::new(&gpu, &scene, &settings).expect("march");
    assert!(march.display_filters(), "the march's display is filtered");
    let before = frames(&gpu, &mut march);

    type Change = fn(&mut SceneDesc);
    let steps: [(&str, Change, MapsRebuilt); 8] = [
        (
            "spot turned",
            |d| {
                let s = spot(d);
                s.direction = (s.direction + Vec3::new(0.0, 0.0, 0.08)).normalize();
            },
            MapsRebuilt::Lights(vec![0]),
        ),
        (
            "fog, camera and the point's intensity",
            |d| {
                let fog = &mut d.fog.as_mut().expect("the demo has fog").value;
                fog.sigma_t *= 1.5;
                fog.albedo *= 0.8;
                d.camera.value.position += Vec3::new(0.2, 0.1, -0.1);
                d.settings.step *= 0.8;
                point(d).intensity *= 2.0;
            },
            MapsRebuilt::None,
        ),
        (
            "glass model",
            // The demo's panes do not overlap, and for one pane crossed by
            // white light the two models give the same tint (1 − α + α·c):
            // the image may stay the same; the maps must still be redone.
            |d| d.glass.model = GlassModel::Blend,
            MapsRebuilt::All,
        ),
        (
            "spot widened past 60° (cube map)",
            |d| spot(d).cos_cutoff = 70f32.to_radians().cos(),
            MapsRebuilt::All,
        ),
        (
            "resized",
            |d| (d.settings.width, d.settings.height) = (40, 30),
            MapsRebuilt::None,
        ),
        (
            "point light moved",
            |d| point(d).position += Vec3::new(-0.3, 0.0, 0.2),
            MapsRebuilt::Lights(vec![1]),
        ),
        (
            // A new light, with its triangles in a buffer that had none.
            "an emissive mesh added",
            |d| {
                use tyndall::description::Origin;
                use tyndall::materials::Material;
                use tyndall::shapes::{Shape, Triangle};
                let glow = d.add_material(
                    Material::emitter(tyndall::Rgb::new(3.0, 2.0, 1.0), true),
                    Origin::Code,
                );
                let corner = |x: f32, y: f32| Vec3::new(x, y, -1.0);
                let triangles = [
                    Triangle::new(corner(-1.0, 1.0), corner(-0.5, 1.0), corner(-0.75, 1.5)),
                    Triangle::new(corner(0.5, 1.0), corner(0.7, 1.0), corner(0.6, 1.2)),
                ]
                .map(|t| Shape::Triangle(t.expect("a proper triangle")));
                d.add_shapes(triangles.to_vec(), glow, Origin::Code);
            },
            MapsRebuilt::All,
        ),
        (
            "single scattering instead of the march",
            |d| d.settings.integrator = IntegratorKind::Single,
            MapsRebuilt::None,
        ),
    ];
    let mut last = before;
    for (what, change, expected_maps) in steps {
        change(&mut desc);
        let (scene, settings) = scene_and_settings(&desc);
        let update = march.update(&gpu, &scene, &settings).expect(what);
        assert_eq!(update.maps, expected_maps, "{what}: maps rebuilt");
        assert_eq!(march.frames(), 0, "{what}: frame count restarted");
        let updated = frames(&gpu, &mut march);
        let fresh = frames(
            &gpu,
            &mut GpuMarch::new(&gpu, &scene, &settings).expect("fresh march"),
        );
        if let Some(i) = first_difference(&updated, &fresh) {
            panic!(
                "{what}: pixel {i} is {:?} after the update, {:?} in a fresh march",
                updated.pixels()[i],
                fresh.pixels()[i]
            );
        }
        // Not vacuous: every change but the glass model's alters the image.
        let same_size = (last.width(), last.height()) == (fresh.width(), fresh.height());
        assert!(
            !same_size || what == "glass model" || first_difference(&last, &fresh).is_some(),
            "{what}: the image did not change"
        );
        last = fresh;
    }
}

/// A refused update (a step the march cannot take) leaves the march
/// rendering the scene it had.
#[test]
fn a_refused_update_changes_nothing() {
    const TEST: &str = "a_refused_update_changes_nothing";
    let Some(gpu) = support::gpu_or_skip(TEST) else {
        return;
    };
    let desc = demo(24, 16);
    let (scene, settings) = scene_and_settings(&desc);
    assert_eq!(settings.in_scattering, InScattering::March);
    let mut march = GpuMarch::new(&gpu, &scene, &settings).expect("march");
    let mut bad = settings;
    bad.step = f32::NAN;
    assert!(march.update(&gpu, &scene, &bad).is_err());
    let after = frames(&gpu, &mut march);
    let fresh = frames(
        &gpu,
        &mut GpuMarch::new(&gpu, &scene, &settings).expect("march"),
    );
    assert_eq!(first_difference(&after, &fresh), None);
}
