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
use crate::math::{Aabb, Transform};

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

    /// A bound on the optical depth of one straight pass through it: the extinction's
    /// majorant (its largest channel) times the length of its box's diagonal in the world.
    /// Tracking a ray through a grid or a cloud takes about that many tentative collisions,
    /// real or null, so this is what a pass costs; a homogeneous medium's tracking ends at
    /// its first collision whatever its density, and it has no box (0).
    pub fn optical_depth_bound(&self) -> f64 {
        let across =
            |bounds: &Aabb, transform: &Transform| bounds.transform(transform).extent().length();
        match self {
            Medium::Homogeneous(_) => 0.0,
            Medium::Grid(m) => {
                (m.sigma_a + m.sigma_s).max_channel()
                    * m.density.max_value()
                    * across(&m.bounds, &m.transform)
            }
            Medium::Cloud(m) => m.sigma_maj().max_channel() * across(&m.bounds, &m.transform),
        }
    }

    /// The medium, if one pass through it has an optical depth of at most `limit`
    /// ([`optical_depth_bound`](Self::optical_depth_bound)): past it a ray's tracking takes
    /// more collisions than a render can wait for (a cloud of density 10¹² takes as many
    /// per ray), so a scene asking for it is refused rather than left to hang.
    pub fn within_optical_depth(self, limit: f64) -> Result<Self, MediumError> {
        let depth = self.optical_depth_bound();
        if depth <= limit {
            Ok(self)
        } else {
            Err(MediumError::OpticalDepth { depth, limit })
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
    /// One pass through the medium crosses more optical depth than the limit.
    #[error("one pass through this medium crosses an optical depth of up to {depth:.3e} (its largest extinction times its box's diagonal), above the limit of {limit:.3e} (--max-optical-depth): tracking a ray through it would take as many steps")]
    OpticalDepth {
        /// The medium's bound.
        depth: f64,
        /// The limit.
        limit: f64,
    },
    /// More media than ids.
    #[error("too many media")]
    TooMany,
}

/// The most optical depth one pass through a grid or cloud may cross, by default (the
/// `--max-optical-depth` flag): each unit is about one tentative collision of a ray's
/// tracking, so 10⁶ is a tenth of a second a pass; dense real media (wax, skin, a thick
/// cloud a kilometre across) cross thousands.
pub const MAX_OPTICAL_DEPTH: f64 = 1e6;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{point, scaling};

    #[test]
    fn a_pass_costs_the_largest_extinction_times_the_box_diagonal_in_the_world() {
        // Densities up to 2 under σt = 1 + 3 (its largest channel), in a unit box scaled by
        // 2: the diagonal in the world is 2√3, the bound 4 × 2 × 2√3.
        let grid = GridMedium::new(
            Color::new(1.0, 0.5, 0.5),
            Color::new(3.0, 1.0, 1.0),
            Color::BLACK,
            HenyeyGreenstein::ISOTROPIC,
            DensityGrid::new([2, 1, 1], vec![0.5, 2.0]).expect("a grid"),
            Aabb::new(point(0.0, 0.0, 0.0), point(1.0, 1.0, 1.0)),
            Transform::new(scaling(2.0, 2.0, 2.0)),
        )
        .expect("a medium");
        let medium = Medium::Grid(Box::new(grid));
        let bound = 16.0 * 3f64.sqrt();
        assert!((medium.optical_depth_bound() - bound).abs() < 1e-9);
        assert!(medium.clone().within_optical_depth(bound + 1e-6).is_ok());
        let refused = medium
            .within_optical_depth(bound - 1e-6)
            .expect_err("too dense");
        assert!(
            refused.to_string().contains("--max-optical-depth"),
            "{refused}"
        );
        // A homogeneous medium's tracking ends at its first collision: no bound to keep.
        let fog = Medium::Homogeneous(Homogeneous {
            sigma_a: Color::WHITE * 1e30,
            sigma_s: Color::WHITE,
            emission: Color::BLACK,
            phase: HenyeyGreenstein::ISOTROPIC,
        });
        assert_eq!(fog.optical_depth_bound(), 0.0);
        assert!(fog.within_optical_depth(1.0).is_ok());
    }
}
