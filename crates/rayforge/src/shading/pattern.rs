//! Patterns (chapter 10 and its "Putting it together" extras): colour as a function of a point.
//!
//! A pattern has its own transform, applied after the object's: the world point is moved into
//! object space, then into pattern space. Patterns that hold other patterns (stripes of stripes,
//! blends, perturbations) evaluate each child in the child's own space, nested inside the parent's.

use super::noise::perlin_noise;
use super::texture::{CubeFace, UvMapping, UvPattern};
use crate::color::Color;
use crate::math::{Point3, Transform};

/// A pattern with its transform.
#[derive(Debug, Clone, PartialEq)]
pub struct Pattern {
    /// What colour goes where.
    pub kind: PatternKind,
    /// Pattern space relative to the object (or parent pattern).
    pub transform: Transform,
}

/// The kinds of pattern. Each holds sub-patterns, so any of them nests; plain colours are
/// [`PatternKind::Solid`].
#[derive(Debug, Clone, PartialEq)]
pub enum PatternKind {
    /// One colour everywhere (the book's `solid_pattern`).
    Solid(Color),
    /// Bands across x, cycling through the sub-patterns (the book has two; the community's files
    /// use three).
    Stripes(Vec<Pattern>),
    /// A linear blend from the first to the second pattern across each unit of x.
    Gradient(Box<Pattern>, Box<Pattern>),
    /// Concentric rings in xz, cycling through the sub-patterns.
    Rings(Vec<Pattern>),
    /// 3D checkers: cells of unit size cycling through the sub-patterns.
    Checkers(Vec<Pattern>),
    /// A gradient that runs outward from the y axis, repeating every unit of radius.
    RadialGradient(Box<Pattern>, Box<Pattern>),
    /// The average of the sub-patterns.
    Blended(Vec<Pattern>),
    /// The sub-pattern evaluated at a point jittered by 3D Perlin noise.
    Perturbed {
        /// The pattern being perturbed.
        pattern: Box<Pattern>,
        /// How far points move (in pattern-space units); the book suggests 0.2 or less.
        scale: f64,
    },
    /// A 2D pattern wrapped onto the surface by a mapping (the texture-mapping bonus chapter).
    Map {
        /// How points become (u, v).
        mapping: UvMapping,
        /// What is drawn on (u, v).
        uv: UvPattern,
    },
    /// A 2D pattern per face of the cube (left, front, right, back, up, down): a skybox.
    CubeMap(Box<[UvPattern; 6]>),
    /// The pattern-space point itself as a colour (the book's `test_pattern`; handy for
    /// checking transforms).
    Position,
}

impl Pattern {
    /// A pattern with the identity transform.
    pub fn new(kind: PatternKind) -> Self {
        Self {
            kind,
            transform: Transform::IDENTITY,
        }
    }

    /// The same pattern with a transform.
    pub fn with_transform(mut self, transform: Transform) -> Self {
        self.transform = transform;
        self
    }

    /// `solid_pattern(color)`.
    pub fn solid(color: Color) -> Self {
        Self::new(PatternKind::Solid(color))
    }

    /// `stripe_pattern(a, b)`.
    pub fn stripes(a: Color, b: Color) -> Self {
        Self::new(PatternKind::Stripes(vec![Self::solid(a), Self::solid(b)]))
    }

    /// `gradient_pattern(a, b)`.
    pub fn gradient(a: Color, b: Color) -> Self {
        Self::new(PatternKind::Gradient(
            Box::new(Self::solid(a)),
            Box::new(Self::solid(b)),
        ))
    }

    /// `ring_pattern(a, b)`.
    pub fn rings(a: Color, b: Color) -> Self {
        Self::new(PatternKind::Rings(vec![Self::solid(a), Self::solid(b)]))
    }

    /// `checkers_pattern(a, b)`.
    pub fn checkers(a: Color, b: Color) -> Self {
        Self::new(PatternKind::Checkers(vec![Self::solid(a), Self::solid(b)]))
    }

    /// `radial_gradient_pattern(a, b)`.
    pub fn radial_gradient(a: Color, b: Color) -> Self {
        Self::new(PatternKind::RadialGradient(
            Box::new(Self::solid(a)),
            Box::new(Self::solid(b)),
        ))
    }

    /// The book's `test_pattern()`.
    pub fn position() -> Self {
        Self::new(PatternKind::Position)
    }

    /// The book's `pattern_at(pattern, point)`: the colour at a point already in pattern space.
    pub fn pattern_at(&self, p: Point3) -> Color {
        match &self.kind {
            PatternKind::Solid(c) => *c,
            PatternKind::Stripes(ps) => cycle(ps, p.x.floor(), p),
            PatternKind::Gradient(a, b) => a.nested_at(p).lerp(b.nested_at(p), p.x - p.x.floor()),
            PatternKind::Rings(ps) => cycle(ps, p.x.hypot(p.z).floor(), p),
            PatternKind::Checkers(ps) => cycle(ps, p.x.floor() + p.y.floor() + p.z.floor(), p),
            PatternKind::RadialGradient(a, b) => {
                let r = p.x.hypot(p.z);
                a.nested_at(p).lerp(b.nested_at(p), r - r.floor())
            }
            PatternKind::Blended(ps) => {
                ps.iter().map(|q| q.nested_at(p)).sum::<Color>() / ps.len().max(1) as f64
            }
            PatternKind::Perturbed { pattern, scale } => {
                pattern.nested_at(p + perturbation(p) * *scale)
            }
            PatternKind::Map { mapping, uv } => {
                let (u, v) = mapping.map(p);
                uv.uv_pattern_at(u, v)
            }
            PatternKind::CubeMap(faces) => {
                let face = CubeFace::from_point(p);
                let (u, v) = face.uv(p);
                faces[face.index()].uv_pattern_at(u, v)
            }
            PatternKind::Position => Color::new(p.x, p.y, p.z),
        }
    }

    /// The colour for a point given in the parent's space (applies this pattern's transform).
    #[inline]
    pub fn nested_at(&self, parent_point: Point3) -> Color {
        self.pattern_at(self.transform.inverse_point(parent_point))
    }
}

/// Picks the sub-pattern for a cell index, cycling (and handling negative cells).
fn cycle(patterns: &[Pattern], cell: f64, p: Point3) -> Color {
    if patterns.is_empty() {
        return Color::BLACK;
    }
    let n = patterns.len() as f64;
    // rem_euclid keeps negative cells in range; the cast is safe because the result is in [0, n).
    let index = cell.rem_euclid(n);
    let index = if index.is_finite() { index as usize } else { 0 };
    patterns[index.min(patterns.len() - 1)].nested_at(p)
}

/// A 3D offset from three decorrelated noise lookups (shifting the sample point per axis).
fn perturbation(p: Point3) -> Point3 {
    Point3::new(
        perlin_noise(p),
        perlin_noise(p + Point3::new(31.7, 47.3, 11.9)),
        perlin_noise(p + Point3::new(-23.1, 5.7, 71.3)),
    )
}
