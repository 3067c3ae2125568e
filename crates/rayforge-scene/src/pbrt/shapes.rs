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
//! - `bilinearmesh` (`P`, `indices` four a patch, optional `N`, `uv`): its patches as
//!   triangles, exactly two for a planar one and a grid within a stated bound of a curved one
//!   ([`super::bilinear`]), fronting, shading and emitting as a `trianglemesh`'s;
//!   `emissionfilename` is refused at its parameter.
//! - `loopsubdiv` (`levels`, default 3, at most [`MAX_LOOP_LEVELS`]; `indices`; `P`): Loop
//!   subdivision to the limit surface as pbrt-v4 does it ([`super::loop_subdiv`]), a triangle
//!   mesh with the limit normals; a mesh that is no manifold is refused at its `indices`.
//! - `plymesh` with `"texture displacement"` (`edgelength`, the option
//!   `displacementedgescale`): refined and displaced as pbrt-v4 does it
//!   ([`super::displace`]). A `trianglemesh`'s `displacement` goes unused, as in pbrt-v4.
//! - Every mesh's triangles count against `--max-triangles` before they are built.
//! - `curve` (`P`, `basis` bezier or bspline, `degree` 2 or 3, `type` flat, cylinder or
//!   ribbon, `width` or `width0`/`width1`, `N` for ribbons, `splitdepth`): pbrt-v4's curves
//!   ([`rayforge::geometry::Curves`]), its segments made as pbrt-v4's `Curve::Create` makes
//!   them (each segment's widths the curve's, linear along the whole curve), each cut into
//!   `2^splitdepth` parts (at most [`MAX_SPLIT_DEPTH`]) that count against `--max-triangles`
//!   before any is made. pbrt-v4 cannot sample a curve as an area light, so one under
//!   `AreaLightSource` is refused (in `build`).
//! - Every other shape is refused at its directive.

use super::displace::{displace, Displaced, Displacing};
use super::input::Files;
use super::params::{Param, Params};
use super::reader::ShapeEntity;
use crate::error::SceneError;
use glam::{DMat4, DVec2, DVec3};
use rayforge::geometry::curve::{Curve, CurveBasis, CurveError, CurveKind};
use rayforge::geometry::curves::MAX_SPLIT_DEPTH;
use rayforge::geometry::{Curves, CutError, Mesh, MeshFace, PartialQuadric, Winding};
use rayforge::{Object, Shape};
use std::sync::Arc;

/// What a shape became.
pub enum Built {
    /// Objects in the shape's own space (the caller places them), and the shape's area there
    /// (for an area light's `power`).
    Objects(Vec<Object>, f64),
    /// A mesh of patches (`bilinearmesh`) in its own space, its area, and how many of its
    /// faces, in order, each patch became: pbrt-v4 makes each patch a shape, and so a light
    /// emitting `power` of its own, where a `trianglemesh`'s every triangle is one.
    Patches(Vec<Object>, f64, Vec<u32>),
}

/// The object(s) of `shape` in its own space, and the triangles it adds to `triangles` (held
/// to `max_triangles`).
pub fn build(
    shape: &ShapeEntity,
    files: &Files,
    displacing: &Displacing<'_>,
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
                let object = sized(
                    shape,
                    Object::sphere(),
                    DMat4::from_scale(DVec3::splat(radius)),
                )?;
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
                let ring = Object::new(Shape::Ring {
                    inner,
                    outer: radius,
                });
                let object = sized(shape, ring, placed)?;
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
                let cylinder = Object::new(Shape::Cylinder {
                    minimum: zmin,
                    maximum: zmax,
                    closed: false,
                });
                let object = sized(shape, cylinder, placed)?;
                let area = 2.0 * std::f64::consts::PI * radius * (zmax - zmin);
                Built::Objects(vec![object], area)
            }
        }
        "curve" => {
            let curves = curve(shape, triangles, max_triangles, files.stop(), warnings)?;
            Built::Objects(vec![Object::new(Shape::Curves(Arc::new(curves)))], 0.0)
        }
        "bilinearmesh" => {
            let (mesh, area, patches) =
                bilinear_mesh(shape, triangles, max_triangles, files.stop())?;
            Built::Patches(vec![Object::mesh(Arc::new(mesh))], area, patches)
        }
        "loopsubdiv" => {
            let (mesh, area) = loop_subdivision(shape, triangles, max_triangles, files.stop())?;
            Built::Objects(vec![Object::mesh(Arc::new(mesh))], area)
        }
        "plymesh" => {
            let (mesh, area) = ply_mesh(shape, files, displacing, triangles, max_triangles)?;
            Built::Objects(vec![Object::mesh(Arc::new(mesh))], area)
        }
        other => {
            return Err(entity.error(format!(
                "the shape \"{}\" is not one rayforge reads; it reads trianglemesh, plymesh, \
                 bilinearmesh, loopsubdiv, curve, sphere, disk and cylinder",
                crate::error::clip_to(other, 60)
            )))
        }
    })
}

