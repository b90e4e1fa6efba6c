//! Denoising for Tyndall: Intel Open Image Denoise (OIDN 2), the field's
//! standard machine-learned denoiser for Monte Carlo renders (Áfra,
//! "Intel Open Image Denoise", <https://www.openimagedenoise.org>),
//! loaded at run time so that Tyndall builds and runs without it.
//!
//! [`Denoiser::find`] looks for the library (see [`Denoiser::find`] for
//! where); [`Denoiser::denoise`] runs OIDN's `RT` filter on a
//! high-dynamic-range radiance image, guided by the first-surface albedo
//! and normal ([`tyndall::guides`]) when given. The guides are averaged
//! over the pixel's samples and so carry some noise themselves (edges,
//! textures, depth of field); as OIDN's documentation recommends for that
//! case, each guide can first be denoised by its own `RT` filter
//! ("prefiltering", [`DenoiseGuides::prefilter`]); the radiance is then
//! filtered with `cleanAux`.

mod ffi;

use ffi::{Api, Handle};
use libloading::Library;
use std::ffi::{CStr, CString, c_void};
use std::path::{Path, PathBuf};
use tyndall::{Image, Rgb};

/// The environment variable naming the OIDN library file, or the folder
/// holding it.
pub const LIBRARY_VARIABLE: &str = "TYNDALL_OIDN";

/// The library's file name on this platform.
#[cfg(target_os = "macos")]
pub const LIBRARY_NAME: &str = "libOpenImageDenoise.2.dylib";
#[cfg(windows)]
pub const LIBRARY_NAME: &str = "OpenImageDenoise.dll";
#[cfg(not(any(target_os = "macos", windows)))]
pub const LIBRARY_NAME: &str = "libOpenImageDenoise.so.2";

/// How to get the library, for error messages.
pub const HOW_TO_GET_IT: &str = "install it with `pip install pyoidn` (its wheel ships libOpenImageDenoise 2.5) and set TYNDALL_OIDN to the wheel's library folder, which `python3 -c \"import pyoidn, os; print(os.path.join(os.path.dirname(pyoidn.__file__), 'oidn', 'lib'))\"` prints (inside an active virtual environment it is found without it), or install Open Image Denoise 2 system-wide";

/// Why denoising could not run.
#[derive(Debug, thiserror::Error)]
pub enum DenoiseError {
    #[error("Open Image Denoise was not found (tried {}); {HOW_TO_GET_IT}", tried.join(", "))]
    NotFound { tried: Vec<String> },
    #[error("{}: this is not a usable Open Image Denoise 2 library: {message}", path.display())]
    Load { path: PathBuf, message: String },
    #[error("Open Image Denoise failed: {0}")]
    Device(String),
    #[error("the {name} guide is {got_w}×{got_h} but the image is {w}×{h}")]
    GuideSize {
        name: &'static str,
        got_w: u32,
        got_h: u32,
        w: u32,
        h: u32,
    },
}

/// The feature images that guide the denoiser: the first-surface albedo
/// and normal of the same pixels ([`tyndall::guides::Guides`]).
#[derive(Clone, Copy)]
pub struct DenoiseGuides<'a> {
    pub albedo: &'a Image,
    pub normal: &'a Image,
    /// Denoise each guide first (two more filter runs: three times the
    /// time), as OIDN advises for noisy guides; without it the guides are
    /// taken as clean. On the shared reference scenes the two are equally
    /// good (docs/benchmarks.md, "Denoising and AOVs"); textured surfaces at a few
    /// samples per pixel give noisy albedo.
    pub prefilter: bool,
}

/// A loaded Open Image Denoise library.
pub struct Denoiser {
    api: Api,
    path: PathBuf,
    // Declared last, dropped last: `api`'s function pointers point into it.
    _library: Library,
}

impl Denoiser {
    /// Finds and loads the library: the file or folder that the
    /// environment variable [`LIBRARY_VARIABLE`] names if it is set (and
    /// nothing else then); otherwise [`LIBRARY_NAME`] by the system's
    /// library search, then in the `pyoidn` wheel of the active Python
    /// virtual environment (`$VIRTUAL_ENV`).
    pub fn find() -> Result<Denoiser, DenoiseError> {
        if let Some(named) = std::env::var_os(LIBRARY_VARIABLE) {
            let named = PathBuf::from(named);
            let path = if named.is_dir() {
                named.join(LIBRARY_NAME)
            } else {
                named
            };
            return Denoiser::load(&path);
        }
        let mut tried = vec![format!("the system's libraries ({LIBRARY_NAME})")];
        if let Ok(denoiser) = Denoiser::load(Path::new(LIBRARY_NAME)) {
            return Ok(denoiser);
        }
        for path in wheel_libraries() {
            if path.exists() {
                return Denoiser::load(&path);
            }
            tried.push(path.display().to_string());
        }
        tried.push(format!("${LIBRARY_VARIABLE} (not set)"));
        Err(DenoiseError::NotFound { tried })
    }

