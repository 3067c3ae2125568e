//! The camera (chapter 7): a pinhole with a field of view, placed by a view transform; with a
//! thin lens (focal blur) and a shutter (motion blur) from chapter 17; or Computer Graphics from
//! Scratch's viewport camera; orthographic and spherical cameras, a canvas window off the
//! axis, pbrt-v4's realistic camera (a lens system traced element by element), and a
//! sensor's response for the scenes of other renderers (glTF, pbrt-v4).
//!
//! Any camera but the viewport one may move while the shutter is open, as pbrt-v4's
//! `CameraTransform` does: its world-from-camera transform is interpolated between the two
//! ends ([`Motion`], translation, rotation and stretch apart) at each ray's instant, and the
//! ray it would cast from its opening placement is carried along.

mod realistic;
mod sample;
mod sensor;
mod spherical;
mod viewport;
mod window;

pub use realistic::{
    ApertureShape, LensError, LensInterface, LensRay, LensSettings, LensSystem, PupilBounds,
};
pub use sample::{CameraRay, CameraSample};
pub use sensor::Sensor;
pub use spherical::SphericalMapping;
pub use viewport::Viewport;
use window::Grid;
pub use window::ScreenWindow;

use crate::math::{Motion, Point3, Ray, Transform, Vec3};

/// A pinhole camera looking down -z in its own space, with the canvas one unit in front of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    hsize: usize,
    vsize: usize,
    field_of_view: f64,
    transform: Transform,
    half_width: f64,
    half_height: f64,
    pixel_size: f64,
    /// Where each image point lies on the canvas: the book's centred grid of `pixel_size`,
    /// or a screen window's.
    grid: Grid,
    /// The screen window the grid was made from, kept so that a resized camera spans it
    /// again (`None`: the centred default).
    window: Option<ScreenWindow>,
    /// Diameter of the thin lens (0: a pinhole, everything in focus).
    aperture: f64,
    /// Distance from the eye to the plane that is in focus.
    focal_distance: f64,
    /// When the shutter opens and closes, in the time of object motions (a moving object is
    /// at its start at 0 and its end at 1).
    shutter: (f64, f64),
    /// Computer Graphics from Scratch's viewport, which then decides every ray.
    viewport: Option<Viewport>,
    /// How rays leave the eye: through a pinhole (or thin lens), in parallel, or to every
    /// direction about it.
    model: Model,
    /// What the film records of each sample's radiance.
    sensor: Sensor,
    /// The pinhole's rays in the world, worked out from the fields above whenever they
    /// change (see [`PinholeRays`]).
    rays: PinholeRays,
    /// Where the camera moves while the shutter is open: its world-from-camera transform
    /// (the view transform's inverse) at time 0, `transform`'s, and at time 1. Boxed: most
    /// cameras stand still.
    moving: Option<Box<Motion>>,
}

/// How a camera's rays leave it.
#[derive(Debug, Clone, PartialEq)]
enum Model {
    /// Through a pinhole (or a thin lens) and the canvas one unit in front of it.
    Pinhole,
    /// In parallel along −z, each from its canvas point at the camera itself (an
    /// orthographic camera, as glTF and pbrt files have); the canvas then spans
    /// `2 × half_width` world units.
    Orthographic,
    /// From the eye to every direction about it, the image laid out by the mapping.
    Spherical(SphericalMapping),
    /// Through a lens system from the film (pbrt-v4's realistic camera), the film's half
    /// width and height beside it; its pinhole fields are the equivalent pinhole's
    /// ([`LensSystem::equivalent_field_of_view`]), for the tools that aim one ray a pixel.
    Realistic(std::sync::Arc<LensSystem>, (f64, f64)),
}

/// A pinhole camera's rays in world space for the path tracer: the eye, and the direction
/// towards the canvas point `(x, y)` (in pixels) as `corner + x · across + y · down`. The
/// canvas point is `(half_width − x · pixel_size, half_height − y · pixel_size, −1)` in the
/// camera's space (the [`Grid`]'s point), and the view transform's inverse is affine, so its linear part takes the
/// canvas's corner and the two pixel steps to the world once for every ray. The book's
/// camera ray is two point transforms: 4 % of the instructions of spheres-materials, whose
/// paths are short. The sums round differently from the book's, so the Whitted renderers,
/// whose images are the books' to the byte, keep the book's ray ([`Camera::ray_through`]);
/// only [`Camera::path_ray_for_sample`] reads these.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PinholeRays {
    eye: Point3,
    corner: Vec3,
    across: Vec3,
    down: Vec3,
}

