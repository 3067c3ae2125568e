//! The torus around the y axis: a tube of radius `minor` whose centre circle has radius `major`
//! in the xz plane (Fundamentals of Ray Tracing, chapter 13, turned to the y-up convention of
//! The Ray Tracer Challenge). Its points satisfy `(|p|² + R² − r²)² = 4R²(x² + z²)`.
//!
//! Sampled by area ([`sample_area`]) as a ring torus (tube no wider than the ring) or as a
//! spindle torus (tube wider: the whole surface the quartic describes, the outer apple and the
//! inner lemon, which is what rays meet), uniformly by the area element `|R + r cos φ|·r`.

use crate::math::roots::{polynomial_roots_in, MAX_DEGREE};
use crate::math::{Point3, Ray, Vec3};
use std::f64::consts::PI;

/// Every hit of the ray with the torus (up to four), in no particular order.
///
/// The quartic is solved in a frame that keeps its coefficients small whatever the ray: the
/// direction is made unit length and the origin moved to the ray's point nearest the centre, so
/// the cubic term vanishes and every root lies within `R + r` of zero. A ray that starts a
/// million units away then loses no more precision than one that starts next to the torus.
pub fn intersect(ray: &Ray, major: f64, minor: f64, mut hit: impl FnMut(f64)) {
    let length = ray.direction.length();
    if length.is_nan() || length <= 0.0 || !length.is_finite() {
        return;
    }
    // One division, then products: the divisions were a tenth of a torus scene.
    let inv_length = 1.0 / length;
    let d = ray.direction * inv_length;
    let s0 = -ray.origin.dot(d);
    let o = ray.origin + d * s0;
    let outer = major + minor;
    let miss_distance_squared = o.length_squared();
    if miss_distance_squared > outer * outer {
        return; // the ray passes outside the bounding sphere
    }
    // Every root lies on the chord of the bounding sphere; pad it so that roots at its very
    // ends (rays grazing the outer equator) are not lost to rounding.
    let half_chord = (outer * outer - miss_distance_squared).sqrt() * (1.0 + 1e-9) + 1e-9 * outer;
    // Every root also lies where the ray is within the tube's slab |y| <= r: a ray that stays
    // above or below it along the whole chord misses, with no quartic to solve.
    if o.y.abs() - d.y.abs() * half_chord > minor * (1.0 + 1e-9) {
        return;
    }
    let e = miss_distance_squared + major * major - minor * minor;
    let four_r2 = 4.0 * major * major;
    let coefficients = [
        e * e - four_r2 * (o.x * o.x + o.z * o.z),
        -2.0 * four_r2 * (o.x * d.x + o.z * d.z),
        2.0 * e - four_r2 * (d.x * d.x + d.z * d.z),
        0.0,
        1.0,
    ];
    let mut roots = [0.0; MAX_DEGREE];
    let n = polynomial_roots_in(&coefficients, -half_chord, half_chord, &mut roots);
    for s in &roots[..n] {
        hit((s + s0) * inv_length);
    }
}

/// Whether `p` is inside the tube: `(|p|² + R² − r²)² < 4R²(x² + z²)`, the surface's equation
/// with its sign.
pub fn contains(p: Point3, major: f64, minor: f64) -> bool {
    let e = p.length_squared() + major * major - minor * minor;
    e * e < 4.0 * major * major * (p.x * p.x + p.z * p.z)
}

/// The outward normal (along the gradient of the surface's equation, out of the solid
/// [`contains`] describes). On a ring torus, and on a spindle torus's outer part, it points
/// away from the nearest point of the centre circle (Cross's construction: `P − Q` with
/// `Q = R·(x, 0, z)/|(x, 0, z)|`). A spindle torus (r > R) also has an inner lemon, swept by
/// the far side of the tube, where `|p|² + R² − r² = −2R·|(x, 0, z)|` is negative: there the
/// tube's centre is `−Q`, and the solid lies outside the lemon (its inside is covered twice
/// and [`contains`] leaves it out), so the outward normal is `−(P + Q)`, into the lemon.
pub fn normal_at(p: Point3, major: f64, minor: f64) -> Vec3 {
    let radial = p.x.hypot(p.z);
    if radial == 0.0 {
        // Only a spindle torus (r > R) has surface on its axis: the normal is along it.
        return Vec3::new(0.0, p.y.signum(), 0.0);
    }
    let scale = major / radial;
    if p.length_squared() + major * major - minor * minor < 0.0 {
        return Vec3::new(-p.x - p.x * scale, -p.y, -p.z - p.z * scale);
    }
    Vec3::new(p.x - p.x * scale, p.y, p.z - p.z * scale)
}

