//! pbrt-v4's cut quadrics, bilinear patches and Loop subdivision surfaces as the reader builds
//! them: what each becomes, its uv and area, the errors at the parameter that fails; and
//! bilinear patches and Loop surfaces turned over and emitting, their light measured.

mod support;

use glam::DVec3;
use rayforge::geometry::{LocalHit, PartialQuadric};
use rayforge::shading::SurfacePoint;
use rayforge::{Ray, Shape};
use rayforge_scene::{LoadOptions, Scene, SceneError};

/// The scene of `text`, written to `s.pbrt` in a fresh folder.
fn load_text(text: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

fn load(text: &str) -> Scene {
    load_text(text).unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> SceneError {
    match load_text(text) {
        Ok(_) => panic!("loaded, but should not have:\n{text}"),
        Err(e) => e,
    }
}

/// Asserts `e` is at `line:col` of `s.pbrt` with `key`, its message containing `part`.
fn assert_at(e: &SceneError, line: usize, column: usize, key: &str, part: &str) {
    let span = e.span.unwrap_or_else(|| panic!("no place: {e}"));
    assert_eq!((span.line, span.column), (line, column), "{e}");
    assert!(e.path.ends_with("s.pbrt"), "{e}");
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert!(e.message.contains(part), "`{part}` not in: {e}");
}

const HEAD: &str = "Camera \"perspective\"\nWorldBegin\n";

/// The cut quadric object `i` of `scene` is.
fn partial(scene: &Scene, i: usize) -> PartialQuadric {
    match &scene.world.objects[i].shape {
        Shape::Partial(q) => **q,
        other => panic!("object {i} is {other:?}"),
    }
}

#[test]
fn cut_spheres_disks_and_cylinders_become_cut_quadrics() {
    let scene = load(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" 2 \"float zmin\" -1 \"float zmax\" 1.5\n\
         Shape \"sphere\" \"float radius\" 2 \"float phimax\" 90\n\
         Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1 \"float phimax\" 180\n\
         Shape \"cylinder\" \"float radius\" 1 \"float phimax\" 270\n\
         Shape \"sphere\" \"float radius\" 2 \"float zmin\" -5 \"float zmax\" 5 \"float phimax\" 400\n\
         Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1\n"
    ));
    assert_eq!(
        partial(&scene, 0),
        PartialQuadric::sphere(2.0, -1.0, 1.5, 360.0).unwrap()
    );
    assert_eq!(partial(&scene, 1).phi_max(), std::f64::consts::FRAC_PI_2);
    assert_eq!(
        partial(&scene, 2),
        PartialQuadric::disk(0.0, 2.0, 1.0, 180.0).unwrap()
    );
    assert_eq!(
        partial(&scene, 3),
        PartialQuadric::cylinder(1.0, -1.0, 1.0, 270.0).unwrap()
    );
    // Cuts past the poles and beyond a whole turn are pbrt's whole sphere; a whole annulus is
    // a ring.
    assert_eq!(scene.world.objects[4].shape, Shape::Sphere);
    assert!(matches!(scene.world.objects[5].shape, Shape::Ring { .. }));
    // Placed as pbrt places them, and cut: a ray down the axis passes the hole above
    // z = 1.5 and the one below z = −1, so it meets nothing; one at x = 1.5 meets the upper
    // side (z = +1.32, kept) and not the lower (z = −1.32, cut away).
    let object = &scene.world.objects[0];
    let down = |x: f64| {
        let ray = Ray::new(DVec3::new(x, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
        let hits = object.intersections(&ray);
        hits.iter().map(|h| h.t).collect::<Vec<_>>()
    };
    assert!(down(0.0).is_empty(), "{:?}", down(0.0));
    let t = down(1.5);
    let z = (4.0f64 - 2.25).sqrt();
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0] - (5.0 - z)).abs() < 1e-9, "{t:?}");
}

#[test]
fn cut_quadrics_have_pbrts_uv() {
    let scene = load(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" 2 \"float zmin\" 0 \"float phimax\" 180\n\
         Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1 \"float phimax\" 90 \
         \"float height\" 0.5\n\
         Shape \"cylinder\" \"float radius\" 1 \"float zmin\" 0 \"float zmax\" 2 \
         \"float phimax\" 180\n"
    ));
    let uv = |i: usize, p: DVec3| {
        let ctx = scene.world.objects[i].texture_context(
            p,
            &SurfacePoint::default(),
            &LocalHit::at(0.0),
            DVec3::Z,
        );
        ctx.uv
    };
    let close = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
    // u = φ / φmax; v from the lower cut's angle to the upper's, from the rim in, from zmin.
    for (i, p, want) in [
        (0, DVec3::new(0.0, 2.0, 0.0), (0.5, 0.0)),
        (0, DVec3::new(0.0, 0.0, 2.0), (0.0, 1.0)),
        (1, DVec3::new(0.0, 1.5, 0.5), (1.0, 0.5)),
        (2, DVec3::new(-1.0, 0.0, 0.5), (1.0, 0.25)),
    ] {
        let got = uv(i, p);
        assert!(close(got, want), "object {i} at {p}: {got:?}, not {want:?}");
    }
}

#[test]
fn a_cut_that_leaves_nothing_is_an_error_at_its_parameter() {
    let e = error(&format!(
        "{HEAD}Shape \"sphere\" \"float radius\" 1\n    \"float phimax\" 0\n"
    ));
    assert_at(&e, 4, 5, "float phimax", "above 0");
    let e = error(&format!(
        "{HEAD}Shape \"sphere\" \"float zmin\" 2 \"float zmax\" 3\n"
    ));
    assert_at(&e, 3, 31, "float zmax", "keeps nothing");
    let e = error(&format!("{HEAD}Shape \"disk\" \"float innerradius\" 1\n"));
    assert_at(&e, 3, 14, "float innerradius", "below its radius");
}

