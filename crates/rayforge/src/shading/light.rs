//! Light sources: point lights (chapter 6), rectangular area lights that cast soft shadows
//! (the bonus chapter "Rendering soft shadows"), spotlights (chapter 17), and the ambient and
//! directional lights of Computer Graphics from Scratch, and point lights whose intensity an
//! image shapes by direction (pbrt-v4's goniometric and projection lights, [`PatternLight`]).
//!
//! These are the scene's lights, one value per light, and every renderer reads the same
//! values: the Whitted integrators and the rasterizer with the books' meaning, through the
//! methods here (a spotlight's cone at a point, a directional light's unit direction, an area
//! light's sample points cell by cell, a light's reach with distance), and the path tracer
//! physically, one kind per file of the `lights` module, each built from these values and
//! asking them the same questions (a spotlight's fall-off, a directional light's direction, an
//! area light's sides). The values live here, below `scene`, so that a `World` can hold them
//! and the books' local lighting terms (`phong.rs`, `cgfs.rs`, `optics.rs`), which the
//! rasterizer shares, can read them; the path tracer's kinds live above `scene`, because an
//! emitting object is a light too and a scene object.

use crate::color::Color;
use crate::math::random::Jitter;
use crate::math::{equal_area_sphere_to_square, Point3, Vec3};
use glam::DMat3;
use std::sync::Arc;

/// A point light: no size, so its shadows are hard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    /// Where the light is.
    pub position: Point3,
    /// Its colour and brightness.
    pub intensity: Color,
    /// Whether its light falls off with the square of the distance (a physical light, glTF's
    /// `KHR_lights_punctual`: `intensity` is then the irradiance at unit distance) or reaches
    /// every distance equally, as the book's lights do.
    pub falloff: bool,
}

impl PointLight {
    /// The book's `point_light(position, intensity)`.
    pub const fn new(position: Point3, intensity: Color) -> Self {
        Self {
            position,
            intensity,
            falloff: false,
        }
    }
}

/// A rectangular light divided into `usteps × vsteps` cells, one sample per cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLight {
    /// One corner of the rectangle.
    pub corner: Point3,
    /// One cell's edge along the first side (the full side divided by `usteps`).
    pub uvec: Vec3,
    /// Cells along the first side.
    pub usteps: u32,
    /// One cell's edge along the second side.
    pub vvec: Vec3,
    /// Cells along the second side.
    pub vsteps: u32,
    /// Its colour and brightness (the whole light's).
    pub intensity: Color,
    /// Whether samples are placed randomly within their cells (banding turns into noise) or at
    /// the cells' centres.
    pub jitter: bool,
}

impl AreaLight {
    /// The book's `area_light(corner, full_uvec, usteps, full_vvec, vsteps, intensity)`.
    /// Step counts below 1 count as 1.
    pub fn new(
        corner: Point3,
        full_uvec: Vec3,
        usteps: u32,
        full_vvec: Vec3,
        vsteps: u32,
        intensity: Color,
    ) -> Self {
        let (usteps, vsteps) = (usteps.max(1), vsteps.max(1));
        Self {
            corner,
            uvec: full_uvec / usteps as f64,
            usteps,
            vvec: full_vvec / vsteps as f64,
            vsteps,
            intensity,
            jitter: false,
        }
    }

    /// The same light with jittered samples.
    pub fn jittered(mut self) -> Self {
        self.jitter = true;
        self
    }

    /// How many samples the light takes.
    pub fn samples(&self) -> u32 {
        self.usteps * self.vsteps
    }

    /// The rectangle's two full sides from its corner (a cell's edge times the cells along
    /// it): what the path tracer samples the light over, uniformly.
    pub fn sides(&self) -> (Vec3, Vec3) {
        (
            self.uvec * f64::from(self.usteps),
            self.vvec * f64::from(self.vsteps),
        )
    }

    /// The centre of the rectangle.
    pub fn position(&self) -> Point3 {
        self.corner
            + self.uvec * (self.usteps as f64 / 2.0)
            + self.vvec * (self.vsteps as f64 / 2.0)
    }

    /// The book's `point_on_light(light, u, v)`: a point in cell (`u`, `v`), its centre or,
    /// when jittered, a random point of it.
    pub fn point_on_light(&self, u: u32, v: u32, jitter: &mut dyn Jitter) -> Point3 {
        let (ju, jv) = if self.jitter {
            (jitter.next_offset(), jitter.next_offset())
        } else {
            (0.5, 0.5)
        };
        self.corner + self.uvec * (u as f64 + ju) + self.vvec * (v as f64 + jv)
    }

