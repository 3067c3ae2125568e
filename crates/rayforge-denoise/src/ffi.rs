//! The only code of the workspace that calls Intel Open Image Denoise: its library opened by
//! path, the dozen functions of its C API (`oidn.h`, OIDN 2) that rayforge uses looked up by
//! name, and safe wrappers that own each handle they make and release it on drop.
//!
//! Every `unsafe` block here rests on one of three facts, said where it is used: the symbol's
//! type is its declaration in `oidn.h` (C's `bool` is Rust's, `size_t` is `usize`, enums are
//! `int`), the library outlives every function pointer taken from it (they live in the same
//! [`Library`], which nothing can take apart), and a handle is used only between the call that
//! made it and its release (each is private to the wrapper that drops it).

use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `OIDN_DEVICE_TYPE_CPU`: the CPU device, whatever GPUs the machine has, so that results do
/// not depend on them.
const DEVICE_TYPE_CPU: c_int = 1;

/// `OIDN_FORMAT_FLOAT3`: three 32-bit floats a pixel.
const FORMAT_FLOAT3: c_int = 3;

/// `OIDN_ERROR_NONE`.
const ERROR_NONE: c_int = 0;

type Handle = *mut c_void;

/// The functions of OIDN's C API that rayforge calls, each with its `oidn.h` signature.
struct Api {
    new_device: unsafe extern "C" fn(c_int) -> Handle,
    set_device_int: unsafe extern "C" fn(Handle, *const c_char, c_int),
    set_device_bool: unsafe extern "C" fn(Handle, *const c_char, bool),
    get_device_int: unsafe extern "C" fn(Handle, *const c_char) -> c_int,
    commit_device: unsafe extern "C" fn(Handle),
    get_device_error: unsafe extern "C" fn(Handle, *mut *const c_char) -> c_int,
    release_device: unsafe extern "C" fn(Handle),
    new_filter: unsafe extern "C" fn(Handle, *const c_char) -> Handle,
    #[allow(clippy::type_complexity)]
    set_shared_filter_image: unsafe extern "C" fn(
        Handle,
        *const c_char,
        *mut c_void,
        c_int,
        usize,
        usize,
        usize,
        usize,
        usize,
    ),
    set_filter_bool: unsafe extern "C" fn(Handle, *const c_char, bool),
    commit_filter: unsafe extern "C" fn(Handle),
    execute_filter: unsafe extern "C" fn(Handle),
    release_filter: unsafe extern "C" fn(Handle),
}

/// An opened OIDN library and its functions.
pub struct Library {
    api: Api,
    // Dropped after `api` (fields drop in order), though nothing calls through `api` then.
    _library: libloading::Library,
    path: PathBuf,
}

impl Library {
    /// Opens the library at `path` (a bare file name asks the system's loader to search) and
    /// looks up every function rayforge calls; the error is the loader's message.
    pub fn open(path: &Path) -> Result<Self, String> {
        // SAFETY: opening a library runs its initialisers. OIDN's are C++ static constructors
        // that set up its own tables; this is the library the caller asked for by name.
        let library = unsafe { libloading::Library::new(path) }.map_err(|e| e.to_string())?;
        macro_rules! function {
            ($name:literal) => {
                // SAFETY: the field's type is the function's declaration in `oidn.h`; the
                // pointer is kept only in `Library`, beside the library it points into.
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .map_err(|e| format!("it has no function {}: {e}", $name))?
            };
        }
        let api = Api {
            new_device: function!("oidnNewDevice"),
            set_device_int: function!("oidnSetDeviceInt"),
            set_device_bool: function!("oidnSetDeviceBool"),
            get_device_int: function!("oidnGetDeviceInt"),
            commit_device: function!("oidnCommitDevice"),
            get_device_error: function!("oidnGetDeviceError"),
            release_device: function!("oidnReleaseDevice"),
            new_filter: function!("oidnNewFilter"),
            set_shared_filter_image: function!("oidnSetSharedFilterImage"),
            set_filter_bool: function!("oidnSetFilterBool"),
            commit_filter: function!("oidnCommitFilter"),
            execute_filter: function!("oidnExecuteFilter"),
            release_filter: function!("oidnReleaseFilter"),
        };
        Ok(Self {
            api,
            _library: library,
            path: path.to_path_buf(),
        })
    }

