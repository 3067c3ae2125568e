//! Part files: what `rayforge render --slice I/N` writes and `rayforge merge` reads. A part
//! holds one slice's film, linear and lossless (each pixel's sums of weighted colours and of
//! weights as 64-bit floats, stored as their bits), behind a header that says which render it
//! belongs to, which slice it is and what that slice covers; a path-traced slice rendered with
//! `--aovs` holds its AOV films too (albedo, normal, depth, samples), which the merge joins as
//! it joins the image, for `merge --aovs` to write and `merge --denoise` to be guided by.
//!
//! ```text
//! offset  size  field
//!      0     8  magic "RAYPART\n"
//!      8     4  format version, u32 (3; version 2 is read too, see below)
//!     12     4  header length H, u32, at most 65 536: the bytes of the fields below
//!     16     H  8  scene fingerprint, u64: FNV-1a 64 of the scene file's bytes, then of each
//!                  file the scene read (models, images, …; `Scene::files`), each as its
//!                  length (u64) and its bytes ([`scene_fingerprint`])
//!               8  image width, u64
//!               8  image height, u64 (width × height at most 2^28)
//!               8  slice index I, u64 (below N)
//!               8  slice count N, u64 (1 to 2^20)
//!               1  cut: 0 rows (rows I, I + N, …), 1 samples (a range of every pixel's)
//!               8  samples per pixel of the whole render, u64 (the path tracer's; else 0)
//!               8  first sample index of this slice, u64 } 0..spp cut by rows, the I-th of
//!               8  end of its sample indices, u64        } N ranges (spp·I/N..) by samples
//!               8  rows this slice covers, u64 (R: the film's height below)
//!               1  development: 0 the colours as they are, 1 automatic exposure (the optics
//!                  model's), 2 the path tracer's (linear; sRGB-encoded for PNG and PPM)
//!               1  overlay: 1 when the scene has canvas items to draw over the image
//!               1  AOVs: 1 when the four AOV films follow the image's film (path tracer
//!                  only), else 0 (version 3 only: a version 2 header has no such byte)
//!             4+n  the scene file's path (absolute where it could be made so), for messages
//!                  only: u32 n, UTF-8
//!             4+n  the settings: every setting that changes a pixel, as text (renderer,
//!                  lighting model, sampling, depth, seed, sampler, filter, rayforge's
//!                  version…): u32 n, UTF-8
//!   16+H     8  FNV-1a 64 of bytes 0 to 16+H: the header's checksum
//!   24+H     …  the slice's film, a film file (magic "RAYFILM\n", crates/rayforge/src/film/
//!               file.rs): width × R pixels, the slice's rows top to bottom, the pixel filter,
//!               the brightest sample, and a CRC-32 of the film
//!      …     …  with AOVs: four more film files of width × R pixels (box filter), in the
//!               order albedo, normal, depth, samples, each with its own CRC-32; each pixel's
//!               sums and weight as the path tracer's AOV films hold them (the samples
//!               film: the count as the sum of a pixel of weight 1)
//! ```
//!
//! Every number is little-endian. The file ends with its last film's checksum. Reading checks
//! the magic, the version, the header's length before reading it and its checksum, every
//! field's range, that the rows and samples covered are the ones the slice's index gives,
//! each film's size against the header before trusting it (the film reader bounds its own
//! size before allocating and grows its buffers only as bytes arrive), each film's checksum,
//! and that nothing follows. Parts are written atomically (a temporary file renamed), so a
//! part that exists was written whole; a part cut short or damaged since is refused, naming
//! the file.
//!
//! **Versions.** Version 3 added the AOV byte and the AOV films. A version 2 part (what
//! rayforge wrote before) is read as a version 3 part without AOVs, and merges with version 3
//! parts of the same render that have none; version 1 (which carried the merge's limits,
//! see below) is refused, naming its version.
//!
//! The merge needs only the parts (and, for the canvas items, the scene file): the header holds
//! how to develop the film, so the merge does not load the scene otherwise.
//!
//! **A part is untrusted input.** Parts come from shared cluster file systems, and their
//! checksums (FNV-1a, CRC-32) find damage, not forgery: anyone who can write a part can make
//! them right. So a part holds nothing the merge must trust. The scene's path is shown in
//! messages and never opened (the merge reads the scene the user names with `--scene`, under
//! the merge's own `--allow-outside` and `--max-triangles`: version 1 carried those two and
//! the merge obeyed them), every field is checked before it is used, and a forged part can at
//! worst make a wrong image of the parts it is merged with, in bounded time and memory.

