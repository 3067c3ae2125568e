//! pbrt-v4's shapes as rayforge's objects.
//!
//! - `trianglemesh` (`P`, `indices`, optional `N` and `uv`): a mesh whose faces' fronts are
//!   pbrt's. pbrt's geometric normal is `(p1 − p0) × (p2 − p0)` in its left-handed space, the
//!   normal matrix taking it to the world ([`Winding::RightHanded`] in rayforge, whose space
//!   is pbrt's); where the mesh has normals `N`, pbrt turns each face's geometric normal to
//!   the side of its shading normal, so each face is wound here to face the mean of its
//!   corners' `N`. `ReverseOrientation` turns every face (and the normals) over.
//! - `sphere` (`radius`, `zmin`, `zmax`, `phimax`); `disk` (`radius`, `innerradius`,
//!   `height`, `phimax`): in the plane z = height facing +z; `cylinder` (`radius`, `zmin`,
//!   `zmax`, `phimax`): open, about z. Their fronts face out (+z for the disk);
//!   `ReverseOrientation` makes an emitting one shine from its back. A whole one is the
//!   shape of its kind (a sphere, a ring, a cylinder) placed to pbrt's frame; one cut by its
//!   heights or sweep is a [`PartialQuadric`], intersected and sampled as its cut leaves it.
//!   Cuts are clamped as pbrt-v4 clamps them (heights to the sphere, `phimax` to 360°); one
//!   that leaves nothing (`phimax` 0 or less, `zmin` and `zmax` beyond the same pole) is
//!   refused at its parameter.
//! - `curves` are left out with a warning (they are hair and fur, not surfaces), and every
//!   other shape is refused at its directive.

use super::input::Files;
use super::params::Param;
use super::reader::ShapeEntity;
use crate::error::SceneError;
use glam::{DMat4, DVec3};
use rayforge::geometry::{CutError, Mesh, MeshFace, PartialQuadric, Winding};
use rayforge::{Object, Shape};
use std::sync::Arc;

/// What a shape became.
pub enum Built {
    /// Objects in the shape's own space (the caller places them), and the shape's area there
    /// (for an area light's `power`).
    Objects(Vec<Object>, f64),
    /// Nothing to draw (`curves`).
    Skipped,
}