    /// Where the library was opened from (as asked: a bare name when the system found it).
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// A committed CPU device of `library` running `threads` threads of its own, not pinned to
/// cores (the renderer's pool shares them); the error is OIDN's message.
pub fn cpu_device(library: &Arc<Library>, threads: usize) -> Result<Device, String> {
    let api = &library.api;
    // SAFETY: `oidnNewDevice` takes a device type and returns a new handle or null.
    let handle = unsafe { (api.new_device)(DEVICE_TYPE_CPU) };
    if handle.is_null() {
        // SAFETY: with a null device, OIDN reports the error of this thread's last call.
        return Err(unsafe { error_of(api, handle) }
            .unwrap_or_else(|| "OIDN made no CPU device".to_string()));
    }
    let device = Device {
        library: library.clone(),
        handle,
    };
    let threads = c_int::try_from(threads).unwrap_or(c_int::MAX);
    // SAFETY: a live device handle and NUL-terminated parameter names from `oidn.h`.
    unsafe {
        (api.set_device_int)(handle, c"numThreads".as_ptr(), threads);
        (api.set_device_bool)(handle, c"setAffinity".as_ptr(), false);
        (api.commit_device)(handle);
    }
    device.check()?;
    Ok(device)
}

/// OIDN's message for the error `device` holds (clearing it), if there is one.
///
/// # Safety
/// `device` is a live device handle of `api`'s library, or null for the thread's error.
unsafe fn error_of(api: &Api, device: Handle) -> Option<String> {
    let mut message: *const c_char = std::ptr::null();
    // SAFETY: as the function's contract; `message` is written with a string OIDN owns,
    // valid until its next call, and copied at once.
    let code = unsafe { (api.get_device_error)(device, &mut message) };
    if code == ERROR_NONE {
        return None;
    }
    let text = if message.is_null() {
        String::new()
    } else {
        // SAFETY: a NUL-terminated string from OIDN, read before any other call.
        unsafe { CStr::from_ptr(message) }
            .to_string_lossy()
            .into_owned()
    };
    Some(format!("{text} (OIDN error {code})"))
}

/// A committed OIDN device; released on drop.
pub struct Device {
    library: Arc<Library>,
    handle: Handle,
}

// SAFETY: a device is an OIDN object reached through its handle, and OIDN documents that
// "all API calls are thread-safe" (its API reference, on objects), so calls may come from
// any thread. Errors are kept "per device" for "each user thread": every method here makes
// its calls and reads their error on one thread, within the one call, so moving the device
// to another thread between calls loses no error. `Device` is not `Sync`: the wrappers never
// use one handle from two threads at once.
unsafe impl Send for Device {}

impl Device {
    /// OIDN's version as `oidn.h` writes it (20501 for 2.5.1).
    pub fn version(&self) -> i32 {
        // SAFETY: a live device handle and a parameter name from `oidn.h`.
        unsafe { (self.library.api.get_device_int)(self.handle, c"version".as_ptr()) }
    }

    /// The error the device holds for this thread, if any.
    fn check(&self) -> Result<(), String> {
        // SAFETY: a live device handle of this library.
        match unsafe { error_of(&self.library.api, self.handle) } {
            Some(message) => Err(message),
            None => Ok(()),
        }
    }