use crate::checkpoint::fnv;
use crate::failure::Failure;
use crate::slice::{Cut, Slice, MAX_SLICES};
use rayforge::film::{Exposure, Film, FilmError, MAX_FILM_PIXELS};
use rayforge_scene::clip;
use rayforge_scene::files::open_regular;
use std::io::{BufReader, Read, Write};
use std::ops::Range;
use std::path::Path;

/// The first bytes of every part file.
pub const PART_MAGIC: &[u8; 8] = b"RAYPART\n";
/// The format version this build writes.
pub const PART_VERSION: u32 = 3;
/// The oldest format version this build reads: version 2, the same without AOVs.
pub const OLDEST_PART_VERSION: u32 = 2;
/// How many AOV films a part with AOVs holds, in the order of
/// [`crate::path_output::AOV_NAMES`].
pub const PART_AOVS: usize = 4;
/// The AOV film that holds each pixel's sample count as the sum of a pixel of weight 1,
/// whose weights are therefore not added up by a merge.
const SAMPLES_AOV: usize = 3;
/// The longest header accepted: its two texts are a path and a line of settings.
const MAX_HEADER_LEN: u32 = 1 << 16;

/// How a merged film becomes the image: as `rayforge render` develops that renderer's films.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Development {
    /// The book renderers' (ray tracer, rasterizer): [`rayforge::film::develop`] with this
    /// exposure.
    Book(Exposure),
    /// The path tracer's: resolved, linear radiance, sRGB-encoded for the 8-bit formats.
    Path,
}

impl Development {
    fn code(self) -> u8 {
        match self {
            Development::Book(Exposure::Fixed) => 0,
            Development::Book(Exposure::Automatic) => 1,
            Development::Path => 2,
        }
    }

    fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Development::Book(Exposure::Fixed)),
            1 => Some(Development::Book(Exposure::Automatic)),
            2 => Some(Development::Path),
            _ => None,
        }
    }
}

/// A part's header: the render it belongs to, and which slice of it this is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PartHeader {
    /// FNV-1a 64 of the scene file's bytes.
    pub fingerprint: u64,
    /// The image's width.
    pub width: usize,
    /// The image's height.
    pub height: usize,
    /// Which slice.
    pub slice: Slice,
    /// The path tracer's samples per pixel for the whole render (0 for the other renderers,
    /// whose samples are not an index sequence).
    pub spp: u64,
    /// How the merged film is developed.
    pub development: Development,
    /// Whether the scene has canvas items, drawn over the merged image.
    pub overlay: bool,
    /// Whether the part holds the path tracer's AOV films beside the image's
    /// (`render --slice --aovs`; never in a version 2 part).
    pub aovs: bool,
    /// The scene file, as the slice named it: for messages only, never opened.
    pub scene: String,
    /// Every setting that changes a pixel, as text.
    pub settings: String,
}

impl PartHeader {
    /// The samples of each pixel this slice rendered.
    pub fn samples(&self) -> Range<u64> {
        self.slice.samples(self.spp)
    }

    /// Whether `other` is a slice of the same render: everything but the index agrees (the
    /// scene's path may differ, from machines that mount it elsewhere, and so may the limits
    /// it was read with). `None` if so, else what differs.
    pub fn differs_from(&self, other: &PartHeader) -> Option<String> {
        let differ = |what: &str, a: &dyn std::fmt::Debug, b: &dyn std::fmt::Debug| {
            Some(format!("{what} differ: {a:?} against {b:?}"))
        };
        if self.fingerprint != other.fingerprint {
            return Some(format!(
                "the scene files differ (fingerprints {:016x} and {:016x}; `{}` and `{}`)",
                self.fingerprint,
                other.fingerprint,
                clip(&self.scene),
                clip(&other.scene)
            ));
        }
        if (self.width, self.height) != (other.width, other.height) {
            return differ(
                "the image sizes",
                &(self.width, self.height),
                &(other.width, other.height),
            );
        }
        if (self.slice.count, self.slice.cut) != (other.slice.count, other.slice.cut) {
            return Some(format!(
                "the cuts differ: {} slices by {} against {} by {}",
                self.slice.count,
                self.slice.cut.name(),
                other.slice.count,
                other.slice.cut.name()
            ));
        }
        if self.settings != other.settings || self.spp != other.spp {
            return differ("the settings", &self.settings, &other.settings);
        }
        if (self.development, self.overlay) != (other.development, other.overlay) {
            return differ(
                "the developments",
                &(self.development, self.overlay),
                &(other.development, other.overlay),
            );
        }
        if self.aovs != other.aovs {
            let with = |aovs: bool| if aovs { "with" } else { "without" };
            return Some(format!(
                "one was rendered {} --aovs and the other {} (render every slice with the same \
                 flags)",
                with(self.aovs),
                with(other.aovs)
            ));
        }
        None
    }

