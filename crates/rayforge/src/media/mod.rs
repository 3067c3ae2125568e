//! Participating media: what fills space between surfaces and absorbs, scatters and gives
//! off light along the way (fog, smoke, coloured liquids, the inside of wax and skin).
//!
//! A [`Medium`] is homogeneous ([`Homogeneous`]), a density grid ([`GridMedium`]) or
//! pbrt-v4's procedural cloud ([`CloudMedium`]); the
//! world's media are a list ([`Media`]) that surfaces name by index ([`MediumId`]). Where a
//! medium is is told by surfaces: an object's [`MediumInterface`] says which medium lies
//! inside it and which outside, and the world names the medium around the camera. Light is
//! tracked through media by null-collision methods ([`tracking`]): delta tracking chooses
//! where a path scatters, ratio tracking estimates what a shadow ray lets through; in a
//! homogeneous medium [`equiangular`] sampling draws points near small lamps besides.

pub mod cloud;
pub mod equiangular;
pub mod glow;
pub mod grid;
pub mod homogeneous;
pub mod majorant;
pub mod phase;
pub mod tracking;

pub use cloud::CloudMedium;
pub use equiangular::{Anchors, Equiangular, MAX_ANCHORS};
pub use glow::{BlackbodyTable, ColorGrid, Glow, LOWEST_GLOWING_KELVIN, MAX_BLACKBODY_ENTRIES};
pub use grid::{DensityGrid, GridMedium, MAX_GRID_SAMPLES};
pub use homogeneous::Homogeneous;
pub use majorant::{MajorantGrid, MAJORANT_CELLS};
pub use phase::{HenyeyGreenstein, PhaseSample, MAX_ASYMMETRY};

use crate::color::Color;

/// A medium: one closed enum, matched once per query.
#[derive(Debug, Clone, PartialEq)]
pub enum Medium {
    /// The same everywhere.
    Homogeneous(Homogeneous),
    /// A density grid.
    Grid(Box<GridMedium>),
    /// A procedural cloud.
    Cloud(Box<CloudMedium>),
}

impl Medium {
    /// How it scatters.
    pub fn phase(&self) -> HenyeyGreenstein {
        match self {
            Medium::Homogeneous(m) => m.phase,
            Medium::Grid(m) => m.phase,
            Medium::Cloud(m) => m.phase,
        }
    }

    /// Whether it gives off light anywhere.
    pub fn emits(&self) -> bool {
        match self {
            Medium::Homogeneous(m) => m.emission.max_channel() > 0.0,
            Medium::Grid(m) => m.emits(),
            // pbrt-v4's cloud gives off no light.
            Medium::Cloud(_) => false,
        }
    }
}

/// A medium's place in the world's list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MediumId(pub u32);

/// The media on the two sides of a surface (`None`: vacuum), and whether the surface is only
/// that: an index-matched boundary (pbrt-v4's `interface` material), which rays cross
/// unbent and which neither reflects nor blocks light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MediumInterface {
    /// The medium on the side its normal points away from.
    pub inside: Option<MediumId>,
    /// The medium on the side its normal points to.
    pub outside: Option<MediumId>,
    /// Whether the surface only separates the media (its material is ignored).
    pub index_matched: bool,
}

impl MediumInterface {
    /// The medium a ray leaving the surface along `direction` travels through, the surface's
    /// geometric normal being `normal` (outward).
    #[inline]
    pub fn towards(
        &self,
        normal: crate::math::Vec3,
        direction: crate::math::Vec3,
    ) -> Option<MediumId> {
        if normal.dot(direction) > 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

/// The world's media, each named by its index.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Media {
    list: Vec<Medium>,
}

impl Media {
    /// No media.
    pub const NONE: Self = Self { list: Vec::new() };

    /// Adds `medium`, returning its id; at most `u32::MAX` media.
    pub fn add(&mut self, medium: Medium) -> Result<MediumId, MediumError> {
        let id = u32::try_from(self.list.len()).map_err(|_| MediumError::TooMany)?;
        self.list.push(medium);
        Ok(MediumId(id))
    }

    /// The medium `id` names.
    #[inline]
    pub fn get(&self, id: MediumId) -> &Medium {
        &self.list[id.0 as usize]
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// How many there are.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// The media, in order of their ids.
    pub fn iter(&self) -> impl Iterator<Item = &Medium> {
        self.list.iter()
    }
}

/// Why a medium cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MediumError {
    /// A coefficient is negative or not finite.
    #[error("`{name}` must be finite and at least 0 in every channel, found {value:?}")]
    Coefficient {
        /// Which coefficient.
        name: &'static str,
        /// What was given.
        value: Color,
    },
    /// The grid's size is zero along an axis, or too large.
    #[error("a density grid's size {0:?} must be at least 1 along each axis and hold at most {MAX_GRID_SAMPLES} samples")]
    GridSize([usize; 3]),
    /// The grid's values do not fill it.
    #[error("a density grid of this size holds {expected} values, found {found}")]
    GridCount {
        /// Its size's product.
        expected: usize,
        /// The values given.
        found: usize,
    },
    /// A density is negative or not finite.
    #[error("density {value} (value {at}, counting from 0) must be finite and at least 0")]
    GridValue {
        /// Which value.
        at: usize,
        /// What it is.
        value: f64,
    },
    /// A medium's scalar parameter is negative or not finite.
    #[error("`{name}` must be finite and at least 0, found {value}")]
    Parameter {
        /// Which parameter.
        name: &'static str,
        /// What was given.
        value: f64,
    },
    /// The medium's box is empty or not finite.
    #[error("a medium's bounds must have a positive, finite extent along each axis")]
    Bounds,
    /// More media than ids.
    #[error("too many media")]
    TooMany,
}

/// `c` checked as a medium's coefficient named `name`.
pub fn coefficient(name: &'static str, c: Color) -> Result<Color, MediumError> {
    if c.to_array().iter().all(|v| v.is_finite() && *v >= 0.0) {
        Ok(c)
    } else {
        Err(MediumError::Coefficient { name, value: c })
    }
}

/// Channel `i` (0 red, 1 green, 2 blue) of `c`: the hero channel of spectral MIS.
#[inline]
pub fn channel(c: Color, i: usize) -> f64 {
    match i {
        0 => c.red,
        1 => c.green,
        _ => c.blue,
    }
}

/// The channel mean.
#[inline]
pub fn average(c: Color) -> f64 {
    (c.red + c.green + c.blue) / 3.0
}

/// `e^(−σ·t)` per channel, 1 where σ is 0 (even for an infinite `t`).
#[inline]
pub fn beer(sigma: Color, t: f64) -> Color {
    let f = |s: f64| if s > 0.0 { (-s * t).exp() } else { 1.0 };
    Color::new(f(sigma.red), f(sigma.green), f(sigma.blue))
}
