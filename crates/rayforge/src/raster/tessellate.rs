//! Shapes as triangles (the book's models): a rasterizer can only draw triangles, so every
//! analytic shape is cut into a mesh in its own object space, with the true surface normal at
//! each vertex so that Gouraud and Phong shading hide the facets.
//!
//! Winding: every generated face is wound so that `(p3 - p1) × (p2 - p1)` points out of the
//! shape, the convention of the book's triangles ([`Winding::Book`]), which back-face culling
//! relies on; a mesh keeps its own faces and winding. Faces are checked
//! against the outward direction as they are made, so no generator can get it wrong.
//!
//! Unbounded shapes are cut at [`EXTENT`] units from their origin: planes become large grids,
//! infinite cylinders and cones long tubes. Grid lines are dense near the origin and grow
//! geometrically further out (the farther parts cover few pixels), so a plane costs a few
//! thousand triangles and Gouraud shading still has vertices near what the camera looks at.
//!
//! A frame's tessellation may be stopped ([`tessellate_until`]): the generators look at the
//! stop flag once per ring or band of faces (a sphere at 4096 divisions is 4096 rings of
//! 8192 triangles) and refinement once per face, so one huge model stops within a ring, not
//! after its 33 million triangles. Not stopped, they make the very same faces.

use crate::geometry::curve::{evaluate, CurveKind};
use crate::geometry::{Curves, Mesh, MeshFace, PartialQuadric, Winding};
use crate::math::{Aabb, Point3, Vec3};
use crate::scene::Csg;
use crate::scene::Shape;
use std::borrow::Cow;
use std::f64::consts::{PI, TAU};
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether `stop` is set.
#[inline]
fn stopped(stop: Option<&AtomicBool>) -> bool {
    stop.is_some_and(|s| s.load(Ordering::Relaxed))
}

/// How far unbounded shapes reach from their origin, in object units.
pub const EXTENT: f64 = 1.0e4;

/// A triangle mesh in object space, borrowed from a [`Mesh`] or generated.
#[derive(Debug, Clone, PartialEq)]
pub struct Tessellation<'a> {
    /// Vertex positions.
    pub positions: Cow<'a, [Point3]>,
    /// Vertex normals, indexed by the faces' `normals` (faces without are flat).
    pub normals: Cow<'a, [Vec3]>,
    /// Texture coordinates, indexed by the faces' `texcoords`.
    pub texcoords: Cow<'a, [[f64; 2]]>,
    /// The triangles.
    pub faces: Faces<'a>,
    /// Whether the surface encloses a volume with every face wound outwards, so that faces
    /// pointing away from the eye are hidden behind others (and may be culled).
    pub closed: bool,
    /// Which side of each face is its front: the book's for a generated shape, the mesh's
    /// own for a mesh (an OBJ model's faces are counter-clockwise in right-handed axes).
    pub winding: Winding,
}

/// A tessellation's triangles: a mesh's own, read face by face where they are kept (a
/// million-triangle mesh is drawn every frame without a copy of its faces, which cost a tenth
/// of such a frame), or generated.
#[derive(Debug, Clone)]
pub enum Faces<'a> {
    /// The faces of a scene's mesh.
    Mesh(&'a Mesh),
    /// Faces made by a generator, a CSG solid's cut or a refinement.
    Generated(Vec<MeshFace>),
}