/// The object(s) of `shape` in its own space, and the triangles it adds to `triangles` (held
/// to `max_triangles`).
pub fn build(
    shape: &ShapeEntity,
    files: &Files,
    triangles: &mut usize,
    max_triangles: usize,
    warnings: &mut Vec<SceneError>,
) -> Result<Built, SceneError> {
    let entity = &shape.entity;
    let params = &entity.params;
    // `alpha` is read where the shape is placed (`build::place`), with the textures.
    // A quadric cut by its sweep or heights becomes one of rayforge's cut quadrics; a whole
    // one stays the shape of its kind (a whole sphere keeps its sampling by the cone it
    // subtends).
    let cut_error = |e: CutError, at: Option<&Param>| match at {
        Some(p) => p.error(e.to_string()),
        None => entity.error(format!("a {} whose {e}", entity.name)),
    };
    let partial = |q: Result<PartialQuadric, CutError>, at: Option<&Param>| {
        q.map(|q| Object::new(Shape::Partial(Box::new(q))))
            .map_err(|e| cut_error(e, at))
    };
    let cut = |sweep: Option<(f64, &Param)>| sweep.is_some_and(|(phi, _)| phi < 360.0);
    Ok(match entity.name.as_str() {
        "trianglemesh" => {
            let (mesh, area) = triangle_mesh(shape, triangles, max_triangles, files.stop())?;
            Built::Objects(vec![Object::mesh(Arc::new(mesh))], area)
        }
        "sphere" => {
            let radius = positive(shape, "radius", 1.0)?;
            let sweep = params.float_at("phimax")?;
            let z_min = params.float_at("zmin")?;
            let z_max = params.float_at("zmax")?;
            let below = z_min.is_some_and(|(z, _)| z > -radius);
            let above = z_max.is_some_and(|(z, _)| z < radius);
            if below || above || cut(sweep) {
                let phi = sweep.map_or(360.0, |(phi, _)| phi);
                let q = PartialQuadric::sphere(
                    radius,
                    z_min.map_or(-radius, |(z, _)| z),
                    z_max.map_or(radius, |(z, _)| z),
                    phi,
                );
                // Name the parameter the cut fails at.
                let at = match q {
                    Err(CutError::Sweep(_)) => sweep.map(|(_, p)| p),
                    _ => z_max.or(z_min).map(|(_, p)| p),
                };
                let area = q.map_or(0.0, |q| q.area());
                Built::Objects(vec![partial(q, at)?], area)
            } else {
                let object =
                    Object::sphere().with_transform(DMat4::from_scale(DVec3::splat(radius)));
                Built::Objects(vec![object], 4.0 * std::f64::consts::PI * radius * radius)
            }
        }
        "disk" => {
            let radius = positive(shape, "radius", 1.0)?;
            let inner = params.float_at("innerradius")?;
            if let Some((r, p)) = inner.filter(|(r, _)| !(0.0..radius).contains(r)) {
                return Err(p.error(format!(
                    "a disk's innerradius is from 0 to below its radius {radius}, found {r}"
                )));
            }
            let inner = inner.map_or(0.0, |(r, _)| r);
            let height = params.float_or("height", 0.0)?;
            let sweep = params.float_at("phimax")?;
            if cut(sweep) {
                let phi = sweep.map_or(360.0, |(phi, _)| phi);
                let q = PartialQuadric::disk(height, radius, inner, phi);
                let area = q.map_or(0.0, |q| q.area());
                Built::Objects(vec![partial(q, sweep.map(|(_, p)| p))?], area)
            } else {
                // rayforge's ring lies in the xz plane facing +y; pbrt's disk in the xy plane
                // facing +z: a quarter turn about x takes +y to +z.
                let placed = DMat4::from_translation(DVec3::new(0.0, 0.0, height))
                    * DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2);
                let object = Object::new(Shape::Ring {
                    inner,
                    outer: radius,
                })
                .with_transform(placed);
                let area = std::f64::consts::PI * (radius * radius - inner * inner);
                Built::Objects(vec![object], area)
            }
        }
        "cylinder" => {
            let radius = positive(shape, "radius", 1.0)?;
            let zmin = params.float_or("zmin", -1.0)?;
            let zmax = params.float_or("zmax", 1.0)?;
            if zmin >= zmax {
                return Err(entity.error(format!(
                    "a cylinder's zmin ({zmin}) is below its zmax ({zmax})"
                )));
            }
            let sweep = params.float_at("phimax")?;
            if cut(sweep) {
                let phi = sweep.map_or(360.0, |(phi, _)| phi);
                let q = PartialQuadric::cylinder(radius, zmin, zmax, phi);
                let area = q.map_or(0.0, |q| q.area());
                Built::Objects(vec![partial(q, sweep.map(|(_, p)| p))?], area)
            } else {
                // rayforge's cylinder stands along y; a quarter turn about x lays it along z.
                let placed = DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2)
                    * DMat4::from_scale(DVec3::new(radius, 1.0, radius));
                let object = Object::new(Shape::Cylinder {
                    minimum: zmin,
                    maximum: zmax,
                    closed: false,
                })
                .with_transform(placed);
                let area = 2.0 * std::f64::consts::PI * radius * (zmax - zmin);
                Built::Objects(vec![object], area)
            }
        }
        "curves" => {
            warnings.push(
                entity.error("curves (hair, fur) are not rendered: rayforge leaves them out"),
            );
            Built::Skipped
        }
        "plymesh" => {
            let (mesh, area) = ply_mesh(shape, files, triangles, max_triangles)?;
            Built::Objects(vec![Object::mesh(Arc::new(mesh))], area)
        }
        other => {
            return Err(entity.error(format!(
                "the shape \"{}\" is not one rayforge reads; it reads trianglemesh, plymesh, \
                 sphere, disk and cylinder",
                crate::error::clip_to(other, 60)
            )))
        }
    })
}

/// A float parameter that must be above 0.
fn positive(shape: &ShapeEntity, name: &str, default: f64) -> Result<f64, SceneError> {
    let v = shape.entity.params.float_or(name, default)?;
    if v <= 0.0 {
        return Err(shape.entity.error(format!(
            "a {}'s {name} is above 0, found {v}",
            shape.entity.name
        )));
    }
    Ok(v)
}

/// A `trianglemesh` (see the [module](self)) and its area in its own space.
fn triangle_mesh(
    shape: &ShapeEntity,
    triangles: &mut usize,
    max_triangles: usize,
    stop: &crate::stop::StopFlag,
) -> Result<(Mesh, f64), SceneError> {
    use super::params::ParamType;
    let entity = &shape.entity;
    let params = &entity.params;
    let Some((positions, _)) = params.points3("P", ParamType::Point3)? else {
        return Err(entity.error("a trianglemesh needs its points, \"point3 P\""));
    };
    let indices: Vec<u32> = match params.numbers("indices", ParamType::Integer)? {
        Some((v, p)) => {
            if v.len() % 3 != 0 {
                return Err(p.error(format!(
                    "takes three indices a triangle; {} is not a multiple of 3",
                    v.len()
                )));
            }
            let mut out = Vec::with_capacity(v.len());
            for &i in v {
                if i < 0.0 || i >= positions.len() as f64 {
                    return Err(p.error(format!(
                        "index {i} is not one of the {} points of \"point3 P\"",
                        positions.len()
                    )));
                }
                out.push(i as u32);
            }
            out
        }
        None if positions.len() == 3 => vec![0, 1, 2],
        None => {
            return Err(
                entity.error("a trianglemesh of more than three points needs \"integer indices\"")
            )
        }
    };
    let normals = match params.points3("N", ParamType::Normal)? {
        Some((n, p)) if n.len() != positions.len() => {
            return Err(p.error(format!(
                "has {} normals for {} points; it takes one a point",
                n.len(),
                positions.len()
            )))
        }
        Some((n, _)) => n,
        None => Vec::new(),
    };
    let texcoords: Vec<[f64; 2]> = match params.points2("uv")? {
        Some((uv, p)) if uv.len() != positions.len() => {
            return Err(p.error(format!(
                "has {} texture coordinates for {} points; it takes one a point",
                uv.len(),
                positions.len()
            )))
        }
        Some((uv, _)) => uv.into_iter().map(|t| [t.x, t.y]).collect(),
        None => Vec::new(),
    };
    counted(shape, indices.len() / 3, triangles, max_triangles)?;
    oriented(shape, positions, normals, texcoords, &indices, stop)
}