impl PinholeRays {
    /// The rays of a pinhole whose canvas is `grid`, placed by `transform`.
    fn of(transform: &Transform, grid: &Grid) -> Self {
        Self {
            eye: transform.inverse_point(Point3::ZERO),
            corner: transform.inverse_vector(Vec3::new(grid.left, grid.top, -1.0)),
            across: transform.inverse_vector(Vec3::new(-grid.step_x, 0.0, 0.0)),
            down: transform.inverse_vector(Vec3::new(0.0, -grid.step_y, 0.0)),
        }
    }
}

impl Camera {
    /// The book's `camera(hsize, vsize, field_of_view)`; the field of view spans the longer side.
    pub fn new(hsize: usize, vsize: usize, field_of_view: f64) -> Self {
        let half_view = (field_of_view / 2.0).tan();
        let aspect = hsize as f64 / vsize as f64;
        let (half_width, half_height) = if aspect >= 1.0 {
            (half_view, half_view / aspect)
        } else {
            (half_view * aspect, half_view)
        };
        let pixel_size = half_width * 2.0 / hsize as f64;
        let grid = Grid::centred(half_width, half_height, pixel_size);
        Self {
            hsize,
            vsize,
            field_of_view,
            transform: Transform::IDENTITY,
            half_width,
            half_height,
            pixel_size,
            grid,
            window: None,
            aperture: 0.0,
            focal_distance: 1.0,
            shutter: (0.0, 1.0),
            viewport: None,
            model: Model::Pinhole,
            sensor: Sensor::IDENTITY,
            rays: PinholeRays::of(&Transform::IDENTITY, &grid),
            moving: None,
        }
    }

    /// The same camera with its transform `transform`, standing still there, and its
    /// pinhole's rays worked out again: what every change of its placement goes through.
    fn placed(mut self, transform: Transform) -> Self {
        self.transform = transform;
        self.rays = PinholeRays::of(&transform, &self.grid);
        self.moving = None;
        self
    }

    /// An orthographic camera: parallel rays along its −z through a canvas whose longer side
    /// spans `2 × half_extent` world units (glTF's `xmag`/`ymag` are such half extents).
    pub fn orthographic(hsize: usize, vsize: usize, half_extent: f64) -> Self {
        // The canvas of a pinhole camera whose tan(fov / 2) is the half extent, met at z = 0.
        let mut camera = Self::new(hsize, vsize, 2.0 * half_extent.atan());
        let aspect = hsize as f64 / vsize as f64;
        (camera.half_width, camera.half_height) = if aspect >= 1.0 {
            (half_extent, half_extent / aspect)
        } else {
            (half_extent * aspect, half_extent)
        };
        camera.pixel_size = camera.half_width * 2.0 / hsize as f64;
        camera.grid = Grid::centred(camera.half_width, camera.half_height, camera.pixel_size);
        camera.model = Model::Orthographic;
        camera.placed(Transform::IDENTITY)
    }

    /// A spherical camera (pbrt-v4's): rays from the eye to every direction about it, laid
    /// out on the `hsize × vsize` image by `mapping` (see [`SphericalMapping`]). It has no
    /// lens, and its field of view is the whole turn (2π).
    pub fn spherical(hsize: usize, vsize: usize, mapping: SphericalMapping) -> Self {
        let mut camera = Self::new(hsize, vsize, std::f64::consts::FRAC_PI_2);
        camera.field_of_view = std::f64::consts::TAU;
        camera.model = Model::Spherical(mapping);
        camera
    }