impl Faces<'_> {
    /// How many faces.
    pub fn len(&self) -> usize {
        match self {
            Faces::Mesh(mesh) => mesh.faces().len(),
            Faces::Generated(faces) => faces.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Face `index` (which must be below [`len`](Self::len)).
    #[inline]
    pub fn get(&self, index: usize) -> MeshFace {
        match self {
            Faces::Mesh(mesh) => mesh.face(index),
            Faces::Generated(faces) => faces[index],
        }
    }

    /// The faces in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = MeshFace> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Adds a face, first copying a mesh's faces if they were borrowed.
    fn push(&mut self, face: MeshFace) {
        if let Faces::Mesh(mesh) = self {
            *self = Faces::Generated(mesh.faces().collect());
        }
        if let Faces::Generated(faces) = self {
            faces.push(face);
        }
    }
}

impl PartialEq for Faces<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl<'a> Tessellation<'a> {
    /// An empty tessellation to add faces to.
    fn empty(closed: bool) -> Tessellation<'static> {
        Tessellation {
            positions: Cow::Owned(Vec::new()),
            normals: Cow::Owned(Vec::new()),
            texcoords: Cow::Owned(Vec::new()),
            faces: Faces::Generated(Vec::new()),
            closed,
            winding: Winding::Book,
        }
    }

    /// A mesh's own arrays, borrowed.
    pub fn of_mesh(mesh: &'a Mesh) -> Self {
        Tessellation {
            positions: Cow::Borrowed(mesh.positions()),
            normals: Cow::Borrowed(mesh.normals()),
            texcoords: Cow::Borrowed(mesh.texcoords()),
            faces: Faces::Mesh(mesh),
            closed: false,
            winding: mesh.winding(),
        }
    }

    /// The corners of a face.
    #[inline]
    pub fn corners(&self, face: &MeshFace) -> [Point3; 3] {
        face.vertices.map(|i| self.positions[i as usize])
    }

    /// The unit normal of a face with corners `p1 p2 p3` (in object space or placed in the
    /// world) towards its front by the tessellation's winding.
    #[inline]
    pub fn front_normal(&self, [p1, p2, p3]: [Point3; 3]) -> Vec3 {
        match self.winding {
            Winding::Book => (p3 - p1).cross(p2 - p1).normalize_or_zero(),
            Winding::RightHanded => (p2 - p1).cross(p3 - p1).normalize_or_zero(),
        }
    }

    /// A sphere around every vertex: the centre of their box and the farthest distance from
    /// it (not the smallest sphere, but close, and found in one pass).
    pub fn bounding_sphere(&self) -> (Point3, f64) {
        let mut bounds = Aabb::EMPTY;
        for &p in self.positions.iter() {
            bounds.add_point(p);
        }
        if bounds.is_empty() {
            return (Point3::ZERO, 0.0);
        }
        let centre = bounds.centroid();
        let radius = self
            .positions
            .iter()
            .map(|p| p.distance_squared(centre))
            .fold(0.0, f64::max)
            .sqrt();
        (centre, radius)
    }

    /// Adds a vertex with its normal (same index in both arrays) and returns its index.
    fn vertex(&mut self, p: Point3, n: Vec3) -> u32 {
        let positions = self.positions.to_mut();
        positions.push(p);
        self.normals.to_mut().push(n);
        (positions.len() - 1) as u32
    }

    /// Adds the face `a b c`, wound so that its normal points along `outward`.
    fn face(&mut self, a: u32, b: u32, c: u32, outward: Vec3) {
        let [p1, p2, p3] = [a, b, c].map(|i| self.positions[i as usize]);
        let v = if (p3 - p1).cross(p2 - p1).dot(outward) < 0.0 {
            [a, c, b]
        } else {
            [a, b, c]
        };
        self.faces.push(MeshFace {
            vertices: v,
            normals: Some(v),
            texcoords: None,
        });
    }

    /// Adds the quad `a b c d` (in order around it) as two faces.
    fn quad(&mut self, [a, b, c, d]: [u32; 4], outward: Vec3) {
        self.face(a, b, c, outward);
        self.face(a, c, d, outward);
    }
}

/// The book's `GenerateSphere(divs)`: the unit sphere as `divs + 1` rings of `divs` vertices
/// each, from the south pole to the north, and `2·divs²` triangles between consecutive rings.
/// The rings at the poles collapse to a point, so `divs` of the triangles touching each pole
/// have no area and draw nothing. Normals are the positions (exact for a sphere).
///
/// The book spaces the rings evenly in y; here they are evenly spaced in latitude, which keeps
/// the triangles near the poles from becoming slivers. `divs` below 3 counts as 3.
pub fn generate_sphere(divs: u32) -> Tessellation<'static> {
    sphere(divs, None).expect("a tessellation without a stop flag is never stopped")
}

