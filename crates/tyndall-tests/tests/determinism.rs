//! Determinism under load (issue 9, item 5): the same scene, seed and
//! settings give the same EXR file, byte for byte, whatever the number of
//! threads and however busy the machine is.

mod common;

use common::Loaded;
use common::{render, repo, scene};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use tyndall::IntegratorKind;
use tyndall::settings::VisibilityMode;

/// Threads that spin until dropped, so that the render's workers are
/// preempted and finish their rows, chunks and blocks in varying order.
struct BusyThreads {
    stop: Arc<AtomicBool>,
    handles: Vec<std::thread::JoinHandle<()>>,
}

impl BusyThreads {
    fn start(n: usize) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let handles = (0..n)
            .map(|i| {
                let stop = Arc::clone(&stop);
                std::thread::spawn(move || {
                    let mut x = i as u64;
                    while !stop.load(Ordering::Relaxed) {
                        x = std::hint::black_box(
                            x.wrapping_mul(6364136223846793005).wrapping_add(1),
                        );
                    }
                })
            })
            .collect();
        Self { stop, handles }
    }
}

impl Drop for BusyThreads {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for h in self.handles.drain(..) {
            let _ = h.join();
        }
    }
}

/// The bytes of the EXR file of a render at `threads` threads.
fn exr_bytes(
    desc: &Loaded,
    kind: IntegratorKind,
    visibility: VisibilityMode,
    threads: usize,
    (width, height): (u32, u32),
) -> Vec<u8> {
    let image = render(desc, |s| {
        s.width = width;
        s.height = height;
        s.spp = 2;
        s.integrator = kind;
        s.step = 0.25;
        s.visibility = visibility;
        s.threads = Some(threads);
    });
    let dir = std::env::temp_dir().join(format!("tyndall-determinism-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(format!("{kind:?}-{}-{threads}.exr", visibility.name()));
    tyndall_image::write_image(&image, &path, 0.0).expect("write exr");
    let bytes = std::fs::read(&path).expect("read exr");
    let _ = std::fs::remove_file(&path);
    bytes
}

/// Every integrator, with shadow rays and shadow maps, on the demo; and
/// `volpath` with caustic light paths (a glass sphere focusing a spot):
/// 1, 2 and 3 threads while three other threads spin, compared byte for
/// byte. The images are wider than one 64-pixel EXR tile and taller than
/// one 16-line block, so block order in the file is exercised too.
#[test]
fn exr_files_are_identical_for_1_2_3_threads_under_load() {
    let _busy = BusyThreads::start(3);
    let demo = common::demo().expect("demo");
    let maps = VisibilityMode::Maps { resolution: 64 };
    for kind in IntegratorKind::ALL {
        for visibility in [VisibilityMode::ShadowRays, maps] {
            let files: Vec<Vec<u8>> = [1, 2, 3]
                .map(|t| exr_bytes(&demo, kind, visibility, t, (80, 36)))
                .into();
            assert!(files[0].len() > 100);
            assert!(
                files[1] == files[0] && files[2] == files[0],
                "{kind:?} with {} differs between 1, 2 and 3 threads",
                visibility.name()
            );
        }
    }
    let focus =
        common::load_native(&repo().join("scenes/glass-sphere-focus.toml")).expect("focus scene");
    assert!(tyndall::testing::has_caustics(&focus.scene));
    let files: Vec<Vec<u8>> = [1, 2, 3]
        .map(|t| {
            exr_bytes(
                &focus,
                IntegratorKind::Volpath,
                VisibilityMode::ShadowRays,
                t,
                (72, 40),
            )
        })
        .into();
    assert!(
        files[1] == files[0] && files[2] == files[0],
        "caustics differ"
    );
}

/// The cause of the issue: EXR blocks stored in the order parallel
/// compression finished them. Written files must declare, and have,
/// increasing block order.
#[test]
fn exr_blocks_are_stored_in_increasing_order() {
    let desc = scene(
        r#"
        [camera]
        position = [0, 0, 5]
        look_at = [0, 0, 0]
        fov_y_deg = 40
        [[lights]]
        type = "point"
        position = [0, 2, 0]
        intensity = 1.0
        [fog]
        sigma_t = 0.2
        albedo = 0.5
        "#,
    );
    let image = render(&desc, |s| {
        s.width = 150;
        s.height = 70;
        s.spp = 1;
    });
    let path = std::env::temp_dir().join(format!("tyndall-order-{}.exr", std::process::id()));
    tyndall_image::write_image(&image, &path, 0.0).expect("write");
    let meta = exr::meta::MetaData::read_from_file(&path, false).expect("meta");
    let _ = std::fs::remove_file(&path);
    let header = &meta.headers[0];
    assert_eq!(
        header.line_order,
        exr::meta::attribute::LineOrder::Increasing
    );
    assert!(header.chunk_count > 1, "the test needs several blocks");
}
