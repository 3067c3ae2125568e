//! The torus around the y axis: a tube of radius `minor` whose centre circle has radius `major`
//! in the xz plane (Fundamentals of Ray Tracing, chapter 13, turned to the y-up convention of
//! The Ray Tracer Challenge). Its points satisfy `(|p|² + R² − r²)² = 4R²(x² + z²)`.

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