/// [`generate_sphere`], `None` once `stop` is set (looked at before each ring of faces).
fn sphere(divs: u32, stop: Option<&AtomicBool>) -> Option<Tessellation<'static>> {
    let divs = divs.max(3);
    let mut t = Tessellation::empty(true);
    for d in 0..=divs {
        let latitude = PI * d as f64 / divs as f64;
        let (y, radius) = (-latitude.cos(), latitude.sin());
        for i in 0..divs {
            let angle = TAU * i as f64 / divs as f64;
            let p = Point3::new(radius * angle.cos(), y, radius * angle.sin());
            t.vertex(p, p);
        }
    }
    for d in 0..divs {
        if stopped(stop) {
            return None;
        }
        for i in 0..divs {
            let i0 = d * divs + i;
            let i1 = (d + 1) * divs + (i + 1) % divs;
            let i2 = d * divs + (i + 1) % divs;
            let i3 = (d + 1) * divs + i;
            let outward = t.positions[i0 as usize] + t.positions[i1 as usize];
            t.face(i0, i1, i2, outward);
            t.face(i0, i3, i1, outward);
        }
    }
    Some(t)
}

/// A torus around the y axis: `2·divs` segments around the axis, `divs` around the tube, each
/// vertex with the surface's own normal.
/// `None` once `stop` is set (looked at before each ring of faces).
fn torus(
    divs: u32,
    major: f64,
    minor: f64,
    stop: Option<&AtomicBool>,
) -> Option<Tessellation<'static>> {
    let around = divs.max(3) * 2;
    let tube = divs.max(3);
    let mut t = Tessellation::empty(true);
    for i in 0..around {
        let u = TAU * i as f64 / around as f64;
        for j in 0..tube {
            let v = TAU * j as f64 / tube as f64;
            let n = Vec3::new(v.cos() * u.cos(), v.sin(), v.cos() * u.sin());
            let centre = Point3::new(major * u.cos(), 0.0, major * u.sin());
            t.vertex(centre + n * minor, n);
        }
    }
    let index = |i: u32, j: u32| (i % around) * tube + (j % tube);
    for i in 0..around {
        if stopped(stop) {
            return None;
        }
        for j in 0..tube {
            let corners = [
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            ];
            let outward = corners
                .iter()
                .map(|&c| t.normals[c as usize])
                .fold(Vec3::ZERO, |a, n| a + n);
            t.quad(corners, outward);
        }
    }
    Some(t)
}

/// A cut quadric as a grid over its (u, v): `4·divs` columns about its axis, `divs` rows
/// along it, each vertex's normal the surface's; open, so seen from both sides.
fn partial(
    divs: u32,
    q: &PartialQuadric,
    stop: Option<&AtomicBool>,
) -> Option<Tessellation<'static>> {
    let (columns, rows) = (divs.max(3) * 4, divs.max(3));
    let mut t = Tessellation::empty(false);
    for i in 0..=columns {
        for j in 0..=rows {
            let p = q.point_at(
                f64::from(i) / f64::from(columns),
                f64::from(j) / f64::from(rows),
            );
            t.vertex(p, q.normal_at(p));
        }
    }
    let index = |i: u32, j: u32| i * (rows + 1) + j;
    for i in 0..columns {
        if stopped(stop) {
            return None;
        }
        for j in 0..rows {
            let corners = [
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            ];
            let front = corners
                .iter()
                .map(|&c| t.normals[c as usize])
                .fold(Vec3::ZERO, |a, n| a + n);
            t.quad(corners, front);
        }
    }
    Some(t)
}

/// A flat ring (or disc) in the xz plane: `4·divs` segments around, seen from both sides.
fn ring(divs: u32, inner: f64, outer: f64) -> Tessellation<'static> {
    let around = divs.max(3) * 4;
    let mut t = Tessellation::empty(false);
    for i in 0..around {
        let a = TAU * i as f64 / around as f64;
        let (x, z) = (a.cos(), a.sin());
        t.vertex(Point3::new(inner * x, 0.0, inner * z), Vec3::Y);
        t.vertex(Point3::new(outer * x, 0.0, outer * z), Vec3::Y);
    }
    for i in 0..around {
        let j = (i + 1) % around;
        t.quad([2 * i, 2 * i + 1, 2 * j + 1, 2 * j], Vec3::Y);
    }
    t
}