    /// The fraction of the light's samples that reach `point`: `blocked(sample)` says whether
    /// something lies between a sample point on the light and `point`.
    pub fn fraction_visible(
        &self,
        jitter: &mut dyn Jitter,
        mut blocked: impl FnMut(Point3) -> bool,
    ) -> f64 {
        let lit = self
            .cells()
            .filter(|&(u, v)| !blocked(self.point_on_light(u, v, jitter)))
            .count();
        lit as f64 / self.samples() as f64
    }

    /// Every cell, row by row.
    pub fn cells(&self) -> impl Iterator<Item = (u32, u32)> {
        let usteps = self.usteps;
        (0..self.vsteps).flat_map(move |v| (0..usteps).map(move |u| (u, v)))
    }
}

/// A spotlight: a point light that shines in a cone, fading out towards the cone's edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotLight {
    /// Where the light is.
    pub position: Point3,
    /// Unit vector along the cone's axis.
    pub direction: Vec3,
    /// Cosine of the half-angle inside which the light is at full strength.
    pub cos_inner: f64,
    /// Cosine of the half-angle outside which there is no light.
    pub cos_outer: f64,
    /// Its colour and brightness.
    pub intensity: Color,
    /// Whether its light falls off with the square of the distance (see
    /// [`PointLight::falloff`]).
    pub falloff: bool,
}

impl SpotLight {
    /// A spotlight at `position` pointing along `direction`, dark beyond `cone_angle` (the
    /// half-angle, radians) and fading over the outer `fade_angle` of it. `None` when the
    /// direction is zero or not finite.
    pub fn new(
        position: Point3,
        direction: Vec3,
        cone_angle: f64,
        fade_angle: f64,
        intensity: Color,
    ) -> Option<Self> {
        let direction = direction.try_normalize()?;
        let outer = cone_angle.clamp(0.0, std::f64::consts::PI);
        let inner = (outer - fade_angle.max(0.0)).max(0.0);
        Some(Self {
            position,
            direction,
            cos_inner: inner.cos(),
            cos_outer: outer.cos(),
            intensity,
            falloff: false,
        })
    }

    /// How strongly the spot lights a point seen along `to_point` (a unit vector from the
    /// light): 1 inside the inner cone, 0 outside the outer, a smooth step between.
    pub fn falloff(&self, to_point: Vec3) -> f64 {
        let cos = to_point.dot(self.direction);
        if cos >= self.cos_inner {
            return 1.0;
        }
        if cos <= self.cos_outer {
            return 0.0;
        }
        let t = (cos - self.cos_outer) / (self.cos_inner - self.cos_outer);
        t * t * (3.0 - 2.0 * t)
    }

    /// How strongly the spot lights `point`: its [`falloff`](Self::falloff) along the unit
    /// vector from the light to the point (0 at the light itself), as every Whitted model and
    /// the rasterizer scale its light.
    #[inline]
    pub fn cone_at(&self, point: Point3) -> f64 {
        self.falloff((point - self.position).normalize_or_zero())
    }
}

/// Parallel light from infinitely far away (the sun), Computer Graphics from Scratch's
/// directional light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalLight {
    /// The direction from any surface towards the light, as given: Computer Graphics from
    /// Scratch uses this vector, unnormalised, as its `L`.
    pub towards: Vec3,
    /// Its colour and brightness.
    pub intensity: Color,
}

impl DirectionalLight {
    /// The unit direction towards the light (zero for a zero `towards`): what the Phong model,
    /// the Whitted shadow rays and the path tracer read (Computer Graphics from Scratch's
    /// model takes `towards` as given).
    #[inline]
    pub fn direction(&self) -> Vec3 {
        self.towards.normalize_or_zero()
    }
}

/// The picture of a [`PatternLight`]: linear RGB, row 0 the top, each row from the left,
/// shared between the light's copies (a light is copied for every renderer that reads it).
#[derive(Debug, Clone, PartialEq)]
pub struct LightImage {
    width: usize,
    height: usize,
    texels: Vec<Color>,
    /// The largest value of any channel of any texel: what bounds the light's reach.
    peak: f64,
}