    /// pbrt-v4's realistic camera: rays from the `hsize × vsize` film through `lens`, the
    /// film's extent its diagonal at the image's aspect ratio. Its [`Self::ray_through`] is
    /// the equivalent pinhole's ray (the same field of view and image orientation), for the
    /// tools that aim one ray a pixel; rendering traces the lens ([`Self::ray_for_sample`]).
    pub fn realistic(hsize: usize, vsize: usize, lens: std::sync::Arc<LensSystem>) -> Self {
        let mut camera = Self::new(hsize, vsize, lens.equivalent_field_of_view(hsize, vsize));
        let extent = lens.film_half_extent(hsize, vsize);
        camera.model = Model::Realistic(lens, extent);
        camera
    }

    /// The lens system of a realistic camera (`None` for any other).
    pub fn lens_system(&self) -> Option<&LensSystem> {
        match &self.model {
            Model::Realistic(lens, _) => Some(lens),
            _ => None,
        }
    }

    /// Whether a camera ray depends on its sample's lens point: a thin lens's or a lens
    /// system's (a pinhole's does not, and its renderers draw no lens point).
    pub fn samples_lens(&self) -> bool {
        self.aperture > 0.0 || matches!(self.model, Model::Realistic(..))
    }

    /// Whether the camera is orthographic.
    pub fn is_orthographic(&self) -> bool {
        self.model == Model::Orthographic
    }

    /// The mapping of a spherical camera (`None` for any other).
    pub fn spherical_mapping(&self) -> Option<SphericalMapping> {
        match self.model {
            Model::Spherical(m) => Some(m),
            _ => None,
        }
    }

    /// The same pinhole or orthographic camera with its image spanning `window` of the
    /// canvas instead of the centred default (pbrt's `screenwindow`): the image then lies off
    /// the axis where the window does, and its pixels are stretched where the window's shape
    /// is not the image's. `None` for a window that is not finite or is empty
    /// ([`ScreenWindow::is_valid`]), and for a spherical or viewport camera, which have no
    /// canvas. What the grid costs each ray is the centred one's: four numbers.
    pub fn with_screen_window(mut self, window: ScreenWindow) -> Option<Self> {
        if !window.is_valid()
            || self.viewport.is_some()
            || matches!(self.model, Model::Spherical(_) | Model::Realistic(..))
        {
            return None;
        }
        self.grid = Grid::of(&window, self.hsize, self.vsize);
        self.window = Some(window);
        self.rays = PinholeRays::of(&self.transform, &self.grid);
        Some(self)
    }

    /// The screen window, when one was given ([`Self::with_screen_window`]).
    pub fn screen_window(&self) -> Option<ScreenWindow> {
        self.window
    }

    /// The same camera recording each sample's radiance through `sensor` (pbrt's film's
    /// imaging ratio and white balance).
    pub fn with_sensor(mut self, sensor: Sensor) -> Self {
        self.sensor = sensor;
        self
    }

    /// What the film records of each sample's radiance.
    pub fn sensor(&self) -> &Sensor {
        &self.sensor
    }

    /// What the film records of a sample's radiance `c`: `c` itself under the identity
    /// sensor (not multiplied by it, so that the books' images keep their bits).
    #[inline]
    pub fn record(&self, c: crate::color::Color) -> crate::color::Color {
        if self.sensor.is_identity() {
            c
        } else {
            self.sensor.record(c)
        }
    }

    /// Computer Graphics from Scratch's camera: a `hsize × vsize` canvas onto `viewport`.
    ///
    /// Its rays are the book's (see [`Viewport`]): unnormalised, reaching the projection plane
    /// at `t = 1`, and only hits beyond that plane count ([`Ray::t_min`] is 1). The camera's
    /// transform is set to the matching view transform, for code that needs one; it is `None`
    /// when the rotation cannot be inverted.
    pub fn viewport(hsize: usize, vsize: usize, viewport: Viewport) -> Option<Self> {
        let r = viewport.rotation;
        let world_from_camera = glam::DMat4::from_cols(
            glam::DVec4::new(r[0][0], r[1][0], r[2][0], 0.0),
            glam::DVec4::new(r[0][1], r[1][1], r[2][1], 0.0),
            glam::DVec4::new(r[0][2], r[1][2], r[2][2], 0.0),
            viewport.position.extend(1.0),
        );
        // The book's camera space has x right and z forward; this crate's looks down -z with
        // x to the left: half a turn about y between them.
        let flip = glam::DMat4::from_rotation_y(std::f64::consts::PI);
        let view = Transform::try_new(flip * world_from_camera.inverse()).ok()?;
        let mut camera = Self::new(hsize, vsize, viewport.field_of_view()).with_transform_of(view);
        camera.viewport = Some(viewport);
        Some(camera)
    }