/// The cube from -1 to 1: four vertices per face (so each face has its own normal), twelve
/// triangles.
fn cube() -> Tessellation<'static> {
    let mut t = Tessellation::empty(true);
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut normal = Vec3::ZERO;
            normal[axis] = sign;
            let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(a, b)| t.vertex(normal + u * a + v * b, normal));
            t.quad(corners, normal);
        }
    }
    t
}

/// Grid lines from `min` to `max`: both ends, and between them every half unit up to 8 from
/// the origin, then every power of two. Infinite ends are cut at ±[`EXTENT`].
fn levels(min: f64, max: f64) -> Vec<f64> {
    let (min, max) = (min.max(-EXTENT), max.min(EXTENT));
    let mut ladder: Vec<f64> = (1..=16).map(|k| k as f64 * 0.5).collect();
    let mut step = 16.0;
    while step < EXTENT {
        ladder.push(step);
        step *= 2.0;
    }
    let mut out = vec![min];
    let inner = ladder
        .iter()
        .rev()
        .map(|v| -v)
        .chain(std::iter::once(0.0))
        .chain(ladder.iter().copied());
    out.extend(inner.filter(|&v| v > min && v < max));
    if max > min {
        out.push(max);
    }
    out
}

/// The xz plane as a grid of quads out to ±[`EXTENT`], normal +y.
fn plane() -> Tessellation<'static> {
    let mut t = Tessellation::empty(false);
    let lines = levels(-EXTENT, EXTENT);
    let n = lines.len() as u32;
    for &z in &lines {
        for &x in &lines {
            t.vertex(Point3::new(x, 0.0, z), Vec3::Y);
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let at = |i: u32, j: u32| j * n + i;
            t.quad(
                [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)],
                Vec3::Y,
            );
        }
    }
    t
}

/// The rectangle: the square from -1 to 1 in x and z, normal +y, as two triangles.
fn rectangle() -> Tessellation<'static> {
    let mut t = Tessellation::empty(false);
    for (x, z) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        t.vertex(Point3::new(x, 0.0, z), Vec3::Y);
    }
    t.quad([0, 1, 2, 3], Vec3::Y);
    t
}

/// A surface of revolution about y between `min` and `max`: radius `radius(y)` and the normal
/// at angle `a` given by `normal(a, y)`; bands between the grid [`levels`], each with its own
/// rings (so a cone's two nappes get their own normals at the apex). Capped ends are fans.
fn revolution(
    segments: u32,
    min: f64,
    max: f64,
    closed: bool,
    radius: impl Fn(f64) -> f64,
    normal: impl Fn(f64, f64) -> Vec3,
    stop: Option<&AtomicBool>,
) -> Option<Tessellation<'static>> {
    let segments = segments.max(3);
    let closed = closed && min.is_finite() && max.is_finite();
    let mut t = Tessellation::empty(closed);
    let lines = levels(min, max);
    let around = |i: u32| TAU * i as f64 / segments as f64;
    for band in lines.windows(2) {
        if stopped(stop) {
            return None;
        }
        let (y0, y1) = (band[0], band[1]);
        let mid = (y0 + y1) / 2.0;
        let ring = |t: &mut Tessellation<'static>, y: f64| -> u32 {
            let first = t.positions.len() as u32;
            for i in 0..segments {
                let a = around(i);
                let r = radius(y);
                t.vertex(Point3::new(r * a.cos(), y, r * a.sin()), normal(a, mid));
            }
            first
        };
        let (lo, hi) = (ring(&mut t, y0), ring(&mut t, y1));
        for i in 0..segments {
            let j = (i + 1) % segments;
            let a = (around(i) + around(i) + TAU / segments as f64) / 2.0;
            t.quad([lo + i, lo + j, hi + j, hi + i], normal(a, mid));
        }
    }
    if closed {
        for (y, up) in [(min, -1.0), (max, 1.0)] {
            let n = Vec3::new(0.0, up, 0.0);
            let centre = t.vertex(Point3::new(0.0, y, 0.0), n);
            let r = radius(y);
            let first = t.positions.len() as u32;
            for i in 0..segments {
                let a = around(i);
                t.vertex(Point3::new(r * a.cos(), y, r * a.sin()), n);
            }
            for i in 0..segments {
                t.face(centre, first + i, first + (i + 1) % segments, n);
            }
        }
    }
    Some(t)
}

