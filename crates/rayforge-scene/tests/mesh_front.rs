//! Which side of a model's faces is the front: what its file format says (OBJ's and glTF's
//! corners turn counter-clockwise, seen from the front, in the file's right-handed axes), and
//! the path tracer's glass, one-sided faces and `emission-side` read it so.

use rayforge::film::Film;
use rayforge::geometry::Winding;
use rayforge::{point, vector, Ray, Shape};
use rayforge_scene::obj::{parse_obj, to_meshes};
use rayforge_scene::Scene;
use std::ops::Range;
use std::path::Path;
use support::{path_scene_head, render_samples};

mod support;

/// The film of `scene` path traced at its camera's size, with samples `samples` of each pixel.
fn render(scene: &Scene, samples: Range<u64>) -> Film {
    render_samples(scene, &scene.camera, samples).0
}

/// A cube from −1 to 1 as Blender writes one: six quads, each quad's corners counter-clockwise
/// seen from outside in the file's right-handed axes (checked with the usual right-hand cross
/// product as they are written).
fn cube_obj() -> String {
    let mut text = String::from("# a cube, counter-clockwise faces\n");
    let corner = |i: usize| [i & 1, (i >> 1) & 1, (i >> 2) & 1].map(|b| b as f64 * 2.0 - 1.0);
    for i in 0..8 {
        let [x, y, z] = corner(i);
        text += &format!("v {x} {y} {z}\n");
    }
    for axis in 0..3 {
        for side in [0, 1] {
            // The face's corners in order around it: the two other axes' bits in Gray order.
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut quad: Vec<usize> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                .iter()
                .map(|&(p, q)| (side << axis) | (p << a) | (q << b))
                .collect();
            let at = |i: usize| glam::DVec3::from(corner(quad[i]));
            let normal = (at(1) - at(0)).cross(at(2) - at(0));
            if normal[axis] * (side as f64 * 2.0 - 1.0) < 0.0 {
                quad.reverse();
            }
            let [p, q, r, s] = [quad[0], quad[1], quad[2], quad[3]].map(|i| i + 1);
            text += &format!("f {p} {q} {r} {s}\n");
        }
    }
    text
}

#[test]
fn an_obj_faces_front_is_the_side_its_corners_turn_counter_clockwise() {
    // Seen from +z (right-handed axes: x right, y up, z towards the viewer) these corners
    // turn counter-clockwise.
    let obj = parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        Path::new("front.obj"),
    )
    .unwrap();
    let meshes = to_meshes(&obj);
    let mesh = &meshes[0].0;
    assert_eq!(mesh.winding(), Winding::RightHanded);
    assert_eq!(mesh.face_normal(0).normalize(), vector(0.0, 0.0, 1.0));
    let ray = Ray::new(point(0.2, 0.2, 5.0), vector(0.0, 0.0, -1.0));
    let hit = mesh.closest_hit(&ray, 0.0, 10.0).unwrap();
    assert_eq!(mesh.normal_at(&hit), vector(0.0, 0.0, 1.0));
    // The corners are kept in the file's order.
    assert_eq!(mesh.face(0).vertices, [0, 1, 2]);
    // Every face of the generated cube fronts outwards.
    let cube = parse_obj(&cube_obj(), Path::new("cube.obj")).unwrap();
    let mesh = &to_meshes(&cube)[0].0;
    assert_eq!(mesh.face_count(), 12);
    for face in 0..mesh.face_count() {
        let [a, b, c] = mesh.corners(&mesh.face(face));
        let centre = (a + b + c) / 3.0;
        assert!(
            mesh.face_normal(face as u32).dot(centre) > 0.0,
            "face {face}"
        );
    }
}

/// Writes `files` into a fresh folder and loads `scene` from it.
fn scene_in(folder: &Path, scene: &str, files: &[(&str, &[u8])]) -> Scene {
    for (name, bytes) in files {
        std::fs::write(folder.join(name), bytes).unwrap();
    }
    let path = folder.join("scene.yml");
    std::fs::write(&path, scene).unwrap();
    rayforge_scene::load_file(&path).unwrap()
}

