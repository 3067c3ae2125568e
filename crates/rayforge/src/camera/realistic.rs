//! pbrt-v4's realistic camera: a lens system of spherical glass interfaces and an aperture
//! stop, traced element by element from the film, as *Physically Based Rendering* (4th
//! edition, section 5.3, "Realistic Cameras") describes it and pbrt-v4's `RealisticCamera`
//! does. A thin lens blurs what is out of focus by a disk; a real lens also vignettes the
//! image's corners, bends straight lines and blurs by the shape its elements and diaphragm
//! cut out, which is what a scene written for pbrt-v4's `realistic` camera shows.
//!
//! What follows pbrt-v4, rule by rule:
//! - **The lens system** is the lens file's rows from the scene's side to the film's
//!   ([`LensInterface`]: curvature radius, thickness to the next interface, index of
//!   refraction behind it, aperture diameter, all in millimetres; a radius of 0 is the
//!   aperture stop), turned into the scene's units (metres) by dividing by 1000. The stop's
//!   diameter is `aperturediameter` where that is smaller than the file's (the file's is the
//!   most the diaphragm opens: a larger one is clamped, and [`LensSystem::clamped_aperture`]
//!   says so). An index of 0 (as the lens files write the stop's) is air.
//! - **Space.** The film is at z = 0 of the camera's space (pbrt's: +z ahead, +y up, +x to
//!   the image's right) and the rear element `thickness` of the last row ahead of it; a
//!   surface of positive radius has its centre on the film's side of its vertex.
//! - **Focus.** The last row's thickness, the film-to-rear-element distance, is found for
//!   `focusdistance` (from the film to the plane in focus): the thick-lens approximation's
//!   cardinal points from two paraxial rays, and the lens moved along its axis by the
//!   Gaussian lens equation; then refined here by a secant search on a paraxial ray traced
//!   from the film's centre, which agrees with the approximation to the paraxial rays'
//!   aberration (a part in a million for the lenses of the tests).
//! - **The exit pupil.** For 64 rings of the film, from its centre to half its diagonal, the
//!   bounds (on the plane of the rear element, the film point on +x) of the rear-element
//!   points a ray from the ring gets through the lens by; each ray's lens point is drawn
//!   uniformly in its ring's bounds, turned to the film point's angle. Rays that hit an
//!   element outside its aperture or reflect totally are vignetted: no ray.
//! - **The weight** of a ray is `cos⁴θ · A / d²` (θ the ray's angle to the axis at the film,
//!   `A` the bounds' area, `d` the film-to-rear distance): the film's irradiance, so corners
//!   darken as pbrt-v4's do, times the diaphragm's transmission.
//! - **The diaphragm.** Circular by default; `gaussian`, `square`, `pentagon` and `star` are
//!   pbrt-v4's built-in shapes, each scaled to pass what the circular stop passes (π over the
//!   shape's area in the stop's square) and evaluated exactly here where pbrt-v4 rasterizes
//!   it at 256 × 256 texels (their edges differ by a texel's bilinear ramp). Like pbrt-v4's
//!   flipped image, the pentagon's point is towards −y.
//!
//! The bounds are found by tracing [`LensSystem::pupil_samples`] rays per ring (pbrt-v4
//! traces 2^20; fewer here, so that a scene loads in a fraction of a second, and the bounds
//! grown by the samples' spacing, pbrt-v4's rule, so that they still hold every ray that gets
//! through: a test draws rays to check it). A ray's own tracing allocates nothing.

use crate::math::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// One row of a lens description file, in the file's millimetres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensInterface {
    /// Radius of curvature (0: the aperture stop, a plane); positive where the surface's
    /// centre lies towards the film.
    pub curvature_radius: f64,
    /// Distance along the axis to the next interface towards the film.
    pub thickness: f64,
    /// Index of refraction of what lies between this interface and the next (0: air).
    pub eta: f64,
    /// Diameter of the interface's aperture.
    pub aperture_diameter: f64,
}

/// The diaphragm's shape: pbrt-v4's built-in `aperture` names, or the circular default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApertureShape {
    /// The stop's own circle (no `aperture` given).
    Circular,
    /// `gaussian`: a Gaussian of σ² = 1 over the stop's circle, less its value at the rim.
    Gaussian,
    /// `square`: a square of half the stop's diameter a side.
    Square,
    /// `pentagon`: a regular pentagon of 0.8 times the stop's radius, its point towards −y.
    Pentagon,
    /// `star`: a five-pointed star touching the stop's circle.
    Star,
}