/// A single triangle (smooth when it has vertex normals). Open: both sides can be seen.
fn triangle(tri: &crate::geometry::Triangle) -> Tessellation<'static> {
    let mut t = Tessellation::empty(false);
    let normals = tri.vertex_normals.unwrap_or([tri.normal; 3]);
    let ids = [tri.p1, tri.p2, tri.p3]
        .iter()
        .zip(normals)
        .map(|(&p, n)| t.vertex(p, n))
        .collect::<Vec<_>>();
    t.faces.push(MeshFace {
        vertices: [ids[0], ids[1], ids[2]],
        normals: tri.vertex_normals.map(|_| [ids[0], ids[1], ids[2]]),
        texcoords: None,
    });
    t
}

/// How many sides a curve's tube has in a tessellation.
const CURVE_SIDES: u32 = 6;

/// How many triangles [`curves`] makes of each part of `c`'s segments.
fn curve_faces_per_part(c: &Curves) -> u64 {
    match c.segments().first().map(|s| s.kind) {
        Some(CurveKind::Ribbon) => 2,
        _ => 2 * u64::from(CURVE_SIDES),
    }
}

/// pbrt-v4's curves as triangles, a ring of vertices at each end of each part of a segment:
/// a flat or cylinder curve as a tube of its width with [`CURVE_SIDES`] sides (the band the
/// ray tracer sees always faces the eye, as wide as its width from every side, which a tube
/// is too, where one fixed band would thin to nothing seen edge-on; the cylinder's normal is
/// the tube's), a ribbon as the band its end normals orient. The rings' frames are carried
/// along the segment without twist (each ring's side the last one's made perpendicular to
/// the new tangent). `None` once `stop` is set (looked at before each segment).
fn curves(c: &Curves, stop: Option<&AtomicBool>) -> Option<Tessellation<'static>> {
    let mut t = Tessellation::empty(false);
    let parts = 1u32 << c.depth();
    for segment in c.segments() {
        if stopped(stop) {
            return None;
        }
        let mut side: Option<Vec3> = None;
        let mut previous: Option<Vec<u32>> = None;
        for k in 0..=parts {
            let u = segment.u_min + (segment.u_max - segment.u_min) * k as f64 / parts as f64;
            let (centre, d) = evaluate(&segment.cp, u);
            let tangent = d.normalize_or_zero();
            let radius = 0.5 * (segment.width[0] + (segment.width[1] - segment.width[0]) * u);
            let ring: Vec<(Point3, Vec3)> = if segment.kind == CurveKind::Ribbon {
                // Across the ribbon: its normal (the one it is hit by) turned a quarter about
                // the tangent.
                let n = segment.normal(u, 0.5, -segment.ribbon_normal(u));
                let across = tangent.cross(n).normalize_or_zero();
                vec![(centre - across * radius, n), (centre + across * radius, n)]
            } else {
                let s = match side {
                    Some(s) => (s - s.dot(tangent) * tangent)
                        .try_normalize()
                        .unwrap_or_else(|| tangent.any_orthonormal_vector()),
                    None => tangent.any_orthonormal_vector(),
                };
                side = Some(s);
                let other = tangent.cross(s);
                (0..CURVE_SIDES)
                    .map(|i| {
                        let a = TAU * i as f64 / CURVE_SIDES as f64;
                        let n = s * a.cos() + other * a.sin();
                        (centre + n * radius, n)
                    })
                    .collect()
            };
            let ids: Vec<u32> = ring.iter().map(|&(p, n)| t.vertex(p, n)).collect();
            if let Some(prev) = previous {
                let m = ids.len();
                let bands = if m == 2 { 1 } else { m };
                for i in 0..bands {
                    let j = (i + 1) % m;
                    let outward = ring[i].1 + ring[j].1;
                    t.quad([prev[i], prev[j], ids[j], ids[i]], outward);
                }
            }
            previous = Some(ids);
        }
    }
    Some(t)
}

