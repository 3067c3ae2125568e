//! Shading the visible pixels (the book's "Shading" and "Textures" chapters): once the depth
//! buffer knows which triangle each pixel sees, the pixel is lit once, with the scene's
//! materials and lights under the scene's lighting model (`lighting.rs`).
//!
//! Attributes are interpolated perspective-correctly: a quantity that is linear on the triangle
//! in 3D is not linear on the screen, but its value divided by z is, as is 1/z; their ratio at
//! a pixel is the right value (the book's u/z and 1/z). Here the interpolated quantities are the
//! barycentric weights themselves, from which position, normal, texture coordinates and vertex
//! lighting all follow.
//!
//! Lighting takes every light as fully visible (a rasterizer has no shadow rays), an area light
//! replaced by a point light at its centre. Flat and Gouraud shading use that it is affine in
//! the surface colour, `lit(s) = s ⊙ A + B` (ambient and diffuse scale with the colour, a
//! highlight does not): A and B are found once per face or per vertex,
//! and the pixel's own texture or pattern colour goes through them, so textures stay sharp
//! under per-vertex lighting.

use super::bin::{Chunk, ClippedPiece, CLIPPED};
use super::instance::Instance;
use super::lanes::PhongRuns;
use super::mipmap::MipChain;
use super::vertex::ViewVertex;
use super::Projection;
use crate::color::Color;
use crate::math::{Point3, Vec3};
use crate::options::{Shading, TextureFilter};
use crate::scene::LightingModel;
use crate::shading::Light;
use glam::DVec3;
use std::collections::HashMap;

/// Everything shading reads, shared by all tiles.
pub(crate) struct ShadeContext<'a, 'w> {
    pub instances: &'a [Instance<'w>],
    pub vertices: &'a [ViewVertex],
    pub normals: &'a [Vec3],
    pub chunks: &'a [Chunk],
    pub projection: &'a Projection,
    pub lights: Vec<Light>,
    /// The world's lighting model (see `lighting.rs`).
    pub lighting: LightingModel,
    pub mips: HashMap<usize, MipChain>,
    pub shading: Shading,
    pub filter: TextureFilter,
    pub bits: u32,
    /// Gouraud shading's lighting at each vertex, for instances whose faces index normals like
    /// vertices (every tessellated shape, most meshes); empty otherwise.
    pub vertex_light: Vec<(Color, Color)>,
    /// Which instances' pixels are shaded in runs (`lanes.rs`), and the lights for them.
    pub runs: PhongRuns,
}

/// The lights as the rasterizer can use them: area lights become point lights at their centre.
pub(crate) fn raster_lights(lights: &[Light]) -> Vec<Light> {
    lights
        .iter()
        .map(|l| match l {
            Light::Area(area) => Light::point(area.position(), area.intensity),
            other => other.clone(),
        })
        .collect()
}

/// A visible triangle with what every one of its pixels needs, built once per triangle.
#[derive(Debug, Clone, Default)]
pub(crate) struct Face {
    pub(super) instance: u32,
    /// Screen-space barycentric planes: weight i at pixel p is `plane[i]·(p.x, p.y, 1)`.
    pub(super) planes: [DVec3; 3],
    pub(super) inv_z: [f64; 3],
    /// Each corner's weights on the original face (the identity unless clipped).
    pub(super) weights: [[f64; 3]; 3],
    /// Whether it is a piece of a clipped face (else `weights` is the identity).
    pub(super) clipped: bool,
    /// The original face's corners in world space.
    pub(super) points: [Point3; 3],
    /// Its normals in world space (the face normal at every corner for flat faces).
    pub(super) normals: [Vec3; 3],
    /// Its texture coordinates, when it has them.
    uvs: Option<[[f64; 2]; 3]>,
    /// `A` and `B` of the affine lighting, per corner (Gouraud) or for the face (flat: all
    /// three the same).
    light_mul: [Color; 3],
    light_add: [Color; 3],
}