impl ApertureShape {
    /// The built-in shapes' names, as pbrt-v4's `aperture` parameter takes them.
    pub const NAMES: [&'static str; 4] = ["gaussian", "square", "pentagon", "star"];

    /// The built-in shape called `name`, if it is one.
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "gaussian" => Some(Self::Gaussian),
            "square" => Some(Self::Square),
            "pentagon" => Some(Self::Pentagon),
            "star" => Some(Self::Star),
            _ => None,
        }
    }
}

/// What a realistic camera is built from besides its lens file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensSettings {
    /// The aperture stop's diameter in millimetres (`aperturediameter`; pbrt-v4's default 1).
    pub aperture_diameter: f64,
    /// From the film to the plane in focus, in scene units (`focusdistance`; default 10).
    pub focus_distance: f64,
    /// The film's diagonal in millimetres (the `Film`'s `diagonal`; default 35).
    pub film_diagonal: f64,
    /// The diaphragm's shape (`aperture`).
    pub aperture: ApertureShape,
    /// Rays traced per ring of the film to bound its exit pupil.
    pub pupil_samples: usize,
}

impl LensSettings {
    /// pbrt-v4's defaults, with [`LensSystem::DEFAULT_PUPIL_SAMPLES`].
    pub const DEFAULT: LensSettings = LensSettings {
        aperture_diameter: 1.0,
        focus_distance: 10.0,
        film_diagonal: 35.0,
        aperture: ApertureShape::Circular,
        pupil_samples: LensSystem::DEFAULT_PUPIL_SAMPLES,
    };
}

impl Default for LensSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a lens system cannot be built; `row` (from 0) is the lens file's row it concerns,
/// when one does.
#[derive(Debug, Clone, PartialEq)]
pub struct LensError {
    /// The row concerned, if one is.
    pub row: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl LensError {
    fn new(row: Option<usize>, message: impl Into<String>) -> Self {
        Self {
            row,
            message: message.into(),
        }
    }
}

impl std::fmt::Display for LensError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for LensError {}

/// One interface in scene units.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Element {
    radius: f64,
    thickness: f64,
    /// The index behind it (towards the film), air's 1 where the file says 0.
    eta: f64,
    aperture_radius: f64,
}

impl Element {
    fn is_stop(&self) -> bool {
        self.radius == 0.0
    }
}

/// A rectangle on the rear element's plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PupilBounds {
    /// Its corner of least x and y.
    pub min: (f64, f64),
    /// Its corner of most x and y.
    pub max: (f64, f64),
}

impl PupilBounds {
    /// Whether `(x, y)` lies in it (edges included).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.min.0 && x <= self.max.0 && y >= self.min.1 && y <= self.max.1
    }

    /// Its area.
    pub fn area(&self) -> f64 {
        (self.max.0 - self.min.0) * (self.max.1 - self.min.1)
    }

    fn point(x: f64, y: f64) -> Self {
        Self {
            min: (x, y),
            max: (x, y),
        }
    }

    fn grown_to(&mut self, x: f64, y: f64) {
        self.min = (self.min.0.min(x), self.min.1.min(y));
        self.max = (self.max.0.max(x), self.max.1.max(y));
    }
}

/// The diaphragm's transmission over the stop's square, `(u, v)` the hit point over the
/// stop's radius: what pbrt-v4's aperture image holds.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Diaphragm {
    shape: ApertureShape,
    /// The transmission inside the shape (π over its area; the Gaussian's peak scale).
    value: f64,
    /// A polygon's corners (the first `corners`).
    polygon: [(f64, f64); 10],
    corners: usize,
}

impl Diaphragm {
    fn of(shape: ApertureShape) -> Self {
        use std::f64::consts::PI;
        let mut polygon = [(0.0, 0.0); 10];
        let (value, corners) = match shape {
            ApertureShape::Circular => (1.0, 0),
            // ∫ over the unit disk of (e^{−r²} − e^{−1}) is π (1 − 2/e).
            ApertureShape::Gaussian => (1.0 / (1.0 - 2.0 / std::f64::consts::E), 0),
            // A square of side 1 in the stop's square of side 2.
            ApertureShape::Square => (PI, 0),
            ApertureShape::Pentagon => {
                let r = 0.8;
                for (k, corner) in polygon.iter_mut().take(5).enumerate() {
                    // The point at −y: pbrt-v4's pentagon, up in its image, flipped.
                    let a = -PI / 2.0 + 2.0 * PI * k as f64 / 5.0;
                    *corner = (r * a.cos(), r * a.sin());
                }
                let area = 2.5 * r * r * (2.0 * PI / 5.0).sin();
                (PI / area, 5)
            }
            ApertureShape::Star => {
                let inner = (72f64).to_radians().cos() / (36f64).to_radians().cos();
                for (k, corner) in polygon.iter_mut().enumerate() {
                    let r = if k % 2 == 1 { 1.0 } else { inner };
                    let a = PI * k as f64 / 5.0;
                    *corner = (r * a.cos(), r * a.sin());
                }
                // Ten triangles from the centre, each between a point and an inner corner.
                let area = 10.0 * 0.5 * inner * (PI / 5.0).sin();
                (PI / area, 10)
            }
        };
        Self {
            shape,
            value,
            polygon,
            corners,
        }
    }

