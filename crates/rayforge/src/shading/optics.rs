//! Fundamentals of Ray Tracing's local illumination (Don Cross): the matte sum of the point
//! lights in view, by the cosine of incidence over the squared distance, and the Fresnel
//! reflection of one polarisation. The ray tracer's optics integrator and the rasterizer both
//! use them.

use super::light::Light;
use crate::color::Color;
use crate::math::{Point3, Vec3};

/// Fundamentals of Ray Tracing's matte sum at `point`: each point light in front of the
/// surface for which `in_view` holds (given its position), by its colour times the cosine of
/// incidence over the squared distance. Spotlights, area lights and image-shaped lights (by
/// their colour towards the point) count as points; ambient
/// and directional lights add nothing in this model (a directional light is a point infinitely
/// far away, whose 1/d² leaves nothing). The rasterizer, which casts no shadow rays, takes
/// every light as in view.
pub fn matte_light(
    lights: &[Light],
    point: Point3,
    normal: Vec3,
    mut in_view: impl FnMut(Point3) -> bool,
) -> Color {
    let mut sum = Color::BLACK;
    for light in lights {
        let (position, color) = match light {
            Light::Point(l) => (l.position, l.intensity),
            Light::Spot(l) => (l.position, l.intensity),
            Light::Pattern(l) => (l.position, l.intensity_at(point)),
            Light::Area(l) => (l.position(), l.intensity),
            Light::Ambient(_) | Light::Directional(_) => continue,
        };
        // A light behind the surface adds nothing: it is not asked whether it is in view
        // (a shadow ray each, for the ray tracer).
        let to_light = position - point;
        let incidence = normal.dot(to_light.normalize());
        if incidence > 0.0 && in_view(position) {
            sum += color * (incidence / to_light.length_squared());
        }
    }
    sum
}

/// One polarisation's Fresnel reflection (the book's `PolarizedReflection`): the fraction of
/// the light reflected passing from index `n1` into `n2` at the given cosines of incidence and
/// refraction; 1 when the denominator is below `epsilon`.
pub fn polarized_reflection(n1: f64, n2: f64, cos_a1: f64, cos_a2: f64, epsilon: f64) -> f64 {
    let left = n1 * cos_a1;
    let right = n2 * cos_a2;
    let numer = left - right;
    let denom = (left + right) * (left + right);
    if denom < epsilon {
        return 1.0;
    }
    (numer * numer / denom).min(1.0)
}