#[test]
fn a_cut_lamps_power_is_spread_over_its_cut_area() {
    // pbrt-v4's `power` is the lamp's emitted power over its own-space area: half a sphere of
    // radius 1 (area 2π) given power 2π² has radiance power / (π · area) = 1.
    let scene = load(&format!(
        "{HEAD}AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" {p}\n\
         Shape \"sphere\" \"float zmin\" 0\nAttributeEnd\n",
        p = std::f64::consts::PI * 2.0 * std::f64::consts::PI
    ));
    let emission = scene.world.objects[0].material.emission;
    assert!((emission.red - 1.0).abs() < 1e-9, "{emission:?}");
}

/// The mesh object `i` of `scene` is.
fn mesh(scene: &Scene, i: usize) -> std::sync::Arc<rayforge::geometry::Mesh> {
    match &scene.world.objects[i].shape {
        Shape::Mesh(m) => m.clone(),
        other => panic!("object {i} is {other:?}"),
    }
}

/// The area of a mesh's triangles.
fn area(m: &rayforge::geometry::Mesh) -> f64 {
    let p = m.positions();
    m.faces()
        .map(|f| {
            let [a, b, c] = f.vertices.map(|i| p[i as usize]);
            (b - a).cross(c - a).length() / 2.0
        })
        .sum()
}

/// Where a ray straight down from `(x, y, 5)` first meets object `i`, if it does.
fn down_at(scene: &Scene, i: usize, x: f64, y: f64) -> Option<f64> {
    let ray = Ray::new(DVec3::new(x, y, 5.0), DVec3::new(0.0, 0.0, -1.0));
    let hits = scene.world.objects[i].intersections(&ray);
    hits.iter()
        .map(|h| 5.0 - h.t)
        .fold(None, |m: Option<f64>, z| Some(m.map_or(z, |m| m.max(z))))
}

#[test]
fn a_planar_bilinear_patch_is_its_two_triangles() {
    // A parallelogram, as a patch (p00 p10 p01 p11) and as the two triangles it is.
    let scene = load(&format!(
        "{HEAD}Shape \"bilinearmesh\" \"point3 P\" [0 0 0  2 0 0  0.5 1 0  2.5 1 0] \
         \"integer indices\" [0 1 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [0 0 0  2 0 0  0.5 1 0  2.5 1 0] \
         \"integer indices\" [0 1 3  0 3 2]\n"
    ));
    let (patch, triangles) = (mesh(&scene, 0), mesh(&scene, 1));
    assert_eq!(patch.face_count(), 2);
    assert!((area(&patch) - 2.0).abs() < 1e-12, "{}", area(&patch));
    assert!((area(&patch) - area(&triangles)).abs() < 1e-12);
    for (x, y) in [
        (0.3, 0.2),
        (1.0, 0.5),
        (2.4, 0.95),
        (0.1, 0.9),
        (2.6, 0.5),
        (-0.1, 0.1),
    ] {
        assert_eq!(
            down_at(&scene, 0, x, y),
            down_at(&scene, 1, x, y),
            "at ({x}, {y})"
        );
    }
    assert_eq!(down_at(&scene, 0, 1.0, 0.5), Some(0.0));
    assert_eq!(down_at(&scene, 0, 0.1, 0.9), None);
    // Its uv is the patch's (u, v): (1, 1) at p11.
    let uv = patch.texcoords();
    assert_eq!(uv.len(), 4);
    assert_eq!(uv[3], [1.0, 1.0]);
}

#[test]
fn a_curved_bilinear_patchs_hits_lie_on_the_patch() {
    // The saddle z = xy over the unit square: P(u, v) = (u, v, uv).
    let scene = load(&format!(
        "{HEAD}Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1]\n"
    ));
    let m = mesh(&scene, 0);
    assert!(
        m.face_count() > 2 && m.face_count() <= 2 * 23 * 23,
        "{}",
        m.face_count()
    );
    // Within the stated bound: 1e-3 of the patch's size (√3).
    let bound = 1e-3 * 3f64.sqrt();
    let mut worst: f64 = 0.0;
    for i in 0..=20 {
        for j in 0..=20 {
            let (x, y) = (0.01 + 0.049 * i as f64, 0.01 + 0.049 * j as f64);
            let z = down_at(&scene, 0, x, y).unwrap_or_else(|| panic!("missed ({x}, {y})"));
            worst = worst.max((z - x * y).abs());
        }
    }
    assert!(worst <= bound, "{worst} > {bound}");
    assert!(
        worst > 0.0,
        "a grid of triangles cannot be exact on a saddle"
    );
    // Its shading normals are the patch's own: ∂P/∂u × ∂P/∂v = (−v, −u, 1) at (u, v).
    let (p, n) = (m.positions(), m.normals());
    for (q, n) in p.iter().zip(n) {
        let want = DVec3::new(-q.y, -q.x, 1.0).normalize();
        assert!(n.normalize().dot(want) > 1.0 - 1e-9, "{n} at {q}");
    }
}

#[test]
fn a_bilinearmesh_refuses_what_it_cannot_read_at_the_parameter() {
    let e = error(&format!(
        "{HEAD}Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n    \
         \"string emissionfilename\" \"e.exr\"\n"
    ));
    assert_at(&e, 4, 5, "string emissionfilename", "not read");
    let e = error(&format!(
        "{HEAD}Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n    \
         \"integer indices\" [0 1 2]\n"
    ));
    assert_at(&e, 4, 5, "integer indices", "multiple of 4");
}