    /// The transmission at `(u, v)` of the stop's square ([-1, 1]²).
    fn weight(&self, u: f64, v: f64) -> f64 {
        match self.shape {
            ApertureShape::Circular => {
                if u * u + v * v <= 1.0 {
                    1.0
                } else {
                    0.0
                }
            }
            ApertureShape::Gaussian => {
                let g = (-(u * u + v * v)).exp() - (-1.0f64).exp();
                g.max(0.0) * self.value
            }
            ApertureShape::Square => {
                if u.abs() <= 0.5 && v.abs() <= 0.5 {
                    self.value
                } else {
                    0.0
                }
            }
            ApertureShape::Pentagon | ApertureShape::Star => {
                if inside_polygon(&self.polygon[..self.corners], u, v) {
                    self.value
                } else {
                    0.0
                }
            }
        }
    }
}

/// Whether `(x, y)` is inside the simple polygon `corners` (crossings of a ray towards +x).
fn inside_polygon(corners: &[(f64, f64)], x: f64, y: f64) -> bool {
    let mut inside = false;
    let mut j = corners.len() - 1;
    for i in 0..corners.len() {
        let ((xi, yi), (xj, yj)) = (corners[i], corners[j]);
        if (yi > y) != (yj > y) && x < xi + (y - yi) / (yj - yi) * (xj - xi) {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// A ray through the lens system: origin and direction in the camera's space (pbrt's: the
/// film at z = 0, +z towards the scene).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensRay {
    /// Where it starts.
    pub origin: Vec3,
    /// Where it goes (not normalized).
    pub direction: Vec3,
}

/// A realistic camera's lens system, focused, with its exit pupil's bounds (see the module's
/// documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct LensSystem {
    /// From the scene's side to the film's; the last one's thickness is the film's distance.
    elements: Vec<Element>,
    diaphragm: Diaphragm,
    /// The film's diagonal, in scene units.
    film_diagonal: f64,
    /// The exit pupil's bounds for each of [`Self::PUPIL_RINGS`] rings of the film (`None`
    /// where no ray gets through).
    pupil: Vec<Option<PupilBounds>>,
    /// The stop diameter asked for and the most the file allows, when the first was larger.
    clamped: Option<(f64, f64)>,
    /// The film distance pbrt-v4's thick-lens focusing alone gives.
    thick_lens_distance: f64,
    /// The image distance from the film-side principal plane: what an equivalent pinhole
    /// has from its canvas.
    image_distance: f64,
    pupil_samples: usize,
}

impl LensSystem {
    /// How many rings of the film have their own exit pupil bounds (pbrt-v4's 64).
    pub const PUPIL_RINGS: usize = 64;
    /// Rays traced per ring to bound its exit pupil by default: 2^14, a sixty-fourth of
    /// pbrt-v4's, so that 64 rings take a million rays (a fraction of a second).
    pub const DEFAULT_PUPIL_SAMPLES: usize = 1 << 14;
    /// The most rays per ring [`LensSettings::pupil_samples`] may ask for (pbrt-v4's 2^20).
    pub const MAX_PUPIL_SAMPLES: usize = 1 << 20;

    /// The lens system of `rows` (a lens file's, from the scene's side), focused and bounded
    /// as `settings` say; an error names the row it concerns where one does.
    pub fn new(rows: &[LensInterface], settings: &LensSettings) -> Result<Self, LensError> {
        let lens = Self::new_until(rows, settings, None)?;
        Ok(lens.expect("nothing stops a build without a stop flag"))
    }

    /// [`new`](Self::new) that gives up (`Ok(None)`) once `stop` is set (Ctrl-C, a server's
    /// cancel): the exit pupil's bounds trace up to [`MAX_PUPIL_SAMPLES`](Self::MAX_PUPIL_SAMPLES)
    /// rays for each of [`PUPIL_RINGS`](Self::PUPIL_RINGS) rings, some 67 million at most, so
    /// each ring looks at the flag every 4,096 rays. Not stopped, the very system `new` makes.
    pub fn new_until(
        rows: &[LensInterface],
        settings: &LensSettings,
        stop: Option<&AtomicBool>,
    ) -> Result<Option<Self>, LensError> {
        if rows.is_empty() {
            return Err(LensError::new(
                None,
                "a lens system has at least one interface",
            ));
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        // Each setting is a length above 0; the error names it and what it was.
        for (value, what) in [
            (
                settings.aperture_diameter,
                "the aperture diameter is above 0 (millimetres)",
            ),
            (settings.focus_distance, "the focus distance is above 0"),
            (
                settings.film_diagonal,
                "the film's diagonal is above 0 (millimetres)",
            ),
        ] {
            if !positive(value) {
                return Err(LensError::new(None, format!("{what}, found {value}")));
            }
        }
        if settings.pupil_samples == 0 || settings.pupil_samples > Self::MAX_PUPIL_SAMPLES {
            return Err(LensError::new(
                None,
                format!(
                    "the exit pupil's samples per ring are from 1 to {}, found {}",
                    Self::MAX_PUPIL_SAMPLES,
                    settings.pupil_samples
                ),
            ));
        }
        let mut clamped = None;
        let mut elements = Vec::with_capacity(rows.len());
        for (i, row) in rows.iter().enumerate() {
            let bad = |what: &str| Err(LensError::new(Some(i), what.to_string()));
            if !row.curvature_radius.is_finite() {
                return bad("a curvature radius is a finite number");
            }
            if !(row.thickness.is_finite() && row.thickness >= 0.0) {
                return bad("a thickness is a finite number, not negative");
            }
            if !(row.eta.is_finite() && (row.eta == 0.0 || row.eta >= 1.0)) {
                return bad("an index of refraction is at least 1 (or 0, air)");
            }
            if !positive(row.aperture_diameter) {
                return bad("an aperture diameter is above 0");
            }
            let mut diameter = row.aperture_diameter;
            if row.curvature_radius == 0.0 {
                if settings.aperture_diameter > diameter {
                    clamped = Some((settings.aperture_diameter, diameter));
                } else {
                    diameter = settings.aperture_diameter;
                }
            } else if row.curvature_radius.abs() < row.aperture_diameter / 2.0 {
                return bad("a spherical interface's aperture is no wider than its sphere");
            }
            elements.push(Element {
                radius: row.curvature_radius / 1000.0,
                thickness: row.thickness / 1000.0,
                eta: if row.eta == 0.0 { 1.0 } else { row.eta },
                aperture_radius: diameter / 2000.0,
            });
        }
        let mut lens = Self {
            elements,
            diaphragm: Diaphragm::of(settings.aperture),
            film_diagonal: settings.film_diagonal / 1000.0,
            pupil: Vec::new(),
            clamped,
            thick_lens_distance: 0.0,
            image_distance: 0.0,
            pupil_samples: settings.pupil_samples,
        };
        let thick = lens.focus_thick_lens(settings.focus_distance)?;
        lens.thick_lens_distance = thick;
        let refined = lens.refined_focus(thick, settings.focus_distance);
        lens.set_film_distance(refined);
        let (principal, _) = lens.film_side_cardinal_points()?;
        // The film-side principal plane's distance ahead of the film.
        lens.image_distance = -principal;
        if !(lens.image_distance.is_finite() && lens.image_distance > 0.0) {
            return Err(LensError::new(
                None,
                "the lens system's rear principal plane is not ahead of the film: it forms \
                 no real image there",
            ));
        }
        let rings = Self::PUPIL_RINGS;
        let half = lens.film_diagonal / 2.0;
        lens.pupil = (0..rings)
            .into_par_iter()
            .map(|i| {
                let r0 = i as f64 / rings as f64 * half;
                let r1 = (i + 1) as f64 / rings as f64 * half;
                lens.bound_exit_pupil(r0, r1, stop)
            })
            .collect();
        if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            return Ok(None);
        }
        Ok(Some(lens))
    }

    /// The stop diameter asked for and the largest the lens file allows, when the first was
    /// larger and the diaphragm is open as far as it goes (pbrt-v4 warns).
    pub fn clamped_aperture(&self) -> Option<(f64, f64)> {
        self.clamped
    }

    /// From the film to the rear element, in scene units: the last row's thickness once
    /// focused.
    pub fn film_distance(&self) -> f64 {
        self.elements.last().map_or(0.0, |e| e.thickness)
    }

    /// The film distance pbrt-v4's thick-lens focusing gives, before this crate's refinement.
    pub fn thick_lens_film_distance(&self) -> f64 {
        self.thick_lens_distance
    }

    /// The film's diagonal in scene units.
    pub fn film_diagonal(&self) -> f64 {
        self.film_diagonal
    }

    /// Rays traced per ring to bound the exit pupil.
    pub fn pupil_samples(&self) -> usize {
        self.pupil_samples
    }

    /// The film's half width and half height for an image of `hsize × vsize` pixels: the
    /// diagonal's, at the image's aspect ratio (pbrt-v4's physical extent).
    pub fn film_half_extent(&self, hsize: usize, vsize: usize) -> (f64, f64) {
        let aspect = vsize as f64 / hsize.max(1) as f64;
        let x = (self.film_diagonal * self.film_diagonal / (1.0 + aspect * aspect)).sqrt();
        (x / 2.0, aspect * x / 2.0)
    }

    /// The field of view across the longer side of an `hsize × vsize` image of a pinhole at
    /// the lens's film-side principal plane: the lens's own as far as a single pinhole can
    /// be (what tools that aim one ray through a pixel use).
    pub fn equivalent_field_of_view(&self, hsize: usize, vsize: usize) -> f64 {
        let (w, h) = self.film_half_extent(hsize, vsize);
        2.0 * (w.max(h) / self.image_distance).atan()
    }

    /// The rear element's z (the film distance) and aperture radius.
    fn rear(&self) -> (f64, f64) {
        self.elements
            .last()
            .map_or((0.0, 0.0), |e| (e.thickness, e.aperture_radius))
    }

    /// The front element's z: every thickness added up.
    fn front_z(&self) -> f64 {
        self.elements.iter().map(|e| e.thickness).sum()
    }

    fn set_film_distance(&mut self, distance: f64) {
        if let Some(last) = self.elements.last_mut() {
            last.thickness = distance;
        }
    }

    /// The ray from the film `origin` along `direction` (camera space) traced through every
    /// element to the scene, with the diaphragm's transmission; `None` when it is vignetted
    /// (an element missed or hit outside its aperture, or reflected totally).
    pub fn trace_from_film(&self, origin: Vec3, direction: Vec3) -> Option<(LensRay, f64)> {
        // The lens's own space: z negated, the scene towards −z.
        let mut o = Vec3::new(origin.x, origin.y, -origin.z);
        let mut d = Vec3::new(direction.x, direction.y, -direction.z);
        let mut element_z = 0.0;
        let mut weight = 1.0;
        for i in (0..self.elements.len()).rev() {
            let element = &self.elements[i];
            element_z -= element.thickness;
            let (t, normal) = meet_element(element, element_z, o, d)?;
            let hit = o + d * t;
            if element.is_stop() && self.diaphragm.shape != ApertureShape::Circular {
                let r = element.aperture_radius;
                weight = self.diaphragm.weight(hit.x / r, hit.y / r);
                if weight == 0.0 {
                    return None;
                }
            } else if hit.x * hit.x + hit.y * hit.y > element.aperture_radius.powi(2) {
                return None;
            }
            o = hit;
            if !element.is_stop() {
                let eta_i = element.eta;
                let eta_t = if i > 0 { self.elements[i - 1].eta } else { 1.0 };
                d = refract(-d.normalize(), normal, eta_t / eta_i)?;
            }
        }
        let ray = LensRay {
            origin: Vec3::new(o.x, o.y, -o.z),
            direction: Vec3::new(d.x, d.y, -d.z),
        };
        Some((ray, weight))
    }

    /// The ray from the scene `origin` along `direction` (camera space) traced through every
    /// element to the film's side (the stop as its circle); `None` when it is vignetted.
    pub fn trace_from_scene(&self, origin: Vec3, direction: Vec3) -> Option<LensRay> {
        let mut o = Vec3::new(origin.x, origin.y, -origin.z);
        let mut d = Vec3::new(direction.x, direction.y, -direction.z);
        let mut element_z = -self.front_z();
        for (i, element) in self.elements.iter().enumerate() {
            let (t, normal) = meet_element(element, element_z, o, d)?;
            let hit = o + d * t;
            if hit.x * hit.x + hit.y * hit.y > element.aperture_radius.powi(2) {
                return None;
            }
            o = hit;
            if !element.is_stop() {
                let eta_i = if i > 0 { self.elements[i - 1].eta } else { 1.0 };
                d = refract(-d.normalize(), normal, element.eta / eta_i)?;
            }
            element_z += element.thickness;
        }
        Some(LensRay {
            origin: Vec3::new(o.x, o.y, -o.z),
            direction: Vec3::new(d.x, d.y, -d.z),
        })
    }

    /// The height off the axis of the paraxial rays that find the cardinal points.
    fn paraxial_height(&self) -> f64 {
        0.001 * self.film_diagonal
    }

    /// The film side's principal plane and focal point (z in the lens's space, the film at 0
    /// and the scene towards −z), from a ray parallel to the axis coming from the scene.
    fn film_side_cardinal_points(&self) -> Result<(f64, f64), LensError> {
        let x = self.paraxial_height();
        let start = Vec3::new(x, 0.0, self.front_z() + 1.0);
        let out = self
            .trace_from_scene(start, Vec3::new(0.0, 0.0, -1.0))
            .ok_or_else(|| {
                LensError::new(
                    None,
                    "no ray parallel to the axis gets from the scene through the lens system \
                     (is the aperture stop extremely small?)",
                )
            })?;
        Ok(cardinal_points(start, out))
    }

    /// The scene side's principal plane and focal point, from a ray parallel to the axis
    /// coming from the film.
    fn scene_side_cardinal_points(&self) -> Result<(f64, f64), LensError> {
        let x = self.paraxial_height();
        let start = Vec3::new(x, 0.0, self.rear().0 - 1.0);
        let (out, _) = self
            .trace_from_film(start, Vec3::new(0.0, 0.0, 1.0))
            .ok_or_else(|| {
                LensError::new(
                    None,
                    "no ray parallel to the axis gets from the film through the lens system \
                     (is the aperture stop extremely small, or the diaphragm's shape closed \
                     on the axis?)",
                )
            })?;
        Ok(cardinal_points(start, out))
    }

    /// The film distance that focuses `focus` ahead of the film by the thick-lens
    /// approximation and the Gaussian lens equation (pbrt-v4's `FocusThickLens`).
    fn focus_thick_lens(&self, focus: f64) -> Result<f64, LensError> {
        let (p_film, f_film) = self.film_side_cardinal_points()?;
        let (p_scene, _) = self.scene_side_cardinal_points()?;
        let f = f_film - p_film;
        let z = -focus;
        let c = (p_scene - z - p_film) * (p_scene - z - 4.0 * f - p_film);
        if c.is_nan() || c <= 0.0 {
            return Err(LensError::new(
                None,
                format!(
                    "the focus distance {focus} is too short for this lens system (its focal \
                     length is {f}): no film distance focuses it"
                ),
            ));
        }
        let delta = (p_scene - z + p_film - c.sqrt()) / 2.0;
        let distance = self.rear().0 + delta;
        if !(distance.is_finite() && distance > 0.0) {
            return Err(LensError::new(
                None,
                format!(
                    "focused at {focus}, the film would lie {distance} behind the rear \
                     element: not behind it"
                ),
            ));
        }
        Ok(distance)
    }

    /// Where a paraxial ray from the film's centre crosses the axis again in the scene, with
    /// the film `distance` behind the rear element; `None` when it does not ahead of the lens.
    fn paraxial_focus(&self, distance: f64) -> Option<f64> {
        let mut lens = self.clone();
        lens.set_film_distance(distance);
        let height = 0.01 * lens.rear().1;
        let (out, _) = lens.trace_from_film(Vec3::ZERO, Vec3::new(height, 0.0, distance))?;
        let t = -out.origin.x / out.direction.x;
        let z = out.origin.z + t * out.direction.z;
        (t > 0.0 && t.is_finite() && z > lens.front_z()).then_some(z)
    }

    /// The film distance a secant search on [`Self::paraxial_focus`] finds for `focus`,
    /// starting at the thick lens's `thick`; `thick` itself when the search does not settle
    /// within a percent of it.
    fn refined_focus(&self, thick: f64, focus: f64) -> f64 {
        // The reciprocals: nearly linear in the film distance (the lens equation).
        let error = |d: f64| self.paraxial_focus(d).map(|z| 1.0 / z - 1.0 / focus);
        let (mut d0, mut d1) = (thick, thick * (1.0 + 1e-4));
        let (Some(mut e0), Some(mut e1)) = (error(d0), error(d1)) else {
            return thick;
        };
        for _ in 0..32 {
            if e1 == e0 {
                break;
            }
            let d2 = d1 - e1 * (d1 - d0) / (e1 - e0);
            if !(d2.is_finite() && (d2 - thick).abs() <= 0.01 * thick) {
                return thick;
            }
            let Some(e2) = error(d2) else {
                return thick;
            };
            (d0, e0, d1, e1) = (d1, e1, d2, e2);
            if (d1 - d0).abs() <= 1e-13 * d1 {
                break;
            }
        }
        d1
    }

    /// The exit pupil's bounds for film points from `x0` to `x1` on +x: every sampled point
    /// of the rear element's plane a ray from the segment gets through by, grown by the
    /// samples' spacing; `None` when none does, or once `stop` is set (the caller looks).
    fn bound_exit_pupil(&self, x0: f64, x1: f64, stop: Option<&AtomicBool>) -> Option<PupilBounds> {
        let n = self.pupil_samples;
        let (rear_z, rear_radius) = self.rear();
        let side = 3.0 * rear_radius;
        let mut bounds: Option<PupilBounds> = None;
        for i in 0..n {
            if i % 4096 == 0 && stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                return None;
            }
            let film = Vec3::new(x0 + (x1 - x0) * ((i as f64 + 0.5) / n as f64), 0.0, 0.0);
            let (u, v) = (radical_inverse(2, i as u64), radical_inverse(3, i as u64));
            let (x, y) = (-1.5 * rear_radius + u * side, -1.5 * rear_radius + v * side);
            if bounds.is_some_and(|b| b.contains(x, y)) {
                continue;
            }
            if self
                .trace_from_film(film, Vec3::new(x, y, rear_z) - film)
                .is_some()
            {
                match &mut bounds {
                    Some(b) => b.grown_to(x, y),
                    None => bounds = Some(PupilBounds::point(x, y)),
                }
            }
        }
        let grow = 2.0 * (side * std::f64::consts::SQRT_2) / (n as f64).sqrt();
        bounds.map(|b| PupilBounds {
            min: (b.min.0 - grow, b.min.1 - grow),
            max: (b.max.0 + grow, b.max.1 + grow),
        })
    }

    /// The exit pupil's bounds for film points `r` from the film's centre (on +x; turn them
    /// to a point's angle), `None` where no ray gets through.
    pub fn exit_pupil_bounds(&self, r: f64) -> Option<PupilBounds> {
        let rings = self.pupil.len();
        let ring = (r / (self.film_diagonal / 2.0) * rings as f64) as usize;
        self.pupil
            .get(ring.min(rings.saturating_sub(1)))
            .copied()
            .flatten()
    }

    /// The ray through the film point at `(s, t)` of the image (each in [0, 1], 0 at the
    /// left and top) of an image of `half_extent` (from [`Self::film_half_extent`]), its
    /// rear-element point drawn from `(u, v)` in [0, 1)², and its weight (see the module's
    /// documentation); `None` when it is vignetted.
    pub fn ray(
        &self,
        (s, t): (f64, f64),
        half_extent: (f64, f64),
        (u, v): (f64, f64),
    ) -> Option<(LensRay, f64)> {
        let (w, h) = half_extent;
        // pbrt-v4's film point: the image's left is +x (the lens turns the image over).
        let film = Vec3::new(-(-w + 2.0 * w * s), -h + 2.0 * h * t, 0.0);
        let r = (film.x * film.x + film.y * film.y).sqrt();
        let bounds = self.exit_pupil_bounds(r)?;
        let px = bounds.min.0 + (bounds.max.0 - bounds.min.0) * u;
        let py = bounds.min.1 + (bounds.max.1 - bounds.min.1) * v;
        let (sin, cos) = if r != 0.0 {
            (film.y / r, film.x / r)
        } else {
            (0.0, 1.0)
        };
        let rear_z = self.rear().0;
        let pupil = Vec3::new(cos * px - sin * py, sin * px + cos * py, rear_z);
        let direction = pupil - film;
        let (ray, transmission) = self.trace_from_film(film, direction)?;
        let cos_theta = direction.z / direction.length();
        let weight = transmission * cos_theta.powi(4) * bounds.area() / (rear_z * rear_z);
        Some((ray, weight))
    }
}