#[test]
fn a_gltf_faces_front_is_the_side_its_corners_turn_counter_clockwise() {
    // One triangle, counter-clockwise seen from glTF's +z; the model is mirrored into the
    // book's space (z flipped), so its front looks towards the book's −z, where the book's
    // cameras stand.
    let mut bin = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let gltf = r#"{
  "asset": { "version": "2.0" },
  "scene": 0,
  "scenes": [{ "nodes": [0] }],
  "nodes": [{ "mesh": 0 }],
  "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
  "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0] }],
  "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
  "buffers": [{ "uri": "triangle.bin", "byteLength": 36 }]
}"#;
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_in(
        dir.path(),
        "- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: gltf\n  file: triangle.gltf\n",
        &[("triangle.gltf", gltf.as_bytes()), ("triangle.bin", &bin)],
    );
    let object = &scene.world.objects[0];
    let Shape::Mesh(_) = &object.shape else {
        panic!("{:?}", object.shape);
    };
    let ray = Ray::new(point(0.2, 0.2, -5.0), vector(0.0, 0.0, 1.0));
    let xs = scene.world.intersect(&ray);
    let hit = rayforge::hit(&xs).expect("the triangle");
    let normal = object.normal_at_hit(ray.position(hit.t), &hit);
    assert!(
        (normal - vector(0.0, 0.0, -1.0)).length() < 1e-12,
        "{normal:?}"
    );
}

/// A glass cube, given by `cube` (an item's `add:` and keys), turned so that every face the
/// camera sees is oblique, over a checkered floor under a bright sky, path traced with
/// independent random numbers and the classic roulette (no pilot pass), its seed `seed`.
fn glass_scene(folder: &Path, cube: &str, seed: u64) -> Scene {
    let head = path_scene_head(24, 24, 0.9, [0.0, 2.5, -5.0], [0.0, 0.6, 0.0]);
    let text = format!(
        "{head}    sampler: independent
    roulette-scale: 1
    sample-allocation: uniform
    seed: {seed}
    background: [1, 1, 1]
- add: plane
  material:
    type: diffuse
    pattern: {{ type: checkers, colors: [[0.9, 0.9, 0.9], [0.05, 0.05, 0.05]], transform: [[scale, 0.3, 0.3, 0.3]] }}
- {cube}
  transform: [[rotate-y, 0.6], [rotate-x, 0.5], [translate, 0, 1.2, 0]]
  material: {{ type: dielectric, refractive-index: 1.5 }}
"
    );
    scene_in(folder, &text, &[("cube.obj", cube_obj().as_bytes())])
}

/// The red channel of each `block`×`block` block's mean, per batch of `spp` samples, over
/// `batches` disjoint sample ranges.
fn block_means(scene: &Scene, block: usize, spp: u64, batches: u64) -> Vec<Vec<f64>> {
    let (width, height) = (scene.camera.hsize(), scene.camera.vsize());
    (0..batches)
        .map(|k| {
            let canvas = render(scene, k * spp..(k + 1) * spp).resolve();
            let mut means = Vec::new();
            for by in (0..height).step_by(block) {
                for bx in (0..width).step_by(block) {
                    let mut sum = 0.0;
                    for y in by..by + block {
                        for x in bx..bx + block {
                            sum += canvas.pixel_at(x, y).red;
                        }
                    }
                    means.push(sum / (block * block) as f64);
                }
            }
            means
        })
        .collect()
}

/// Mean and variance of the mean of `values` (independent estimates).
fn mean_and_variance(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = values.clone().count() as f64;
    let mean = values.clone().sum::<f64>() / n;
    let spread = values.map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, spread / n)
}

