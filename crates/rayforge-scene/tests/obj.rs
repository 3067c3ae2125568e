//! Chapter 15: the OBJ file parser, and OBJ models in scene files.
use rayforge::book::BookMaterial;
use rayforge::color::color;
use rayforge::{hit, prepare_computations, Ray};
use rayforge::{point, vector, Shape};
use rayforge_scene::obj::{parse_obj, read_obj_file, to_meshes};
use std::path::{Path, PathBuf};

fn parse(text: &str) -> rayforge_scene::obj::ObjFile {
    parse_obj(text, Path::new("test.obj")).expect("parses")
}

/// Reads an OBJ file, loading any texture maps it names without a cache.
fn read_obj(path: &Path) -> Result<rayforge_scene::obj::ObjFile, rayforge_scene::SceneError> {
    read_obj_file(path, &mut |image| {
        let text = std::fs::read_to_string(image)
            .map_err(|e| rayforge_scene::SceneError::new(image, e.to_string()))?;
        // The fixtures' images are plain PPMs of one colour: read the first pixel.
        let numbers: Vec<f64> = text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .flat_map(|l| l.split_whitespace())
            .skip(4)
            .map(|v| v.parse::<f64>().unwrap() / 255.0)
            .collect();
        let pixel = rayforge::Color::new(numbers[0], numbers[1], numbers[2]);
        Ok(std::sync::Arc::new(
            rayforge::shading::Texture::new(1, 1, vec![pixel], rayforge::shading::Filter::Nearest)
                .unwrap(),
        ))
    })
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

#[test]
fn ignoring_unrecognized_lines() {
    let gibberish = "There was a young lady named Bright\n\
                     who traveled much faster than light.\n\
                     She set out one day\n\
                     in a relative way,\n\
                     and came back the previous night.\n";
    assert_eq!(parse(gibberish).ignored_lines, 5);
}

#[test]
fn vertex_records() {
    let obj = parse("v -1 1 0\nv -1.0000 0.5000 0.0000\nv 1 0 0\nv 1 1 0\n");
    // The book's vertices are 1-based: vertices[1] is the first.
    assert_eq!(obj.vertices[0], point(-1.0, 1.0, 0.0));
    assert_eq!(obj.vertices[1], point(-1.0, 0.5, 0.0));
    assert_eq!(obj.vertices[2], point(1.0, 0.0, 0.0));
    assert_eq!(obj.vertices[3], point(1.0, 1.0, 0.0));
}

#[test]
fn parsing_triangle_faces() {
    let obj = parse("v -1 1 0\nv -1 0 0\nv 1 0 0\nv 1 1 0\n\nf 1 2 3\nf 1 3 4\n");
    let g = obj.default_group();
    assert_eq!(g.triangles[0].vertices, [0, 1, 2]);
    assert_eq!(g.triangles[1].vertices, [0, 2, 3]);
}

#[test]
fn triangulating_polygons() {
    let obj = parse("v -1 1 0\nv -1 0 0\nv 1 0 0\nv 1 1 0\nv 0 2 0\n\nf 1 2 3 4 5\n");
    let g = obj.default_group();
    assert_eq!(g.triangles.len(), 3);
    assert_eq!(g.triangles[0].vertices, [0, 1, 2]);
    assert_eq!(g.triangles[1].vertices, [0, 2, 3]);
    assert_eq!(g.triangles[2].vertices, [0, 3, 4]);
}

#[test]
fn triangles_in_groups() {
    let obj = read_obj(&fixture("triangles.obj")).unwrap();
    let g1 = obj.group("FirstGroup").unwrap();
    let g2 = obj.group("SecondGroup").unwrap();
    assert_eq!(g1.triangles[0].vertices, [0, 1, 2]);
    assert_eq!(g2.triangles[0].vertices, [0, 2, 3]);
}

#[test]
fn converting_an_obj_file_to_a_group() {
    let obj = read_obj(&fixture("triangles.obj")).unwrap();
    let meshes = to_meshes(&obj);
    // One mesh per named group (the default group is empty here).
    assert_eq!(meshes.len(), 2);
    let first = &meshes[0].0;
    assert_eq!(
        first.corners(&first.face(0)),
        [obj.vertices[0], obj.vertices[1], obj.vertices[2]]
    );
}

#[test]
fn vertex_normal_records() {
    let obj = parse("vn 0 0 1\nvn 0.707 0 -0.707\nvn 1 2 3\n");
    assert_eq!(obj.normals[0], vector(0.0, 0.0, 1.0));
    assert_eq!(obj.normals[1], vector(0.707, 0.0, -0.707));
    assert_eq!(obj.normals[2], vector(1.0, 2.0, 3.0));
}

#[test]
fn faces_with_normals() {
    let obj = parse(
        "v 0 1 0\nv -1 0 0\nv 1 0 0\n\nvn -1 0 0\nvn 1 0 0\nvn 0 1 0\n\n\
         f 1//3 2//1 3//2\nf 1/0/3 2/102/1 3/14/2\n",
    );
    let g = obj.default_group();
    let (t1, t2) = (&g.triangles[0], &g.triangles[1]);
    assert_eq!(t1.vertices, [0, 1, 2]);
    assert_eq!(t1.normals, Some([2, 0, 1]));
    assert_eq!(
        t2, t1,
        "texture indices without texture coordinates are ignored"
    );
}

#[test]
fn negative_indices_count_back_from_the_latest_vertex() {
    let obj = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n");
    assert_eq!(obj.default_group().triangles[0].vertices, [0, 1, 2]);
}

#[test]
fn texture_coordinates_are_kept() {
    let obj = read_obj(&fixture("cube.obj")).unwrap();
    let front = obj.group("front").unwrap();
    assert_eq!(obj.texcoords.len(), 4);
    assert_eq!(front.triangles[0].texcoords, Some([0, 3, 2]));
}

#[test]
fn materials_from_the_library_map_onto_rayforge_materials() {
    let obj = read_obj(&fixture("cube.obj")).unwrap();
    let red = &obj.materials["red"];
    assert_eq!(red.color, color(0.8, 0.1, 0.1));
    assert!((red.specular - 0.3).abs() < 1e-12);
    assert_eq!(red.shininess, 50.0);
    let shiny = &obj.materials["shiny"];
    assert!((shiny.transparency - 0.25).abs() < 1e-12);
    assert_eq!(shiny.refractive_index, 1.5);
    assert!((shiny.reflective - 0.9).abs() < 1e-12, "illum 3 reflects");
    // front (red), back (shiny), sides (red and shiny): four meshes.
    assert_eq!(to_meshes(&obj).len(), 4);
}

#[test]
fn a_face_with_an_out_of_range_index_is_located() {
    let e = parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 7\n", Path::new("bad.obj")).unwrap_err();
    let span = e.span.unwrap();
    assert_eq!((span.line, span.column), (3, 7));
    assert_eq!(e.key.as_deref(), Some("f"));
    assert!(e.message.contains("vertex index 7 is out of range"), "{e}");
}

#[test]
fn a_vertex_with_a_bad_number_is_located() {
    let e = parse_obj("v 0 zero 0\n", Path::new("bad.obj")).unwrap_err();
    let span = e.span.unwrap();
    assert_eq!((span.line, span.column), (1, 5));
    assert!(e.message.contains("expected a number, found `zero`"), "{e}");
}

#[test]
fn a_face_with_two_corners_is_refused() {
    let e = parse_obj("v 0 0 0\nv 1 0 0\nf 1 2\n", Path::new("bad.obj")).unwrap_err();
    assert!(e.message.contains("at least 3 corners"), "{e}");
}

#[test]
fn a_scene_places_an_obj_model_with_its_transform_and_materials() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["cube.obj", "cube.mtl", "tint.ppm", "triangles.obj"] {
        std::fs::copy(fixture(f), dir.path().join(f)).unwrap();
    }
    let scene_path = dir.path().join("scene.yml");
    std::fs::write(
        &scene_path,
        "- add: camera\n  width: 8\n  height: 8\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n\
         - add: obj\n  file: cube.obj\n  transform:\n    - [translate, 0, 2, 0]\n\
         - add: obj\n  file: triangles.obj\n  material:\n    color: [0, 1, 0]\n",
    )
    .unwrap();
    let scene = rayforge_scene::load_file(&scene_path).unwrap();
    assert_eq!(scene.world.objects.len(), 6);
    let cube_front = &scene.world.objects[0];
    assert!(matches!(cube_front.shape, Shape::Mesh(_)));
    assert_eq!(cube_front.material.color, color(0.8, 0.1, 0.1));
    assert!(cube_front
        .transform
        .matrix()
        .abs_diff_eq(rayforge::math::translation(0.0, 2.0, 0.0), 1e-12));
    assert_eq!(scene.world.objects[5].material.color, color(0.0, 1.0, 0.0));
    // The cube renders: a ray down its middle hits its front face at z = -1.
    let r = rayforge::Ray::new(point(0.0, 2.0, -5.0), vector(0.0, 0.0, 1.0));
    let xs = scene.world.intersect(&r);
    assert!((xs[0].t - 4.0).abs() < 1e-9, "{:?}", xs[0].t);
}

