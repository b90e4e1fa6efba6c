//! The part of Open Image Denoise's C API (`OpenImageDenoise/oidn.h`,
//! version 2) that Tyndall calls, resolved from a loaded library.
//!
//! Hand-written rather than through the `oidn` crate: that crate links
//! the library at build time, and Tyndall must build and run where it is
//! absent (the requirement); a dozen functions resolved by name
//! are the whole binding.

use libloading::Library;
use std::ffi::{c_char, c_int, c_void};

/// `OIDNDevice`, `OIDNFilter`, `OIDNBuffer`: opaque handles.
pub type Handle = *mut c_void;

/// `OIDN_DEVICE_TYPE_DEFAULT`: the library picks the device.
pub const DEVICE_TYPE_DEFAULT: c_int = 0;
/// `OIDN_FORMAT_FLOAT3`: three f32 per pixel.
pub const FORMAT_FLOAT3: c_int = 3;
/// `OIDN_ERROR_NONE`.
pub const ERROR_NONE: c_int = 0;

/// The C functions, as function pointers into the library. Each field's
/// type is the C prototype of the function of the same name in `oidn.h`
/// (OIDN 2.x): `bool` is C's `_Bool`, `size_t` is `usize`, enums are
/// `int`.
pub struct Api {
    pub new_device: unsafe extern "C" fn(c_int) -> Handle,
    pub commit_device: unsafe extern "C" fn(Handle),
    pub release_device: unsafe extern "C" fn(Handle),
    pub get_device_error: unsafe extern "C" fn(Handle, *mut *const c_char) -> c_int,
    pub new_buffer: unsafe extern "C" fn(Handle, usize) -> Handle,
    pub write_buffer: unsafe extern "C" fn(Handle, usize, usize, *const c_void),
    pub read_buffer: unsafe extern "C" fn(Handle, usize, usize, *mut c_void),
    pub release_buffer: unsafe extern "C" fn(Handle),
    pub new_filter: unsafe extern "C" fn(Handle, *const c_char) -> Handle,
    #[allow(clippy::type_complexity)]
    pub set_filter_image: unsafe extern "C" fn(
        Handle,
        *const c_char,
        Handle,
        c_int,
        usize,
        usize,
        usize,
        usize,
        usize,
    ),
    pub set_filter_bool: unsafe extern "C" fn(Handle, *const c_char, bool),
    pub commit_filter: unsafe extern "C" fn(Handle),
    pub execute_filter: unsafe extern "C" fn(Handle),
    pub release_filter: unsafe extern "C" fn(Handle),
}

impl Api {
    /// Resolves every function from `library`, or names the first one
    /// missing (a library that is not OIDN 2).
    pub fn resolve(library: &Library) -> Result<Api, String> {
        macro_rules! symbol {
            ($name:literal) => {
                // SAFETY: the symbol is looked up by its C name and given
                // the type of its prototype in oidn.h (see `Api`'s
                // fields, whose types the assignment below fixes); the
                // copied function pointer is used only while `library`
                // is loaded, which `Denoiser` guarantees by owning both.
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .map_err(|e| format!("`{}` not found ({e})", $name))?
            };
        }
        Ok(Api {
            new_device: symbol!("oidnNewDevice"),
            commit_device: symbol!("oidnCommitDevice"),
            release_device: symbol!("oidnReleaseDevice"),
            get_device_error: symbol!("oidnGetDeviceError"),
            new_buffer: symbol!("oidnNewBuffer"),
            write_buffer: symbol!("oidnWriteBuffer"),
            read_buffer: symbol!("oidnReadBuffer"),
            release_buffer: symbol!("oidnReleaseBuffer"),
            new_filter: symbol!("oidnNewFilter"),
            set_filter_image: symbol!("oidnSetFilterImage"),
            set_filter_bool: symbol!("oidnSetFilterBool"),
            commit_filter: symbol!("oidnCommitFilter"),
            execute_filter: symbol!("oidnExecuteFilter"),
            release_filter: symbol!("oidnReleaseFilter"),
        })
    }
}