/// A regular tetrahedron about the origin, its faces wound outwards.
const TETRAHEDRON: &str = "\"point3 P\" [1 1 1  1 -1 -1  -1 1 -1  -1 -1 1] \
                           \"integer indices\" [0 1 2  0 3 1  0 2 3  1 3 2]";

#[test]
fn loop_subdivision_of_a_tetrahedron_has_loops_counts_and_limit() {
    let text = (0..=3)
        .map(|l| format!("Shape \"loopsubdiv\" \"integer levels\" {l} {TETRAHEDRON}\n"))
        .collect::<String>();
    let scene = load(&format!("{HEAD}{text}"));
    // Each level: faces × 4, vertices + edges (V − E + F = 2).
    for (l, (v, f)) in [(4, 4), (10, 16), (34, 64), (130, 256)]
        .into_iter()
        .enumerate()
    {
        let m = mesh(&scene, l);
        assert_eq!((m.positions().len(), m.face_count()), (v, f), "level {l}");
    }
    // An original vertex's limit point is the same at every level (Loop's limit mask), and
    // by symmetry on its own axis: (1 − 3γ) p + γ Σ ring with γ = 1/5 at valence 3.
    let want = DVec3::splat(0.4 * 1.0 + 0.2 * (1.0 - 1.0 - 1.0));
    for l in 0..=3 {
        let m = mesh(&scene, l);
        let p = m.positions()[0];
        assert!((p - want).length() < 1e-12, "level {l}: {p}");
        // Its limit normal is along the axis, and, as pbrt-v4's tangents' cross product
        // makes it, against the input faces' (p1 − p0) × (p2 − p0): inwards here.
        let n = m.normals()[0].normalize();
        assert!(
            n.dot(-DVec3::ONE.normalize()) > 1.0 - 1e-9,
            "level {l}: {n}"
        );
        // The faces front as their corners' normals do, as a trianglemesh's with N.
        let face = m.faces().next().unwrap();
        let [a, b, c] = face.vertices.map(|i| m.positions()[i as usize]);
        let ns: DVec3 = face.vertices.iter().map(|&i| m.normals()[i as usize]).sum();
        assert!((b - a).cross(c - a).dot(ns) > 0.0, "level {l}");
        // The surface is symmetric about the centre.
        let mean: DVec3 = m.positions().iter().copied().sum::<DVec3>() / m.positions().len() as f64;
        assert!(mean.length() < 1e-12, "level {l}: {mean}");
    }
    // Refining shrinks the mesh towards its limit: the finest and the next agree closely.
    let radius = |l: usize| {
        let m = mesh(&scene, l);
        m.positions().iter().map(|p| p.length()).fold(0.0, f64::max)
    };
    assert!(
        (radius(3) - radius(2)).abs() < 0.02 * radius(3),
        "{} {}",
        radius(2),
        radius(3)
    );
}

#[test]
fn loop_subdivision_keeps_a_boundary() {
    // One triangle: every vertex on the boundary; the surface stays in its plane, and a
    // corner's limit is pbrt-v4's 3/5 of it and 1/5 of each boundary neighbour.
    let scene = load(&format!(
        "{HEAD}Shape \"loopsubdiv\" \"integer levels\" 0 \"point3 P\" [0 0 0  1 0 0  0 1 0] \
         \"integer indices\" [0 1 2]\n\
         Shape \"loopsubdiv\" \"integer levels\" 2 \"point3 P\" [0 0 0  1 0 0  0 1 0] \
         \"integer indices\" [0 1 2]\n"
    ));
    let m = mesh(&scene, 0);
    let p = m.positions();
    assert!(
        (p[0] - DVec3::new(0.2, 0.2, 0.0)).length() < 1e-12,
        "{}",
        p[0]
    );
    let m = mesh(&scene, 1);
    assert_eq!((m.positions().len(), m.face_count()), (15, 16));
    assert!(m.positions().iter().all(|p| p.z == 0.0));
    for n in m.normals() {
        assert!(n.x.abs() < 1e-12 && n.y.abs() < 1e-12, "{n}");
        // Against the face's (p1 − p0) × (p2 − p0), as at an interior point.
        assert!(n.z < 0.0, "{n}");
    }
}

#[test]
fn loop_subdivision_refuses_a_non_manifold_mesh_at_its_indices() {
    // Three triangles on one edge.
    let e = error(&format!(
        "{HEAD}Shape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0 0 -1 0 0 0 1]\n    \
         \"integer indices\" [0 1 2  1 0 3  0 1 4]\n"
    ));
    assert_at(&e, 4, 5, "integer indices", "manifold");
    // Two cones meeting at a point.
    let e = error(&format!(
        "{HEAD}Shape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0 -1 0 0 0 -1 0]\n    \
         \"integer indices\" [0 1 2  0 3 4]\n"
    ));
    assert_at(&e, 4, 5, "integer indices", "one fan");
    let e = error(&format!(
        "{HEAD}Shape \"loopsubdiv\" {TETRAHEDRON}\n    \"integer levels\" 16\n"
    ));
    assert_at(&e, 4, 5, "integer levels", "0 to 15");
}