/// A float parameter that must be above 0.
/// `object` sized and placed in its own space by `matrix` (a radius, a height), refused at the
/// shape when the sizes are past what 64-bit numbers can invert (a sphere of radius 1e300
/// scales by 1e900 in volume: the media fuzz target's finding, a panic before).
fn sized(shape: &ShapeEntity, object: Object, matrix: DMat4) -> Result<Object, SceneError> {
    let transform = rayforge::math::Transform::try_new(matrix).map_err(|e| {
        shape.entity.error(format!(
            "a {}'s size cannot be used: {e}",
            shape.entity.name
        ))
    })?;
    Ok(object.with_transform_of(transform))
}

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
    let indices: Vec<u32> = match point_indices(shape, 3, "a triangle", positions.len())? {
        Some((v, _)) => v,
        None if positions.len() == 3 => vec![0, 1, 2],
        None => {
            return Err(
                entity.error("a trianglemesh of more than three points needs \"integer indices\"")
            )
        }
    };
    let normals = point_normals(params, positions.len())?.unwrap_or_default();
    let texcoords: Vec<[f64; 2]> = (point_uvs(params, positions.len())?.unwrap_or_default())
        .into_iter()
        .map(|t| [t.x, t.y])
        .collect();
    counted(shape, indices.len() / 3, triangles, max_triangles)?;
    oriented(shape, positions, normals, texcoords, &indices, stop)
}

/// The shape's `normal N`, one for each of its `points` points; `None` when absent.
fn point_normals(params: &Params, points: usize) -> Result<Option<Vec<DVec3>>, SceneError> {
    match params.points3("N", super::params::ParamType::Normal)? {
        Some((n, p)) if n.len() != points => Err(p.error(format!(
            "has {} normals for {points} points; it takes one a point",
            n.len()
        ))),
        found => Ok(found.map(|(n, _)| n)),
    }
}

/// The shape's `point2 uv`, one for each of its `points` points; `None` when absent.
fn point_uvs(params: &Params, points: usize) -> Result<Option<Vec<DVec2>>, SceneError> {
    match params.points2("uv")? {
        Some((uv, p)) if uv.len() != points => Err(p.error(format!(
            "has {} texture coordinates for {points} points; it takes one a point",
            uv.len()
        ))),
        found => Ok(found.map(|(uv, _)| uv)),
    }
}

/// The shape's `integer indices`, `group` a face (`what`, for the error), each one of the
/// `points` points of `P`; `None` when absent.
fn point_indices<'a>(
    shape: &'a ShapeEntity,
    group: usize,
    what: &str,
    points: usize,
) -> Result<Option<(Vec<u32>, &'a Param)>, SceneError> {
    use super::params::ParamType;
    let Some((v, p)) = shape.entity.params.numbers("indices", ParamType::Integer)? else {
        return Ok(None);
    };
    if v.len() % group != 0 {
        return Err(p.error(format!(
            "takes {group} indices {what}; {} is not a multiple of {group}",
            v.len()
        )));
    }
    let mut out = Vec::with_capacity(v.len());
    for &i in v {
        if i < 0.0 || i >= points as f64 {
            return Err(p.error(format!(
                "index {i} is not one of the {points} points of \"point3 P\""
            )));
        }
        out.push(i as u32);
    }
    Ok(Some((out, p)))
}

