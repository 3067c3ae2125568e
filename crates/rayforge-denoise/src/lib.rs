//! Denoising rendered images with Intel Open Image Denoise (OIDN): its `RT` filter on a
//! linear HDR image, guided by the first surfaces' albedo and normal, which are denoised first
//! by their own passes (OIDN's advice for images of few samples, where the guides are noisy
//! too), and the beauty filtered with `cleanAux`.
//!
//! # Why the library is loaded at run time
//! The `oidn` crate links OIDN when rayforge is built: its build script stops the build
//! unless `OIDN_DIR` (or pkg-config) names an installed OIDN, so a machine without one could
//! not build rayforge at all, and a binary linked to it would not start where the library is
//! missing (the system's loader refuses it before `main`). Both would need a cargo feature to
//! leave OIDN out, and builds with and without it. Loaded at run time instead (by
//! `libloading`), one build serves every machine: the library's absence is an ordinary error
//! that `--denoise` turns into instructions (exit 2), and everything else runs as before. The
//! price is this crate's own declarations of the dozen OIDN functions it calls, in one module
//! ([`ffi`], the crate's only `unsafe` code).
//!
//! # Where the library is looked for
//! [`Denoiser::load`] tries, in order: `$RAYFORGE_OIDN_DIR/lib/` when the variable is set
//! (and nothing else then, so a test can point it at an empty folder); the `.oidn/lib/` folder
//! of the checkout this crate was built from, where `tools/oidn/install.sh` puts the library;
//! then the system's own search (`LD_LIBRARY_PATH`, installed libraries).
//!
//! # One device and its filters per render
//! Making an OIDN device and committing a filter cost far more than filtering a small image
//! (a 48×48 preview spent nearly all of its 390 ms there, `docs/performance.md`), and OIDN
//! asks for one device per process and filters reused for images of one size. A [`Session`]
//! does so: it makes its CPU device at its first image and its three filters (albedo,
//! normal, image) for each new size and set of guides, then only points them at each
//! frame's pixels. A render holds one session for its passes and its final image, the live
//! page one for all its renders; the bytes are those of a fresh device and filters (tested).
//!
//! # Determinism
//! OIDN's CPU device is deterministic for a given library version and processor: its
//! convolutions compute each output from fixed weights in a fixed order, whatever its thread
//! count (rayforge's tests check the bytes for one thread and two, and twice over). Another
//! processor (other vector instructions) or another OIDN version may round differently.
#![deny(missing_docs)]
#![deny(unsafe_code)]

#[allow(unsafe_code)]
mod ffi;

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The environment variable naming the folder OIDN is installed in (its `lib/` holds the
/// library), for both `tools/oidn/install.sh` and the loader.
pub const DIR_VARIABLE: &str = "RAYFORGE_OIDN_DIR";

/// The library's file name, in its folder `lib/` (OIDN 2's name).
#[cfg(target_os = "macos")]
pub const LIBRARY_FILE: &str = "libOpenImageDenoise.2.dylib";
/// The library's file name, in its folder `lib/` (OIDN 2's name).
#[cfg(windows)]
pub const LIBRARY_FILE: &str = "OpenImageDenoise.dll";
/// The library's file name, in its folder `lib/` (OIDN 2's name).
#[cfg(not(any(target_os = "macos", windows)))]
pub const LIBRARY_FILE: &str = "libOpenImageDenoise.so.2";

/// The `.oidn` folder of the checkout this crate was built from (two folders above it), the
/// install script's default.
fn checkout_dir() -> PathBuf {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = crate_dir.ancestors().nth(2).unwrap_or(crate_dir);
    root.join(".oidn")
}

/// How to get the library, as every message about its absence says.
pub const HOW_TO_INSTALL: &str = "install it with `tools/oidn/install.sh` in the rayforge \
     checkout (it fetches PyPI's pyoidn wheel into .oidn/, where rayforge looks), or set \
     RAYFORGE_OIDN_DIR to a folder whose lib/ holds it";

/// Why the denoiser could not be loaded: every place tried, with the loader's reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "Intel Open Image Denoise 2 ({LIBRARY_FILE}) could not be loaded: {}; {HOW_TO_INSTALL}",
    tried.iter().map(|(p, why)| place(p, why)).collect::<Vec<_>>().join("; ")
)]
pub struct LoadError {
    /// Each path tried (a bare file name for the system's search) and why it failed.
    pub tried: Vec<(PathBuf, String)>,
}