    /// The viewport, for a Computer Graphics from Scratch camera.
    pub fn viewport_of(&self) -> Option<&Viewport> {
        self.viewport.as_ref()
    }

    /// The same camera with its shutter open from `open` to `close` (motion blur shows what
    /// moves in between; `open == close` freezes the motion at that instant). Non-finite
    /// values keep the default, the whole motion from 0 to 1.
    pub fn with_shutter(mut self, open: f64, close: f64) -> Self {
        if open.is_finite() && close.is_finite() {
            self.shutter = (open.min(close), open.max(close));
        }
        self
    }

    /// When the shutter opens and closes.
    pub fn shutter(&self) -> (f64, f64) {
        self.shutter
    }

    /// The same camera with a thin lens of diameter `aperture`, focused at `focal_distance`
    /// (focal blur). Negative or non-finite values mean a pinhole.
    pub fn with_lens(mut self, aperture: f64, focal_distance: f64) -> Self {
        let valid = aperture.is_finite() && aperture > 0.0 && focal_distance.is_finite();
        self.aperture = if valid { aperture } else { 0.0 };
        self.focal_distance = if valid { focal_distance.max(1e-9) } else { 1.0 };
        self
    }

    /// The lens diameter (0 for a pinhole).
    pub fn aperture(&self) -> f64 {
        self.aperture
    }

    /// The distance in focus.
    pub fn focal_distance(&self) -> f64 {
        self.focal_distance
    }

    /// The same camera at another resolution, keeping its field of view and placement.
    pub fn resized(&self, hsize: usize, vsize: usize) -> Self {
        if let Some(viewport) = self.viewport {
            // Built afresh for the new canvas: its pixel size (which the rasterizer projects
            // with) changes with it. The viewport was accepted once, so it is accepted again.
            if let Some(camera) = Self::viewport(hsize, vsize, viewport) {
                return camera
                    .with_lens(self.aperture, self.focal_distance)
                    .with_shutter(self.shutter.0, self.shutter.1)
                    .with_sensor(self.sensor);
            }
        }
        let mut camera = match &self.model {
            Model::Orthographic => {
                let half_longer = self.half_width.max(self.half_height);
                Self::orthographic(hsize, vsize, half_longer)
            }
            Model::Pinhole => Self::new(hsize, vsize, self.field_of_view),
            Model::Spherical(mapping) => Self::spherical(hsize, vsize, *mapping),
            // The same lens and film diagonal: the extent follows the new aspect ratio.
            Model::Realistic(lens, _) => Self::realistic(hsize, vsize, lens.clone()),
        };
        if let Some(window) = self.window {
            // The same window over the new pixels: the same field of view. It was accepted
            // once, so it is accepted again.
            camera = camera.clone().with_screen_window(window).unwrap_or(camera);
        }
        let mut camera = camera
            .with_transform_of(self.transform)
            .with_lens(self.aperture, self.focal_distance)
            .with_shutter(self.shutter.0, self.shutter.1)
            .with_sensor(self.sensor);
        camera.moving = self.moving.clone();
        camera
    }

    /// The same camera placed by a view transform (`camera_from_world`).
    ///
    /// # Panics
    /// When the matrix is singular; use [`Camera::with_transform_of`] with a checked
    /// [`Transform`] for user input.
    pub fn with_transform(self, matrix: glam::DMat4) -> Self {
        self.with_transform_of(Transform::new(matrix))
    }

    /// The same camera with a prepared view transform, standing still.
    pub fn with_transform_of(self, transform: Transform) -> Self {
        self.placed(transform)
    }