/// A CSG solid's surface: each primitive's tessellation, moved into the solid's space, keeping
/// the faces whose centre the solid keeps (see [`Csg::keeps_surface_point`]). Faces that cross
/// the boundary of another operand are kept or dropped whole, so the cut edges are as jagged as
/// the tessellation is coarse. The renderer draws CSG primitives one by one with the same rule,
/// each with its own material; this is the single-mesh form.
fn csg(csg: &Csg, divisions: u32, stop: Option<&AtomicBool>) -> Option<Tessellation<'static>> {
    let mut out = Tessellation::empty(false);
    for (leaf, object) in csg.leaves().iter().enumerate() {
        let part = tessellate_until(&object.shape, divisions, stop)?;
        let base = out.positions.len() as u32;
        let normal_base = out.normals.len() as u32;
        let uv_base = out.texcoords.len() as u32;
        out.positions
            .to_mut()
            .extend(part.positions.iter().map(|&p| object.transform.point(p)));
        out.normals
            .to_mut()
            .extend(part.normals.iter().map(|&n| object.transform.normal(n)));
        out.texcoords.to_mut().extend(part.texcoords.iter());
        for mut face in part.faces.iter() {
            let [a, b, c] = part.corners(&face).map(|p| object.transform.point(p));
            if !csg.keeps_surface_point(leaf, (a + b + c) / 3.0) {
                continue;
            }
            face.vertices = face.vertices.map(|i| i + base);
            face.normals = face.normals.map(|n| n.map(|i| i + normal_base));
            face.texcoords = face.texcoords.map(|n| n.map(|i| i + uv_base));
            if object.transform.matrix().determinant() < 0.0 {
                face.vertices.swap(1, 2);
                face.normals = face.normals.map(|mut n| {
                    n.swap(1, 2);
                    n
                });
                face.texcoords = face.texcoords.map(|mut n| {
                    n.swap(1, 2);
                    n
                });
            }
            out.faces.push(face);
        }
    }
    Some(out)
}

/// The most pieces per side [`refine`] cuts a face into.
const MAX_REFINE: u32 = 32;