/// The principal plane and focal point (z in the lens's space) of the ray `start`, parallel
/// to the axis at height `start.x`, that left the lens system as `out` (camera space).
fn cardinal_points(start: Vec3, out: LensRay) -> (f64, f64) {
    let tf = -out.origin.x / out.direction.x;
    let focal = -(out.origin.z + tf * out.direction.z);
    let tp = (start.x - out.origin.x) / out.direction.x;
    let principal = -(out.origin.z + tp * out.direction.z);
    (principal, focal)
}

/// Where the ray `o + t·d` (the lens's space) meets `element`, whose vertex is at
/// `element_z`: `t` and the surface's normal (none for the stop, a plane); `None` where it
/// misses or meets it behind.
fn meet_element(element: &Element, element_z: f64, o: Vec3, d: Vec3) -> Option<(f64, Vec3)> {
    if element.is_stop() {
        let t = (element_z - o.z) / d.z;
        (t >= 0.0 && t.is_finite()).then_some((t, Vec3::ZERO))
    } else {
        intersect_element(element.radius, element_z + element.radius, o, d)
    }
}

/// Where the ray `o + t·d` meets the spherical interface of `radius` centred at `z_center`
/// on the axis: the hit on the side the interface bulges towards the ray, and the normal
/// there facing the ray's origin.
fn intersect_element(radius: f64, z_center: f64, o: Vec3, d: Vec3) -> Option<(f64, Vec3)> {
    let oc = o - Vec3::new(0.0, 0.0, z_center);
    let a = d.length_squared();
    let b = 2.0 * d.dot(oc);
    let c = oc.length_squared() - radius * radius;
    let discriminant = b * b - 4.0 * a * c;
    if discriminant.is_nan() || discriminant < 0.0 || a == 0.0 {
        return None;
    }
    // The numerically stable pair of roots.
    let q = -0.5 * (b + b.signum() * discriminant.sqrt());
    let (r0, r1) = (q / a, if q != 0.0 { c / q } else { -b / (2.0 * a) });
    let (t0, t1) = (r0.min(r1), r0.max(r1));
    let closer = (d.z > 0.0) ^ (radius < 0.0);
    let t = if closer { t0 } else { t1 };
    if !(t >= 0.0 && t.is_finite()) {
        return None;
    }
    let mut n = (oc + d * t).normalize();
    if n.dot(-d) < 0.0 {
        n = -n;
    }
    Some((t, n))
}