    /// The same camera moving while the shutter is open: placed by its view transform at
    /// time 0 and by `end` (a view transform too, `camera_from_world`) at time 1, in the time
    /// of object motions (see [`Self::with_shutter`]). Between them its world-from-camera
    /// transform is interpolated as a moving object's is, as pbrt-v4 interpolates its
    /// camera's. `None` for a viewport camera, whose rays keep the book's unnormalised
    /// length (the projection plane at `t = 1`), which a moving placement would stretch.
    pub fn with_motion(mut self, end: Transform) -> Option<Self> {
        if self.viewport.is_some() {
            return None;
        }
        let inverse = |t: &Transform| Transform::try_new(t.inverse_matrix()).ok();
        self.moving = (end != self.transform)
            .then(|| {
                Some(Box::new(Motion::new(
                    inverse(&self.transform)?,
                    inverse(&end)?,
                )))
            })
            .flatten();
        Some(self)
    }

    /// Whether the camera moves while the shutter is open ([`Self::with_motion`]).
    pub fn moves(&self) -> bool {
        self.moving.is_some()
    }

    /// The camera's world-from-camera transform at time 1, when it moves.
    pub fn motion_end(&self) -> Option<&Transform> {
        self.moving.as_ref().map(|m| m.end())
    }

    /// The same camera moved as a rigid body: its eye turned by `rotation` about the world
    /// point `pivot`, and its view turned with it (a viewer's orbit). A viewport camera's
    /// position and rotation move; another camera's view transform does, and the turned
    /// camera stands still (a viewer turns the frame it shows). `None` when the moved view
    /// transform cannot be inverted.
    pub fn turned_about(&self, pivot: Point3, rotation: glam::DQuat) -> Option<Self> {
        let mut camera = self.clone();
        if let Some(viewport) = &mut camera.viewport {
            viewport.position = pivot + rotation * (viewport.position - pivot);
            // `rotation` holds rows: the matrix is the transpose of the one its rows make as
            // columns.
            let rows = glam::DMat3::from_cols_array_2d(&viewport.rotation).transpose();
            let turned = glam::DMat3::from_quat(rotation) * rows;
            viewport.rotation = turned.transpose().to_cols_array_2d();
            return Some(camera);
        }
        // The world moves by the inverse of the eye's motion, before the old view.
        let about = glam::DMat4::from_translation(pivot)
            * glam::DMat4::from_quat(rotation.inverse())
            * glam::DMat4::from_translation(-pivot);
        let moved = Transform::try_new(self.transform.matrix() * about).ok()?;
        Some(camera.placed(moved))
    }

    /// Width in pixels.
    pub fn hsize(&self) -> usize {
        self.hsize
    }

    /// Height in pixels.
    pub fn vsize(&self) -> usize {
        self.vsize
    }

    /// Field of view in radians, across the longer side.
    pub fn field_of_view(&self) -> f64 {
        self.field_of_view
    }

    /// The view transform.
    pub fn transform(&self) -> &Transform {
        &self.transform
    }

    /// Size of one pixel of the centred canvas one unit in front of the eye (a screen
    /// window's pixels are its own: [`Self::screen_window`]).
    pub fn pixel_size(&self) -> f64 {
        self.pixel_size
    }

    /// The book's `ray_for_pixel(camera, px, py)`: through the centre of the pixel.
    pub fn ray_for_pixel(&self, px: usize, py: usize) -> Ray {
        self.ray_through(px as f64 + 0.5, py as f64 + 0.5)
    }

    /// The ray for one camera sample: through its image point, from its lens point, at its
    /// instant of the shutter interval, with its weight. `None` where a realistic camera's
    /// lens system vignettes the sample: no light reaches that film point from that lens
    /// point, and the sample's radiance is zero (it still counts in its pixel, as pbrt-v4
    /// counts it). Every other camera's ray has weight 1.
    pub fn ray_for_sample(&self, sample: &CameraSample) -> Option<CameraRay> {
        if let Model::Realistic(lens, extent) = &self.model {
            return self.lens_system_ray(lens, *extent, sample);
        }
        let ray = self.ray_through_lens(sample.x, sample.y, sample.lens_u, sample.lens_v);
        Some(CameraRay::unweighted(self.in_shutter(ray, sample.time)))
    }