/// The power a flat lamp in the plane z = 1 sends towards the camera at the origin, measured
/// by rendering: an orthographic camera looking down +z sees each point's radiance, and a
/// lamp that is Lambertian emits π ∫ L dA from its lit side, so the power is π × the sum of
/// the pixels' radiances (green) × a pixel's area. A lamp facing away gives 0.
fn measured_power(body: &str) -> f64 {
    let scene = load(&format!(
        "Camera \"orthographic\"\nPixelFilter \"box\"\n\
         Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 64\nWorldBegin\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{body}"
    ));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let (a, b) = (
        scene.camera.ray_through(0.0, 32.0).origin,
        scene.camera.ray_through(64.0, 32.0).origin,
    );
    let side = (b - a).length() / 64.0;
    let img = support::render(&scene, 64, 64, 16).resolve();
    let mut sum = 0.0;
    for y in 0..64 {
        for x in 0..64 {
            sum += img.pixel_at(x, y).green;
        }
    }
    sum * side * side * std::f64::consts::PI
}

/// Two planar patches in z = 1, of areas 0.5 and 1, wound so that pbrt-v4's front
/// `(p10 − p00) × (p01 − p00)` is +z, away from the camera.
const PATCHES: &str = "Shape \"bilinearmesh\" \"point3 P\" [-0.9 -0.9 1  -0.4 -0.9 1  -0.9 0.1 1  \
                       -0.4 0.1 1  0 -0.9 1  1 -0.9 1  0 0.1 1  1 0.1 1] \
                       \"integer indices\" [0 1 2 3  4 5 6 7]\n";

/// A bilinear mesh as a one-sided area light shines from its front only, which
/// `ReverseOrientation` turns over; its power is radiance × area × π (here 1.5 π for `L` 1),
/// and `power` is each patch's, as pbrt-v4 makes every patch a light (two patches given
/// `power` 2 emit 4, not 2 for each of their four triangles). Within 1.5 % (the pixels on
/// the patches' edges).
#[test]
fn a_bilinear_mesh_lamp_shines_from_its_front_with_each_patchs_power() {
    let pi = std::f64::consts::PI;
    let away = measured_power(&format!("AreaLightSource \"diffuse\"\n{PATCHES}"));
    assert_eq!(away, 0.0, "it faces away from the camera");
    let turned = |light: &str| {
        measured_power(&format!(
            "AreaLightSource \"diffuse\" {light}\nReverseOrientation\n{PATCHES}"
        ))
    };
    let lit = turned("\"rgb L\" [1 1 1]");
    assert!((lit - 1.5 * pi).abs() < 0.015 * 1.5 * pi, "{lit}");
    let powered = turned("\"float power\" 2");
    assert!((powered - 4.0).abs() < 0.015 * 4.0, "{powered}");
    // Two-sided, each side half the power: the camera's side gives 2.
    let both = measured_power(&format!(
        "AreaLightSource \"diffuse\" \"float power\" 2 \"bool twosided\" true\n{PATCHES}"
    ));
    assert!((both - 2.0).abs() < 0.015 * 2.0, "{both}");
}

/// A planar Loop surface as a one-sided area light: its faces front against the input's
/// `(p1 − p0) × (p2 − p0)` (pbrt-v4's limit normals), towards the camera here, and
/// `ReverseOrientation` turns them away; its power is radiance × its limit surface's area ×
/// π, and `power` is each triangle's, pbrt-v4 refining it into a triangle mesh (every
/// triangle a light). Within 1.5 %.
#[test]
fn a_loop_surface_lamp_shines_from_its_front_with_each_triangles_power() {
    let pi = std::f64::consts::PI;
    let square = "Shape \"loopsubdiv\" \"integer levels\" 2 \
                  \"point3 P\" [-0.9 -0.9 1  0.9 -0.9 1  0.9 0.9 1  -0.9 0.9 1] \
                  \"integer indices\" [0 1 2  0 2 3]\n";
    let scene = load(&format!("{HEAD}{square}"));
    let m = mesh(&scene, 0);
    let (faces, limit_area) = (m.face_count() as f64, area(&m));
    assert_eq!(faces, 32.0);
    let lit = measured_power(&format!(
        "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n{square}"
    ));
    assert!(
        (lit - pi * limit_area).abs() < 0.015 * pi * limit_area,
        "{lit} vs {}",
        pi * limit_area
    );
    let away = measured_power(&format!(
        "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nReverseOrientation\n{square}"
    ));
    assert_eq!(away, 0.0, "turned away from the camera");
    let powered = measured_power(&format!(
        "AreaLightSource \"diffuse\" \"float power\" 0.1\n{square}"
    ));
    assert!(
        (powered - 0.1 * faces).abs() < 0.015 * 0.1 * faces,
        "{powered}"
    );
}

/// A 2 × 2 quad in z = 0 with (u, v) = (x, y) / 2, its PLY file written beside `s.pbrt`, the
/// scene `body` after it; the scene's first mesh.
fn displaced(body: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let quad = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                property float z\nproperty float u\nproperty float v\nelement face 1\n\
                property list uchar int vertex_indices\nend_header\n\
                0 0 0 0 0\n2 0 0 1 0\n2 2 0 1 1\n0 2 0 0 1\n4 0 1 2 3\n";
    std::fs::write(dir.path().join("quad.ply"), quad).unwrap();
    let flat = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                end_header\n0 0 0\n2 0 0\n2 2 0\n3 0 1 2\n";
    std::fs::write(dir.path().join("nouv.ply"), flat).unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, body).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

fn mesh_of(scene: &Scene) -> &rayforge::geometry::Mesh {
    match &scene.world.objects[0].shape {
        Shape::Mesh(mesh) => mesh,
        other => panic!("{other:?}"),
    }
}