/// Texture coordinates: `u` around the y axis (as the cylindrical mapping measures it), `v`
/// around the tube, starting at its outer equator and going over the top.
pub fn toroidal_map(p: Point3, major: f64) -> (f64, f64) {
    let around_axis = p.x.atan2(p.z) / (2.0 * PI);
    let around_tube = p.y.atan2(p.x.hypot(p.z) - major) / (2.0 * PI);
    (1.0 - (around_axis + 0.5), around_tube.rem_euclid(1.0))
}

/// Whether the torus can be sampled by area: a ring torus (`R ≥ r > 0`) or a spindle torus
/// (`r > R > 0`), finite.
pub fn is_sampled(major: f64, minor: f64) -> bool {
    major.is_finite() && minor.is_finite() && minor > 0.0 && major > 0.0
}

/// The area: `4π² R r` for a ring torus; for a spindle torus (r > R)
/// `2π r ∫₀^{2π} |R + r cos φ| dφ = 2π r (4 R φ₀ + 4 r sin φ₀ − 2π R)` with `φ₀ = acos(−R/r)`.
pub fn area(major: f64, minor: f64) -> f64 {
    if major >= minor {
        4.0 * PI * PI * major * minor
    } else {
        let phi0 = (-major / minor).clamp(-1.0, 1.0).acos();
        2.0 * PI * minor * (4.0 * major * phi0 + 4.0 * minor * phi0.sin() - 2.0 * PI * major)
    }
}

/// A point of a ring or spindle torus (see [`is_sampled`]) uniformly by area, from `u` in
/// [0, 1)², and its unit outward normal (as [`normal_at`] orients it).
pub fn sample_area(major: f64, minor: f64, [u, v]: [f64; 2]) -> (Point3, Vec3) {
    if major >= minor {
        let phi = tube_angle(major, minor, u);
        return point_at(major, minor, phi, 2.0 * PI * v);
    }
    let phi = spindle_tube_angle(major, minor, u);
    let (p, n) = point_at(major, minor, phi, 2.0 * PI * v);
    // On the lemon (`R + r cos φ < 0`) the tube's direction points out of the lemon, into the
    // solid: its outward normal is the other way (see `normal_at`).
    if major + minor * phi.cos() < 0.0 {
        (p, -n)
    } else {
        (p, n)
    }
}

/// The angle φ around a ring torus's tube, uniformly by area from `u` in [0, 1): the tube's
/// circumference at φ is proportional to `R + r cos φ`, so φ solves
/// `R φ + r sin φ = 2π R u` (increasing, as r ≤ R). Newton's steps kept inside a shrinking
/// bracket converge in a few steps.
fn tube_angle(major: f64, minor: f64, u: f64) -> f64 {
    let target = 2.0 * PI * major * u;
    let (mut lo, mut hi) = (0.0, 2.0 * PI);
    let mut phi = 2.0 * PI * u;
    for _ in 0..60 {
        let f = major * phi + minor * phi.sin() - target;
        if f.abs() <= 1e-13 * major.max(1.0) {
            break;
        }
        if f > 0.0 {
            hi = phi;
        } else {
            lo = phi;
        }
        let slope = major + minor * phi.cos();
        let next = phi - f / slope;
        phi = if slope > 0.0 && next > lo && next < hi {
            next
        } else {
            (lo + hi) / 2.0
        };
    }
    phi
}

/// The angle φ around a spindle torus's tube, uniformly by area from `u` in [0, 1): the surface
/// element is `|R + r cos φ|·r dφ dθ` (the lemon, where `R + r cos φ < 0`, is surface too), so
/// φ inverts `G(φ) = ∫₀^φ |R + r cos t| dt`. By symmetry about π, the lower half of `u` covers
/// [0, π] and the upper half mirrors it onto [π, 2π). On [0, π], with `φ₀ = acos(−R/r)` and
/// `f(φ) = R φ + r sin φ`, `G` is `f` up to φ₀ and `2 f(φ₀) − f` beyond: increasing, and
/// inverted by Newton's steps inside a shrinking bracket.
fn spindle_tube_angle(major: f64, minor: f64, u: f64) -> f64 {
    let phi0 = (-major / minor).clamp(-1.0, 1.0).acos();
    let f = |phi: f64| major * phi + minor * phi.sin();
    let at_phi0 = f(phi0);
    let half = 2.0 * at_phi0 - major * PI;
    let (w, mirrored) = if u < 0.5 {
        (2.0 * u, false)
    } else {
        (2.0 - 2.0 * u, true)
    };
    let target = w * half;
    let g = |phi: f64| {
        if phi <= phi0 {
            f(phi)
        } else {
            2.0 * at_phi0 - f(phi)
        }
    };
    let (mut lo, mut hi) = (0.0, PI);
    let mut phi = PI * w;
    for _ in 0..80 {
        let error = g(phi) - target;
        if error.abs() <= 1e-13 * (major + minor) {
            break;
        }
        if error > 0.0 {
            hi = phi;
        } else {
            lo = phi;
        }
        let slope = (major + minor * phi.cos()).abs();
        let next = phi - error / slope;
        phi = if slope > 0.0 && next > lo && next < hi {
            next
        } else {
            (lo + hi) / 2.0
        };
    }
    if mirrored {
        2.0 * PI - phi
    } else {
        phi
    }
}