    /// The header's bytes, from the magic to its checksum.
    fn to_bytes(&self) -> Vec<u8> {
        let mut fields = Vec::new();
        let u64s = [
            self.fingerprint,
            self.width as u64,
            self.height as u64,
            self.slice.index,
            self.slice.count,
        ];
        u64s.iter()
            .for_each(|v| fields.extend_from_slice(&v.to_le_bytes()));
        fields.push(match self.slice.cut {
            Cut::Rows => 0,
            Cut::Samples => 1,
        });
        let samples = self.samples();
        let rows = self.slice.row_count(self.height) as u64;
        for v in [self.spp, samples.start, samples.end, rows] {
            fields.extend_from_slice(&v.to_le_bytes());
        }
        fields.push(self.development.code());
        fields.push(u8::from(self.overlay));
        fields.push(u8::from(self.aovs));
        for text in [&self.scene, &self.settings] {
            fields.extend_from_slice(&(text.len() as u32).to_le_bytes());
            fields.extend_from_slice(text.as_bytes());
        }
        let mut out = PART_MAGIC.to_vec();
        out.extend_from_slice(&PART_VERSION.to_le_bytes());
        out.extend_from_slice(&(fields.len() as u32).to_le_bytes());
        out.extend_from_slice(&fields);
        let sum = fnv(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Reads and checks a header (see [the layout](self)); the error says why, for the caller
    /// to name the file.
    fn read_from(input: &mut impl Read) -> Result<Self, String> {
        let mut start = [0u8; 16];
        read_exact(input, &mut start)?;
        if &start[..8] != PART_MAGIC {
            return Err("it is not a rayforge part file (wrong magic bytes)".into());
        }
        let version = u32::from_le_bytes(array(&start[8..]));
        if !(OLDEST_PART_VERSION..=PART_VERSION).contains(&version) {
            return Err(format!(
                "it is a part file of format version {version}; this build reads versions \
                 {OLDEST_PART_VERSION} to {PART_VERSION}"
            ));
        }
        let len = u32::from_le_bytes(array(&start[12..]));
        if len > MAX_HEADER_LEN {
            return Err(format!(
                "its header claims {len} bytes, more than the {MAX_HEADER_LEN} a header may have"
            ));
        }
        let mut fields = vec![0u8; len as usize];
        read_exact(input, &mut fields)?;
        let mut sum = [0u8; 8];
        read_exact(input, &mut sum)?;
        let mut covered = start.to_vec();
        covered.extend_from_slice(&fields);
        if fnv(&covered) != u64::from_le_bytes(sum) {
            return Err("its header is damaged (the checksum does not match)".into());
        }
        Self::parse(&fields, version)
    }

    /// The header's fields (checksum already checked) in format `version`, each in range.
    fn parse(fields: &[u8], version: u32) -> Result<Self, String> {
        let mut at = Fields { bytes: fields };
        let fingerprint = at.u64()?;
        let (width, height) = (at.u64()?, at.u64()?);
        if width
            .checked_mul(height)
            .is_none_or(|n| n > MAX_FILM_PIXELS)
        {
            return Err(format!(
                "its image is {width}×{height}, larger than the limit of {MAX_FILM_PIXELS} pixels"
            ));
        }
        let (index, count) = (at.u64()?, at.u64()?);
        if count == 0 || count > MAX_SLICES || index >= count {
            return Err(format!(
                "it claims to be slice {index}/{count}, which no render cuts"
            ));
        }
        let cut = match at.u8()? {
            0 => Cut::Rows,
            1 => Cut::Samples,
            code => return Err(format!("unknown cut code {code} (0 rows, 1 samples)")),
        };
        let slice = Slice { index, count, cut };
        let spp = at.u64()?;
        let samples = at.u64()?..at.u64()?;
        let rows = at.u64()?;
        // Within the limit checked above, so these fit in usize.
        let (width, height) = (width as usize, height as usize);
        if samples != slice.samples(spp) || rows != slice.row_count(height) as u64 {
            return Err(format!(
                "it claims samples {samples:?} and {rows} rows, which are not what slice \
                 {slice} by {} of {spp} samples and {height} rows covers",
                cut.name()
            ));
        }
        let development = at.u8()?;
        let development = Development::from_code(development)
            .ok_or_else(|| format!("unknown development code {development}"))?;
        let overlay = at.flag()?;
        // Version 2 has no AOV byte, and no AOVs.
        let aovs = version >= 3 && at.flag()?;
        if aovs && development != Development::Path {
            return Err("it claims AOV films, which only the path tracer renders".into());
        }
        let scene = at.text()?;
        let settings = at.text()?;
        if !at.bytes.is_empty() {
            return Err(format!(
                "its header has {} bytes after its last field",
                at.bytes.len()
            ));
        }
        Ok(Self {
            fingerprint,
            width,
            height,
            slice,
            spp,
            development,
            overlay,
            aovs,
            scene,
            settings,
        })
    }
}

/// The header's fields, read in turn; each read fails rather than run past the end.
struct Fields<'a> {
    bytes: &'a [u8],
}

impl Fields<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        if self.bytes.len() < n {
            return Err("its header ends before its last field".into());
        }
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Ok(head)
    }

    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }

    fn flag(&mut self) -> Result<bool, String> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            other => Err(format!("a flag in its header is {other}, neither 0 nor 1")),
        }
    }

    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(array(self.take(8)?)))
    }

    fn text(&mut self) -> Result<String, String> {
        let len = u32::from_le_bytes(array(self.take(4)?)) as usize;
        // Bounded by the header's length, itself bounded before it was read.
        let bytes = self.take(len)?;
        String::from_utf8(bytes.to_vec()).map_err(|_| "a text in its header is not UTF-8".into())
    }
}

