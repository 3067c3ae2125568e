//! Phong shading of a tile's visible pixels in runs of [`LANES`], for the common case: the
//! Phong lighting model, per-pixel normals, point lights, and a surface of one plain colour
//! (no texture, pattern or bumps).
//!
//! One pixel at a time, the ray tracer's `lighting_with` is a chain of dependent square roots
//! and divisions (the weights, the eye and normal vectors, each light's direction) that leaves
//! the processor waiting on each. Here each step is done for a run of pixels at once, on arrays
//! of fixed size without branches (choices are selects), which LLVM turns into vector
//! instructions with the run's pixels in the lanes. Every lane performs exactly the operations
//! of the scalar path (`ShadeContext::shade` through `lighting_with`), in the same order and in
//! `f64`, so the image is the same to the bit: only the schedule differs. Every other pixel
//! is shaded alone (`ShadeContext::shade`).

use super::instance::Instance;
use super::shade::Face;
use crate::color::Color;
use crate::math::Point3;
use crate::options::Shading;
use crate::scene::LightingModel;
use crate::shading::Light;

/// Pixels shaded together.
pub(crate) const LANES: usize = 4;

/// One value per pixel of a run.
type Lanes = [f64; LANES];

/// Three components of a vector, each a lane array.
type Vectors = [Lanes; 3];

/// A point light as the runs use it.
#[derive(Debug, Clone, Copy)]
struct RunLight {
    position: Point3,
    intensity: Color,
    falloff: bool,
}

/// What a run needs of its instance's material.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RunMaterial {
    colour: Color,
    ambient: f64,
    diffuse: f64,
    specular: f64,
    /// The shininess, a whole number (`highlight` raises to it by repeated squaring).
    exponent: u32,
}

/// Which instances can be shaded in runs, and the lights they are shaded with.
#[derive(Debug, Default)]
pub(crate) struct PhongRuns {
    lights: Vec<RunLight>,
    /// Per instance, its material when its pixels can go into runs.
    materials: Vec<Option<RunMaterial>>,
}

impl PhongRuns {
    /// The runs of a frame; empty (every pixel shaded alone) unless the scene is lit by the
    /// Phong model with per-pixel normals and point lights only.
    pub fn new(
        lighting: LightingModel,
        shading: Shading,
        lights: &[Light],
        instances: &[Instance<'_>],
    ) -> Self {
        let lights: Option<Vec<RunLight>> = lights
            .iter()
            .map(|light| match light {
                Light::Point(l) => Some(RunLight {
                    position: l.position,
                    intensity: l.intensity,
                    falloff: l.falloff,
                }),
                _ => None,
            })
            .collect();
        let (LightingModel::Phong, Shading::Phong, Some(lights)) = (lighting, shading, lights)
        else {
            return Self::default();
        };
        let materials = instances
            .iter()
            .map(|instance| {
                let m = &instance.surface.material;
                // The plain colour is what `surface_colour` gives without texture or pattern,
                // and `highlight` squares for a whole shininess in this range.
                let plain = m.texture.is_none() && m.pattern.is_none() && m.bump.is_none();
                let whole = m.shininess.fract() == 0.0 && (0.0..=4096.0).contains(&m.shininess);
                (plain && whole).then_some(RunMaterial {
                    colour: m.color,
                    ambient: m.ambient,
                    diffuse: m.diffuse,
                    specular: m.specular,
                    exponent: m.shininess as u32,
                })
            })
            .collect();
        Self { lights, materials }
    }

    /// The material of `instance` when its pixels go into runs.
    #[inline]
    pub fn material(&self, instance: u32) -> Option<&RunMaterial> {
        self.materials.get(instance as usize)?.as_ref()
    }
}

/// A run being gathered: up to [`LANES`] pixels of one instance, each with the slot of the
/// tile's cache of faces that holds its face. The faces are read where they are when the run
/// is shaded (a copy of each pixel's face data into the lanes cost more than the shading
/// saved), so a slot in use must not be overwritten before: see [`uses_slot`](Self::uses_slot).
#[derive(Debug, Clone)]
pub(crate) struct Run {
    len: usize,
    instance: u32,
    /// The cache slots the pending pixels read, one bit per slot.
    slots_used: u64,
    /// Whether a pixel's face is a clipped piece: only then are the corners' weights on the
    /// original face read (else they are the identity, a constant).
    clipped: bool,
    slots: [usize; LANES],
    /// Where each pixel goes in the band.
    outputs: [usize; LANES],
    x: Lanes,
    y: Lanes,
}

impl Run {
    pub fn new() -> Self {
        Self {
            len: 0,
            instance: 0,
            slots_used: 0,
            clipped: false,
            slots: [0; LANES],
            outputs: [0; LANES],
            x: [0.0; LANES],
            y: [0.0; LANES],
        }
    }