/// The normal at the point `p` of `mesh`.
fn normal_at_point(mesh: &rayforge::geometry::Mesh, p: DVec3) -> DVec3 {
    let i = mesh
        .positions()
        .iter()
        .position(|q| q.distance(p) < 1e-12)
        .unwrap_or_else(|| panic!("no point {p} in {:?}", mesh.positions()));
    mesh.normals()[i]
}

/// A displaced `plymesh` is refined until its edges are shorter than `edgelength` (times the
/// option `displacementedgescale`, measured after the shape's transform), each point moved
/// along its normal by the texture at its (u, v), and its normals made again from the
/// displaced faces, as pbrt-v4 does.
#[test]
fn a_displaced_plymesh_is_refined_moved_and_its_normals_made_again() {
    let shape = |texture: &str, edge: &str| {
        format!(
            "{HEAD}{texture}\nShape \"plymesh\" \"string filename\" \"quad.ply\" \
             \"texture displacement\" \"d\" {edge}\n"
        )
    };
    let constant = "Texture \"d\" \"float\" \"constant\" \"float value\" 0.5";
    // Each half of the quad (legs 2, long side 2√2) is cut at its long side, then each half
    // again at its long side (2): four triangles with edges 1, 1, √2 < 1.5. Nine points.
    let scene = displaced(&shape(constant, "\"float edgelength\" 1.5")).unwrap();
    let mesh = mesh_of(&scene);
    assert_eq!(mesh.face_count(), 8);
    assert_eq!(mesh.positions().len(), 9);
    for (p, n) in mesh.positions().iter().zip(mesh.normals()) {
        assert_eq!(p.z, 0.5, "{p}");
        assert!(n.distance(DVec3::Z) < 1e-12, "{n}");
    }
    for face in mesh.faces() {
        let [a, b, c] = mesh.corners(&face);
        for d in [a.distance(b), b.distance(c), c.distance(a)] {
            assert!(d < 1.5, "{d}");
        }
    }
    // Edges of 2 and 2√2 are not shorter than 2: the same cuts; 3 leaves the two halves.
    let scene = displaced(&shape(constant, "\"float edgelength\" 2")).unwrap();
    assert_eq!(mesh_of(&scene).face_count(), 8);
    let scene = displaced(&shape(constant, "\"float edgelength\" 3")).unwrap();
    assert_eq!(mesh_of(&scene).face_count(), 2);
    // The option scales the length, and lengths are measured after the shape's transform.
    let scaled = format!(
        "Option \"displacementedgescale\" 0.5\n{}",
        shape(constant, "\"float edgelength\" 3")
    );
    assert_eq!(mesh_of(&displaced(&scaled).unwrap()).face_count(), 8);
    let grown = shape(constant, "\"float edgelength\" 3")
        .replace("WorldBegin\n", "WorldBegin\nScale 0.75 0.75 0.75\n");
    assert_eq!(mesh_of(&displaced(&grown).unwrap()).face_count(), 2);
    let grown = grown.replace("Scale 0.75 0.75 0.75", "Scale 2 2 2");
    assert_eq!(mesh_of(&displaced(&grown).unwrap()).face_count(), 8);
    // A checkerboard of 0 and 1 with two squares along u and v: the corners and the middle
    // (whose (2u, 2v) sum is even) stay; the edges' midpoints rise by 1.
    let checker = "Texture \"d\" \"float\" \"checkerboard\" \"float tex1\" 0 \"float tex2\" 1 \
                   \"float uscale\" 2 \"float vscale\" 2";
    let scene = displaced(&shape(checker, "\"float edgelength\" 1.5")).unwrap();
    let mesh = mesh_of(&scene);
    assert_eq!(mesh.face_count(), 8);
    for p in mesh.positions() {
        let odd = ((p.x + p.y) as i64) % 2 == 1;
        assert_eq!(p.z, if odd { 1.0 } else { 0.0 }, "{p}");
    }
    // The middle's normal is +z by symmetry; the midpoint of the side y = 0 (at height 1,
    // between two corners and the middle at 0) has the mean of its two faces' unit normals,
    // (−1, 1, 1)/√3 and (1, 1, 1)/√3: (0, 1, 1)/√2.
    assert!(normal_at_point(mesh, DVec3::new(1.0, 1.0, 0.0)).distance(DVec3::Z) < 1e-12);
    let side = normal_at_point(mesh, DVec3::new(1.0, 0.0, 1.0));
    let expected = DVec3::new(0.0, 1.0, 1.0).normalize();
    assert!(side.distance(expected) < 1e-12, "{side}");
    // A scale texture scales what it reads.
    let scale = "Texture \"c\" \"float\" \"constant\" \"float value\" 0.25\n\
                 Texture \"d\" \"float\" \"scale\" \"texture tex\" \"c\" \"float scale\" -2";
    let scene = displaced(&shape(scale, "\"float edgelength\" 3")).unwrap();
    let mesh = mesh_of(&scene);
    assert!(mesh.positions().iter().all(|p| p.z == -0.5));
    // A trianglemesh's displacement goes unused (pbrt-v4 displaces only a plymesh), with the
    // unused-parameter warning at its line.
    let scene = displaced(&format!(
        "{HEAD}{constant}\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0] \
         \"integer indices\" [0 1 2] \"texture displacement\" \"d\"\n"
    ))
    .unwrap();
    assert_eq!(mesh_of(&scene).face_count(), 1);
    assert!(mesh_of(&scene).positions().iter().all(|p| p.z == 0.0));
    let warned = scene
        .warnings
        .iter()
        .find(|w| {
            w.message.contains("displacement") || w.key.as_deref() == Some("texture displacement")
        })
        .unwrap_or_else(|| panic!("{:?}", scene.warnings));
    assert_eq!(warned.span.map(|s| s.line), Some(4), "{warned}");
    // Without a displacement nothing is refined.
    let scene = displaced(&format!(
        "{HEAD}Shape \"plymesh\" \"string filename\" \"quad.ply\" \"float edgelength\" 0.01\n"
    ))
    .unwrap();
    assert_eq!(mesh_of(&scene).face_count(), 2);
}

