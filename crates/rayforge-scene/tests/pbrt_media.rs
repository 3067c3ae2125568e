//! pbrt-v4's media through the reader: `MakeNamedMedium` (homogeneous, uniformgrid, rgbgrid),
//! `MediumInterface` on shapes (with the `interface` material a boundary only), the camera's
//! medium, and what is refused, each at its place.
use rayforge::media::{Medium, MediumId, MediumInterface};
use rayforge::Color;
use rayforge_scene::{LoadOptions, Scene, SceneError};

fn load_text(text: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    rayforge_scene::load_file_with(&path, &LoadOptions::default())
}

#[track_caller]
fn assert_at(text: &str, line: usize, column: usize, key: &str, part: &str) {
    let e = load_text(text).expect_err("refused");
    let span = e.span.unwrap_or_else(|| panic!("no place: {e}"));
    assert_eq!((span.line, span.column), (line, column), "{e}");
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert!(e.message.contains(part), "`{part}` not in: {e}");
}

#[test]
fn media_interfaces_and_the_camera_medium_are_read() {
    let text = r#"MediumInterface "" "fog"
Camera "perspective"
WorldBegin
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [0.1 0.2 0.3] "rgb sigma_s" [1 1 1] "float scale" 2 "float g" 0.5
MakeNamedMedium "puff" "string type" "uniformgrid" "integer nx" 2 "float density" [1 3] "point3 p0" [-1 -1 -1] "point3 p1" [1 1 1] "rgb sigma_s" [4 4 4] "rgb sigma_a" [0 0 0]
AttributeBegin
  MediumInterface "puff" "fog"
  Material "interface"
  Shape "sphere"
AttributeEnd
AttributeBegin
  MediumInterface "" "fog"
  Material "dielectric"
  Shape "sphere"
AttributeEnd
Shape "sphere"
"#;
    let scene = load_text(text).unwrap_or_else(|e| panic!("{e}"));
    let world = &scene.world;
    assert_eq!(world.media.len(), 2);
    // Ids in the names' order: fog 0, puff 1.
    let (fog, puff) = (Some(MediumId(0)), Some(MediumId(1)));
    let Medium::Homogeneous(m) = world.media.get(MediumId(0)) else {
        panic!("fog is homogeneous")
    };
    assert_eq!(m.sigma_a, Color::new(0.2, 0.4, 0.6));
    assert_eq!(m.sigma_s, Color::new(2.0, 2.0, 2.0));
    assert_eq!(m.phase.g, 0.5);
    let Medium::Grid(g) = world.media.get(MediumId(1)) else {
        panic!("puff is a grid")
    };
    assert_eq!(g.density.size(), [2, 1, 1]);
    assert_eq!(world.camera_medium, fog);
    assert_eq!(
        world.objects[0].media,
        Some(MediumInterface {
            inside: puff,
            outside: fog,
            index_matched: true
        })
    );
    assert_eq!(
        world.objects[1].media,
        Some(MediumInterface {
            inside: None,
            outside: fog,
            index_matched: false
        })
    );
    // The interface before `Camera` is still in force (`WorldBegin` resets the transform only).
    assert_eq!(world.objects[2].media, world.objects[1].media);
    assert!(
        !scene.warnings.iter().any(|w| w.message.contains("media")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn an_interface_that_separates_nothing_is_not_there() {
    // pbrt-v4 skips an `interface` surface (and its shadow rays do, in `volpath`): without a
    // `MediumInterface`, or with the same medium on both sides, it changes nothing for any
    // ray, and is left out; its area light is ignored, with pbrt's warning. `none` and an
    // empty name are read as `interface`, as pbrt-v4 reads them.
    let text = r#"Camera "perspective"
WorldBegin
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_s" [1 1 1] "rgb sigma_a" [0 0 0]
Material "interface"
Shape "sphere"
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Shape "sphere" "float radius" 2
AttributeEnd
AttributeBegin
  MediumInterface "fog" "fog"
  Shape "sphere" "float radius" 3
AttributeEnd
Material "none"
Shape "sphere" "float radius" 4
AttributeBegin
  MediumInterface "fog" ""
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Shape "sphere" "float radius" 5
AttributeEnd
Material "diffuse"
Shape "sphere" "float radius" 6
"#;
    let scene = load_text(text).unwrap_or_else(|e| panic!("{e}"));
    let world = &scene.world;
    assert_eq!(world.objects.len(), 2, "{:?}", world.objects.len());
    // The boundary of the fog (its light ignored), then the diffuse ball.
    assert_eq!(
        world.objects[0].media,
        Some(MediumInterface {
            inside: Some(MediumId(0)),
            outside: None,
            index_matched: true
        })
    );
    assert_eq!(world.objects[0].material.emission, Color::BLACK);
    assert_eq!(world.objects[1].media, None);
    let ignored = scene
        .warnings
        .iter()
        .filter(|w| w.message.contains("\"interface\" material gives no light"))
        .count();
    assert_eq!(ignored, 2, "{:?}", scene.warnings);
}

#[test]
fn measured_presets_and_pbrts_defaults_give_the_coefficients() {
    // `preset` in place of `sigma_a` and `sigma_s` (which are then not read), times `scale`;
    // without either, pbrt-v4's 1.
    let text = r#"Camera "perspective"
WorldBegin
MakeNamedMedium "a" "string type" "homogeneous" "string preset" "Ketchup" "float scale" 10 "rgb sigma_a" [5 5 5]
MakeNamedMedium "b" "string type" "homogeneous"
MakeNamedMedium "c" "string type" "homogeneous" "string preset" "Pacific Ocean Surface Water"
"#;
    let scene = load_text(text).unwrap_or_else(|e| panic!("{e}"));
    let coefficients = |i: u32| match scene.world.media.get(MediumId(i)) {
        Medium::Homogeneous(m) => (m.sigma_a, m.sigma_s),
        _ => panic!("homogeneous"),
    };
    let (a, s) = coefficients(0);
    let close = |x: Color, y: Color| (x - y).to_array().iter().all(|d| d.abs() < 1e-12);
    assert!(close(a, Color::new(0.61, 9.7, 14.5)), "{a:?}");
    assert!(close(s, Color::new(1.8, 0.7, 0.3)), "{s:?}");
    assert_eq!(coefficients(1), (Color::WHITE, Color::WHITE));
    assert_eq!(coefficients(2).0, Color::new(0.031845, 0.031324, 0.030147));
    // The `sigma_a` the preset replaces is reported unread, as pbrt-v4 would.
    assert!(
        scene.warnings.iter().any(|w| w.message.contains("sigma_a")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn a_grid_glows_by_le_and_lescale_or_by_temperature() {
    // pbrt-v4's grid emission: `Le` times the grid `Lescale`, or a blackbody (1 at its peak)
    // at `(temperature − temperatureoffset) × temperaturescale`, none at or below 100 K.
    let text = r#"Camera "perspective"
WorldBegin
MakeNamedMedium "a" "string type" "uniformgrid" "integer nx" 2 "float density" [1 1] "rgb Le" [1 0.5 0.25] "float Lescale" [0 4]
MakeNamedMedium "b" "string type" "uniformgrid" "integer nx" 2 "float density" [1 1] "float temperature" [150 2000] "float temperatureoffset" 100 "float temperaturescale" 2
MakeNamedMedium "c" "string type" "uniformgrid" "float density" [1] "rgb Le" [0.5 0.5 0.5]
"#;
    let scene = load_text(text).unwrap_or_else(|e| panic!("{e}"));
    let grid = |i: u32| match scene.world.media.get(MediumId(i)) {
        Medium::Grid(g) => g.clone(),
        _ => panic!("a grid"),
    };
    let at = |i: u32, x: f64| grid(i).coefficients_at(glam::DVec3::new(x, 0.5, 0.5)).2;
    assert_eq!(at(0, 0.25), Color::BLACK);
    assert_eq!(at(0, 0.75), Color::new(4.0, 2.0, 1.0));
    // 100 K (at the cut-off) gives nothing; 3800 K glows orange: red over green over blue.
    assert_eq!(at(1, 0.25), Color::BLACK);
    let hot = at(1, 0.75);
    assert!(
        hot.red > hot.green && hot.green > hot.blue && hot.blue > 0.0,
        "{hot:?}"
    );
    assert!(hot.red < 2.0, "normalised at its peak: {hot:?}");
    assert!(grid(0).emits() && grid(1).emits());
    assert_eq!(at(2, 0.5), Color::new(0.5, 0.5, 0.5));
}

#[test]
fn an_rgb_grid_reads_its_colours_per_sample_and_one_where_absent() {
    // pbrt-v4's RGBGridMedium: σa and σs grids of colours times `scale` (either may be absent,
    // then 1), `Le` a grid of colours times `Lescale`.
    let text = r#"Camera "perspective"
WorldBegin
MakeNamedMedium "a" "string type" "rgbgrid" "integer nx" 2 "rgb sigma_a" [1 2 3 0 0 4] "rgb sigma_s" [0 1 0 2 2 2] "float scale" 3 "rgb Le" [0 0 0 1 0.5 0.25] "float Lescale" 2 "float g" 0.3
MakeNamedMedium "b" "string type" "rgbgrid" "rgb sigma_s" [0.5 0.25 1] "point3 p0" [-1 -1 -1] "point3 p1" [1 1 1]
"#;
    let scene = load_text(text).unwrap_or_else(|e| panic!("{e}"));
    let grid = |i: u32| match scene.world.media.get(MediumId(i)) {
        Medium::Grid(g) => g.clone(),
        _ => panic!("a grid"),
    };
    let at = |i: u32, x: f64| grid(i).coefficients_at(glam::DVec3::new(x, 0.5, 0.5));
    assert_eq!(
        at(0, 0.25),
        (
            Color::new(3.0, 6.0, 9.0),
            Color::new(0.0, 3.0, 0.0),
            Color::BLACK
        )
    );
    assert_eq!(
        at(0, 0.75),
        (
            Color::new(0.0, 0.0, 12.0),
            Color::new(6.0, 6.0, 6.0),
            Color::new(2.0, 1.0, 0.5)
        )
    );
    assert_eq!(grid(0).phase.g, 0.3);
    assert!(grid(0).emits() && !grid(1).emits());
    // No σa: 1 throughout, as pbrt-v4.
    assert_eq!(
        at(1, 0.5),
        (Color::WHITE, Color::new(0.5, 0.25, 1.0), Color::BLACK)
    );
    // The majorants bound the colours' largest channels: σa's 4 and σs's 2 at the second
    // sample, times the scale.
    assert!(grid(0).density.max_value() * grid(0).sigma_s.red >= 18.0 - 1e-9);
}

#[test]
fn what_is_not_rendered_is_refused_at_its_place() {
    let head = "Camera \"perspective\"\nWorldBegin\n";
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"smoke\"\n"),
        3,
        1,
        "MakeNamedMedium",
        "homogeneous, uniformgrid, rgbgrid and cloud",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"cloud\" \"float wispiness\" -1\n"),
        3,
        43,
        "float wispiness",
        "a cloud's `wispiness` is finite and at least 0, found -1",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"cloud\" \"point3 p0\" [0 0 0] \"point3 p1\" [1 0 1]\n"),
        3,
        1,
        "MakeNamedMedium",
        "bounds must have a positive, finite extent",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" \"Skin3\"\n"),
        3,
        49,
        "string preset",
        "no measured medium is named \"Skin3\"; pbrt-v4's are: Apple, Chicken1",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"smoke.nvdb\"\n"),
        3,
        1,
        "MakeNamedMedium",
        "NanoVDB files",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1] \"rgb Le\" [1 1 1] \"float temperature\" [900]\n"),
        3,
        69,
        "rgb Le",
        "`Le` or `temperature`, not both",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [1 1] \"float Lescale\" [1]\n"),
        3,
        86,
        "float Lescale",
        "takes 2 values, found 1",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"float scale\" 2\n"),
        3,
        1,
        "MakeNamedMedium",
        "needs `\"rgb sigma_a\"`, `\"rgb sigma_s\"` or both",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_s\" [1 1 1] \"rgb Le\" [1 1 1]\n"),
        3,
        1,
        "MakeNamedMedium",
        "giving `Le` needs",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"rgb sigma_a\" [1 1 1]\n"),
        3,
        60,
        "rgb sigma_a",
        "takes 2 colours, found 1",
    );
    assert_at(
        &format!("{head}MediumInterface \"smoke\" \"\"\nShape \"sphere\"\n"),
        3,
        1,
        "MediumInterface",
        "no medium is named \"smoke\"",
    );
    assert_at(
        &format!("{head}MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [1]\n"),
        3,
        64,
        "float density",
        "holds 2 values, found 1",
    );
}