    /// The path tracer's ray for one camera sample: [`Self::ray_for_sample`]'s ray to
    /// rounding, but a pinhole's from the eye, canvas corner and pixel steps worked out once
    /// ([`PinholeRays`]) instead of two point transforms per ray. Its last bits may differ
    /// from the book's, which only a Monte Carlo estimate can afford.
    pub fn path_ray_for_sample(&self, sample: &CameraSample) -> Option<CameraRay> {
        if self.aperture == 0.0 && self.viewport.is_none() && self.model == Model::Pinhole {
            let ray = self.pinhole_ray_through(sample.x, sample.y);
            return Some(CameraRay::unweighted(self.in_shutter(ray, sample.time)));
        }
        self.ray_for_sample(sample)
    }

    /// A realistic camera's ray for `sample`: from its film point through `lens` (the film's
    /// half extent `extent`), turned from pbrt's camera space into the book's (x and z
    /// negated) and placed in the world.
    fn lens_system_ray(
        &self,
        lens: &LensSystem,
        extent: (f64, f64),
        sample: &CameraSample,
    ) -> Option<CameraRay> {
        let film = (sample.x / self.hsize as f64, sample.y / self.vsize as f64);
        let (ray, weight) = lens.ray(film, extent, (sample.lens_u, sample.lens_v))?;
        let book = |v: Vec3| Vec3::new(-v.x, v.y, -v.z);
        let origin = self.transform.inverse_point(book(ray.origin));
        let direction = self
            .transform
            .inverse_vector(book(ray.direction))
            .normalize();
        let ray = self.in_shutter(Ray::new(origin, direction), sample.time);
        Some(CameraRay { ray, weight })
    }

    /// `ray` (cast from the camera's opening placement) at the instant `time` (in [0, 1)) of
    /// the shutter interval: carried, when the camera moves, to where the camera is then
    /// (taken back to the camera's space by the view transform, and out by the
    /// world-from-camera transform of that instant; its direction made unit again, as every
    /// camera ray here but a viewport's is).
    #[inline]
    fn in_shutter(&self, ray: Ray, time: f64) -> Ray {
        let (open, close) = self.shutter;
        let time = open + (close - open) * time;
        let Some(motion) = &self.moving else {
            return ray.at_time(time);
        };
        let moved = ray.transform(motion.at(time).matrix() * self.transform.matrix());
        Ray::new(moved.origin, moved.direction.normalize())
            .from_t(ray.t_min)
            .at_time(time)
    }

    /// A pinhole's ray through the canvas point `(x, y)` from its [`PinholeRays`].
    fn pinhole_ray_through(&self, x: f64, y: f64) -> Ray {
        let PinholeRays {
            eye,
            corner,
            across,
            down,
        } = self.rays;
        Ray::new(eye, (corner + across * x + down * y).normalize())
    }

    /// The ray through a point of the canvas from a point of the lens: `lens_u`, `lens_v` in
    /// [0, 1) pick the point on the lens disk (0.5, 0.5 is its centre). The ray passes through
    /// the canvas point's image on the focal plane, so only that plane is sharp.
    pub fn ray_through_lens(&self, x: f64, y: f64, lens_u: f64, lens_v: f64) -> Ray {
        if self.aperture == 0.0 || self.viewport.is_some() || self.model != Model::Pinhole {
            return self.ray_through(x, y);
        }
        let (canvas_x, canvas_y) = self.grid.point(x, y);
        let canvas = Point3::new(canvas_x, canvas_y, -1.0);
        let focus = canvas * self.focal_distance;
        let (dx, dy) = concentric_disk(lens_u, lens_v);
        let lens = Point3::new(dx, dy, 0.0) * (self.aperture / 2.0);
        let origin = self.transform.inverse_point(lens);
        let target = self.transform.inverse_point(focus);
        Ray::new(origin, (target - origin).normalize())
    }