impl LightImage {
    /// The `width × height` image of `texels` (row by row from the top); `None` when it is
    /// empty, the texels are not `width × height`, or a value is negative or not finite.
    pub fn new(width: usize, height: usize, texels: Vec<Color>) -> Option<Self> {
        let fine = |c: &Color| c.to_array().iter().all(|v| v.is_finite() && *v >= 0.0);
        if width == 0 || height == 0 || texels.len() != width * height || !texels.iter().all(fine) {
            return None;
        }
        let peak = texels.iter().map(|c| c.max_channel()).fold(0.0, f64::max);
        Some(Self {
            width,
            height,
            texels,
            peak,
        })
    }

    /// Pixels across.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Pixels down.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The texels, row by row from the top.
    pub fn texels(&self) -> &[Color] {
        &self.texels
    }

    /// The largest value of any channel.
    pub fn peak(&self) -> f64 {
        self.peak
    }

    /// The texel nearest `(u, v)` of the unit square (`v` down from the top row), clamped at
    /// the edges: pbrt-v4's nearest look-up (the coordinates times the size, truncated).
    #[inline]
    pub fn nearest(&self, u: f64, v: f64) -> Color {
        let at = |t: f64, n: usize| ((t * n as f64) as usize).min(n - 1);
        self.texels[at(v, self.height) * self.width + at(u, self.width)]
    }
}

/// How a [`PatternLight`]'s image lies over the directions of its own space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PatternShape {
    /// Over the whole sphere in the equal-area square layout (the square's centre the light's
    /// +z, its corners −z): pbrt-v4's goniometric light.
    Sphere,
    /// Through the window `[-half_width, half_width] × [-half_height, half_height]` of the
    /// plane one unit along the light's +z, the image's top row at +y, its left column at −x;
    /// nothing beyond the window or behind the light: pbrt-v4's projection light.
    Frustum {
        /// Half the window's width at unit distance.
        half_width: f64,
        /// Half its height.
        half_height: f64,
    },
}

/// Below this cosine with the light's axis a frustum gives nothing (pbrt-v4's near plane).
const HITHER: f64 = 1e-3;

/// A point light whose intensity in each direction is its `intensity` times the image's texel
/// that direction meets (pbrt-v4's goniometric and projection lights): hard shadows, as a point
/// light's, shaped like a photometric web or a slide projector's beam.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternLight {
    /// Where the light is.
    pub position: Point3,
    /// Its intensity where the image is 1 (at unit distance, falling off as a point light's).
    pub intensity: Color,
    /// Whether its light falls off with the square of the distance (see [`PointLight`]).
    pub falloff: bool,
    /// From the world's directions into the light's own (any invertible matrix: what it does
    /// to a direction's length does not matter, each is normalised).
    pub to_light: DMat3,
    /// How the image covers the light's directions.
    pub shape: PatternShape,
    /// The image.
    pub image: Arc<LightImage>,
}

impl PatternLight {
    /// The image's colour (before `intensity`) along the world direction `towards` leaving
    /// the light; black where the image does not reach.
    #[inline]
    pub fn pattern(&self, towards: Vec3) -> Color {
        let d = (self.to_light * towards).normalize_or_zero();
        match self.shape {
            PatternShape::Sphere => {
                if d == Vec3::ZERO {
                    return Color::BLACK;
                }
                let (u, v) = equal_area_sphere_to_square(d);
                self.image.nearest(u, v)
            }
            PatternShape::Frustum {
                half_width,
                half_height,
            } => {
                // (`d` is finite: a direction that is not normalises to zero.)
                if d.z < HITHER {
                    return Color::BLACK;
                }
                let (x, y) = (d.x / d.z, d.y / d.z);
                if x.abs() > half_width || y.abs() > half_height {
                    return Color::BLACK;
                }
                let u = (x + half_width) / (2.0 * half_width);
                let v = (half_height - y) / (2.0 * half_height);
                self.image.nearest(u, v)
            }
        }
    }

    /// Its intensity towards `point` (black at the light itself): what every Whitted model and
    /// the rasterizer light the point with, before the fall-off with distance.
    #[inline]
    pub fn intensity_at(&self, point: Point3) -> Color {
        self.intensity * self.pattern(point - self.position)
    }