#[test]
fn a_cloud_is_read_with_pbrts_defaults_and_placed_by_the_transform() {
    let text = r#"Camera "perspective"
WorldBegin
AttributeBegin
  Translate 0 2 0
  Scale 2 2 2
  MakeNamedMedium "sky" "string type" "cloud" "rgb sigma_s" [2 3 4] "float density" 3 "float frequency" 2 "float g" 0.4 "point3 p0" [-1 0 -1] "point3 p1" [1 1 1] "float scale" 7
AttributeEnd
MakeNamedMedium "plain" "string type" "cloud"
"#;
    let scene = load_text(text).unwrap_or_else(|e| panic!("{e}"));
    let warnings = &scene.warnings;
    let cloud = |id: u32| match scene.world.media.get(MediumId(id)) {
        Medium::Cloud(c) => c.clone(),
        other => panic!("not a cloud: {other:?}"),
    };
    // Ids in the names' order: plain 0, sky 1.
    let (plain, sky) = (cloud(0), cloud(1));
    assert_eq!(
        (plain.density, plain.wispiness, plain.frequency),
        (1.0, 1.0, 5.0)
    );
    assert_eq!((plain.sigma_a, plain.sigma_s), (Color::WHITE, Color::WHITE));
    assert_eq!(plain.phase.g, 0.0);
    assert_eq!((sky.density, sky.wispiness, sky.frequency), (3.0, 1.0, 2.0));
    assert_eq!(sky.sigma_s, Color::new(2.0, 3.0, 4.0));
    assert_eq!(sky.phase.g, 0.4);
    // The box's bottom face (y = 0 in the medium) lies at world y = 2, where the density is 1;
    // the box reaches x = ±2 in the world and no further.
    let at = |x: f64, y: f64, z: f64| sky.coefficients_at(glam::DVec3::new(x, y, z)).1;
    assert_eq!(at(1.9, 2.0, -1.9), Color::new(2.0, 3.0, 4.0));
    assert_eq!(at(2.1, 2.0, 0.0), Color::BLACK);
    // pbrt-v4 reads no `scale` for a cloud: it is warned about, not applied.
    assert!(
        warnings
            .iter()
            .any(|w| w.to_string().contains("scale") && w.span.map(|s| s.line) == Some(6)),
        "{warnings:?}"
    );
}

#[test]
fn a_medium_too_dense_to_track_is_refused_at_its_directive() {
    // A cloud of σs 10¹² over a box of diagonal 2√3 · 10: tracking one ray through it would
    // take some 10¹³ steps.
    let text = r#"Camera "perspective"
WorldBegin
Scale 10 10 10
MakeNamedMedium "thick" "string type" "cloud" "rgb sigma_s" [1e12 1e12 1e12] "point3 p0" [-1 -1 -1] "point3 p1" [1 1 1]
"#;
    assert_at(text, 4, 1, "MakeNamedMedium", "--max-optical-depth");
}