impl<'a, 'w> ShadeContext<'a, 'w> {
    /// The screen corners (on the grid) and 1/z of a binned triangle.
    #[inline]
    pub fn screen_triangle(
        &self,
        chunk: &Chunk,
        instance: u32,
        prim: u32,
    ) -> ([super::edge::FixedPoint; 3], [f64; 3]) {
        if prim & CLIPPED != 0 {
            let piece = &chunk.clipped[(prim & !CLIPPED) as usize];
            return (piece.screen, piece.inv_z);
        }
        let instance = &self.instances[instance as usize];
        let face = instance.model.mesh.faces.get(prim as usize);
        let v = face
            .vertices
            .map(|i| &self.vertices[instance.vertex_base + i as usize]);
        (v.map(|v| v.screen), v.map(|v| v.inv_z))
    }

    /// Prepares a binned triangle for shading, in place (a face is large: the tile keeps a few
    /// and overwrites them rather than moving new ones in).
    pub fn fill_face(&self, out: &mut Face, chunk: &Chunk, instance_index: u32, prim: u32) {
        let instance = &self.instances[instance_index as usize];
        let (screen, inv_z) = self.screen_triangle(chunk, instance_index, prim);
        let (face_index, weights) = if prim & CLIPPED != 0 {
            let ClippedPiece { face, weights, .. } = chunk.clipped[(prim & !CLIPPED) as usize];
            (face, weights)
        } else {
            (prim, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        };
        let mesh = &instance.model.mesh;
        let face = &mesh.faces.get(face_index as usize);
        let points = mesh.corners(face).map(|p| instance.transform.point(p));
        let normals = match face.normals {
            Some(n) => n.map(|i| self.normals[instance.normal_base + i as usize]),
            None => [mesh.front_normal(points); 3],
        };
        let uvs = face
            .texcoords
            .map(|t| t.map(|i| mesh.texcoords[i as usize]));
        let scale = 1.0 / (1u64 << self.bits) as f64;
        let s = screen.map(|p| (p.x as f64 * scale, p.y as f64 * scale));
        let area = (s[1].0 - s[0].0) * (s[2].1 - s[0].1) - (s[1].1 - s[0].1) * (s[2].0 - s[0].0);
        // Weight of corner i: the area of the triangle the pixel makes with the opposite edge.
        let plane = |i: usize| {
            let (a, b) = (s[(i + 1) % 3], s[(i + 2) % 3]);
            DVec3::new(
                -(b.1 - a.1),
                b.0 - a.0,
                (b.1 - a.1) * a.0 - (b.0 - a.0) * a.1,
            ) / area
        };
        out.instance = instance_index;
        out.planes = [plane(0), plane(1), plane(2)];
        out.inv_z = inv_z;
        out.weights = weights;
        out.clipped = prim & CLIPPED != 0;
        out.points = points;
        out.normals = normals;
        out.uvs = uvs;
        match self.shading {
            Shading::Flat => {
                let centre = (points[0] + points[1] + points[2]) / 3.0;
                let flat = mesh.front_normal(points);
                let (mul, add) = self.affine_light(instance, centre, flat);
                out.light_mul = [mul; 3];
                out.light_add = [add; 3];
            }
            Shading::Gouraud => {
                for k in 0..3 {
                    // Vertices behind the eye (corners of a clipped face) were not lit.
                    let vertex = instance.vertex_base + face.vertices[k] as usize;
                    let shared = face.normals == Some(face.vertices)
                        && !self.vertex_light.is_empty()
                        && self.vertices[vertex].view.z > 0.0;
                    let (mul, add) = if shared {
                        self.vertex_light[vertex]
                    } else {
                        self.affine_light(instance, points[k], normals[k])
                    };
                    out.light_mul[k] = mul;
                    out.light_add[k] = add;
                }
            }
            Shading::Phong => {}
        }
    }

    /// Lights every vertex in front of the eye once, in parallel, for Gouraud shading: a
    /// vertex is shared by about six triangles, each of which would otherwise light it again.
    pub fn light_vertices(&mut self) {
        use rayon::prelude::*;
        let mut lights = vec![(Color::BLACK, Color::BLACK); self.vertices.len()];
        let this = &*self;
        let mut rest = lights.as_mut_slice();
        let mut jobs = Vec::with_capacity(this.instances.len());
        for instance in this.instances {
            let (part, tail) = rest.split_at_mut(instance.model.mesh.positions.len());
            jobs.push((instance, part));
            rest = tail;
        }
        jobs.into_par_iter().for_each(|(instance, part)| {
            let mesh = &instance.model.mesh;
            // Only where a vertex's normal has the vertex's own index can one result serve
            // every face around it.
            if mesh.normals.len() != mesh.positions.len() {
                return;
            }
            let views = &this.vertices[instance.vertex_base..][..part.len()];
            let normals = &this.normals[instance.normal_base..][..part.len()];
            part.par_chunks_mut(1024).enumerate().for_each(|(c, out)| {
                for (i, o) in out.iter_mut().enumerate() {
                    let k = c * 1024 + i;
                    if views[k].view.z > 0.0 {
                        let point = instance.transform.point(mesh.positions[k]);
                        *o = this.affine_light(instance, point, normals[k]);
                    }
                }
            });
        });
        self.vertex_light = lights;
    }

    /// `A` and `B` with `lit(s) = s ⊙ A + B` at a point with a (not yet eye-facing) normal.
    fn affine_light(&self, instance: &Instance<'_>, point: Point3, normal: Vec3) -> (Color, Color) {
        let surface = instance.surface;
        let eyev = (self.projection.eye() - point).normalize_or_zero();
        let normal = self.shading_normal(instance, point, normal, eyev);
        let add = self.light(&surface.material, Color::BLACK, point, eyev, normal);
        let white = self.light(&surface.material, Color::WHITE, point, eyev, normal);
        (white - add, add)
    }

    /// The weights on the original face at pixel coordinates `(x, y)` (continuous; pixel
    /// centres at half-integers), perspective-correct.
    #[inline]
    fn weights_at(face: &Face, x: f64, y: f64) -> [f64; 3] {
        let p = DVec3::new(x, y, 1.0);
        let screen = face.planes.map(|plane| plane.dot(p));
        let q = [0, 1, 2].map(|i| screen[i] * face.inv_z[i]);
        let sum = q[0] + q[1] + q[2];
        let mu = if sum != 0.0 {
            q.map(|v| v / sum)
        } else {
            screen
        };
        [0, 1, 2].map(|k| {
            mu[0] * face.weights[0][k] + mu[1] * face.weights[1][k] + mu[2] * face.weights[2][k]
        })
    }

    /// The colour of pixel (`px`, `py`) showing `face`.
    pub fn shade(&self, face: &Face, px: i64, py: i64) -> Color {
        let instance = &self.instances[face.instance as usize];
        let surface = instance.surface;
        let material = &surface.material;
        let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
        let w = Self::weights_at(face, x, y);
        let blend3 = |v: &[DVec3; 3], w: &[f64; 3]| v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
        let point = blend3(&face.points, &w);
        let uv_at = |w: &[f64; 3]| {
            face.uvs.map(|t| {
                (
                    t[0][0] * w[0] + t[1][0] * w[1] + t[2][0] * w[2],
                    t[0][1] * w[0] + t[1][1] * w[1] + t[2][1] * w[2],
                )
            })
        };
        let colour = self.surface_colour(surface, point, uv_at(&w), |dx, dy| {
            let w = Self::weights_at(face, x + dx, y + dy);
            (blend3(&face.points, &w), uv_at(&w))
        });
        match self.shading {
            Shading::Flat | Shading::Gouraud => {
                let mul =
                    face.light_mul[0] * w[0] + face.light_mul[1] * w[1] + face.light_mul[2] * w[2];
                let add =
                    face.light_add[0] * w[0] + face.light_add[1] * w[1] + face.light_add[2] * w[2];
                colour * mul + add
            }
            Shading::Phong => {
                let eyev = (self.projection.eye() - point).normalize_or_zero();
                let normal = blend3(&face.normals, &w).normalize_or_zero();
                let normal = self.shading_normal(instance, point, normal, eyev);
                self.light(material, colour, point, eyev, normal)
            }
        }
    }
}