    /// A new `RT` filter for images of `width × height` pixels, its `flags` (`hdr`,
    /// `cleanAux`) set; committed by its first [`RtFilter::execute`], which sets its images.
    pub fn rt_filter(
        &self,
        width: usize,
        height: usize,
        flags: &[(&CStr, bool)],
    ) -> Result<RtFilter, String> {
        let api = &self.library.api;
        // SAFETY: a live device handle and the filter type's NUL-terminated name.
        let handle = unsafe { (api.new_filter)(self.handle, c"RT".as_ptr()) };
        self.check()?;
        if handle.is_null() {
            return Err("OIDN made no RT filter".to_string());
        }
        let filter = RtFilter {
            library: self.library.clone(),
            handle,
            width,
            height,
        };
        for (name, value) in flags {
            // SAFETY: a live filter handle and a NUL-terminated parameter name.
            unsafe { (api.set_filter_bool)(filter.handle, name.as_ptr(), *value) };
        }
        self.check()?;
        Ok(filter)
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: the handle is live, and this is its one release.
        unsafe { (self.library.api.release_device)(self.handle) }
    }
}

/// An OIDN `RT` filter for images of one size, made by [`Device::rt_filter`]; released on
/// drop.
///
/// OIDN keeps the image pointers a filter was last given. Here they are set again by every
/// [`RtFilter::execute`] (always the same names: a filter's inputs are fixed when it is made)
/// from that call's borrows, and OIDN reads or writes them only while that call runs: between
/// calls the filter holds stale pointers that nothing dereferences (releasing a filter does
/// not touch its images). Re-setting images of the same size and format only moves them, and
/// OIDN's commit then keeps what it built: its reference says a filter is best reused "as
/// long as these images have the same size, format, and features (i.e., only the memory
/// locations and pixel values may be different)".
pub struct RtFilter {
    library: Arc<Library>,
    handle: Handle,
    width: usize,
    height: usize,
}

// SAFETY: as for `Device`: OIDN's calls are thread-safe, each `execute` makes its calls and
// reads their error on one thread, and the stale image pointers a filter keeps between calls
// are never read (see the type's doc). Not `Sync`: `execute` takes `&mut self`.
unsafe impl Send for RtFilter {}

impl RtFilter {
    /// Runs the filter once on `device` (the one that made it): each of `inputs` (`color`,
    /// `albedo`, `normal`: the same names on every call) and `output` an image of the
    /// filter's size, three 32-bit floats a pixel, row by row. Returns when the output is
    /// written.
    pub fn execute(
        &mut self,
        device: &Device,
        inputs: &[(&CStr, &[f32])],
        output: &mut [f32],
    ) -> Result<(), String> {
        let (width, height) = (self.width, self.height);
        let len = width * height * 3;
        if let Some((name, _)) = inputs.iter().find(|(_, image)| image.len() != len) {
            return Err(format!("the {name:?} image is not {width}×{height} pixels"));
        }
        if output.len() != len {
            return Err(format!("the output is not {width}×{height} pixels"));
        }
        let api = &self.library.api;
        let handle = self.handle;
        let image = |name: &CStr, pixels: *mut c_void| {
            // SAFETY: a live filter handle; `pixels` points at `len` floats, laid out as
            // FLOAT3 pixels in rows without padding (strides 0 mean packed), that stay
            // borrowed until this function returns, after the filter has run.
            unsafe {
                (api.set_shared_filter_image)(
                    handle,
                    name.as_ptr(),
                    pixels,
                    FORMAT_FLOAT3,
                    width,
                    height,
                    0,
                    0,
                    0,
                )
            }
        };
        for (name, pixels) in inputs {
            // OIDN reads its input images and never writes them.
            image(name, pixels.as_ptr().cast_mut().cast());
        }
        image(c"output", output.as_mut_ptr().cast());
        // SAFETY: a live filter handle, its images set above and borrowed for this call;
        // `oidnExecuteFilter` returns once the output is written.
        unsafe {
            (api.commit_filter)(handle);
            (api.execute_filter)(handle);
        }
        device.check()
    }
}

impl Drop for RtFilter {
    fn drop(&mut self) {
        // SAFETY: the handle is live, and this is its one release (the session that holds
        // filters drops them before their device).
        unsafe { (self.library.api.release_filter)(self.handle) }
    }
}