/// A tiny `edgelength` is refused at it before its triangles are made (they would pass
/// `--max-triangles`); so are a length that is no positive number, a mesh without (u, v), a
/// texture that is not there and a bad option.
#[test]
fn a_displacement_that_cannot_be_made_is_refused_at_its_parameter() {
    let shape = |file: &str, edge: &str| {
        format!(
            "{HEAD}Texture \"d\" \"float\" \"constant\" \"float value\" 0.5\n\
             Shape \"plymesh\" \"string filename\" \"{file}\" \"texture displacement\" \"d\" {edge}\n"
        )
    };
    let e = displaced(&shape("quad.ply", "\"float edgelength\" 1e-9")).unwrap_err();
    assert_at(&e, 4, 73, "float edgelength", "--max-triangles");
    assert!(e.message.contains("edgelength"), "{e}");
    for bad in ["0", "-1"] {
        let e = displaced(&shape("quad.ply", &format!("\"float edgelength\" {bad}"))).unwrap_err();
        assert_at(&e, 4, 73, "float edgelength", "positive length");
    }
    let e = displaced(&shape("nouv.ply", "")).unwrap_err();
    assert_at(&e, 4, 46, "texture displacement", "(u, v)");
    let e = displaced(&shape("quad.ply", "").replace("\"d\" \n", "\"none\" \n")).unwrap_err();
    assert!(e.message.contains("no float texture"), "{e}");
    let e = displaced(&format!(
        "Option \"displacementedgescale\" 0\n{}",
        shape("quad.ply", "")
    ))
    .unwrap_err();
    assert!(e.message.contains("displacementedgescale"), "{e}");
}

/// The curves object `i` of `scene` holds.
fn curves(scene: &Scene, i: usize) -> std::sync::Arc<rayforge::geometry::Curves> {
    match &scene.world.objects[i].shape {
        Shape::Curves(c) => c.clone(),
        other => panic!("object {i} is {other:?}"),
    }
}

/// A `curve` becomes pbrt-v4's segments: a cubic B-spline of six points three Bézier
/// segments (the first starting at (p0 + 4 p1 + p2) / 6), a quadratic Bézier of five points
/// two, each segment's widths the curve's `width0` to `width1` at its ends, each cut into
/// `2^splitdepth` parts (default 3); a ribbon keeps its end normals, unit length.
#[test]
fn a_curve_becomes_pbrt_v4s_segments_and_parts() {
    let scene = load(&format!(
        "{HEAD}Shape \"curve\" \"string basis\" \"bspline\" \"integer splitdepth\" 2 \
         \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0  0 2 1  1 2 1] \
         \"float width0\" 0.3 \"float width1\" 0.0\n\
         Shape \"curve\" \"integer degree\" 2 \"string type\" \"cylinder\" \"float width\" 0.1 \
         \"point3 P\" [0 0 0  1 0 0  2 1 0  3 1 0  4 0 0]\n\
         Shape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [0 0 0  1 0 0  2 0 0  3 0 0] \
         \"normal N\" [0 0 2  0 1 0]\n"
    ));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let spline = curves(&scene, 0);
    assert_eq!((spline.segments().len(), spline.part_count()), (3, 12));
    let first = spline.segments()[0];
    assert!((first.cp[0] - DVec3::new(5.0 / 6.0, 1.0 / 6.0, 0.0)).length() < 1e-12);
    for (i, s) in spline.segments().iter().enumerate() {
        let w = |t: f64| 0.3 * (1.0 - t);
        assert!((s.width[0] - w(i as f64 / 3.0)).abs() < 1e-12, "{s:?}");
        assert!(
            (s.width[1] - w((i + 1) as f64 / 3.0)).abs() < 1e-12,
            "{s:?}"
        );
        assert_eq!(s.kind, rayforge::geometry::curve::CurveKind::Flat);
    }
    let quadratic = curves(&scene, 1);
    assert_eq!(
        (quadratic.segments().len(), quadratic.part_count()),
        (2, 16)
    );
    assert_eq!(quadratic.segments()[1].cp[3], DVec3::new(4.0, 0.0, 0.0));
    assert_eq!(quadratic.segments()[0].width, [0.1, 0.1]);
    let ribbon = curves(&scene, 2).segments()[0];
    assert_eq!(ribbon.kind, rayforge::geometry::curve::CurveKind::Ribbon);
    assert_eq!(ribbon.normals, [DVec3::Z, DVec3::Y]);
    // A ray down onto the ribbon's middle meets it, at (u, v) along and across.
    let object = &scene.world.objects[2];
    let local = object.ray_to_object(&Ray::new(
        DVec3::new(1.5, 0.01, 3.0),
        DVec3::new(0.0, 0.0, -1.0),
    ));
    let hit = object
        .shape
        .closest_hit(&local, 0.0, f64::INFINITY)
        .expect("a hit");
    assert!(
        (hit.t - 3.0).abs() < 1e-9 && (hit.u - 0.5).abs() < 1e-9,
        "{hit:?}"
    );
    assert_eq!(
        object.shape.surface_point(&hit).uv,
        Some((hit.u, hit.v)),
        "pbrt-v4's uv"
    );
}