    /// Loads the library at `path` (a bare file name goes through the
    /// system's library search).
    pub fn load(path: &Path) -> Result<Denoiser, DenoiseError> {
        let load = |message: String| DenoiseError::Load {
            path: path.to_owned(),
            message,
        };
        // SAFETY: loading a library runs its initialisers. OIDN's are
        // its C++ runtime's static constructors, which have no
        // preconditions; a library that is not OIDN is refused below by
        // its missing symbols before any of its functions is called.
        let library = unsafe { Library::new(path) }.map_err(|e| load(e.to_string()))?;
        let api = Api::resolve(&library).map_err(load)?;
        Ok(Denoiser {
            api,
            path: path.to_owned(),
            _library: library,
        })
    }

    /// The library file loaded.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `beauty` (linear HDR radiance) denoised by OIDN's `RT` filter,
    /// with `guides` (prefiltered if they ask) as clean auxiliary images.
    pub fn denoise(
        &self,
        beauty: &Image,
        guides: Option<DenoiseGuides>,
    ) -> Result<Image, DenoiseError> {
        let (w, h) = (beauty.width(), beauty.height());
        if let Some(g) = guides {
            for (name, image) in [("albedo", g.albedo), ("normal", g.normal)] {
                if (image.width(), image.height()) != (w, h) {
                    return Err(DenoiseError::GuideSize {
                        name,
                        got_w: image.width(),
                        got_h: image.height(),
                        w,
                        h,
                    });
                }
            }
        }
        let device = Device::new(&self.api)?;
        let color = device.buffer(beauty)?;
        let output = device.buffer(beauty)?;
        let mut images = vec![("color", &color), ("output", &output)];
        let guide_buffers = match guides {
            Some(g) => Some((device.buffer(g.albedo)?, device.buffer(g.normal)?)),
            None => None,
        };
        if let Some((albedo, normal)) = &guide_buffers {
            // Prefiltering: each guide denoised in place by its own filter.
            if guides.is_some_and(|g| g.prefilter) {
                for (name, buffer) in [("albedo", albedo), ("normal", normal)] {
                    device.run_filter(&[(name, buffer), ("output", buffer)], w, h, &[])?;
                }
            }
            images.push(("albedo", albedo));
            images.push(("normal", normal));
        }
        let flags: &[(&str, bool)] = match guides {
            Some(_) => &[("hdr", true), ("cleanAux", true)],
            None => &[("hdr", true)],
        };
        device.run_filter(&images, w, h, flags)?;
        output.read(w, h)
    }
}

/// Where a `pyoidn` wheel in the active virtual environment keeps the
/// library: `$VIRTUAL_ENV/lib/python3.*/site-packages/pyoidn/oidn/lib`.
fn wheel_libraries() -> Vec<PathBuf> {
    let Some(venv) = std::env::var_os("VIRTUAL_ENV") else {
        return Vec::new();
    };
    let lib = PathBuf::from(venv).join("lib");
    let Ok(entries) = std::fs::read_dir(&lib) else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with("python3"))
        .map(|e| {
            e.path()
                .join("site-packages/pyoidn/oidn/lib")
                .join(LIBRARY_NAME)
        })
        .collect();
    found.sort();
    found
}

/// An OIDN device, released when dropped.
struct Device<'a> {
    api: &'a Api,
    handle: Handle,
}

impl<'a> Device<'a> {
    fn new(api: &'a Api) -> Result<Self, DenoiseError> {
        // SAFETY: `oidnNewDevice` takes a device type and returns a new
        // handle or null; it has no other precondition.
        let handle = unsafe { (api.new_device)(ffi::DEVICE_TYPE_DEFAULT) };
        if handle.is_null() {
            return Err(DenoiseError::Device("no device could be created".into()));
        }
        let device = Device { api, handle };
        // SAFETY: `handle` is a live device (not null, released only on drop).
        unsafe { (api.commit_device)(handle) };
        device.check()?;
        Ok(device)
    }

    /// The device's pending error, if any.
    fn check(&self) -> Result<(), DenoiseError> {
        let mut message: *const std::ffi::c_char = std::ptr::null();
        // SAFETY: the device is live and `message` a valid out-pointer;
        // OIDN sets it to null or to a NUL-terminated string it owns,
        // valid until the next call on the device, and we copy it at once.
        let code = unsafe { (self.api.get_device_error)(self.handle, &mut message) };
        if code == ffi::ERROR_NONE {
            return Ok(());
        }
        let text = if message.is_null() {
            format!("error code {code}")
        } else {
            // SAFETY: see above: a NUL-terminated string owned by OIDN.
            unsafe { CStr::from_ptr(message) }
                .to_string_lossy()
                .into_owned()
        };
        Err(DenoiseError::Device(text))
    }