#[test]
fn a_glass_obj_cube_renders_as_the_built_in_glass_cube() {
    // Two independent renders (other seeds) of one image: each 4×4 block's mean agrees
    // within noise (a z-test from 8 independent batches per render), and so does the whole
    // image's. Read inside out, the OBJ cube's glass refracts as if its index were 1/1.5
    // (light enters it bending away from the normal, much of it reflected back): its blocks
    // are then tens of standard errors off.
    let dir = tempfile::tempdir().unwrap();
    let built_in = glass_scene(dir.path(), "add: cube", 1);
    let obj = glass_scene(dir.path(), "add: obj\n  file: cube.obj", 2);
    assert!(matches!(obj.world.objects[1].shape, Shape::Mesh(_)));
    const BATCHES: u64 = 8;
    let a = block_means(&built_in, 4, 8, BATCHES);
    let b = block_means(&obj, 4, 8, BATCHES);
    let blocks = a[0].len();
    let mut worst: f64 = 0.0;
    let mut images = (vec![0.0; BATCHES as usize], vec![0.0; BATCHES as usize]);
    for i in 0..blocks {
        let (ma, va) = mean_and_variance(a.iter().map(|batch| batch[i]));
        let (mb, vb) = mean_and_variance(b.iter().map(|batch| batch[i]));
        if va + vb > 0.0 {
            worst = worst.max((ma - mb).abs() / (va + vb).sqrt());
        } else {
            assert_eq!(ma, mb, "block {i}");
        }
        for k in 0..BATCHES as usize {
            images.0[k] += a[k][i] / blocks as f64;
            images.1[k] += b[k][i] / blocks as f64;
        }
    }
    // The largest of 36 blocks' |z| (each a t statistic of about 14 degrees of freedom):
    // above 6 by chance about once in 10^4 renders.
    assert!(worst < 6.0, "a block is {worst:.1} standard errors off");
    let (ma, va) = mean_and_variance(images.0.into_iter());
    let (mb, vb) = mean_and_variance(images.1.into_iter());
    let z = (ma - mb) / (va + vb).sqrt();
    assert!(z.abs() < 4.5, "image means {ma} and {mb}: z {z:.1}");
}

/// A glowing OBJ square in the xz plane, `emission-side: front`, its corners `corners` (the
/// square's four in turn), over a white floor, seen from `from` towards `(0, to, 0)`.
fn lamp_scene(folder: &Path, corners: [usize; 4], from: [f64; 3], to: f64, up: [f64; 3]) -> Scene {
    let [x, y, z] = from;
    let [ux, uy, uz] = up;
    let text = format!(
        "- add: camera
  width: 8
  height: 8
  field-of-view: 0.5
  from: [{x}, {y}, {z}]
  to: [0, {to}, 0]
  up: [{ux}, {uy}, {uz}]
- world:
    renderer: path
    roulette-scale: 1
    sample-allocation: uniform
    background: [0, 0, 0]
- add: obj
  file: lamp.obj
  material: {{ type: diffuse, color: [0, 0, 0], emission: [1, 1, 1], emission-side: front }}
- add: rectangle
  transform: [[scale, 4, 1, 4], [translate, 0, -1, 0]]
  material: {{ type: diffuse, color: [1, 1, 1] }}
"
    );
    let [a, b, c, d] = corners;
    let lamp =
        format!("v -0.5 0 -0.5\nv -0.5 0 0.5\nv 0.5 0 0.5\nv 0.5 0 -0.5\nf {a} {b} {c} {d}\n");
    scene_in(folder, &text, &[("lamp.obj", lamp.as_bytes())])
}

#[test]
fn emission_side_front_on_an_obj_lights_the_side_its_corners_turn_counter_clockwise() {
    // Seen from +y in right-handed axes (x right, z down the page), the square's corners in
    // this order turn counter-clockwise: its front is +y; in the other order, −y.
    const UP: [usize; 4] = [1, 2, 3, 4];
    const DOWN: [usize; 4] = [4, 3, 2, 1];
    let dir = tempfile::tempdir().unwrap();
    // Seen face on from above and from below (looking straight at it): its radiance from the
    // front, nothing from behind.
    let centre = |corners, y: f64| {
        let scene = lamp_scene(dir.path(), corners, [0.0, y, 0.0001], 0.0, [0.0, 0.0, 1.0]);
        render(&scene, 0..4).resolve().pixel_at(4, 4).red
    };
    assert_eq!((centre(UP, 0.5), centre(UP, -0.5)), (1.0, 0.0));
    assert_eq!((centre(DOWN, 0.5), centre(DOWN, -0.5)), (0.0, 1.0));
    // Seen edge on from the side: the floor under it is lit only by its back (light the lamp
    // is sampled for, and light paths happen on).
    let floor = |corners| {
        let scene = lamp_scene(dir.path(), corners, [0.0, 0.0, -3.0], -0.5, [0.0, 1.0, 0.0]);
        let canvas = render(&scene, 0..16).resolve();
        canvas.pixels().iter().map(|c| c.red).sum::<f64>()
    };
    assert_eq!(floor(UP), 0.0);
    let lit = floor(DOWN);
    assert!(lit > 1.0, "the floor under a lamp facing it: {lit}");
}