/// The share of a 64 × 64 orthographic view (2 × 2 units) of a light background that
/// black `curves` at z = 1 cover: 1 − the image's mean (each pixel the mean of 16 samples).
fn covered(curves: &str) -> f64 {
    let scene = load(&format!(
        "Camera \"orthographic\"\nPixelFilter \"box\"\n\
         Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 64\nWorldBegin\n\
         LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{curves}"
    ));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let img = support::render(&scene, 64, 64, 16).resolve();
    let mut sum = 0.0;
    for y in 0..64 {
        for x in 0..64 {
            sum += img.pixel_at(x, y).green;
        }
    }
    1.0 - sum / 4096.0
}

/// A fan of eight straight curves, radii 0.2 to 0.9 at every 45°, each `width` wide, of
/// `kind`; ribbons get normals at both ends perpendicular to the curve, leaning `tilt`
/// degrees from the camera's −z. They do not overlap, so a flat or cylinder one covers
/// `8 × width × 0.7` of the view's 4 square units.
fn fan(kind: &str, width: f64, tilt: Option<f64>) -> String {
    let mut out = String::new();
    for k in 0..8 {
        let a = std::f64::consts::FRAC_PI_4 * k as f64;
        let (c, s) = (a.cos(), a.sin());
        let p: Vec<String> = [0.2, 0.2 + 0.7 / 3.0, 0.2 + 1.4 / 3.0, 0.9]
            .iter()
            .map(|r| format!("{} {} 1", r * c, r * s))
            .collect();
        let normals = tilt.map_or(String::new(), |t: f64| {
            let (ct, st) = (t.to_radians().cos(), t.to_radians().sin());
            let n = format!("{} {} {}", -s * st, c * st, -ct);
            format!("\"normal N\" [{n}  {n}]")
        });
        out += &format!(
            "Shape \"curve\" \"string type\" \"{kind}\" \"float width\" {width} \
             \"point3 P\" [{}] {normals}\n",
            p.join("  ")
        );
    }
    out
}

/// A fan of curves in front of a light background covers its share of the image: flat
/// and cylinder curves (which face every ray) their width's, a ribbon facing the camera
/// the same, and one leaning 60° from it half (its width is seen at cos 60°). Within 4 %
/// of the share (the pixels on the curves' edges, 16 samples each, vary it by about 1 %).
#[test]
fn a_fan_of_curves_covers_its_share_of_the_view() {
    let share = 8.0 * 0.05 * 0.7 / 4.0;
    for (kind, tilt, expected) in [
        ("flat", None, share),
        ("cylinder", None, share),
        ("ribbon", Some(0.0), share),
        ("ribbon", Some(60.0), share / 2.0),
    ] {
        let found = covered(&fan(kind, 0.05, tilt));
        assert!(
            (found - expected).abs() < 0.04 * expected,
            "{kind} {tilt:?}: covered {found}, expected {expected}"
        );
    }
    // Wider curves cover more, in proportion.
    let wide = covered(&fan("flat", 0.1, None));
    assert!((wide - 2.0 * share).abs() < 0.04 * 2.0 * share, "{wide}");
}

/// What a curve cannot be is refused at the parameter (or directive) that makes it so.
#[test]
fn a_curve_refuses_what_it_cannot_be_at_its_parameter() {
    let p4 = "\"point3 P\" [0 0 0  1 0 0  2 0 0  3 0 0]";
    let cases = [
        (
            format!("Shape \"curve\" {p4} \"integer degree\" 4"),
            55,
            "integer degree",
            "2 or 3",
        ),
        (
            "Shape \"curve\" \"point3 P\" [0 0 0  1 0 0  2 0 0  3 0 0  4 0 0]".to_string(),
            15,
            "point3 P",
            "4 + n·3",
        ),
        (
            format!("Shape \"curve\" {p4} \"string basis\" \"hermite\""),
            55,
            "string basis",
            "bspline",
        ),
        (
            format!("Shape \"curve\" {p4} \"string type\" \"tube\""),
            55,
            "string type",
            "ribbon",
        ),
        (
            format!("Shape \"curve\" {p4} \"integer splitdepth\" 11"),
            55,
            "integer splitdepth",
            "0 to 10",
        ),
        (
            format!("Shape \"curve\" {p4} \"float width1\" -0.5"),
            55,
            "float width1",
            "0 or more",
        ),
        (
            format!("Shape \"curve\" {p4} \"string type\" \"ribbon\" \"normal N\" [0 0 1]"),
            78,
            "normal N",
            "takes 2 normals",
        ),
        (
            format!("Shape \"curve\" {p4} \"string type\" \"ribbon\" \"normal N\" [0 0 1  0 0 0]"),
            78,
            "normal N",
            "not zero",
        ),
    ];
    for (body, column, key, part) in cases {
        let e = error(&format!("{HEAD}{body}\n"));
        assert_at(&e, 3, column, key, part);
    }
    let e = error(&format!(
        "{HEAD}Shape \"curve\" {p4} \"string type\" \"ribbon\"\n"
    ));
    assert_at(&e, 3, 1, "Shape", "needs its normals");
    let e = error(&format!("{HEAD}Shape \"curve\"\n"));
    assert_at(&e, 3, 1, "Shape", "point3 P");
    // pbrt-v4 cannot sample a curve's light: refused at the shape.
    let e = error(&format!(
        "{HEAD}AreaLightSource \"diffuse\"\nShape \"curve\" {p4}\n"
    ));
    assert_at(&e, 4, 1, "Shape", "area light");
    // Normals on a flat curve go unused, with a warning at them.
    let scene = load(&format!(
        "{HEAD}Shape \"curve\" {p4} \"normal N\" [0 0 1  0 0 1]\n"
    ));
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.to_string().contains("s.pbrt:3:55")
                && w.message.contains("only by \"ribbon\"")),
        "{:?}",
        scene.warnings
    );
    // The parts count against `--max-triangles` before any is made: one segment at
    // splitdepth 3 is 8.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, format!("{HEAD}Shape \"curve\" {p4}\n")).unwrap();
    let options = |max_triangles| LoadOptions {
        max_triangles,
        ..LoadOptions::default()
    };
    assert!(rayforge_scene::load_file_with(&path, &options(8)).is_ok());
    let e = rayforge_scene::load_file_with(&path, &options(7)).unwrap_err();
    assert_at(&e, 3, 1, "Shape", "--max-triangles");
}