/// Adds a mesh's `faces` to the scene's `triangles`, held to `max_triangles`.
fn counted(
    shape: &ShapeEntity,
    faces: usize,
    triangles: &mut usize,
    max_triangles: usize,
) -> Result<(), SceneError> {
    *triangles = triangles.saturating_add(faces);
    if *triangles > max_triangles {
        return Err(shape.entity.error(format!(
            "the scene's meshes hold more than {max_triangles} triangles (`--max-triangles` \
             on the command line)"
        )));
    }
    Ok(())
}

/// A `plymesh` (`filename`, found as every name of the scene is: see [`Files::resolve`]): the
/// PLY file's triangles (its quads split as pbrt-v4 splits them), fronting as a
/// `trianglemesh`'s do (the PLY reader's counter-clockwise faces are pbrt's
/// `(p1 − p0) × (p2 − p0)`), and its area in its own space.
fn ply_mesh(
    shape: &ShapeEntity,
    files: &Files,
    triangles: &mut usize,
    max_triangles: usize,
) -> Result<(Mesh, f64), SceneError> {
    let entity = &shape.entity;
    let Some((name, param)) = entity.params.string("filename")? else {
        return Err(entity.error("a plymesh needs its file, \"string filename\""));
    };
    let path = files.resolve(name);
    files.check(&path, &param.loc, "filename")?;
    let left = max_triangles.saturating_sub(*triangles);
    let read = crate::ply::read_ply_in(&path, left, files.stop()).map_err(|mut e| {
        // The error's place is in the PLY file; say which directive named it.
        e.message = format!(
            "{} (the PLY file of the plymesh at {}:{}:{})",
            e.message,
            param.loc.file.display(),
            param.loc.span.line,
            param.loc.span.column
        );
        e
    })?;
    counted(shape, read.face_count(), triangles, max_triangles)?;
    let indices: Vec<u32> = read.faces().flat_map(|face| face.vertices).collect();
    let normals = read.normals().to_vec();
    let normals = if normals.len() == read.positions().len() {
        normals
    } else {
        Vec::new()
    };
    let texcoords = read.texcoords().to_vec();
    let texcoords = if texcoords.len() == read.positions().len() {
        texcoords
    } else {
        Vec::new()
    };
    oriented(
        shape,
        read.positions().to_vec(),
        normals,
        texcoords,
        &indices,
        files.stop(),
    )
}

/// A mesh of the triangles `indices` over `positions` (with per-point `normals` and
/// `texcoords` where not empty), each face fronting as pbrt-v4's do (see the
/// [module](self)), and its area.
fn oriented(
    shape: &ShapeEntity,
    positions: Vec<DVec3>,
    mut normals: Vec<DVec3>,
    texcoords: Vec<[f64; 2]>,
    indices: &[u32],
    stop: &crate::stop::StopFlag,
) -> Result<(Mesh, f64), SceneError> {
    let entity = &shape.entity;
    if shape.reverse {
        for n in &mut normals {
            *n = -*n;
        }
    }
    let mut area = 0.0;
    let faces: Vec<MeshFace> = indices
        .chunks_exact(3)
        .map(|c| {
            let [a, b, d] = [c[0], c[1], c[2]];
            let [pa, pb, pd] = [a, b, d].map(|i| positions[i as usize]);
            let geometric = (pb - pa).cross(pd - pa);
            area += geometric.length() / 2.0;
            let front = if normals.is_empty() {
                !shape.reverse
            } else {
                let shading: DVec3 = [a, b, d].iter().map(|&i| normals[i as usize]).sum();
                geometric.dot(shading) >= 0.0
            };
            // The front is (p1 − p0) × (p2 − p0) as given; swapping two corners turns it over.
            let vertices = if front { [a, b, d] } else { [a, d, b] };
            MeshFace {
                vertices,
                normals: (!normals.is_empty()).then_some(vertices),
                texcoords: (!texcoords.is_empty()).then_some(vertices),
            }
        })
        .collect();
    // Stopped while its BVH was built: the stop's error, at the shape.
    let mesh = Mesh::with_texcoords_until(positions, normals, texcoords, faces, stop.flag())
        .map_err(|e| match e {
            rayforge::geometry::MeshError::Stopped => SceneError::interrupted(&entity.loc.file)
                .at(entity.loc.span)
                .with_key("Shape"),
            e => entity.error(e.to_string()),
        })?
        .with_winding(Winding::RightHanded);
    Ok((mesh, area))
}