    /// The mean over the sphere of directions of its image's colour (black beyond a frustum):
    /// the intensity of the point light of the same power. pbrt-v4's power sums: the texels'
    /// mean for the sphere; for a frustum, each texel weighted by the solid angle it subtends
    /// at its centre (`cos³θ` times its area of the window), the sum over `4π`.
    pub fn mean_pattern(&self) -> Color {
        let image = &self.image;
        let (w, h) = (image.width, image.height);
        let n = (w * h) as f64;
        match self.shape {
            PatternShape::Sphere => image.texels.iter().copied().sum::<Color>() / n,
            PatternShape::Frustum {
                half_width,
                half_height,
            } => {
                let texel_area = 4.0 * half_width * half_height / n;
                let mut sum = Color::BLACK;
                for (i, c) in image.texels.iter().enumerate() {
                    let x = half_width * (2.0 * ((i % w) as f64 + 0.5) / w as f64 - 1.0);
                    let y = half_height * (2.0 * ((i / w) as f64 + 0.5) / h as f64 - 1.0);
                    let cos = 1.0 / (1.0 + x * x + y * y).sqrt();
                    sum += *c * (cos * cos * cos * texel_area);
                }
                sum / (4.0 * std::f64::consts::PI)
            }
        }
    }

    /// The world direction of its axis (+z of its space), unit: a frustum's centre.
    pub fn axis(&self) -> Vec3 {
        (self.to_light.inverse() * Vec3::Z).normalize_or_zero()
    }

    /// The angle between its axis and the farthest direction its light reaches: a frustum's
    /// corner, π for the sphere (in the light's space, which an unrotating matrix keeps).
    pub fn spread(&self) -> f64 {
        match self.shape {
            PatternShape::Sphere => std::f64::consts::PI,
            PatternShape::Frustum {
                half_width,
                half_height,
            } => {
                let m = self.to_light.inverse();
                let axis = (m * Vec3::Z).normalize_or_zero();
                // Every corner is as far from the axis for a rotation; a stretch may move them.
                [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
                    .iter()
                    .map(|(sx, sy)| {
                        let c = m * Vec3::new(sx * half_width, sy * half_height, 1.0);
                        axis.dot(c.normalize_or_zero()).clamp(-1.0, 1.0).acos()
                    })
                    .fold(0.0, f64::max)
            }
        }
    }
}

/// A light source of any kind.
#[derive(Debug, Clone, PartialEq)]
pub enum Light {
    /// A point light.
    Point(PointLight),
    /// A rectangular area light.
    Area(AreaLight),
    /// A spotlight.
    Spot(SpotLight),
    /// Light that reaches every surface equally, from no direction and unshadowed (Computer
    /// Graphics from Scratch's ambient light).
    Ambient(Color),
    /// Parallel light from infinitely far away.
    Directional(DirectionalLight),
    /// A point light shaped by an image.
    Pattern(PatternLight),
}

/// How far away a directional light is taken to be where a position is needed.
const FAR_AWAY: f64 = 1e12;

impl Light {
    /// The book's `point_light(position, intensity)` as a [`Light`].
    pub const fn point(position: Point3, intensity: Color) -> Self {
        Light::Point(PointLight::new(position, intensity))
    }

    /// How much of its intensity reaches `point`: `1 / d²` for a light that falls off with
    /// distance, 1 for every other.
    #[inline]
    pub fn reach(&self, point: Point3) -> f64 {
        let position = match self {
            Light::Point(l) if l.falloff => l.position,
            Light::Spot(l) if l.falloff => l.position,
            Light::Pattern(l) if l.falloff => l.position,
            _ => return 1.0,
        };
        1.0 / (position - point).length_squared().max(1e-300)
    }

    /// Whether its light falls off with distance (a physical light, which adds no ambient
    /// term to the book's lighting).
    #[inline]
    pub fn falls_off(&self) -> bool {
        matches!(
            self,
            Light::Point(PointLight { falloff: true, .. })
                | Light::Spot(SpotLight { falloff: true, .. })
                | Light::Pattern(PatternLight { falloff: true, .. })
        )
    }

    /// The light's colour and brightness (at unit distance, for one that falls off; an image's
    /// light where the image is 1).
    pub fn intensity(&self) -> Color {
        match self {
            Light::Pattern(l) => l.intensity,
            Light::Point(l) => l.intensity,
            Light::Area(l) => l.intensity,
            Light::Spot(l) => l.intensity,
            Light::Ambient(intensity) => *intensity,
            Light::Directional(l) => l.intensity,
        }
    }

    /// The light's position: an area light's centre; for a directional light, a point very far
    /// along its direction (so that code needing a position sees a distant point light); the
    /// origin for ambient light, which has none.
    pub fn position(&self) -> Point3 {
        match self {
            Light::Point(l) => l.position,
            Light::Area(l) => l.position(),
            Light::Spot(l) => l.position,
            Light::Pattern(l) => l.position,
            Light::Ambient(_) => Point3::ZERO,
            Light::Directional(l) => l.direction() * FAR_AWAY,
        }
    }
}