/// A part: its header, the film of the rows it covers and, with AOVs, theirs.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Which render and which slice.
    pub header: PartHeader,
    /// The slice's rows, top to bottom (all rows when cut by samples).
    film: Film,
    /// The AOVs' films of the same rows, when the header says so.
    aovs: Option<[Film; PART_AOVS]>,
}

/// The films a merge adds the parts into: the image's and, when the parts hold them, the
/// AOVs' (in the order of [`crate::path_output::AOV_NAMES`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MergedFilms {
    /// The image's film.
    pub film: Film,
    /// The AOVs' films.
    pub aovs: Option<[Film; PART_AOVS]>,
}

impl MergedFilms {
    /// The films once every part is added: the sample counts as `rayforge render` holds them,
    /// each pixel's count the sum of one pixel of weight 1 (the parts' weights of 1 were added
    /// up with their counts).
    pub fn finished(mut self) -> Self {
        if let Some(samples) = self.aovs.as_mut().map(|a| &mut a[SAMPLES_AOV]) {
            for y in 0..samples.height() {
                for x in 0..samples.width() {
                    if samples.weight(x, y) > 0.0 {
                        samples.set_pixel_sum(x, y, samples.sum(x, y), 1.0);
                    }
                }
            }
        }
        self
    }
}

impl Part {
    /// The part of the slice `header` names, from `film`, the film of the rows it covers, top
    /// to bottom (what a slice renders into, see [`rayforge::film::SharedFilm::with_rows`]),
    /// and the AOVs' films of those rows when the header says it has AOVs. Refused when a film
    /// is not that size or the AOVs are not as the header says: a part is only ever made of
    /// its own rows.
    pub fn new(
        header: PartHeader,
        film: Film,
        aovs: Option<[Film; PART_AOVS]>,
    ) -> Result<Self, Failure> {
        let rows = header.slice.row_count(header.height);
        if aovs.is_some() != header.aovs {
            return Err(Failure::internal(format!(
                "slice {}'s header and its AOV films disagree on whether it has AOVs",
                header.slice
            )));
        }
        for film in std::iter::once(&film).chain(aovs.iter().flatten()) {
            if (film.width(), film.height()) != (header.width, rows) {
                return Err(Failure::internal(format!(
                    "slice {} of {} rows was rendered into a {}×{} film, not one of its {}×{rows}",
                    header.slice,
                    header.height,
                    film.width(),
                    film.height(),
                    header.width
                )));
            }
        }
        Ok(Self { header, film, aovs })
    }

    /// Writes the part file (see [the layout](self)) to `out` as it goes, so that a slice
    /// never holds the file's bytes beside its films.
    pub fn write_to(&self, out: &mut dyn Write) -> std::io::Result<()> {
        out.write_all(&self.header.to_bytes())?;
        for film in std::iter::once(&self.film).chain(self.aovs.iter().flatten()) {
            film.write_to(&mut &mut *out).map_err(|e| match e {
                FilmError::Io(e) => e,
                other => std::io::Error::other(other.to_string()),
            })?;
        }
        Ok(())
    }

