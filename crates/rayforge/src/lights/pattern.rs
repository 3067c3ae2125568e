//! A point light shaped by an image ([`PatternLight`]: pbrt-v4's goniometric and projection
//! lights) as the path tracer reads it: a point light ([`PointEmitter`](super::PointEmitter)'s
//! meaning) whose light towards each direction is scaled by the image's texel there, as
//! pbrt-v4's `GoniometricLight::I` and `ProjectionLight::I` scale theirs. A delta light, as
//! the point light is; it is picked by its power (pbrt-v4's `Phi`: the image's mean over the
//! sphere, a frustum's texels weighed by the solid angle each subtends).

use super::light_bounds::{Cone, LightBounds};
use super::point::{point_power, PointEmitter};
use super::sample::LightSample;
use crate::math::Point3;
use crate::shading::{PatternLight, PatternShape, PointLight};

/// An image-shaped point light in the path tracer's light list.
#[derive(Debug, Clone)]
pub struct PatternEmitter {
    /// The scene's light.
    light: PatternLight,
    /// The point light it is where its image is 1.
    point: PointEmitter,
    power: f64,
}

impl PatternEmitter {
    /// The scene's `light` (see [`PointEmitter::new`](super::PointEmitter) for
    /// `model_falloff` and `disc`).
    pub(super) fn new(light: &PatternLight, model_falloff: bool, disc: f64) -> Self {
        let point = PointLight {
            position: light.position,
            intensity: light.intensity,
            falloff: light.falloff,
        };
        let falloff = model_falloff || light.falloff;
        Self {
            power: point_power(light.intensity * light.mean_pattern(), falloff, disc),
            light: light.clone(),
            point: PointEmitter::new(&point, model_falloff, disc),
        }
    }

    /// The direction towards the light from `point` and the irradiance it brings there through
    /// its image, the light picked with probability `probability`; `None` at the light itself
    /// and where the image gives nothing.
    #[inline]
    pub fn sample_li(&self, point: Point3, probability: f64) -> Option<LightSample> {
        self.point
            .shaped_sample(point, probability, |irradiance, direction| {
                irradiance * self.light.pattern(-direction)
            })
    }

    /// What the light samplers pick it by: the power of the point light of its image's mean.
    pub fn power(&self) -> f64 {
        self.power
    }

    /// Its bounds for the light tree: its point, its light within its frustum (every way, for
    /// the sphere); `None` without fall-off.
    pub(super) fn bounds(&self) -> Option<LightBounds> {
        let cone = match self.light.shape {
            PatternShape::Sphere => Cone::EVERYWHERE,
            PatternShape::Frustum { .. } => Cone {
                axis: self.light.axis(),
                theta_o: self.light.spread(),
                theta_e: 0.0,
            },
        };
        let mut bounds = self.point.bounds_in(cone)?;
        bounds.power = self.power;
        Some(bounds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use crate::math::Vec3;
    use crate::shading::LightImage;
    use glam::DMat3;
    use std::f64::consts::PI;
    use std::sync::Arc;

    fn frustum(to_light: DMat3, half_width: f64, half_height: f64, n: usize) -> PatternLight {
        let texels = (0..n * n)
            .map(|i| Color::new(1.0 + (i % 5) as f64, 1.0, 1.0))
            .collect();
        PatternLight {
            position: Point3::new(1.0, -2.0, 0.5),
            intensity: Color::WHITE,
            falloff: true,
            to_light,
            shape: PatternShape::Frustum {
                half_width,
                half_height,
            },
            image: Arc::new(LightImage::new(n, n, texels).unwrap()),
        }
    }

    #[test]
    fn a_uniform_frustum_s_mean_is_its_solid_angle_over_the_sphere() {
        // A rectangle of half-widths a, b at unit distance subtends
        // 4 asin(ab / √((1 + a²)(1 + b²))).
        let (a, b) = (0.8, 0.3);
        let mut light = frustum(DMat3::IDENTITY, a, b, 64);
        light.image = Arc::new(LightImage::new(64, 64, vec![Color::WHITE; 64 * 64]).unwrap());
        let omega = 4.0 * (a * b / ((1.0 + a * a) * (1.0 + b * b)).sqrt()).asin();
        let mean = light.mean_pattern().green;
        assert!((mean - omega / (4.0 * PI)).abs() < 1e-4, "{mean}");
    }

    #[test]
    fn the_tree_s_cone_holds_every_direction_a_frustum_lights() {
        // Turned and stretched: every lit direction within the cone the tree is told.
        let m = DMat3::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 1.1)
            * DMat3::from_diagonal(Vec3::new(1.0, 2.5, 0.7));
        let light = frustum(m.inverse(), 1.2, 0.4, 8);
        let emitter = PatternEmitter::new(&light, false, 1.0);
        let cone = emitter.bounds().unwrap().cone;
        let mut lit = 0;
        for i in 0..4000 {
            let (u, v) = ((i % 63) as f64 / 63.0, (i / 63) as f64 / 63.0);
            let d = crate::math::equal_area_square_to_sphere(u, v);
            if light.pattern(d).max_channel() > 0.0 {
                lit += 1;
                let angle = cone.axis.dot(d).clamp(-1.0, 1.0).acos();
                assert!(
                    angle <= cone.theta_o + cone.theta_e + 1e-9,
                    "{d:?}: {angle}"
                );
            }
        }
        assert!(lit > 50, "{lit}");
        // The point light of the image's mean: its power, as the point light's of that
        // intensity.
        let point = PointEmitter::new(
            &PointLight {
                position: light.position,
                intensity: light.mean_pattern(),
                falloff: true,
            },
            false,
            1.0,
        );
        assert!((emitter.power() - point.power()).abs() < 1e-12 * point.power());
    }

    #[test]
    fn a_sample_brings_the_image_s_light_over_the_distance_squared() {
        let light = frustum(DMat3::IDENTITY, 1.0, 1.0, 8);
        let emitter = PatternEmitter::new(&light, false, 1.0);
        let at = light.position + Vec3::new(0.3, -0.2, 2.0);
        let s = emitter.sample_li(at, 0.5).unwrap();
        let want = light.intensity_at(at) * (PI / at.distance_squared(light.position));
        assert!(
            (s.radiance.red - want.red).abs() < 1e-12,
            "{s:?} vs {want:?}"
        );
        assert!(s.delta && s.pdf == 0.5);
        // Behind the light: nothing.
        assert!(emitter.sample_li(light.position - Vec3::Z, 1.0).is_none());
    }
}