    /// Whether a pending pixel reads cache slot `slot` (below 64): the run must be shaded
    /// before the slot takes another face.
    #[inline]
    pub fn uses_slot(&self, slot: usize) -> bool {
        self.slots_used & (1 << slot) != 0
    }

    /// Whether a pixel of `instance` can join the run without shading it first.
    #[inline]
    pub fn accepts(&self, instance: u32) -> bool {
        self.len == 0 || (self.instance == instance && self.len < LANES)
    }

    /// Adds pixel (`px`, `py`), which sees `face`, held in cache slot `slot`, to be written to
    /// `band[output]`; the run must [accept](Self::accepts) the face's instance.
    #[inline]
    pub fn push(&mut self, face: &Face, slot: usize, px: i64, py: i64, output: usize) {
        let i = self.len;
        self.instance = face.instance;
        self.clipped |= face.clipped;
        self.slots_used |= 1 << slot;
        self.slots[i] = slot;
        self.outputs[i] = output;
        (self.x[i], self.y[i]) = (px as f64 + 0.5, py as f64 + 0.5);
        self.len += 1;
    }

    /// Shades the pending pixels, whose faces are in `cache`, into `band` and empties the run.
    pub fn flush(
        &mut self,
        runs: &PhongRuns,
        eye: Point3,
        cache: &[(u32, u32, Face)],
        band: &mut [Color],
    ) {
        if self.len == 0 {
            return;
        }
        let material = runs
            .material(self.instance)
            .expect("only instances with a run material join runs");
        // Lanes past the run's end read an earlier run's slots (any face will do, and the
        // cache always has every slot); their results are dropped.
        let faces: [&Face; LANES] = std::array::from_fn(|i| &cache[self.slots[i]].2);
        let [red, green, blue] = shade_lanes(
            &faces,
            self.clipped,
            &self.x,
            &self.y,
            eye,
            material,
            &runs.lights,
        );
        for i in 0..self.len {
            band[self.outputs[i]] = Color::new(red[i], green[i], blue[i]);
        }
        self.len = 0;
        self.slots_used = 0;
        self.clipped = false;
    }
}

/// An unclipped face's weights on itself in every lane: multiplying by its constants is
/// exact, so the lanes compute what the scalar path computes with the identity.
const IDENTITY_LANES: [Vectors; 3] = [
    [[1.0; LANES], [0.0; LANES], [0.0; LANES]],
    [[0.0; LANES], [1.0; LANES], [0.0; LANES]],
    [[0.0; LANES], [0.0; LANES], [1.0; LANES]],
];

/// One value of each lane's face, side by side.
#[inline(always)]
fn lanes(faces: &[&Face; LANES], value: impl Fn(&Face) -> f64) -> Lanes {
    std::array::from_fn(|i| value(faces[i]))
}

/// A `[corner][component]` value of each lane's face, side by side.
#[inline(always)]
fn corners(faces: &[&Face; LANES], value: impl Fn(&Face, usize, usize) -> f64) -> [Vectors; 3] {
    std::array::from_fn(|k| std::array::from_fn(|c| lanes(faces, |f| value(f, k, c))))
}

/// `a · b` lane by lane, summed in glam's order (x, then y, then z).
#[inline(always)]
fn dot(a: &Vectors, b: &Vectors) -> Lanes {
    let mut out = [0.0; LANES];
    for i in 0..LANES {
        out[i] = a[0][i] * b[0][i] + a[1][i] * b[1][i] + a[2][i] * b[2][i];
    }
    out
}

/// `v` normalized, or zero where it cannot be (glam's `normalize_or_zero`, lane by lane).
#[inline(always)]
fn normalize_or_zero(v: &Vectors) -> Vectors {
    let length_squared = dot(v, v);
    let mut rcp = [0.0; LANES];
    for i in 0..LANES {
        let r = 1.0 / length_squared[i].sqrt();
        rcp[i] = if r.is_finite() && r > 0.0 { r } else { 0.0 };
    }
    let mut out = [[0.0; LANES]; 3];
    for c in 0..3 {
        for i in 0..LANES {
            // Where glam gives zero, `v · 0` could be NaN: the select keeps it zero.
            out[c][i] = if rcp[i] > 0.0 { v[c][i] * rcp[i] } else { 0.0 };
        }
    }
    out
}

/// `Σ v[k] · w[k]` over a face's three corners, per component (`blend3` of the scalar path).
#[inline(always)]
fn blend(v: &[Vectors; 3], w: &Vectors) -> Vectors {
    let mut out = [[0.0; LANES]; 3];
    for c in 0..3 {
        for i in 0..LANES {
            out[c][i] = v[0][c][i] * w[0][i] + v[1][c][i] * w[1][i] + v[2][c][i] * w[2][i];
        }
    }
    out
}

/// The colours of a run's pixels at pixel centres (`x`, `y`): `ShadeContext::shade` for Phong
/// shading under the Phong model, each step for every lane at once. (Kept out of the tile's
/// loop, whose registers it would otherwise compete for.)
#[inline(never)]
fn shade_lanes(
    faces: &[&Face; LANES],
    clipped: bool,
    x: &Lanes,
    y: &Lanes,
    eye: Point3,
    m: &RunMaterial,
    lights: &[RunLight],
) -> Vectors {
    // `weights_at`: the perspective-correct weights on the original face.
    let planes = corners(faces, |f, k, c| f.planes[k][c]);
    let inv_z: [Lanes; 3] = std::array::from_fn(|k| lanes(faces, |f| f.inv_z[k]));
    let mut screen = [[0.0; LANES]; 3];
    let mut q = [[0.0; LANES]; 3];
    for k in 0..3 {
        let p = &planes[k];
        for i in 0..LANES {
            screen[k][i] = p[0][i] * x[i] + p[1][i] * y[i] + p[2][i];
            q[k][i] = screen[k][i] * inv_z[k][i];
        }
    }
    let mut sum = [0.0; LANES];
    for i in 0..LANES {
        sum[i] = q[0][i] + q[1][i] + q[2][i];
    }
    let mut mu = [[0.0; LANES]; 3];
    for k in 0..3 {
        for i in 0..LANES {
            mu[k][i] = if sum[i] != 0.0 {
                q[k][i] / sum[i]
            } else {
                screen[k][i]
            };
        }
    }
    let w = if clipped {
        blend(&corners(faces, |f, k, c| f.weights[k][c]), &mu)
    } else {
        blend(&IDENTITY_LANES, &mu)
    };
    let point = blend(&corners(faces, |f, k, c| f.points[k][c]), &w);
    let mut to_eye = [[0.0; LANES]; 3];
    for c in 0..3 {
        for i in 0..LANES {
            to_eye[c][i] = eye[c] - point[c][i];
        }
    }
    let eyev = normalize_or_zero(&to_eye);
    let mut normal = normalize_or_zero(&blend(&corners(faces, |f, k, c| f.normals[k][c]), &w));
    // `shading_normal`: turned towards the eye.
    let facing = dot(&normal, &eyev);
    for n in &mut normal {
        for i in 0..LANES {
            n[i] = if facing[i] < 0.0 { -n[i] } else { n[i] };
        }
    }
    // `light`: `lighting_with` per light, summed from black.
    let mut total = [[0.0; LANES]; 3];
    for light in lights {
        let effective = m.colour * light.intensity;
        let ambient = if light.falloff {
            Color::BLACK
        } else {
            effective * m.ambient
        };
        let diffuse_colour = effective * m.diffuse;
        let specular_colour = light.intensity * m.specular;
        let (ambient, diffuse_colour, specular_colour) = (
            [ambient.red, ambient.green, ambient.blue],
            [
                diffuse_colour.red,
                diffuse_colour.green,
                diffuse_colour.blue,
            ],
            [
                specular_colour.red,
                specular_colour.green,
                specular_colour.blue,
            ],
        );
        let mut towards = [[0.0; LANES]; 3];
        for c in 0..3 {
            for i in 0..LANES {
                towards[c][i] = light.position[c] - point[c][i];
            }
        }
        // `normalize`, which (unlike `normalize_or_zero`) keeps whatever the division gives.
        let length_squared = dot(&towards, &towards);
        let mut lightv = towards;
        for i in 0..LANES {
            let rcp = 1.0 / length_squared[i].sqrt();
            for l in &mut lightv {
                l[i] *= rcp;
            }
        }
        let light_dot_normal = dot(&lightv, &normal);
        // `reflect(-lightv, normal)`.
        let mut incoming = lightv;
        for l in &mut incoming {
            for v in l.iter_mut() {
                *v = -*v;
            }
        }
        let along = dot(&incoming, &normal);
        let mut reflected = incoming;
        for c in 0..3 {
            for i in 0..LANES {
                reflected[c][i] -= normal[c][i] * 2.0 * along[i];
            }
        }
        let reflect_dot_eye = dot(&reflected, &eyev);
        let highlight = if m.specular != 0.0 {
            powi(reflect_dot_eye, m.exponent)
        } else {
            [0.0; LANES]
        };
        let mut reach = [1.0; LANES];
        if light.falloff {
            for i in 0..LANES {
                reach[i] = 1.0 / length_squared[i].max(1e-300);
            }
        }
        for c in 0..3 {
            for i in 0..LANES {
                let diffuse = diffuse_colour[c] * light_dot_normal[i];
                let specular = if reflect_dot_eye[i] <= 0.0 || m.specular == 0.0 {
                    0.0
                } else {
                    specular_colour[c] * highlight[i]
                };
                let lit = if light_dot_normal[i] < 0.0 {
                    0.0
                } else {
                    diffuse + specular
                };
                total[c][i] += ambient[c] + lit * reach[i];
            }
        }
    }
    total
}

/// `highlight` for a whole exponent: `f64::powi` lane by lane, by repeated squaring as the
/// runtime's `__powidf2` does it, so that the results agree to the bit (tested).
#[inline(always)]
fn powi(mut base: Lanes, exponent: u32) -> Lanes {
    let mut power = [1.0; LANES];
    let mut e = exponent;
    loop {
        if e & 1 != 0 {
            for i in 0..LANES {
                power[i] *= base[i];
            }
        }
        e >>= 1;
        if e == 0 {
            return power;
        }
        for b in &mut base {
            *b *= *b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{powi, LANES};
    use crate::camera::Camera;
    use crate::color::Color;
    use crate::math::{scaling, translation, view_transform, Point3, Vec3};
    use crate::options::RasterOptions;
    use crate::raster::{render, render_with_stats};
    use crate::scene::{Object, World};
    use crate::shading::{Light, Material, PointLight};

    #[test]
    fn runs_shade_every_pixel_as_the_scalar_path_does() {
        // Shiny and matte surfaces, a plane the clipping planes cut into pieces, a light that
        // falls off and one that does not.
        let camera = Camera::new(96, 64, 1.2).with_transform(view_transform(
            Point3::new(0.5, 1.5, -5.0),
            Point3::new(0.0, 0.5, 0.0),
            Vec3::Y,
        ));
        let shiny = Material {
            color: Color::new(0.8, 0.3, 0.2),
            specular: 0.9,
            shininess: 200.0,
            ..Material::DEFAULT
        };
        let matte = Material {
            color: Color::new(0.2, 0.6, 0.9),
            specular: 0.0,
            ..Material::DEFAULT
        };
        let mut world = World {
            objects: vec![
                Object::sphere()
                    .with_transform(translation(0.0, 1.0, 0.0))
                    .with_material(shiny.clone()),
                Object::cube()
                    .with_transform(translation(2.0, 0.5, 1.0) * scaling(0.5, 0.5, 0.5))
                    .with_material(Material {
                        shininess: 10.0,
                        ..shiny
                    }),
                Object::plane().with_material(matte),
            ],
            lights: vec![
                Light::point(Point3::new(-10.0, 10.0, -10.0), Color::new(0.8, 0.8, 0.8)),
                Light::Point(PointLight {
                    position: Point3::new(3.0, 4.0, -2.0),
                    intensity: Color::new(20.0, 15.0, 10.0),
                    falloff: true,
                }),
            ],
            ..World::default()
        };
        let options = RasterOptions::default();
        let (runs, stats) = render_with_stats(&camera, &world, &options).expect("a small scene");
        assert!(stats.clipped > 0, "the plane is cut by the clipping planes");
        // A black ambient light adds nothing, but only point lights go into runs: every pixel
        // is then shaded alone.
        world.lights.push(Light::Ambient(Color::BLACK));
        let alone = render(&camera, &world, &options).expect("a small scene");
        for (a, b) in runs.pixels().iter().zip(alone.pixels()) {
            for (x, y) in [(a.red, b.red), (a.green, b.green), (a.blue, b.blue)] {
                assert_eq!(x.to_bits(), y.to_bits(), "{a:?} against {b:?}");
            }
        }
    }

    #[test]
    fn the_squaring_is_powi_to_the_bit() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..4_000 {
            let bases: [f64; LANES] = std::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            });
            for exponent in [0u32, 1, 2, 3, 10, 200, 255, 300, 4095, 4096] {
                let powers = powi(bases, exponent);
                for (base, power) in bases.iter().zip(powers) {
                    assert_eq!(power.to_bits(), base.powi(exponent as i32).to_bits());
                }
            }
        }
    }
}
