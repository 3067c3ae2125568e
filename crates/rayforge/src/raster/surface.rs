//! A surface's own colour at a pixel, before lighting: the material's image texture at the
//! surface's texture coordinates, else its pattern, else its colour. Images (textures, and the
//! images of mapped patterns and cube maps) are read through their MIP maps with the chosen
//! filter (the book's "Textures" chapter, and the filtering it leaves "TO DO").

use super::instance::Instance;
use super::mipmap::MipChain;
use super::shade::ShadeContext;
use crate::color::Color;
use crate::math::Point3;
use crate::options::TextureFilter;
use crate::scene::Object;
use crate::shading::{CubeFace, PatternKind, Texture, UvPattern};
use std::collections::HashMap;
use std::sync::Arc;

/// The images that materials read through texture coordinates, mapped patterns or cube maps,
/// each with its MIP map, keyed by the image's address.
pub(crate) fn build_mips(instances: &[Instance<'_>]) -> HashMap<usize, MipChain> {
    let mut mips = HashMap::new();
    for instance in instances {
        let material = &instance.surface.material;
        let pattern_images: &[UvPattern] = match material.pattern.as_ref().map(|p| &p.kind) {
            Some(PatternKind::Map { uv, .. }) => std::slice::from_ref(uv),
            Some(PatternKind::CubeMap(faces)) => &faces[..],
            _ => &[],
        };
        for image in material
            .texture
            .as_deref()
            .into_iter()
            .chain(pattern_images)
        {
            if let UvPattern::Image(texture) = image {
                mips.entry(Arc::as_ptr(texture) as usize)
                    .or_insert_with(|| MipChain::new(texture));
            }
        }
    }
    mips
}

/// How far from the pixel's centre its footprint is measured, in pixels: the texture
/// coordinates' rate of change is their difference over this step, divided by it.
///
/// Why not the neighbouring pixel: mappings wrap (a sphere's longitude from 1 back to 0 at its
/// seam, a planar map every unit), so a difference is only known up to whole periods, and is
/// taken as the shortest one (`wrapped`). Towards the horizon a floor's pixel spans many
/// periods, which a one-pixel difference would lose, measuring a tiny footprint and picking a
/// sharp MIP level that shimmers. Over 1/256 of a pixel the difference is exact up to 128
/// periods per pixel, far past where the coarsest MIP level (one texel for the whole image, a
/// footprint of one period) is reached; only the last row or so before the horizon itself can
/// go beyond.
const FOOTPRINT_STEP: f64 = 1.0 / 256.0;

/// A texture-coordinate difference taken the short way round the wrap (see
/// [`FOOTPRINT_STEP`]).
fn wrapped(d: f64) -> f64 {
    d - d.round()
}

impl ShadeContext<'_, '_> {
    /// The surface colour at `point`: the material's texture at the surface's own coordinates
    /// `uv`, else its pattern, else its colour. Images are filtered with the chosen filter; the
    /// pixel's footprint (for the MIP level) comes from `neighbour(dx, dy)`, the point and
    /// coordinates `dx` pixels across and `dy` down from the pixel's centre.
    pub(crate) fn surface_colour(
        &self,
        surface: &Object,
        point: Point3,
        uv: Option<(f64, f64)>,
        neighbour: impl Fn(f64, f64) -> (Point3, Option<(f64, f64)>),
    ) -> Color {
        let material = &surface.material;
        // A glTF material's base texture wraps as its sampler says: its coordinates are brought
        // into the image before the MIP map (which clamps) reads it; the footprint is measured
        // on the coordinates as they run across the surface.
        let slot = material
            .metal_rough
            .as_ref()
            .and_then(|m| m.base_texture.as_ref());
        if let (Some(texture), Some((u, v))) = (material.texture.as_deref(), uv) {
            let UvPattern::Image(image) = texture else {
                return texture.uv_pattern_at(u, v) * material.color;
            };
            let footprint = || {
                let h = FOOTPRINT_STEP;
                let ((_, ux), (_, uy)) = (neighbour(h, 0.0), neighbour(0.0, h));
                let (ux, uy) = (ux.unwrap_or((u, v)), uy.unwrap_or((u, v)));
                (
                    (ux.0 - u) / h,
                    (ux.1 - v) / h,
                    (uy.0 - u) / h,
                    (uy.1 - v) / h,
                )
            };
            let (su, sv) = slot.map_or((u, v), |s| s.wrapped_uv(u, v));
            return self.sample(image, su, sv, footprint) * material.color;
        }
        let Some(pattern) = &material.pattern else {
            return material.color;
        };
        // A point in the pattern's own space.
        let local = |p: Point3| pattern.transform.inverse_point(surface.world_to_object(p));
        // (u, v) by `map` at the pixel, and the footprint from its neighbours by the same map.
        let mapped = |image: &Arc<Texture>, map: &dyn Fn(Point3) -> (f64, f64)| {
            let (u, v) = map(local(point));
            let footprint = || {
                let h = FOOTPRINT_STEP;
                let ((px, _), (py, _)) = (neighbour(h, 0.0), neighbour(0.0, h));
                let ((ux, vx), (uy, vy)) = (map(local(px)), map(local(py)));
                (
                    wrapped(ux - u) / h,
                    wrapped(vx - v) / h,
                    wrapped(uy - u) / h,
                    wrapped(vy - v) / h,
                )
            };
            self.sample(image, u, v, footprint)
        };
        match &pattern.kind {
            PatternKind::Map {
                mapping,
                uv: UvPattern::Image(image),
            } => mapped(image, &|p| mapping.map(p)),
            PatternKind::CubeMap(faces) => {
                // The face is the pixel's own; its neighbours are read on the same face's
                // coordinates, so a pixel beside an edge keeps its footprint.
                let face = CubeFace::from_point(local(point));
                match &faces[face.index()] {
                    UvPattern::Image(image) => mapped(image, &|p| face.uv(p)),
                    other => {
                        let (u, v) = face.uv(local(point));
                        other.uv_pattern_at(u, v)
                    }
                }
            }
            _ => pattern.nested_at(surface.world_to_object(point)),
        }
    }

    /// An image at (u, v) through its MIP map.
    fn sample(
        &self,
        image: &Arc<Texture>,
        u: f64,
        v: f64,
        footprint: impl Fn() -> (f64, f64, f64, f64),
    ) -> Color {
        let Some(mip) = self.mips.get(&(Arc::as_ptr(image) as usize)) else {
            return image.sample(u, v);
        };
        let lod = if self.filter == TextureFilter::Trilinear {
            let (du_dx, dv_dx, du_dy, dv_dy) = footprint();
            mip.level_of_detail(du_dx, dv_dx, du_dy, dv_dy)
        } else {
            0.0
        };
        mip.sample(u, v, lod, self.filter)
    }
}
