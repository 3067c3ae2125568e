//! The Phong reflection model (chapter 6) with the soft-shadows bonus chapter's light fraction
//! and area-light sampling, on a surface colour already found (the book's `lighting`, which
//! finds it from the object, is in the crate's `book` facade).

use super::light::Light;
use super::material::Material;
use crate::color::Color;
use crate::math::random::Jitter;
use crate::math::{reflect, Point3, Vec3};

/// Whether `light` can add anything beyond its ambient term at `point` (with normal `normalv`):
/// false for a point, spot or directional light behind the surface or a spot light aimed
/// away, where [`lighting_with`] gives the ambient term whatever the light fraction. The Whitted
/// integrator asks this before casting a shadow ray, which the answer then cannot change. Area
/// lights are spread out, so some of their samples may be in front: always true.
pub fn can_light(light: &Light, point: Point3, normalv: Vec3) -> bool {
    // The same expressions as `lighting_with`, so the two agree to the bit.
    let faces = |lightv: Vec3| {
        let d = lightv.dot(normalv);
        d >= 0.0 || d.is_nan()
    };
    match light {
        Light::Ambient(_) => false,
        Light::Directional(l) => faces(l.direction()),
        Light::Point(l) => faces((l.position - point).normalize()),
        Light::Spot(spot) => {
            spot.cone_at(point) > 0.0 && faces((spot.position - point).normalize())
        }
        Light::Pattern(l) => {
            l.intensity_at(point).max_channel() > 0.0 && faces((l.position - point).normalize())
        }
        Light::Area(_) => true,
    }
}

/// The most `light` can add beyond its ambient term anywhere on a surface of `material` whose
/// colour is `surface` (the largest channel of its diffuse and specular terms, each at its
/// peak, in magnitude): what adaptive depth control weighs a shadow ray by. A shadow ray whose answer can
/// move the pixel by less than the bailout is not cast (see `TraceState::set_bailout` in the render module).
pub fn most_light(material: &Material, surface: Color, light: &Light) -> f64 {
    if matches!(light, Light::Ambient(_)) {
        return 0.0;
    }
    // Magnitudes: a scene may give negative colours or coefficients, whose light subtracts.
    let largest = |c: Color| c.red.abs().max(c.green.abs()).max(c.blue.abs());
    let intensity = match light {
        Light::Pattern(l) => l.intensity * l.image.peak(),
        _ => light.intensity(),
    };
    largest(surface * intensity) * material.diffuse.abs()
        + largest(intensity) * material.specular.abs()
}

/// The book's `lighting` with the surface colour already found (see
/// [`Material::surface_color`]) and the jitter source for area-light samples given.
///
/// An area light's diffuse and specular terms are averaged over one sample point per cell
/// (the bonus chapter's algorithm); a point light is its own single sample.
#[allow(clippy::too_many_arguments)]
pub fn lighting_with(
    material: &Material,
    surface: Color,
    light: &Light,
    point: Point3,
    eyev: Vec3,
    normalv: Vec3,
    light_fraction: f64,
    jitter: &mut dyn Jitter,
) -> Color {
    let effective = surface * light.intensity();
    // A physical light's share of ambient would depend on nothing but its brightness; the
    // scene's ambient light stands for indirect light instead.
    let ambient = if light.falls_off() {
        Color::BLACK
    } else {
        effective * material.ambient
    };
    if light_fraction <= 0.0 || matches!(light, Light::Ambient(_)) {
        return ambient;
    }
    let shade = |lightv: Vec3| {
        let light_dot_normal = lightv.dot(normalv);
        if light_dot_normal < 0.0 {
            // The light is on the other side of the surface.
            return Color::BLACK;
        }
        let diffuse = effective * material.diffuse * light_dot_normal;
        let reflect_dot_eye = reflect(-lightv, normalv).dot(eyev);
        // (A matte surface skips the power, the costliest step of the model.)
        let specular = if reflect_dot_eye <= 0.0 || material.specular == 0.0 {
            Color::BLACK
        } else {
            light.intensity() * material.specular * highlight(reflect_dot_eye, material.shininess)
        };
        diffuse + specular
    };
    let sample = |light_position: Point3| shade((light_position - point).normalize());
    let reach = light.reach(point);
    let lit = match light {
        Light::Ambient(_) => Color::BLACK,
        Light::Directional(l) => shade(l.direction()),
        Light::Point(l) => sample(l.position),
        Light::Spot(spot) => {
            let falloff = spot.cone_at(point);
            if falloff > 0.0 {
                sample(spot.position) * falloff
            } else {
                Color::BLACK
            }
        }
        // The pattern scales diffuse and specular alike, as a spot's cone does.
        Light::Pattern(l) => sample(l.position) * l.pattern(point - l.position),
        Light::Area(area) => {
            let sum: Color = area
                .cells()
                .map(|(u, v)| sample(area.point_on_light(u, v, jitter)))
                .sum();
            sum / area.samples() as f64
        }
    };
    ambient + lit * (light_fraction * reach)
}

/// `cos_angle` raised to the shininess. Shininess is nearly always a whole number (the books'
/// 10, 200 and 300), and then repeated squaring (`powi`, eight multiplications for 200)
/// replaces the general `pow` call, which was a tenth of the rasterizer's Phong frame; the two
/// agree to a few units in the last place.
#[inline]
pub(crate) fn highlight(cos_angle: f64, shininess: f64) -> f64 {
    if shininess.fract() == 0.0 && (0.0..=4096.0).contains(&shininess) {
        cos_angle.powi(shininess as i32)
    } else {
        cos_angle.powf(shininess)
    }
}

#[cfg(test)]
mod tests {
    use super::highlight;

    #[test]
    fn a_whole_shininess_raised_by_squaring_agrees_with_pow() {
        for &base in &[0.0, 1e-3, 0.25, 0.5, 0.9, 0.999_999, 1.0] {
            for shininess in [0.0, 1.0, 2.0, 10.0, 200.0, 300.0, 4096.0] {
                let (fast, exact) = (highlight(base, shininess), f64::powf(base, shininess));
                assert!(
                    (fast - exact).abs() <= 1e-13 * exact.abs().max(f64::MIN_POSITIVE),
                    "{base}^{shininess}: {fast} against {exact}"
                );
            }
        }
        // Fractional and out-of-range exponents go to pow itself.
        assert_eq!(highlight(0.5, 2.5), 0.5f64.powf(2.5));
        assert_eq!(highlight(0.5, 1e6), 0.5f64.powf(1e6));
        assert_eq!(highlight(0.5, -2.0), 0.5f64.powf(-2.0));
    }
}
