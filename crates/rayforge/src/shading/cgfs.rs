//! Computer Graphics from Scratch's local illumination (Gabriel Gambetta, part I,
//! `ComputeLighting`): the summed light intensity at a point from ambient, point, directional,
//! spot and area lights, by the book's diffuse and specular terms, repeated operation for
//! operation in the book's order so that its figures come out bit for bit.
//!
//! The ray tracer's integrator (which casts a shadow ray per light first) and the rasterizer
//! (which takes every light as visible: [`unshadowed_intensity`]) both sum their lights here.

use super::light::Light;
use crate::color::Color;
use crate::math::{Point3, Vec3};

/// A colour or an intensity per channel, on the book's scale, unclamped.
pub type Rgb = [f64; 3];

/// `a + b` per channel.
#[inline]
pub fn add(a: Rgb, b: Rgb) -> Rgb {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `c * n` per channel.
#[inline]
pub fn scale(c: Rgb, n: f64) -> Rgb {
    c.map(|v| v * n)
}

/// What `ComputeLighting` keeps while it sums the lights at one point.
#[derive(Debug, Clone, Copy)]
pub struct CgfsLighting {
    /// The intensity summed so far, per channel (each computed as the book computes its one
    /// scalar).
    pub intensity: Rgb,
    point: Point3,
    normal: Vec3,
    view: Vec3,
    length_n: f64,
    length_v: f64,
    shininess: f64,
}

impl CgfsLighting {
    /// No light yet at `point` (normal `normal`, not necessarily of unit length), seen along
    /// `view`. `shininess` is the book's specular exponent; a negative one (the book's -1)
    /// means a matte surface.
    pub fn new(point: Point3, normal: Vec3, view: Vec3, shininess: f64) -> Self {
        Self {
            intensity: [0.0; 3],
            point,
            normal,
            view,
            length_n: normal.length(),
            length_v: view.length(),
            shininess,
        }
    }

    /// The point being lit.
    pub fn point(&self) -> Point3 {
        self.point
    }

    /// An ambient light, which reaches everywhere.
    pub fn add_ambient(&mut self, light: Rgb) {
        self.intensity = add(self.intensity, light);
    }

    /// One visible light's diffuse and specular terms, added to the sum: the book's formula.
    /// `vec_l` is the book's unnormalised `L` from the point towards the light.
    pub fn add_light(&mut self, vec_l: Vec3, light: Rgb) {
        let n_dot_l = self.normal.dot(vec_l);
        if n_dot_l > 0.0 {
            let denominator = self.length_n * vec_l.length();
            for (sum, i) in self.intensity.iter_mut().zip(light) {
                *sum += i * n_dot_l / denominator;
            }
        }
        if self.shininess >= 0.0 {
            let vec_r = self.normal * (2.0 * n_dot_l) - vec_l;
            let r_dot_v = vec_r.dot(self.view);
            if r_dot_v > 0.0 {
                let highlight = super::phong::highlight(
                    r_dot_v / (vec_r.length() * self.length_v),
                    self.shininess,
                );
                for (sum, i) in self.intensity.iter_mut().zip(light) {
                    *sum += i * highlight;
                }
            }
        }
    }
}

/// Computer Graphics from Scratch's light intensity at a point, every light taken as visible
/// (for the rasterizer, which casts no shadows): ambient lights summed, point, spot and
/// directional lights by the book's diffuse and specular terms, area lights at their centre.
/// Per channel; the surface colour times it is the lit colour.
pub fn unshadowed_intensity(
    lights: &[Light],
    point: Point3,
    normal: Vec3,
    view: Vec3,
    shininess: f64,
) -> Color {
    let mut lit = CgfsLighting::new(point, normal, view, shininess);
    for light in lights {
        match light {
            Light::Ambient(c) => lit.add_ambient(c.to_array()),
            Light::Directional(l) => lit.add_light(l.towards, l.intensity.to_array()),
            Light::Point(l) => lit.add_light(l.position - point, l.intensity.to_array()),
            Light::Spot(l) => {
                let falloff = l.cone_at(point);
                lit.add_light(l.position - point, (l.intensity * falloff).to_array());
            }
            Light::Pattern(l) => {
                lit.add_light(l.position - point, l.intensity_at(point).to_array());
            }
            Light::Area(l) => lit.add_light(l.position() - point, l.intensity.to_array()),
        }
    }
    let [r, g, b] = lit.intensity;
    Color::new(r, g, b)
}
