//! The mesh's eight-wide BVH and single-precision packets: every query agrees with testing every
//! face in `f64`, no ray slips between faces that share an edge, rays leaving a face do not
//! hit it again, far-away rays keep their precision, and a mesh stays within its memory budget.
use proptest::prelude::*;
use rayforge::geometry::{sphere_mesh, LocalHit, Mesh, MeshFace};
use rayforge::{point, vector, Point3, Ray, Vec3};

/// Every hit of `ray` on `mesh` by testing each face in f64 (Möller–Trumbore, the book's
/// triangle test): what the BVH must reproduce.
fn brute_force(mesh: &Mesh, ray: &Ray) -> Vec<(u32, f64)> {
    let mut hits = Vec::new();
    for (i, face) in mesh.faces().enumerate() {
        let [p1, p2, p3] = mesh.corners(&face);
        let (e1, e2) = (p2 - p1, p3 - p1);
        let dir_cross_e2 = ray.direction.cross(e2);
        let det = e1.dot(dir_cross_e2);
        if det == 0.0 {
            continue;
        }
        let f = 1.0 / det;
        let to_origin = ray.origin - p1;
        let u = f * to_origin.dot(dir_cross_e2);
        let origin_cross_e1 = to_origin.cross(e1);
        let v = f * ray.direction.dot(origin_cross_e1);
        if (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 {
            hits.push((i as u32, f * e2.dot(origin_cross_e1)));
        }
    }
    hits.sort_by(|a, b| a.1.total_cmp(&b.1));
    hits
}

/// A bumpy closed surface: a sphere of `rings` rings whose radius varies with direction, so
/// faces have many sizes and orientations.
fn bumpy_sphere(rings: u32, seed: f64) -> Mesh {
    let sphere = sphere_mesh(rings, 2 * rings);
    let positions: Vec<Point3> = sphere
        .positions()
        .iter()
        .map(|p| *p * (1.0 + 0.3 * (5.0 * p.x + seed).sin() * (3.0 * p.y - seed).cos()))
        .collect();
    let faces: Vec<MeshFace> = sphere
        .faces()
        .map(|f| MeshFace { normals: None, ..f })
        .collect();
    Mesh::new(positions, Vec::new(), faces).expect("the sphere's own indices")
}

fn unit_direction() -> impl Strategy<Value = Vec3> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_filter("not too short", |d| vector(d.0, d.1, d.2).length() > 0.05)
        .prop_map(|d| vector(d.0, d.1, d.2).normalize())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The nearest hit, the shadow test and the list of all hits agree with testing every
    /// face in f64, for rays from outside and inside, at any distance.
    #[test]
    fn mesh_queries_agree_with_testing_every_face(
        seed in 0.0..6.0f64,
        origin in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        direction in unit_direction(),
        far in prop::sample::select(vec![1.0, 1.0e3, 1.0e6]),
    ) {
        let mesh = bumpy_sphere(12, seed);
        // Far rays start `far` units back along themselves: the same line.
        let start = point(origin.0, origin.1, origin.2) - direction * (far - 1.0);
        let ray = Ray::new(start, direction);
        let expected = brute_force(&mesh, &ray);
        let ahead: Vec<&(u32, f64)> = expected.iter().filter(|h| h.1 >= 0.0).collect();
        let found = mesh.closest_hit(&ray, 0.0, f64::INFINITY);
        // Tolerances: the distance to within rounding of the travel; ties between faces
        // (a ray through a shared edge) may pick either.
        let tolerance = 1e-9 * far.max(1.0);
        match (found, ahead.first()) {
            (None, None) => {}
            (Some(h), Some(&&(_, t))) => prop_assert!((h.t - t).abs() <= tolerance, "{} vs {}", h.t, t),
            (found, expected) => {
                // Only a ray that grazes an edge within rounding may disagree.
                let (face, t) = match (found, expected) {
                    (Some(h), _) => (h.face, h.t),
                    (_, Some(e)) => (e.0, e.1),
                    _ => unreachable!(),
                };
                let corners = mesh.corners(&mesh.face(face as usize));
                let distance = edge_distance(ray.position(t), corners);
                prop_assert!(distance < 1e-6 * far, "found {found:?}, expected {expected:?}");
            }
        }
        prop_assert_eq!(mesh.any_hit(&ray, 0.0, f64::INFINITY), found.is_some());
        if far == 1.0 {
            let mut all: Vec<LocalHit> = Vec::new();
            mesh.intersect(&ray, |h| all.push(h));
            all.sort_by(|a, b| a.t.total_cmp(&b.t));
            prop_assert_eq!(all.len(), expected.len());
            for (h, e) in all.iter().zip(&expected) {
                prop_assert!((h.t - e.1).abs() <= tolerance);
            }
        }
    }
}