/// The same surface with every face cut into `k²` smaller ones, `k` chosen so that no edge is
/// longer than `max_edge` (at most 32 per side); normals and texture coordinates are blended at the new vertices
/// (normals renormalised). CSG primitives are refined so that keeping or dropping whole
/// triangles by their centre follows the solid's edges closely.
pub fn refine(t: &Tessellation<'_>, max_edge: f64) -> Tessellation<'static> {
    refine_until(t, max_edge, None).expect("a refinement without a stop flag is never stopped")
}

/// [`refine`], `None` once `stop` is set (looked at before each face is cut).
pub(crate) fn refine_until(
    t: &Tessellation<'_>,
    max_edge: f64,
    stop: Option<&AtomicBool>,
) -> Option<Tessellation<'static>> {
    let mut out = Tessellation::empty(t.closed);
    out.winding = t.winding;
    for face in t.faces.iter() {
        if stopped(stop) {
            return None;
        }
        let p = t.corners(&face);
        let k = refinement(p, max_edge);
        let n = face.normals.map(|n| n.map(|i| t.normals[i as usize]));
        let uv = face.texcoords.map(|c| c.map(|i| t.texcoords[i as usize]));
        let first = out.positions.len() as u32;
        let first_uv = out.texcoords.len() as u32;
        // Grid points (i, j) with i + j <= k, weights (k - i - j, i, j) / k on the corners.
        let index = |i: u32, j: u32| first + j * (k + 1) - j * (j.saturating_sub(1)) / 2 + i;
        for j in 0..=k {
            for i in 0..=k - j {
                let w = [(k - i - j) as f64, i as f64, j as f64].map(|w| w / k as f64);
                let blend = |v: [Vec3; 3]| v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
                let normal = n.map_or(Vec3::ZERO, |n| blend(n).normalize_or_zero());
                out.vertex(blend(p), normal);
                if let Some(c) = uv {
                    out.texcoords.to_mut().push([
                        c[0][0] * w[0] + c[1][0] * w[1] + c[2][0] * w[2],
                        c[0][1] * w[0] + c[1][1] * w[1] + c[2][1] * w[2],
                    ]);
                }
            }
        }
        let mut push = |a: u32, b: u32, c: u32| {
            let v = [a, b, c];
            out.faces.push(MeshFace {
                vertices: v,
                normals: face.normals.map(|_| v),
                texcoords: uv.map(|_| v.map(|i| i - first + first_uv)),
            });
        };
        for j in 0..k {
            for i in 0..k - j {
                push(index(i, j), index(i + 1, j), index(i, j + 1));
                if i + j + 1 < k {
                    push(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
                }
            }
        }
    }
    Some(out)
}

/// How many triangles [`tessellate`] makes of `shape` at most, counted without making them, so
/// that a render can refuse a scene whose tessellation would not fit in memory before it
/// allocates any of it (a sphere at 4096 divisions is 33 million triangles, 3.4 GB).
pub fn face_count(shape: &Shape, divisions: u32) -> u64 {
    let d = u64::from(divisions.max(3));
    match shape {
        Shape::Sphere => 2 * d * d,
        Shape::Torus { .. } => 4 * d * d,
        Shape::Ring { .. } => 8 * d,
        Shape::Partial(_) => 8 * d * d,
        Shape::Cube => 12,
        Shape::Rectangle => 2,
        Shape::Triangle(_) => 1,
        Shape::Plane => {
            let n = levels(-EXTENT, EXTENT).len() as u64;
            2 * (n - 1) * (n - 1)
        }
        Shape::Cylinder {
            minimum,
            maximum,
            closed,
        }
        | Shape::Cone {
            minimum,
            maximum,
            closed,
        } => {
            let bands = levels(*minimum, *maximum).len().saturating_sub(1) as u64;
            let caps = if *closed { 2 * d } else { 0 };
            bands * 2 * d + caps
        }
        Shape::Mesh(mesh) => mesh.faces().len() as u64,
        Shape::Curves(c) => curve_faces_per_part(c) * c.part_count() as u64,
        Shape::Csg(c) => c
            .leaves()
            .iter()
            .map(|leaf| face_count(&leaf.shape, divisions))
            .sum(),
    }
}

/// How many triangles [`refine`] makes of `t` with `max_edge`, counted without making them.
pub fn refined_face_count(t: &Tessellation<'_>, max_edge: f64) -> u64 {
    t.faces
        .iter()
        .map(|face| u64::from(refinement(t.corners(&face), max_edge)).pow(2))
        .sum()
}

/// How many pieces [`refine`] cuts each side of a triangle with corners `p` into.
fn refinement(p: [Point3; 3], max_edge: f64) -> u32 {
    let longest = (p[1] - p[0])
        .length()
        .max((p[2] - p[1]).length())
        .max((p[0] - p[2]).length());
    if max_edge > 0.0 && longest.is_finite() {
        ((longest / max_edge).ceil() as u32).clamp(1, MAX_REFINE)
    } else {
        1
    }
}

/// Any shape as triangles in its own object space. `divisions` sets the resolution of curved
/// shapes (see [`generate_sphere`]; cylinders and cones get as many segments around). Meshes
/// are borrowed as they are; planes and infinite cylinders and cones are cut at [`EXTENT`].
pub fn tessellate(shape: &Shape, divisions: u32) -> Tessellation<'_> {
    tessellate_until(shape, divisions, None)
        .expect("a tessellation without a stop flag is never stopped")
}