#[test]
fn a_missing_obj_file_is_reported_at_the_file_key() {
    let e = rayforge_scene::load_str(
        "- add: obj\n  file: nowhere.obj\n",
        Path::new("/tmp/scene.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("file"));
    assert_eq!(e.span.unwrap().line, 2);
    assert!(e.message.contains("nowhere.obj"), "{e}");
}

#[test]
fn map_kd_multiplies_the_colour_at_the_models_texture_coordinates() {
    let obj = read_obj(&fixture("cube.obj")).unwrap();
    let red = &obj.materials["red"];
    assert!(red.texture.is_some(), "map_Kd is read");
    let dir = tempfile::tempdir().unwrap();
    for f in ["cube.obj", "cube.mtl", "tint.ppm"] {
        std::fs::copy(fixture(f), dir.path().join(f)).unwrap();
    }
    let scene_path = dir.path().join("scene.yml");
    std::fs::write(
        &scene_path,
        "- add: camera\n  width: 8\n  height: 8\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: obj\n  file: cube.obj\n",
    )
    .unwrap();
    let scene = rayforge_scene::load_file(&scene_path).unwrap();
    // Straight at the front face (z = -1), a quarter of the way in from its lower-left corner.
    let r = Ray::new(point(-0.5, -0.5, -5.0), vector(0.0, 0.0, 1.0));
    let xs = scene.world.intersect(&r);
    let h = hit(&xs).unwrap();
    let comps = prepare_computations(h, &r, &xs);
    let (u, v) = comps
        .surface_point
        .uv
        .expect("the front face has texture coordinates");
    assert!(
        (u - 0.25).abs() < 1e-9 && (v - 0.25).abs() < 1e-9,
        "({u}, {v})"
    );
    let c = comps.surface.material.color_at(
        comps.surface,
        comps.point,
        comps.surface_point.uv,
        comps.time,
    );
    let expected = color(128.0 / 255.0 * 0.8, 0.1, 0.1);
    // Images decode to 32-bit floats: compare at that precision.
    assert!((c.red - expected.red).abs() < 1e-6, "{c:?}");
    assert!((c.green - expected.green).abs() < 1e-6, "{c:?}");
}

/// Finding 10: texture-coordinate indices out of range were accepted silently while vertex and
/// normal indices were refused. In a file with texture coordinates they are now checked the
/// same way; "vertexs" is now "vertices".
#[test]
fn obj_texture_coordinate_indices_out_of_range_are_located_errors() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1/1 2/2 3/3\n";
    let e = parse_obj(obj, Path::new("t.obj")).unwrap_err();
    assert_eq!(
        e.message,
        "texture coordinate index 3 is out of range (there are 2 texture coordinates so far)"
    );
    assert_eq!(e.key.as_deref(), Some("f"));
    assert_eq!(e.span.map(|s| (s.line, s.column)), Some((6, 11)));
    let e = parse_obj("v 0 0 0\nf 1 2 3\n", Path::new("t.obj")).unwrap_err();
    assert_eq!(
        e.message,
        "vertex index 2 is out of range (there are 1 vertices so far)"
    );
    let e = parse_obj("v 0 0 0\nvn 0 0 1\nf 1//1 1//2 1//1\n", Path::new("t.obj")).unwrap_err();
    assert!(e.message.contains("there are 1 normals so far"), "{e}");
    // Without any `vt`, texture indices name nothing and are ignored, as the book's are.
    let obj = parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/9 2/0 3/-4\n",
        Path::new("t.obj"),
    )
    .unwrap();
    assert_eq!(obj.default_group().triangles[0].texcoords, None);
}