/// The direction refracted from `wi` (towards where the ray came from, unit) through the
/// interface of normal `n` (on `wi`'s side) with relative index `eta` (transmitted over
/// incident); `None` on total internal reflection.
fn refract(wi: Vec3, n: Vec3, eta: f64) -> Option<Vec3> {
    let (mut n, mut eta) = (n, eta);
    let mut cos_i = n.dot(wi);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wi / eta + n * (cos_i / eta - cos_t))
}

/// The van der Corput radical inverse of `i` in `base`: a low-discrepancy coordinate.
fn radical_inverse(base: u64, mut i: u64) -> f64 {
    let inverse_base = 1.0 / base as f64;
    let (mut reversed, mut scale) = (0.0, inverse_base);
    while i > 0 {
        reversed += (i % base) as f64 * scale;
        i /= base;
        scale *= inverse_base;
    }
    reversed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_radical_inverse_mirrors_the_digits() {
        assert_eq!(radical_inverse(2, 1), 0.5);
        assert_eq!(radical_inverse(2, 6), 0.375);
        assert!((radical_inverse(3, 5) - (2.0 / 3.0 + 1.0 / 9.0)).abs() < 1e-15);
    }

    /// Each built-in shape passes what the circular stop passes: its transmission summed
    /// over the stop's square is π, the circle's area.
    #[test]
    fn every_diaphragm_passes_the_circles_light() {
        for shape in [
            ApertureShape::Circular,
            ApertureShape::Gaussian,
            ApertureShape::Square,
            ApertureShape::Pentagon,
            ApertureShape::Star,
        ] {
            let d = Diaphragm::of(shape);
            let n = 800;
            let mut sum = 0.0;
            for j in 0..n {
                for i in 0..n {
                    let u = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                    let v = -1.0 + 2.0 * (j as f64 + 0.5) / n as f64;
                    sum += d.weight(u, v);
                }
            }
            let integral = sum * 4.0 / (n * n) as f64;
            assert!(
                (integral - std::f64::consts::PI).abs() < 0.01,
                "{shape:?}: {integral}"
            );
        }
        // The pentagon's point is towards −y.
        let p = Diaphragm::of(ApertureShape::Pentagon);
        assert!(p.weight(0.0, -0.75) > 0.0 && p.weight(0.0, 0.75) == 0.0);
    }

    #[test]
    fn refraction_bends_towards_the_normal_into_glass() {
        let wi = Vec3::new(-(0.5f64).sin(), 0.0, (0.5f64).cos());
        let t = refract(wi, Vec3::Z, 1.5).expect("no total reflection into glass");
        let sin_t = t.x.abs() / t.length();
        assert!((sin_t - (0.5f64).sin() / 1.5).abs() < 1e-12);
        assert!(refract(
            -Vec3::new(0.9, 0.0, (1.0f64 - 0.81).sqrt()),
            -Vec3::Z,
            1.0 / 1.5
        )
        .is_none());
    }
}