    /// A device buffer holding `image`'s pixels (three f32 each).
    fn buffer(&self, image: &Image) -> Result<Buffer<'_>, DenoiseError> {
        let pixels = image.pixels();
        let bytes = std::mem::size_of_val(pixels);
        // SAFETY: the device is live; OIDN returns a buffer of `bytes`
        // bytes or null with the error recorded on the device.
        let handle = unsafe { (self.api.new_buffer)(self.handle, bytes) };
        self.check()?;
        if handle.is_null() {
            return Err(DenoiseError::Device("a buffer could not be created".into()));
        }
        let buffer = Buffer {
            device: self,
            handle,
            bytes,
        };
        // SAFETY: `Rgb` is glam's `Vec3`, three contiguous f32 with no
        // padding (size 12, asserted below), so `pixels` is `bytes`
        // readable bytes of f32 triples; the buffer holds `bytes` bytes.
        const _: () = assert!(std::mem::size_of::<Rgb>() == 12);
        unsafe {
            (self.api.write_buffer)(handle, 0, bytes, pixels.as_ptr() as *const c_void);
        }
        self.check()?;
        Ok(buffer)
    }

    /// Runs a new `RT` filter on `images` (name, buffer: `w`×`h` FLOAT3)
    /// with the boolean parameters `flags`.
    fn run_filter(
        &self,
        images: &[(&str, &Buffer)],
        w: u32,
        h: u32,
        flags: &[(&str, bool)],
    ) -> Result<(), DenoiseError> {
        let c = |s: &str| CString::new(s).expect("parameter names have no NUL");
        // SAFETY: the device is live and the type a NUL-terminated string.
        let handle = unsafe { (self.api.new_filter)(self.handle, c("RT").as_ptr()) };
        self.check()?;
        if handle.is_null() {
            return Err(DenoiseError::Device(
                "the RT filter could not be created".into(),
            ));
        }
        let filter = Filter {
            api: self.api,
            handle,
        };
        for (name, buffer) in images {
            // SAFETY: the filter and buffer are live; the buffer holds
            // w·h FLOAT3 pixels, which byte offset 0 and strides 0
            // (meaning packed) describe.
            unsafe {
                (self.api.set_filter_image)(
                    filter.handle,
                    c(name).as_ptr(),
                    buffer.handle,
                    ffi::FORMAT_FLOAT3,
                    w as usize,
                    h as usize,
                    0,
                    0,
                    0,
                );
            }
        }
        for (name, value) in flags {
            // SAFETY: a live filter and a NUL-terminated parameter name.
            unsafe { (self.api.set_filter_bool)(filter.handle, c(name).as_ptr(), *value) };
        }
        // SAFETY: a live filter whose images were set above.
        unsafe { (self.api.commit_filter)(filter.handle) };
        self.check()?;
        // SAFETY: a committed filter; `oidnExecuteFilter` is synchronous.
        unsafe { (self.api.execute_filter)(filter.handle) };
        self.check()
    }
}

impl Drop for Device<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released once, here; buffers and
        // filters borrow the device, so they were released before.
        unsafe { (self.api.release_device)(self.handle) };
    }
}

/// An OIDN buffer, released when dropped.
struct Buffer<'d> {
    device: &'d Device<'d>,
    handle: Handle,
    bytes: usize,
}

impl Buffer<'_> {
    /// The buffer's `w`×`h` pixels as an image.
    fn read(&self, w: u32, h: u32) -> Result<Image, DenoiseError> {
        let mut pixels = vec![Rgb::ZERO; w as usize * h as usize];
        assert_eq!(std::mem::size_of_val(pixels.as_slice()), self.bytes);
        // SAFETY: the buffer is live and holds `bytes` bytes; `pixels` is
        // `bytes` writable bytes of f32 triples (see `Device::buffer`),
        // and any bit pattern is a valid f32.
        unsafe {
            (self.device.api.read_buffer)(
                self.handle,
                0,
                self.bytes,
                pixels.as_mut_ptr() as *mut c_void,
            );
        }
        self.device.check()?;
        Ok(Image::from_pixels(w, h, pixels))
    }
}

impl Drop for Buffer<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released once, here.
        unsafe { (self.device.api.release_buffer)(self.handle) };
    }
}

/// An OIDN filter, released when dropped.
struct Filter<'a> {
    api: &'a Api,
    handle: Handle,
}

impl Drop for Filter<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released once, here.
        unsafe { (self.api.release_filter)(self.handle) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A library that is not OIDN is refused by name, not called.
    #[test]
    fn a_library_that_is_not_oidn_is_refused() {
        let libc = if cfg!(target_os = "linux") {
            "libc.so.6"
        } else {
            return;
        };
        match Denoiser::load(Path::new(libc)) {
            Err(DenoiseError::Load { message, .. }) => {
                assert!(message.contains("oidnNewDevice"), "{message}")
            }
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("libc was taken for OIDN"),
        }
    }

    /// A missing file is an error naming it.
    #[test]
    fn a_missing_library_is_named() {
        let path = Path::new("/nonexistent/libOpenImageDenoise.so.2");
        let e = Denoiser::load(path).err().expect("no such file");
        assert!(e.to_string().contains("/nonexistent/"), "{e}");
    }
}