/// A place tried and why it failed, the path named once (the system's loader names it too).
fn place(path: &Path, why: &str) -> String {
    let path = path.display().to_string();
    if why.contains(&path) {
        why.to_string()
    } else {
        format!("{path}: {why}")
    }
}

/// Why an image could not be denoised.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DenoiseError {
    /// A guide is not the image's size.
    #[error("the {guide} image is {found}, not the image's {expected}")]
    SizeMismatch {
        /// `albedo` or `normal`.
        guide: &'static str,
        /// Its size (width × height, or a count of values).
        found: String,
        /// The image's.
        expected: String,
    },
    /// A normal guide without an albedo one (OIDN takes the normal only beside the albedo).
    #[error("a normal image needs an albedo image beside it")]
    NormalWithoutAlbedo,
    /// A pixel is not finite.
    #[error("the {image} image's pixel (column {x}, row {y} from the top) is not finite: {value}")]
    NonFinite {
        /// `color`, `albedo` or `normal`.
        image: &'static str,
        /// Its column.
        x: usize,
        /// Its row, from the top.
        y: usize,
        /// The value found.
        value: f32,
    },
    /// The image is empty.
    #[error("the image is empty ({width}×{height} pixels)")]
    Empty {
        /// Its width.
        width: usize,
        /// Its height.
        height: usize,
    },
    /// OIDN itself refused or failed.
    #[error("Intel Open Image Denoise failed: {0}")]
    Library(String),
}

/// An image to denoise and its guides: each `width × height` pixels of three 32-bit floats,
/// rows from the top, linear values (radiance; albedo in [0, 1]; normals in [-1, 1]).
#[derive(Debug, Clone, Copy)]
pub struct Images<'a> {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// The noisy image.
    pub color: &'a [f32],
    /// The first surfaces' albedo, if known.
    pub albedo: Option<&'a [f32]>,
    /// Their normals, if known (needs `albedo`).
    pub normal: Option<&'a [f32]>,
}

/// OIDN, loaded.
pub struct Denoiser {
    library: Arc<ffi::Library>,
    version: i32,
}

impl std::fmt::Debug for Denoiser {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Denoiser({})", self.describe())
    }
}

impl Denoiser {
    /// Loads OIDN from the first place that has it (see the crate's doc): `$RAYFORGE_OIDN_DIR`
    /// alone when set, else the checkout's `.oidn/`, else the system's search.
    pub fn load() -> Result<Self, LoadError> {
        let candidates = match std::env::var_os(DIR_VARIABLE) {
            Some(dir) => vec![Path::new(&dir).join("lib").join(LIBRARY_FILE)],
            None => vec![
                checkout_dir().join("lib").join(LIBRARY_FILE),
                PathBuf::from(LIBRARY_FILE),
            ],
        };
        Self::load_from(&candidates)
    }

    /// Loads OIDN from the first of `candidates` that opens and starts a CPU device.
    pub fn load_from(candidates: &[PathBuf]) -> Result<Self, LoadError> {
        let mut tried = Vec::new();
        for path in candidates {
            let started = ffi::Library::open(path).and_then(|library| {
                let library = Arc::new(library);
                let version = ffi::cpu_device(&library, 1)?.version();
                Ok((library, version))
            });
            match started {
                Ok((library, version)) => return Ok(Self { library, version }),
                Err(why) => tried.push((path.clone(), why)),
            }
        }
        Err(LoadError { tried })
    }

    /// The version and where it was loaded from, e.g. `OIDN 2.5.1 from .oidn/lib/…`.
    pub fn describe(&self) -> String {
        let v = self.version;
        format!(
            "OIDN {}.{}.{} from {}",
            v / 10000,
            v / 100 % 100,
            v % 100,
            self.library.path().display()
        )
    }