    /// Adds this slice's samples to `films`, the image's: each of its rows onto the image's
    /// row it covers, pixel by pixel (sums and weights), its brightest sample, and the same for
    /// each AOV when both hold them. Refused when the pixel filters differ.
    pub fn add_to(&self, films: &mut MergedFilms) -> Result<(), FilmError> {
        if films.film.filter() != self.film.filter() {
            return Err(FilmError::FilterMismatch(
                self.film.filter(),
                films.film.filter(),
            ));
        }
        let pairs = std::iter::once((&self.film, &mut films.film));
        let aovs = self
            .aovs
            .iter()
            .flatten()
            .zip(films.aovs.iter_mut().flatten());
        for (part, film) in pairs.chain(aovs) {
            for (j, y) in self.header.slice.rows(self.header.height).enumerate() {
                let sums = part.row_sums(j).iter();
                for (x, (&sum, &weight)) in sums.zip(part.row_weights(j)).enumerate() {
                    film.add_pixel_sum(x, y, sum, weight);
                }
            }
            film.note_brightest(part.brightest());
        }
        Ok(())
    }

    /// The films this part's slice adds to: the image's size, its pixel filter, no samples;
    /// the AOVs' beside it when the part has AOVs.
    pub fn empty_image_films(&self) -> Result<MergedFilms, FilmError> {
        let (width, height) = (self.header.width, self.header.height);
        Ok(MergedFilms {
            film: Film::with_filter(width, height, self.film.filter())?,
            aovs: self
                .aovs
                .as_ref()
                .map(|_| std::array::from_fn(|_| Film::new(width, height))),
        })
    }

    /// Reads and checks the part file at `path` (see [the layout](self)); the error names the
    /// file and what is wrong with it.
    pub fn read(path: &Path) -> Result<Self, Failure> {
        let mut input = open(path)?;
        let header = PartHeader::read_from(&mut input).map_err(|why| unusable(path, &why))?;
        let rows = header.slice.row_count(header.height);
        let mut film = |what: &str| -> Result<Film, Failure> {
            let film =
                Film::read_from(&mut input).map_err(|e| unusable(path, &film_error(what, e)))?;
            if (film.width(), film.height()) != (header.width, rows) {
                return Err(unusable(
                    path,
                    &format!(
                        "its {what} is {}×{}, where its header says {}×{rows}",
                        film.width(),
                        film.height(),
                        header.width
                    ),
                ));
            }
            Ok(film)
        };
        let image = film("film")?;
        let aovs = if header.aovs {
            let mut films = Vec::with_capacity(PART_AOVS);
            for name in crate::path_output::AOV_NAMES {
                films.push(film(&format!("{name} film"))?);
            }
            films.try_into().ok()
        } else {
            None
        };
        let mut rest = [0u8; 1];
        match input.read(&mut rest) {
            Ok(0) => Ok(Self {
                header,
                film: image,
                aovs,
            }),
            Ok(_) => Err(unusable(
                path,
                "it has bytes after its last film's checksum",
            )),
            Err(e) => Err(unusable(path, &e.to_string())),
        }
    }

    /// Whether the file at `path` is a regular file that begins as a part file does (its
    /// magic bytes), whatever follows: a part, perhaps damaged, and not another kind of file.
    pub fn looks_like_one(path: &Path) -> bool {
        let mut magic = [0u8; 8];
        open_regular(path)
            .is_ok_and(|(mut file, _)| file.read_exact(&mut magic).is_ok() && &magic == PART_MAGIC)
    }

    /// Reads and checks only the part file's header: enough to see which slice of which render
    /// it is without reading its film.
    pub fn read_header(path: &Path) -> Result<PartHeader, Failure> {
        PartHeader::read_from(&mut open(path)?).map_err(|why| unusable(path, &why))
    }
}

/// The file at `path`, buffered: a regular file (a directory, a device or a named pipe is
/// refused before anything waits on it, see [`open_regular`]).
fn open(path: &Path) -> Result<BufReader<std::fs::File>, Failure> {
    open_regular(path)
        .map(|(file, _)| BufReader::new(file))
        .map_err(|e| Failure::usage(format!("cannot read the part `{}`: {e}", path.display())))
}

/// The failure of a part file that cannot be used, and why.
fn unusable(path: &Path, why: &str) -> Failure {
    Failure::usage(format!(
        "`{}` is not a usable part file: {why}",
        path.display()
    ))
}