    /// The ray through a point of the canvas in pixel units (0,0 is the top-left corner),
    /// as the book computes it (its `ray_for_pixel`: the canvas point and the eye each taken
    /// through the view transform's inverse), so the Whitted renderers' images keep its bits.
    pub fn ray_through(&self, x: f64, y: f64) -> Ray {
        if let Some(viewport) = &self.viewport {
            let (w, h) = (self.hsize as f64, self.vsize as f64);
            let (cx, cy) = Viewport::canvas_point(x, y, w, h);
            return Ray::new(viewport.position, viewport.direction(cx, cy, w, h)).from_t(1.0);
        }
        if let Model::Spherical(mapping) = self.model {
            let direction = mapping.direction(x / self.hsize as f64, y / self.vsize as f64);
            let origin = self.transform.inverse_point(Point3::ZERO);
            return Ray::new(origin, self.transform.inverse_vector(direction).normalize());
        }
        let (world_x, world_y) = self.grid.point(x, y);
        if self.model == Model::Orthographic {
            let origin = self
                .transform
                .inverse_point(Point3::new(world_x, world_y, 0.0));
            let ahead = self
                .transform
                .inverse_point(Point3::new(world_x, world_y, -1.0));
            return Ray::new(origin, (ahead - origin).normalize());
        }
        let pixel = self
            .transform
            .inverse_point(Point3::new(world_x, world_y, -1.0));
        let origin = self.transform.inverse_point(Point3::ZERO);
        Ray::new(origin, (pixel - origin).normalize())
    }
}