    /// A session denoising on `threads` of OIDN's own threads: its device made at its first
    /// image and kept, its filters kept while the images' size and guides stay the same.
    pub fn session(&self, threads: usize) -> Session {
        Session {
            library: self.library.clone(),
            threads: threads.max(1),
            state: Mutex::new(State::default()),
        }
    }
}

/// What a [`Session`] has made and done, to show that it reuses its device and filters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SessionStats {
    /// OIDN devices made (one, unless OIDN failed and the session started afresh).
    pub devices: usize,
    /// Times its filters were made and committed for a new size or set of guides.
    pub setups: usize,
    /// Images denoised.
    pub denoised: usize,
}

/// The `RT` filters of one size and set of guides: the guides' own passes, then the image's.
struct Filters {
    shape: Shape,
    albedo: Option<ffi::RtFilter>,
    normal: Option<ffi::RtFilter>,
    image: ffi::RtFilter,
}

/// What a session's filters are made for; another shape makes them afresh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Shape {
    width: usize,
    height: usize,
    hdr: bool,
    albedo: bool,
    normal: bool,
}

/// A session's OIDN objects. The filters come first so that they are dropped before their
/// device.
#[derive(Default)]
struct State {
    filters: Option<Filters>,
    device: Option<ffi::Device>,
    stats: SessionStats,
}

/// OIDN's device and filters kept from image to image (see the crate's doc), for the frames
/// of a render or the renders of a page.
///
/// # Threads
/// A render's passes are denoised on a thread beside it and its final image on the render's
/// own thread, so a session is shared (`Sync`): its device and filters sit behind a mutex and
/// each image is denoised whole under it, one at a time (OIDN would serialise calls on one
/// device anyway). OIDN's API is thread-safe and keeps errors per thread, and each
/// [`Session::denoise`] makes its calls and reads their errors on the one thread that holds
/// the lock, so which thread that is does not matter; see `ffi`'s `Send` for the device and
/// its filters.
pub struct Session {
    library: Arc<ffi::Library>,
    threads: usize,
    state: Mutex<State>,
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Session({} threads, {:?})", self.threads, self.stats())
    }
}

impl Session {
    /// What the session has made and done so far.
    pub fn stats(&self) -> SessionStats {
        self.lock().stats
    }

    /// The state, even after a panic elsewhere while it was held: its filters are then made
    /// afresh (a panic may have come between setting a filter's images and running it).
    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|poisoned| {
            let mut state = poisoned.into_inner();
            state.filters = None;
            state
        })
    }

    /// The denoised image (`width × height × 3` floats, as the input): the guides denoised
    /// first by their own `RT` passes, then the image with `cleanAux`; `hdr` for linear
    /// radiance (any range), else values in [0, 1]. Guides of another size, a normal without
    /// an albedo and values that are not finite are refused before OIDN runs. The result is
    /// the same as a fresh device's and filters'.
    pub fn denoise(&self, images: &Images<'_>, hdr: bool) -> Result<Vec<f32>, DenoiseError> {
        images.check()?;
        let shape = Shape {
            width: images.width,
            height: images.height,
            hdr,
            albedo: images.albedo.is_some(),
            normal: images.normal.is_some(),
        };
        let mut state = self.lock();
        let result = run(&self.library, self.threads, &mut state, shape, images);
        match result {
            Ok(output) => {
                state.stats.denoised += 1;
                Ok(output)
            }
            Err(message) => {
                // What OIDN failed on is not kept: the next image starts afresh.
                state.filters = None;
                state.device = None;
                Err(DenoiseError::Library(message))
            }
        }
    }
}

impl Images<'_> {
    /// Refuses images OIDN must not be given: empty, not `width × height × 3` values (a size
    /// whose values no memory could hold among them), guides of another size, a normal
    /// without an albedo, values that are not finite. [`Session::denoise`] checks this first;
    /// it needs no OIDN, so a caller may check its inputs before loading it.
    pub fn check(&self) -> Result<(), DenoiseError> {
        check(self)
    }
}