/// Why a part's film (`what`: `film`, or an AOV's) could not be read, in the part's terms.
fn film_error(what: &str, e: FilmError) -> String {
    match e {
        FilmError::Truncated => format!("it is truncated (its {what} ends early)"),
        FilmError::BadChecksum { .. } => format!("its {what} is damaged: {e}"),
        other => format!("its {what} cannot be read: {other}"),
    }
}

/// Fills `buf`, or says the file ends early.
fn read_exact(input: &mut impl Read, buf: &mut [u8]) -> Result<(), String> {
    input.read_exact(buf).map_err(|e| match e.kind() {
        std::io::ErrorKind::UnexpectedEof => "it is truncated (its header ends early)".into(),
        _ => e.to_string(),
    })
}

/// The first `N` bytes of `bytes` (which the callers' fixed layouts guarantee are there).
fn array<const N: usize>(bytes: &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    out.copy_from_slice(&bytes[..N]);
    out
}

/// The fingerprint of a scene as rendered: FNV-1a 64 over the scene file's bytes and then,
/// for each file it read (in the order read), the file's length as a little-endian `u64` and
/// its bytes, so that parts rendered against different versions of a texture or model do not
/// merge. The files are read again in blocks (a model may be a gigabyte); the error names the
/// file that could not be.
pub fn scene_fingerprint(scene: &[u8], files: &[std::path::PathBuf]) -> Result<u64, String> {
    use std::io::Read;
    let mut hash = crate::checkpoint::Fnv::new();
    hash.write(scene);
    let mut block = vec![0u8; 1 << 16];
    for path in files {
        let cannot = |e: String| format!("cannot read `{}` again: {e}", path.display());
        let (mut file, length) = open_regular(path).map_err(cannot)?;
        hash.write(&length.to_le_bytes());
        loop {
            let n = file.read(&mut block).map_err(|e| cannot(e.to_string()))?;
            if n == 0 {
                break;
            }
            hash.write(&block[..n]);
        }
    }
    Ok(hash.finish())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayforge::color::Color;
    use rayforge::film::SharedFilm;

    fn header(index: u64, count: u64, cut: Cut) -> PartHeader {
        PartHeader {
            fingerprint: 0x1234,
            width: 3,
            height: 5,
            slice: Slice { index, count, cut },
            spp: 10,
            development: Development::Path,
            overlay: false,
            aovs: false,
            scene: "/s.yml".into(),
            settings: "path; spp 10".into(),
        }
    }

    /// A 3×5 film whose pixel sums are distinct, negative zeros and a NaN included.
    fn film() -> Film {
        let mut film = Film::new(3, 5);
        for y in 0..5 {
            for x in 0..3 {
                let v = (y * 3 + x) as f64 * 0.1;
                film.add_pixel_sum(x, y, Color::new(v, -0.0, f64::NAN), 1.0 + v);
            }
        }
        film.note_brightest(7.5);
        film
    }

    /// The part of `header`'s slice of `full`: its rows copied, to the bit, into a film that
    /// holds only them, as a slice renders.
    fn part(header: PartHeader, full: &Film) -> Part {
        let whole = SharedFilm::from(full.clone());
        let rows = header.slice.rows(header.height);
        let film = SharedFilm::with_rows(3, 5, full.filter(), rows).unwrap();
        for y in header.slice.rows(header.height) {
            film.set_row(y, &whole.row(y).unwrap()).unwrap();
        }
        let mut film = film.into_film();
        film.note_brightest(full.brightest());
        Part::new(header, film, None).unwrap()
    }

    /// The part file's bytes.
    fn bytes(part: &Part) -> Vec<u8> {
        let mut out = Vec::new();
        part.write_to(&mut out).unwrap();
        out
    }

    fn read_bytes(bytes: &[u8]) -> Result<Part, Failure> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.part");
        std::fs::write(&path, bytes).unwrap();
        Part::read(&path)
    }

    fn message(failure: Failure) -> String {
        match failure {
            Failure::Input(m) => m,
            other => panic!("not a usage error: {other:?}"),
        }
    }

    #[test]
    fn a_part_reads_back_as_written_and_adds_its_rows_in_place() {
        let full = film();
        let mut merged = MergedFilms {
            film: Film::new(3, 5),
            aovs: None,
        };
        for index in 0..2 {
            let part = part(header(index, 2, Cut::Rows), &full);
            let back = read_bytes(&bytes(&part)).unwrap();
            assert_eq!(back.header, part.header);
            assert_eq!(bytes(&back), bytes(&part));
            back.add_to(&mut merged).unwrap();
        }
        // Bit for bit, NaNs included (which `==` would not see).
        assert_eq!(merged.film.to_bytes(), full.to_bytes());
    }

    #[test]
    fn a_part_is_made_of_its_slice_s_rows_only() {
        // Slice 1/2 of 5 rows has rows 1 and 3: a film of the whole image is not its film.
        let Err(Failure::Internal(m)) = Part::new(header(1, 2, Cut::Rows), film(), None) else {
            panic!("a whole-image film made a part of two rows");
        };
        assert!(m.contains("a 3×5 film, not one of its 3×2"), "{m}");
        assert!(Part::new(header(1, 2, Cut::Rows), Film::new(3, 2), None).is_ok());
        assert!(Part::new(header(1, 2, Cut::Samples), Film::new(3, 5), None).is_ok());
        // The AOVs as the header says, each of the slice's rows.
        let with_aovs = PartHeader {
            aovs: true,
            ..header(1, 2, Cut::Rows)
        };
        let aovs = || std::array::from_fn(|_| Film::new(3, 2));
        assert!(Part::new(with_aovs.clone(), Film::new(3, 2), Some(aovs())).is_ok());
        assert!(Part::new(with_aovs.clone(), Film::new(3, 2), None).is_err());
        assert!(Part::new(header(1, 2, Cut::Rows), Film::new(3, 2), Some(aovs())).is_err());
        let mut wrong = aovs();
        wrong[2] = Film::new(3, 5);
        assert!(Part::new(with_aovs, Film::new(3, 2), Some(wrong)).is_err());
    }

    #[test]
    fn every_truncation_and_every_flipped_byte_is_refused() {
        let bytes = bytes(&part(header(1, 3, Cut::Samples), &film()));
        for len in 0..bytes.len() {
            let m = message(read_bytes(&bytes[..len]).unwrap_err());
            assert!(m.contains("p.part` is not a usable part file"), "{m}");
        }
        for i in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[i] ^= 0x40;
            assert!(read_bytes(&bad).is_err(), "byte {i} flipped was accepted");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        let m = message(read_bytes(&longer).unwrap_err());
        assert!(m.contains("bytes after"), "{m}");
    }

    #[test]
    fn a_header_claiming_a_huge_length_or_image_is_refused_before_allocating() {
        let mut bytes = bytes(&part(header(0, 1, Cut::Rows), &film()));
        bytes[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        let m = message(read_bytes(&bytes).unwrap_err());
        assert!(m.contains("more than the 65536"), "{m}");
        let mut big = header(0, 1, Cut::Rows);
        big.width = 1 << 20;
        big.height = 1 << 20;
        let mut bytes = big.to_bytes();
        bytes.extend_from_slice(&film().to_bytes());
        let m = message(read_bytes(&bytes).unwrap_err());
        assert!(m.contains("larger than the limit"), "{m}");
    }

    #[test]
    fn parts_of_other_renders_are_told_apart() {
        let a = header(0, 2, Cut::Rows);
        assert_eq!(a.differs_from(&header(1, 2, Cut::Rows)), None);
        let mut b = header(1, 2, Cut::Rows);
        b.fingerprint = 9;
        assert!(a.differs_from(&b).unwrap().contains("scene files differ"));
        assert!(a
            .differs_from(&header(1, 3, Cut::Rows))
            .unwrap()
            .contains("cuts differ"));
        let mut c = header(1, 2, Cut::Rows);
        c.settings.push('!');
        assert!(a.differs_from(&c).unwrap().contains("settings differ"));
    }

    /// The AOV films of `header`'s slice: distinct sums, the sample count as a sum of weight 1.
    fn aov_films(header: &PartHeader) -> [Film; PART_AOVS] {
        let rows = header.slice.row_count(header.height);
        std::array::from_fn(|i| {
            let mut film = Film::new(header.width, rows);
            for y in 0..rows {
                for x in 0..header.width {
                    let v = (i * 100 + y * 10 + x) as f64 + header.slice.index as f64 * 0.5;
                    let weight = if i == SAMPLES_AOV { 1.0 } else { 2.0 };
                    film.add_pixel_sum(x, y, Color::new(v, v, v), weight);
                }
            }
            film
        })
    }

    #[test]
    fn a_part_with_aovs_reads_back_and_merges_its_aovs_as_a_whole_render_holds_them() {
        let parts: Vec<Part> = (0..2)
            .map(|index| {
                let header = PartHeader {
                    aovs: true,
                    ..header(index, 2, Cut::Samples)
                };
                let aovs = aov_films(&header);
                Part::new(header, Film::new(3, 5), Some(aovs)).unwrap()
            })
            .collect();
        let mut merged = parts[0].empty_image_films().unwrap();
        for part in &parts {
            let back = read_bytes(&bytes(part)).unwrap();
            assert_eq!(&back, part);
            back.add_to(&mut merged).unwrap();
        }
        let merged = merged.finished();
        let aovs = merged.aovs.unwrap();
        // Albedo (i = 0) at (1, 2): sums 21 and 21.5 over weights 2 and 2.
        assert_eq!(aovs[0].sum(1, 2).red, 42.5);
        assert_eq!(aovs[0].weight(1, 2), 4.0);
        // The counts added, their weight still 1: the pixel's count is the sum.
        assert_eq!(aovs[SAMPLES_AOV].sum(1, 2).red, 321.0 + 321.5);
        assert_eq!(aovs[SAMPLES_AOV].weight(1, 2), 1.0);
        // Every AOV film damaged or cut short is refused, naming it.
        let whole = bytes(&parts[1]);
        let last_film = whole.len() - Film::new(3, 5).to_bytes().len();
        let m = message(read_bytes(&whole[..last_film + 10]).unwrap_err());
        assert!(m.contains("its samples film ends early"), "{m}");
        let mut bad = whole.clone();
        bad[last_film + 60] ^= 1;
        let m = message(read_bytes(&bad).unwrap_err());
        assert!(m.contains("its samples film is damaged"), "{m}");
    }

    #[test]
    fn parts_with_and_without_aovs_are_not_one_render() {
        let with = PartHeader {
            aovs: true,
            ..header(0, 2, Cut::Rows)
        };
        let m = with.differs_from(&header(1, 2, Cut::Rows)).unwrap();
        assert!(
            m.contains("rendered with --aovs and the other without"),
            "{m}"
        );
    }

    #[test]
    fn only_the_path_tracer_s_parts_may_claim_aovs() {
        let forged = PartHeader {
            aovs: true,
            development: Development::Book(rayforge::film::Exposure::Fixed),
            ..header(0, 1, Cut::Rows)
        };
        let mut bytes = forged.to_bytes();
        bytes.extend_from_slice(&film().to_bytes());
        let m = message(read_bytes(&bytes).unwrap_err());
        assert!(m.contains("only the path tracer renders"), "{m}");
    }

    /// `bytes`, a version 3 part without AOVs, as version 2 wrote it: no AOV byte.
    fn as_version_2(bytes: &[u8]) -> Vec<u8> {
        let len = u32::from_le_bytes(array(&bytes[12..])) as usize;
        let fields = &bytes[16..16 + len];
        // The AOV byte follows the nine u64s, the cut, the development and the overlay.
        let aov_at = 9 * 8 + 3;
        assert_eq!(fields[aov_at], 0);
        let mut out = PART_MAGIC.to_vec();
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(len as u32 - 1).to_le_bytes());
        out.extend_from_slice(&fields[..aov_at]);
        out.extend_from_slice(&fields[aov_at + 1..]);
        let sum = fnv(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out.extend_from_slice(&bytes[16 + len + 8..]);
        out
    }

    #[test]
    fn a_version_2_part_reads_as_one_without_aovs_and_versions_outside_are_refused() {
        let part = part(header(1, 3, Cut::Samples), &film());
        let old = as_version_2(&bytes(&part));
        let back = read_bytes(&old).unwrap();
        // Bit for bit (the film holds a NaN, which `==` would not see).
        assert_eq!(back.header, part.header);
        assert_eq!(bytes(&back), bytes(&part));
        // A part version 2 rayforge wrote (the fuzzer's seed before version 3): the one slice,
        // by samples, of a 4×3 path-traced Cornell box of 2 samples per pixel.
        let written = include_bytes!("../tests/fixtures/parts/v2-path-samples.part");
        let header = read_bytes(written).unwrap().header;
        assert!(!header.aovs);
        assert_eq!(header.development, Development::Path);
        for version in [1u32, 4] {
            let mut other = old.clone();
            other[8..12].copy_from_slice(&version.to_le_bytes());
            let m = message(read_bytes(&other).unwrap_err());
            assert!(
                m.contains(&format!(
                    "format version {version}; this build reads versions 2 to 3"
                )),
                "{m}"
            );
        }
    }
}