/// [`tessellate`], `None` once `stop` is set (see the [module](self)).
pub(crate) fn tessellate_until<'s>(
    shape: &'s Shape,
    divisions: u32,
    stop: Option<&AtomicBool>,
) -> Option<Tessellation<'s>> {
    Some(match shape {
        Shape::Sphere => sphere(divisions, stop)?,
        Shape::Cube => cube(),
        Shape::Plane => plane(),
        Shape::Rectangle => rectangle(),
        Shape::Cylinder {
            minimum,
            maximum,
            closed,
        } => revolution(
            divisions,
            *minimum,
            *maximum,
            *closed,
            |_| 1.0,
            |a, _| Vec3::new(a.cos(), 0.0, a.sin()),
            stop,
        )?,
        Shape::Cone {
            minimum,
            maximum,
            closed,
        } => revolution(
            divisions,
            *minimum,
            *maximum,
            *closed,
            f64::abs,
            // The side of x² + z² = y² leans out at 45°: down on the upper nappe, up on the
            // lower (the ray tracer's normal, normalised).
            |a, y| Vec3::new(a.cos(), -y.signum(), a.sin()) / std::f64::consts::SQRT_2,
            stop,
        )?,
        Shape::Torus { major, minor } => torus(divisions, *major, *minor, stop)?,
        Shape::Ring { inner, outer } => ring(divisions, *inner, *outer),
        Shape::Triangle(tri) => triangle(tri),
        Shape::Mesh(mesh) => Tessellation::of_mesh(mesh),
        Shape::Curves(c) => curves(c, stop)?,
        Shape::Csg(c) => csg(c, divisions, stop)?,
        Shape::Partial(q) => partial(divisions, q, stop)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{CsgOperation, Object};

    /// A curve's tessellation makes the faces [`face_count`] counts, a tube's vertices half
    /// its width from its centre line and a ribbon's on the band across its normal.
    #[test]
    fn curves_become_tubes_and_bands_of_their_width() {
        use crate::geometry::curve::Curve;
        let cp = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(2.0, -1.0, 0.5),
            Point3::new(3.0, 0.0, 0.0),
        ];
        for kind in [CurveKind::Flat, CurveKind::Cylinder, CurveKind::Ribbon] {
            let segment = Curve::new(cp, [0.2, 0.2], kind, [Vec3::Z; 2], 0.0, 1.0);
            let shape = Shape::Curves(std::sync::Arc::new(Curves::new(vec![segment], 2)));
            let t = tessellate(&shape, 16);
            assert_eq!(t.faces.len() as u64, face_count(&shape, 16));
            for (k, p) in t.positions.iter().enumerate() {
                let per_ring = if kind == CurveKind::Ribbon {
                    2
                } else {
                    CURVE_SIDES
                } as usize;
                let u = (k / per_ring) as f64 / 4.0;
                let (centre, d) = evaluate(&cp, u);
                let off = *p - centre;
                assert!((off.length() - 0.1).abs() < 1e-12, "{kind:?} {k}");
                assert!(off.dot(d).abs() < 1e-9, "{kind:?} {k}");
                if kind == CurveKind::Ribbon {
                    assert!(off.dot(Vec3::Z).abs() < 1e-9);
                }
            }
        }
    }

    /// Each generator that makes many faces gives up once the stop flag is set, and with the
    /// flag clear makes the very faces it makes without one.
    #[test]
    fn a_tessellation_gives_up_at_its_stop_flag_and_is_otherwise_the_same() {
        let (clear, set) = (AtomicBool::new(false), AtomicBool::new(true));
        let solid = Object::csg(
            CsgOperation::Difference,
            Object::new(Shape::Cube),
            Object::new(Shape::Sphere),
        )
        .unwrap();
        let shapes = [
            Shape::Sphere,
            Shape::Torus {
                major: 1.0,
                minor: 0.25,
            },
            Shape::Cylinder {
                minimum: -1.0,
                maximum: 1.0,
                closed: true,
            },
            Shape::Cone {
                minimum: -1.0,
                maximum: 0.0,
                closed: false,
            },
            solid.shape,
        ];
        for shape in &shapes {
            let plain = tessellate(shape, 64);
            assert_eq!(
                tessellate_until(shape, 64, Some(&clear)).as_ref(),
                Some(&plain)
            );
            assert!(
                tessellate_until(shape, 64, Some(&set)).is_none(),
                "{shape:?}"
            );
            let fine = refine(&plain, 0.01);
            assert_eq!(refine_until(&plain, 0.01, Some(&clear)), Some(fine));
            assert!(refine_until(&plain, 0.01, Some(&set)).is_none());
        }
    }
}