/// The mean green of a 64 × 64 orthographic view of `curves` at z = 1 (diffuse, reflectance
/// 0.5) lit only by a distant light of irradiance π shining `to` (from the camera's side):
/// each point on a curve sends 0.5 × cos of its normal's angle to the light.
fn lit_from_the_camera(curves: &str, to: &str) -> f64 {
    let scene = load(&format!(
        "Camera \"orthographic\"\nPixelFilter \"box\"\n\
         Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 64\nWorldBegin\n\
         LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [{to}] \
         \"rgb L\" [3.14159265 3.14159265 3.14159265]\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n{curves}"
    ));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let img = support::render(&scene, 64, 64, 16).resolve();
    let mut sum = 0.0;
    for y in 0..64 {
        for x in 0..64 {
            sum += img.pixel_at(x, y).green;
        }
    }
    sum / 4096.0
}

/// The path tracer shades a curve by its material at the hit's normal: a flat curve faces
/// the camera and the light behind it, so it sends 0.5 over its whole width; a cylinder's
/// normal turns from −90° to +90° across it, so it sends 0.5 cos θ, 2/π of that on average
/// (a tube's shading). Lit from 40° off the view, a flat curve sends 0.5 cos 40° over its
/// whole width: the shadow rays leaving it do not meet it again, though it turns to face
/// them. Within 4 % (the curves' edge pixels).
#[test]
fn curves_are_shaded_by_their_material_at_their_normal() {
    let share = 8.0 * 0.05 * 0.7 / 4.0;
    let flat = lit_from_the_camera(&fan("flat", 0.05, None), "0 0 1");
    assert!((flat - 0.5 * share).abs() < 0.04 * 0.5 * share, "{flat}");
    let (s, c) = 40f64.to_radians().sin_cos();
    let slanted = lit_from_the_camera(&fan("flat", 0.05, None), &format!("{s} 0 {c}"));
    let expected = 0.5 * c * share;
    assert!(
        (slanted - expected).abs() < 0.04 * expected,
        "{slanted} vs {expected}"
    );
    let cylinder = lit_from_the_camera(&fan("cylinder", 0.05, None), "0 0 1");
    let tube = 0.5 * share * 2.0 / std::f64::consts::PI;
    assert!(
        (cylinder - tube).abs() < 0.04 * tube,
        "{cylinder} vs {tube}"
    );
}

/// The Whitted ray tracer meets curves as the path tracer does: in a 128 × 128 view of the
/// fan, flat, lit by a dim distant light along the view on a black background (no pixel
/// saturates; 16 rays a pixel), a flat curve lit face on is lit evenly, so the image's sum
/// over its brightest pixel is the area the fan covers, its share (within 4 %); and the
/// cylinder fan lights the same pixels (the same silhouette; within 2 %), dimmer (its normal
/// turns from the light towards its edges).
#[test]
fn the_whitted_ray_tracer_draws_curves_too() {
    let view = |kind: &str| {
        let scene = load(&format!(
            "Camera \"orthographic\"\n\
             Film \"rgb\" \"integer xresolution\" 128 \"integer yresolution\" 128\nWorldBegin\n\
             LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 1] \
             \"rgb L\" [0.3 0.3 0.3]\n\
             Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n{}",
            fan(kind, 0.05, None)
        ));
        // A 4 × 4 grid of rays a pixel: one through each centre would count the curves lying
        // along the pixel rows in whole rows.
        let options = rayforge::render::RenderOptions {
            sampling: rayforge::render::Sampling::with_samples(16),
            ..Default::default()
        };
        let (canvas, _) = rayforge::render::render(&scene.camera, &scene.world, &options);
        let pixels: Vec<f64> = (0..128 * 128)
            .map(|i| canvas.pixel_at(i % 128, i / 128).green)
            .collect();
        let brightest = pixels.iter().copied().fold(0.0, f64::max);
        assert!(brightest > 0.0 && brightest < 0.9, "{brightest}");
        let n = (128 * 128) as f64;
        let lit = pixels.iter().filter(|&&g| g > 1e-9).count() as f64 / n;
        let mean = pixels.iter().sum::<f64>() / n;
        (mean / brightest, lit, mean)
    };
    let share = 8.0 * 0.05 * 0.7 / 4.0;
    let (flat, flat_any, flat_mean) = view("flat");
    assert!((flat - share).abs() < 0.04 * share, "{flat} vs {share}");
    let (_, cylinder_any, cylinder_mean) = view("cylinder");
    assert!(
        cylinder_mean < 0.8 * flat_mean,
        "{cylinder_mean} vs {flat_mean}"
    );
    assert!(
        (cylinder_any - flat_any).abs() < 0.02 * flat_any,
        "{cylinder_any} vs {flat_any}"
    );
}