/// The distance from `p` to the nearest edge of a triangle.
fn edge_distance(p: Point3, [a, b, c]: [Point3; 3]) -> f64 {
    let segment = |a: Point3, b: Point3| {
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        (a + ab * t).distance(p)
    };
    segment(a, b).min(segment(b, c)).min(segment(c, a))
}

/// A flat grid of `n`×`n` unit squares in the plane z = 0, each cut into two triangles.
fn grid(n: u32) -> Mesh {
    let mut positions = Vec::new();
    for y in 0..=n {
        for x in 0..=n {
            positions.push(point(x as f64, y as f64, 0.0));
        }
    }
    let at = |x: u32, y: u32| y * (n + 1) + x;
    let mut faces = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let (a, b, c, d) = (at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1));
            for vertices in [[a, b, c], [a, c, d]] {
                faces.push(MeshFace {
                    vertices,
                    normals: None,
                    texcoords: None,
                });
            }
        }
    }
    Mesh::new(positions, Vec::new(), faces).expect("the grid's own indices")
}

/// Watertightness: rays aimed exactly at the grid's shared edges and vertices, from many
/// slants, all hit it (Möller–Trumbore on precomputed edges can miss both faces of an edge).
/// (The grid's outer border belongs to one face only; rays there may fall either side.)
#[test]
fn rays_through_shared_edges_and_vertices_never_slip_through() {
    let mesh = grid(16);
    let mut misses = Vec::new();
    for i in 1..64 {
        for j in 1..64 {
            // Every quarter unit: vertices, edge midpoints and the diagonals' points.
            let target = point(i as f64 * 0.25, j as f64 * 0.25, 0.0);
            for slant in [
                vector(0.0, 0.0, 1.0),
                vector(0.3, -0.2, 1.0),
                vector(-0.7, 0.45, 0.5),
            ] {
                let ray = Ray::new(target - slant * 3.0, slant);
                if !mesh.any_hit(&ray, 0.0, f64::INFINITY) {
                    misses.push((i, j));
                }
            }
        }
    }
    assert!(
        misses.is_empty(),
        "{} rays slipped through: {misses:?}",
        misses.len()
    );
}

/// A ray leaving the surface where it starts (a shadow ray from a hit point, nudged off
/// along the normal as the book does) does not find its own face again.
#[test]
fn rays_leaving_a_face_do_not_hit_it_again() {
    let mesh = bumpy_sphere(40, 1.0);
    let mut self_hits = 0;
    for k in 0..2000 {
        let a = k as f64 * 0.618_033_988_75;
        let direction = vector(
            a.cos() * (a * 0.37).sin(),
            (a * 0.37).cos(),
            a.sin() * (a * 0.37).sin(),
        );
        let ray = Ray::new(point(0.0, 0.0, 0.0) - direction * 5.0, direction);
        let Some(hit) = mesh.closest_hit(&ray, 0.0, f64::INFINITY) else {
            continue;
        };
        let normal = mesh.normal_at(&hit);
        let normal = if normal.dot(ray.direction) > 0.0 {
            -normal
        } else {
            normal
        };
        let over = ray.position(hit.t) + normal * rayforge::EPSILON;
        // Towards a light on the same side, at a grazing angle.
        let towards = (normal + direction * 0.9).normalize();
        let leaving = Ray::new(over, towards);
        if let Some(again) = mesh.closest_hit(&leaving, 0.0, f64::INFINITY) {
            if again.face == hit.face {
                self_hits += 1;
            }
        }
    }
    assert_eq!(self_hits, 0);
}