/// Maps the unit square onto the unit disk keeping strata compact (Shirley and Chiu's
/// concentric mapping), so stratified lens samples stay stratified.
fn concentric_disk(u: f64, v: f64) -> (f64, f64) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f64::consts::FRAC_PI_4;
    let (r, theta) = if a.abs() > b.abs() {
        (a, quarter * (b / a))
    } else {
        (b, 2.0 * quarter - quarter * (a / b))
    };
    (r * theta.cos(), r * theta.sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{point, vector, view_transform};

    /// The ray through `(x, y)` as the canvas point and the eye taken through the view
    /// transform's inverse one at a time (what [`PinholeRays`] works out once).
    fn ray_by_two_points(camera: &Camera, x: f64, y: f64) -> Ray {
        let (canvas_x, canvas_y) = camera.grid.point(x, y);
        let canvas = Point3::new(canvas_x, canvas_y, -1.0);
        let eye = camera.transform.inverse_point(Point3::ZERO);
        let pixel = camera.transform.inverse_point(canvas);
        Ray::new(eye, (pixel - eye).normalize())
    }

    /// Every way a camera is placed or changed keeps its pinhole's rays those of its
    /// transform: placed, turned about a point, resized, and placed again.
    #[test]
    fn the_pinhole_rays_follow_every_change_of_the_camera() {
        let placed = Camera::new(64, 48, 1.1).with_transform(view_transform(
            point(1.0, 2.0, -5.0),
            point(0.3, 0.0, 0.2),
            vector(0.1, 1.0, 0.0),
        ));
        let turned = placed
            .turned_about(
                point(0.5, -0.2, 1.0),
                glam::DQuat::from_rotation_y(0.7) * glam::DQuat::from_rotation_x(-0.3),
            )
            .expect("a rotation keeps the transform invertible");
        let resized = turned.resized(33, 80);
        let moved_again = resized.clone().with_transform(view_transform(
            point(-3.0, 1.0, 4.0),
            point(0.0, 0.5, 0.0),
            vector(0.0, 1.0, 0.0),
        ));
        for camera in [
            Camera::new(10, 10, 0.9),
            placed,
            turned,
            resized,
            moved_again,
        ] {
            for (x, y) in [(0.0, 0.0), (0.5, 0.5), (3.25, 7.75), (9.999, 4.0)] {
                let (ours, theirs) = (
                    camera.pinhole_ray_through(x, y),
                    ray_by_two_points(&camera, x, y),
                );
                assert!((ours.origin - theirs.origin).length() < 1e-12);
                assert!((ours.direction - theirs.direction).length() < 1e-12);
            }
        }
    }

    /// The Whitted renderers' camera rays are the book's to the bit (their images are pinned
    /// to the byte): every pixel of scenes/bench/chessboard.yml's camera at 48 × 27, whose
    /// image changed bytes when these rays were the path tracer's precomputed ones. That
    /// some of those differ in their last bits here shows this test can fail.
    #[test]
    fn the_whitted_camera_rays_are_the_books_to_the_bit() {
        let camera = Camera::new(48, 27, 0.9).with_transform(view_transform(
            point(0.0, 5.0, -9.0),
            point(0.0, 0.0, 0.0),
            vector(0.0, 1.0, 0.0),
        ));
        let bits = |r: &Ray| {
            [r.origin.x, r.origin.y, r.origin.z]
                .into_iter()
                .chain([r.direction.x, r.direction.y, r.direction.z])
                .map(f64::to_bits)
                .collect::<Vec<_>>()
        };
        let mut precomputed_differ = 0;
        for py in 0..27 {
            for px in 0..48 {
                let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                let book = bits(&ray_by_two_points(&camera, x, y));
                assert_eq!(bits(&camera.ray_for_pixel(px, py)), book, "pixel {px},{py}");
                let sample = CameraSample {
                    x,
                    y,
                    lens_u: 0.5,
                    lens_v: 0.5,
                    time: 0.5,
                };
                let ray = camera.ray_for_sample(&sample).expect("a pinhole's ray");
                assert_eq!(ray.weight, 1.0);
                assert_eq!(bits(&ray.ray), book, "pixel {px},{py}");
                let path = camera
                    .path_ray_for_sample(&sample)
                    .expect("a pinhole's ray");
                if bits(&path.ray) != book {
                    precomputed_differ += 1;
                }
            }
        }
        assert!(precomputed_differ > 0);
    }

    /// A moving camera casts its opening placement's rays at time 0, its closing
    /// placement's at time 1 (each camera kind: pinhole, thin lens, orthographic, spherical),
    /// and half way through a pure translation from the point half way along it; the
    /// shutter's interval picks the instants. A camera placed again, or turned, stands still.
    #[test]
    fn a_moving_camera_casts_each_instants_rays() {
        let start = view_transform(
            point(0.0, 1.0, -5.0),
            point(0.0, 0.0, 0.0),
            vector(0.0, 1.0, 0.0),
        );
        let end = view_transform(
            point(2.0, 1.0, -5.0),
            point(2.0, 0.0, 0.0),
            vector(0.0, 1.0, 0.0),
        );
        let kinds = [
            Camera::new(16, 12, 1.0),
            Camera::new(16, 12, 1.0).with_lens(0.3, 4.0),
            Camera::orthographic(16, 12, 2.0),
            Camera::spherical(16, 12, SphericalMapping::Equirectangular),
        ];
        let close = |a: &Ray, b: &Ray| {
            (a.origin - b.origin).length() < 1e-9 && (a.direction - b.direction).length() < 1e-9
        };
        for kind in kinds {
            let moving = kind
                .clone()
                .with_transform(start)
                .with_motion(Transform::new(end))
                .expect("not a viewport camera");
            assert!(moving.moves());
            let (first, last) = (kind.clone().with_transform(start), kind.with_transform(end));
            for (x, y) in [(0.5, 0.5), (7.25, 3.5), (15.0, 11.0)] {
                let sample = |time| CameraSample {
                    x,
                    y,
                    lens_u: 0.3,
                    lens_v: 0.8,
                    time,
                };
                let ray = |c: &Camera, time| c.path_ray_for_sample(&sample(time)).unwrap().ray;
                assert!(close(&ray(&moving, 0.0), &ray(&first, 0.0)));
                assert!(close(&ray(&moving, 1.0), &ray(&last, 1.0)));
                let (a, b, mid) = (ray(&first, 0.5), ray(&last, 0.5), ray(&moving, 0.5));
                assert!((mid.origin - (a.origin + b.origin) * 0.5).length() < 1e-9);
                assert!((mid.direction - a.direction).length() < 1e-9);
                assert_eq!(mid.time, 0.5);
                // A shutter from 0.25 to 0.5 sees the motion between those instants.
                let late = moving.clone().with_shutter(0.25, 0.5);
                let r = ray(&late, 1.0);
                assert_eq!(r.time, 0.5);
                assert!(close(&r, &mid));
                assert!(late.resized(16, 12).moves());
            }
            assert!(!moving.clone().with_transform(start).moves());
            let turned =
                moving.turned_about(point(0.0, 0.0, 0.0), glam::DQuat::from_rotation_y(0.1));
            assert!(!turned.expect("a rotation").moves());
        }
        let viewport = Camera::viewport(8, 8, Viewport::BOOK).expect("an invertible rotation");
        assert!(viewport.with_motion(Transform::new(end)).is_none());
    }
}