/// A `bilinearmesh` (`P`, `indices` four a patch in pbrt-v4's order `p00 p10 p01 p11`,
/// optional `N` and `uv` one a point): its patches as triangles ([`super::bilinear`]), fronting
/// as a `trianglemesh`'s do, their area, and the triangles of each patch (in order).
fn bilinear_mesh(
    shape: &ShapeEntity,
    triangles: &mut usize,
    max_triangles: usize,
    stop: &crate::stop::StopFlag,
) -> Result<(Mesh, f64, Vec<u32>), SceneError> {
    use super::bilinear::{Patch, Tessellation};
    use super::params::ParamType;
    let entity = &shape.entity;
    let params = &entity.params;
    if let Some((_, p)) = params.string("emissionfilename")? {
        return Err(p.error(
            "an image emitted over the patches is not read by rayforge; give the area light \
             its radiance (\"rgb L\", \"spectrum L\") instead",
        ));
    }
    let Some((positions, _)) = params.points3("P", ParamType::Point3)? else {
        return Err(entity.error("a bilinearmesh needs its points, \"point3 P\""));
    };
    let indices = match point_indices(shape, 4, "a patch", positions.len())? {
        Some((v, _)) => v,
        None if positions.len() == 4 => vec![0, 1, 2, 3],
        None => {
            return Err(
                entity.error("a bilinearmesh of more than four points needs \"integer indices\"")
            )
        }
    };
    let normals = point_normals(params, positions.len())?;
    let uv = point_uvs(params, positions.len())?;
    let patches: Vec<Patch> = indices
        .chunks_exact(4)
        .map(|c| {
            let c = [c[0], c[1], c[2], c[3]].map(|i| i as usize);
            Patch {
                p: c.map(|i| positions[i]),
                n: normals.as_ref().map(|n| c.map(|i| n[i])),
                uv: match &uv {
                    Some(uv) => c.map(|i| uv[i]),
                    None => [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                        .map(|(u, v)| glam::DVec2::new(u, v)),
                },
            }
        })
        .collect();
    // Count before building, so a scene past the limit is refused without its triangles.
    let cells: Vec<usize> = patches.iter().map(Patch::cells).collect();
    let count = cells
        .iter()
        .fold(0usize, |sum, n| sum.saturating_add(2 * n * n));
    counted(shape, count, triangles, max_triangles)?;
    let mut out = Tessellation::default();
    for (patch, &n) in patches.iter().zip(&cells) {
        patch.tessellate(n, &mut out);
    }
    // Each patch is 2n² triangles (n at most 23), in the patches' order.
    let per_patch = cells.iter().map(|&n| (2 * n * n) as u32).collect();
    let (mesh, area) = oriented(
        shape,
        out.positions,
        out.normals,
        out.texcoords,
        &out.indices,
        stop,
    )?;
    Ok((mesh, area, per_patch))
}

/// The most levels a `loopsubdiv` is refined (each quadruples its triangles; the scene's
/// `--max-triangles` holds them too): pbrt-v4 sets none, and 4¹⁵ is a billion triangles of
/// one face.
pub const MAX_LOOP_LEVELS: i64 = 15;

/// A `loopsubdiv` (`levels`, default 3; `indices`; `P`): the mesh refined by Loop's rules to
/// its limit surface ([`super::loop_subdiv`]), with its limit normals, fronting as a
/// `trianglemesh`'s do, and its area.
fn loop_subdivision(
    shape: &ShapeEntity,
    triangles: &mut usize,
    max_triangles: usize,
    stop: &crate::stop::StopFlag,
) -> Result<(Mesh, f64), SceneError> {
    use super::loop_subdiv::{subdivide, triangles_after, TriMesh};
    use super::params::ParamType;
    let entity = &shape.entity;
    let params = &entity.params;
    let levels = match params.integer("levels")? {
        Some((l, p)) if !(0..=MAX_LOOP_LEVELS).contains(&l) => {
            return Err(p.error(format!(
                "a loopsubdiv is refined 0 to {MAX_LOOP_LEVELS} levels, found {l}"
            )))
        }
        Some((l, _)) => l as u32,
        None => 3,
    };
    let Some((positions, _)) = params.points3("P", ParamType::Point3)? else {
        return Err(entity.error("a loopsubdiv needs its points, \"point3 P\""));
    };
    let Some((indices, at)) = point_indices(shape, 3, "a triangle", positions.len())? else {
        return Err(entity.error("a loopsubdiv needs its triangles, \"integer indices\""));
    };
    let faces: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let count = triangles_after(faces.len(), levels).unwrap_or(usize::MAX);
    counted(shape, count, triangles, max_triangles)?;
    let limit = subdivide(TriMesh { positions, faces }, levels)
        .map_err(|e| at.error(format!("Loop subdivision needs a manifold mesh: {e}")))?;
    let indices: Vec<u32> = limit.faces.into_iter().flatten().collect();
    oriented(
        shape,
        limit.positions,
        limit.normals,
        Vec::new(),
        &indices,
        stop,
    )
}

/// A `curve` (see the [module](self)): its segments, cut into parts that count against
/// `max_triangles` before any is made.
fn curve(
    shape: &ShapeEntity,
    triangles: &mut usize,
    max_triangles: usize,
    stop: &crate::stop::StopFlag,
    warnings: &mut Vec<SceneError>,
) -> Result<Curves, SceneError> {
    use super::params::ParamType;
    use rayforge::geometry::curve::{bezier_segments, segment_count};
    let entity = &shape.entity;
    let params = &entity.params;
    let basis = match params.string("basis")? {
        None | Some(("bezier", _)) => CurveBasis::Bezier,
        Some(("bspline", _)) => CurveBasis::BSpline,
        Some((other, p)) => {
            return Err(p.error(format!(
                "a curve's basis is \"bezier\" or \"bspline\", found \"{}\"",
                crate::error::clip_to(other, 40)
            )))
        }
    };
    let (degree, degree_at) = match params.integer("degree")? {
        Some((d, p)) => (d, Some(p)),
        None => (3, None),
    };
    let kind = match params.string("type")? {
        None | Some(("flat", _)) => CurveKind::Flat,
        Some(("cylinder", _)) => CurveKind::Cylinder,
        Some(("ribbon", _)) => CurveKind::Ribbon,
        Some((other, p)) => {
            return Err(p.error(format!(
                "a curve's type is \"flat\", \"cylinder\" or \"ribbon\", found \"{}\"",
                crate::error::clip_to(other, 40)
            )))
        }
    };
    let Some((numbers, at_p)) = params.numbers("P", ParamType::Point3)? else {
        return Err(entity.error("a curve needs its control points, \"point3 P\""));
    };
    let segments = segment_count(numbers.len() / 3, degree, basis).map_err(|e| match e {
        CurveError::Degree(_) => {
            degree_at.map_or_else(|| entity.error(e.to_string()), |p| p.error(e.to_string()))
        }
        e => at_p.error(e.to_string()),
    })?;
    let depth = match params.integer("splitdepth")? {
        Some((d, p)) if !(0..=i64::from(MAX_SPLIT_DEPTH)).contains(&d) => {
            return Err(p.error(format!(
                "a curve's splitdepth is 0 to {MAX_SPLIT_DEPTH}, found {d}"
            )))
        }
        Some((d, _)) => d as u32,
        None => 3,
    };
    let width = |name: &str, default: f64| -> Result<f64, SceneError> {
        match params.float_at(name)? {
            Some((w, p)) if !(w >= 0.0 && w.is_finite()) => Err(p.error(format!(
                "a curve's {name} is a length of 0 or more, found {w}"
            ))),
            Some((w, _)) => Ok(w),
            None => Ok(default),
        }
    };
    let w = width("width", 1.0)?;
    let (w0, w1) = (width("width0", w)?, width("width1", w)?);
    let normals =
        match (params.points3("N", ParamType::Normal)?, kind) {
            (Some((_, p)), CurveKind::Flat | CurveKind::Cylinder) => {
                warnings.push(
                    p.error("a curve's normals are used only by \"ribbon\" curves (as in pbrt-v4)"),
                );
                None
            }
            (Some((n, p)), _) if n.len() != segments + 1 => {
                return Err(p.error(format!(
                    "a ribbon of {segments} segments takes {} normals, one at each end of each, \
                 found {}",
                    segments + 1,
                    n.len()
                )))
            }
            (Some((n, p)), _) => {
                if n.iter().any(|n| !(n.length() > 0.0 && n.is_finite())) {
                    return Err(p.error("a ribbon's normals are directions, not zero"));
                }
                Some(n)
            }
            (None, CurveKind::Ribbon) => return Err(entity.error(
                "a ribbon curve needs its normals, \"normal N\", one at each end of each segment",
            )),
            (None, _) => None,
        };
    // Count before building, so a scene past the limit is refused without its parts.
    let parts = segments
        .checked_shl(depth)
        .filter(|&n| n >> depth == segments);
    counted(shape, parts.unwrap_or(usize::MAX), triangles, max_triangles)?;
    let (points, _) = params
        .points3("P", ParamType::Point3)?
        .expect("P was found above");
    let cps = bezier_segments(&points, degree, basis).map_err(|e| at_p.error(e.to_string()))?;
    let n = cps.len() as f64;
    let lerp = |t: f64| w0 + (w1 - w0) * t;
    let built: Vec<Curve> = cps
        .into_iter()
        .enumerate()
        .map(|(i, cp)| {
            let ends = normals.as_ref().map_or([DVec3::Z; 2], |n| [n[i], n[i + 1]]);
            let widths = [lerp(i as f64 / n), lerp((i + 1) as f64 / n)];
            Curve::new(cp, widths, kind, ends, 0.0, 1.0)
        })
        .collect();
    Curves::new_until(built, depth, stop.flag()).ok_or_else(|| {
        SceneError::interrupted(&entity.loc.file)
            .at(entity.loc.span)
            .with_key("Shape")
    })
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
    displacing: &Displacing<'_>,
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
    let mesh = Displaced {
        positions: read.positions().to_vec(),
        normals,
        texcoords,
        indices,
    };
    // A displaced mesh's refined triangles are counted (before they are made) in its place.
    let mesh = displace(shape, displacing, mesh, left, files.stop())?;
    counted(shape, mesh.indices.len() / 3, triangles, max_triangles)?;
    oriented(
        shape,
        mesh.positions,
        mesh.normals,
        mesh.texcoords,
        &mesh.indices,
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