/// See [`Images::check`].
fn check(images: &Images<'_>) -> Result<(), DenoiseError> {
    let Images {
        width,
        height,
        color,
        albedo,
        normal,
    } = *images;
    if width == 0 || height == 0 {
        return Err(DenoiseError::Empty { width, height });
    }
    let Some(len) = width.checked_mul(height).and_then(|n| n.checked_mul(3)) else {
        return Err(DenoiseError::Library(format!(
            "an image of {width}×{height} pixels is past what memory can address"
        )));
    };
    if color.len() != len {
        return Err(DenoiseError::Library(format!(
            "the image holds {} values, not {width}×{height}×3",
            color.len()
        )));
    }
    if normal.is_some() && albedo.is_none() {
        return Err(DenoiseError::NormalWithoutAlbedo);
    }
    for (guide, pixels) in [("albedo", albedo), ("normal", normal)] {
        if let Some(pixels) = pixels.filter(|p| p.len() != len) {
            return Err(DenoiseError::SizeMismatch {
                guide,
                found: format!("{} values", pixels.len()),
                expected: format!("{width}×{height}×3 = {len}"),
            });
        }
    }
    for (image, pixels) in [
        ("color", Some(color)),
        ("albedo", albedo),
        ("normal", normal),
    ] {
        if let Some(at) = pixels.and_then(|p| p.iter().position(|v| !v.is_finite())) {
            let pixel = at / 3;
            return Err(DenoiseError::NonFinite {
                image,
                x: pixel % width,
                y: pixel / width,
                value: pixels.map_or(0.0, |p| p[at]),
            });
        }
    }
    Ok(())
}

/// Denoises checked `images` with the state's device and filters, making the device if there
/// is none and the filters if theirs is another `shape`; the error is OIDN's.
fn run(
    library: &Arc<ffi::Library>,
    threads: usize,
    state: &mut State,
    shape: Shape,
    images: &Images<'_>,
) -> Result<Vec<f32>, String> {
    let State {
        filters,
        device,
        stats,
    } = state;
    let device = match device {
        Some(device) => device,
        None => {
            stats.devices += 1;
            device.insert(ffi::cpu_device(library, threads)?)
        }
    };
    let filters = match filters {
        Some(kept) if kept.shape == shape => kept,
        stale => {
            // The old ones released before the new ones are made.
            *stale = None;
            let Shape { width, height, .. } = shape;
            let guide = |wanted: bool| {
                wanted
                    .then(|| device.rt_filter(width, height, &[]))
                    .transpose()
            };
            let flags = [(c"hdr", shape.hdr), (c"cleanAux", shape.albedo)];
            let made = Filters {
                shape,
                albedo: guide(shape.albedo)?,
                normal: guide(shape.normal)?,
                image: device.rt_filter(width, height, &flags)?,
            };
            stats.setups += 1;
            stale.insert(made)
        }
    };
    let len = images.color.len();
    // Each guide denoised alone, as OIDN documents for noisy guides: the filter with only
    // that guide set, under its own name, writes its clean version.
    let clean = |filter: Option<&mut ffi::RtFilter>, name: &std::ffi::CStr, pixels| match (
        filter, pixels,
    ) {
        (Some(filter), Some(pixels)) => {
            let mut out = vec![0.0; len];
            filter.execute(device, &[(name, pixels)], &mut out)?;
            Ok(Some(out))
        }
        _ => Ok::<_, String>(None),
    };
    let albedo = clean(filters.albedo.as_mut(), c"albedo", images.albedo)?;
    let normal = clean(filters.normal.as_mut(), c"normal", images.normal)?;
    let mut inputs = vec![(c"color", images.color)];
    inputs.extend(albedo.as_deref().map(|a| (c"albedo", a)));
    inputs.extend(normal.as_deref().map(|n| (c"normal", n)));
    let mut output = vec![0.0; len];
    filters.image.execute(device, &inputs, &mut output)?;
    Ok(output)
}