/// The performance issue's budget: the mesh's faces, packets and BVH take at most 100 bytes
/// per triangle beyond the vertex data.
#[test]
fn a_large_mesh_takes_at_most_100_bytes_per_triangle_beyond_its_vertices() {
    let mesh = sphere_mesh(150, 300);
    let triangles = mesh.face_count();
    let per_triangle = mesh.index_bytes() as f64 / triangles as f64;
    assert!(per_triangle <= 100.0, "{per_triangle} bytes per triangle");
}

/// A degenerate mesh (every face the same point, or faces in a long geometric progression)
/// builds and answers every ray: the build cannot recurse too deep for the walk's stack.
#[test]
fn degenerate_meshes_build_and_answer() {
    let n = 20_000u32;
    let same: Vec<Point3> = vec![point(1.0, 2.0, 3.0); 3];
    let faces: Vec<MeshFace> = (0..n)
        .map(|_| MeshFace {
            vertices: [0, 1, 2],
            normals: None,
            texcoords: None,
        })
        .collect();
    let mesh = Mesh::new(same, Vec::new(), faces).unwrap();
    let ray = Ray::new(point(1.0, 2.0, -5.0), vector(0.0, 0.0, 1.0));
    assert_eq!(mesh.closest_hit(&ray, 0.0, f64::INFINITY), None);
    // Faces spread geometrically from 1e-3 to 1e287: one long chain for a naive SAH. Those
    // beyond 1e30 cannot be held in single precision (rays pass them by, as documented); the
    // hierarchy's f32 frame then spans 1e30, where the faces near 1e29 are well resolved. The
    // rays there run parallel to the axis of the spread, 10^29 units from the frame's centre:
    // each axis in turn, since the slab test of that axis is the one at risk of overflowing.
    for axis in 0..3 {
        // (along the spread, across it, along the ray), in the order of this turn's axes.
        let at = |spread: f64, across: f64, along: f64| {
            let mut p = [0.0; 3];
            p[axis] = spread;
            p[(axis + 1) % 3] = across;
            p[(axis + 2) % 3] = along;
            point(p[0], p[1], p[2])
        };
        let mut positions = Vec::new();
        let mut faces = Vec::new();
        for i in 0..3000u32 {
            let x = 1.0e-3 * 1.25f64.powi(i as i32);
            positions.extend([at(x, 0.0, 0.0), at(x * 1.1, 1.0, 0.0), at(x, 1.0, 0.0)]);
            faces.push(MeshFace {
                vertices: [3 * i, 3 * i + 1, 3 * i + 2],
                normals: None,
                texcoords: None,
            });
        }
        let mesh = Mesh::new(positions, Vec::new(), faces).unwrap();
        let toward = at(0.0, 0.0, 1.0) - Point3::ZERO;
        let x = 1.0e-3 * 1.25f64.powi(330);
        let ray = Ray::new(at(x * 1.02, 0.5, -1.0), toward);
        let hit = mesh
            .closest_hit(&ray, 0.0, f64::INFINITY)
            .unwrap_or_else(|| panic!("face 330, spread along axis {axis}"));
        assert_eq!(hit.face, 330);
        assert!((hit.t - 1.0).abs() < 1e-12);
        let beyond = 1.0e-3 * 1.25f64.powi(2000);
        let ray = Ray::new(at(beyond * 1.02, 0.5, -1.0), toward);
        assert_eq!(mesh.closest_hit(&ray, 0.0, f64::INFINITY), None);
    }
}