/// The point of the torus at angle `phi` around the tube and `theta` around the axis, and the
/// unit normal of the tube there.
fn point_at(major: f64, minor: f64, phi: f64, theta: f64) -> (Point3, Vec3) {
    let n = Vec3::new(phi.cos() * theta.cos(), phi.sin(), phi.cos() * theta.sin());
    let centre = Point3::new(major * theta.cos(), 0.0, major * theta.sin());
    (centre + n * minor, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::{Jitter, SplitMix64};

    #[test]
    fn a_spindle_torus_is_sampled_uniformly_by_area() {
        // Uniform by area, the tube angle φ has density ∝ |R + r cos φ| (the lemon, where
        // R + r cos φ < 0, included): the mean of cos φ and the area against a fine midpoint
        // quadrature, and every point on the quartic.
        let (major, minor) = (0.5, 0.8);
        let n = 100_000;
        let (mut weight, mut moment) = (0.0, 0.0);
        for i in 0..n {
            let phi = 2.0 * PI * (i as f64 + 0.5) / n as f64;
            let w = (major + minor * phi.cos()).abs();
            weight += w;
            moment += w * phi.cos();
        }
        let expected = moment / weight;
        let quadrature = 2.0 * PI * minor * weight * 2.0 * PI / n as f64;
        let exact = area(major, minor);
        assert!(
            (exact - quadrature).abs() < 1e-6 * quadrature,
            "{exact} vs {quadrature}"
        );
        let mut rng = SplitMix64::new(31);
        let mut sum = 0.0;
        for _ in 0..n {
            let phi = spindle_tube_angle(major, minor, rng.next_offset());
            assert!((0.0..=2.0 * PI).contains(&phi), "{phi}");
            sum += phi.cos();
            let (p, normal) = sample_area(major, minor, [rng.next_offset(), rng.next_offset()]);
            let e = p.length_squared() + major * major - minor * minor;
            let f = e * e - 4.0 * major * major * (p.x * p.x + p.z * p.z);
            assert!(f.abs() < 1e-9, "{p:?}: {f}");
            // The sampled normal is the quartic's gradient's direction, oriented outwards.
            let g = normal_at(p, major, minor).normalize();
            assert!((g - normal).length() < 1e-6, "{g:?} {normal:?}");
        }
        // cos φ lies in [−1, 1]: four standard errors of the mean are under 0.013.
        let mean = sum / n as f64;
        assert!((mean - expected).abs() < 0.013, "{mean} vs {expected}");
        // The inversion is exact at the ends, the middle and the lemon's edge.
        assert_eq!(spindle_tube_angle(major, minor, 0.0), 0.0);
        assert!((spindle_tube_angle(major, minor, 0.5) - PI).abs() < 1e-9);
        assert!((spindle_tube_angle(major, minor, 0.999_999_999) - 2.0 * PI).abs() < 1e-6);
    }

    #[test]
    fn a_ring_torus_is_sampled_uniformly_by_area() {
        // Uniform by area, the distance from the axis ρ = R + r cos φ has density ∝ ρ, so its
        // mean is (R² + r²/2) / R; every point lies on the tube, its normal outward.
        let (major, minor) = (1.0, 0.4);
        let mut rng = SplitMix64::new(99);
        let n = 200_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let (p, normal) = sample_area(major, minor, [rng.next_offset(), rng.next_offset()]);
            let rho = p.x.hypot(p.z);
            assert!(((rho - major).hypot(p.y) - minor).abs() < 1e-9, "{p:?}");
            assert!((normal - normal_at(p, major, minor).normalize()).length() < 1e-9);
            sum += rho;
        }
        let expected = (major * major + minor * minor / 2.0) / major;
        // ρ spreads over ±0.4: four standard errors are under 0.003.
        assert!(
            (sum / n as f64 - expected).abs() < 0.003,
            "{}",
            sum / n as f64
        );
        assert!((area(major, minor) - 4.0 * PI * PI * major * minor).abs() < 1e-12);
        // The tube angle inverts its distribution at the ends and the middle.
        assert_eq!(tube_angle(major, minor, 0.0), 0.0);
        assert!((tube_angle(major, minor, 0.5) - PI).abs() < 1e-9);
    }
}
