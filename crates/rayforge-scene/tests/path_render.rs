//! The path tracer behind every scene file: each scene shipped under `scenes/` (the media
//! scenes of `scenes/pbr/media/` among them) renders under it (tiny, a few samples) with every
//! sample finite (none left out by the renderer), and the reference scenes of `scenes/pbr/` give
//! the answers they are built to give.

mod support;

use rayforge::film::Film;
use rayforge::options::PathOptions;
use rayforge_scene::Scene;
use std::path::{Path, PathBuf};
use support::{path_scene_head, render, render_counted};

/// The scenes shipped in the repository (those reading models from `../shared`, which a fresh
/// clone lacks, are left out when it is missing).
fn shipped_scenes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut scenes: Vec<PathBuf> = walkdir::WalkDir::new(root)
        .into_iter()
        .filter_map(Result::ok)
        .map(|e| e.into_path())
        .filter(|p| p.extension().is_some_and(|e| e == "yml"))
        .collect();
    scenes.sort();
    scenes
}

#[test]
fn every_shipped_scene_renders_under_the_path_tracer() {
    let (mut rendered, mut media) = (0, 0);
    for path in shipped_scenes() {
        // A scene reading the models beside the repository says, in its usage line, that it
        // needs `--allow-outside`; every other scene keeps to its folder.
        let options = rayforge_scene::LoadOptions {
            allow_outside: std::fs::read_to_string(&path)
                .unwrap()
                .contains("--allow-outside"),
            ..Default::default()
        };
        let scene = match rayforge_scene::load_file_with(&path, &options) {
            Ok(scene) => scene,
            // Only the scenes reading the models beside the repository may fail to load.
            Err(e) if options.allow_outside && e.to_string().contains("shared") => continue,
            Err(e) => panic!("{}: {e}", path.display()),
        };
        // The renderer leaves a non-finite sample out of its pixel and counts it: the count
        // must be nought, and the pixels finite (a pixel left with no weight would not be).
        let (film, stats) = render_counted(&scene, 6, 4, 2);
        assert_eq!(
            stats.discarded,
            0,
            "{}: {} of {} samples were not finite",
            path.display(),
            stats.discarded,
            stats.samples
        );
        for c in film.resolve().pixels() {
            assert!(
                c.red.is_finite() && c.green.is_finite() && c.blue.is_finite(),
                "{}: {c:?}",
                path.display()
            );
        }
        rendered += 1;
        media += usize::from(path.parent().is_some_and(|p| p.ends_with("pbr/media")));
    }
    assert!(rendered >= 50, "only {rendered} scenes rendered");
    // The media scenes among them: the Cornell box's, the sunbeam, the smoke grid, the glass
    // of liquid, the wax and the cloud.
    assert!(
        media >= 6,
        "only {media} scenes of scenes/pbr/media rendered"
    );
}

fn reference(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/pbr")
        .join(format!("{name}.yml"));
    rayforge_scene::load_file(&path).unwrap()
}

#[test]
fn the_reference_scenes_ask_for_the_path_tracer_with_a_box_filter() {
    for name in [
        "furnace",
        "furnace-closed",
        "cornell",
        "spheres-materials",
        "envmap",
    ] {
        let scene = reference(name);
        let options = scene.path.expect("renderer: path");
        assert_eq!(options.filter, rayforge::film::PixelFilter::Box, "{name}");
        assert_eq!(options.max_depth, PathOptions::DEFAULT_MAX_DEPTH, "{name}");
    }
    let envmap = reference("envmap");
    let sky = envmap.world.environment.as_ref().expect("the sky map");
    assert_eq!((sky.width(), sky.height()), (64, 32));
}

#[test]
fn the_closed_furnace_is_one_everywhere() {
    // 0.2 / (1 − 0.8) = 1 in every pixel. Russian roulette makes single samples noisy here
    // (paths are long: each carries 0.8 of the last), so the test takes the image's mean, 4096
    // samples, and bounds each pixel's loosely.
    let canvas = render(&reference("furnace-closed"), 4, 4, 256).resolve();
    let mean = canvas.pixels().iter().map(|c| c.red).sum::<f64>() / 16.0;
    assert!((mean - 1.0).abs() < 0.02, "mean {mean}");
    for c in canvas.pixels() {
        assert!((c.red - 1.0).abs() < 0.15, "{c:?}");
        assert_eq!((c.red, c.red), (c.green, c.blue));
    }
}

#[test]
fn the_furnace_sphere_shows_its_albedo_and_the_sky_is_one() {
    let canvas = render(&reference("furnace"), 9, 9, 16).resolve();
    // The corner sees the sky alone; the centre the sphere, which sees the sky alone.
    assert_eq!(canvas.pixel_at(0, 0).red, 1.0);
    assert!((canvas.pixel_at(4, 4).red - 0.8).abs() < 1e-9);
}

/// A metal sphere and a glass one on a floor under a sky, their `roughness` and
/// `refractive-index` written as `rough` and `index` (numbers or pattern mappings).
fn textured_scene(rough: &str, index: &str) -> Scene {
    let head = path_scene_head(12, 8, 1.0, [0.0, 1.5, -5.0], [0.0, 0.5, 0.0]);
    let text = format!(
        "{head}    background: [0.8, 0.9, 1.0]
- add: plane
  material: {{ type: diffuse, color: [0.5, 0.5, 0.5] }}
- add: sphere
  transform: [[translate, -1.1, 1, 0]]
  material:
    type: conductor
    metal: gold
    roughness: {rough}
- add: sphere
  transform: [[translate, 1.1, 1, 0]]
  material:
    type: dielectric
    roughness: 0.2
    refractive-index: {index}
"
    );
    rayforge_scene::load_str(&text, Path::new("scene.yml")).unwrap()
}

/// Every bit of a film.
fn bits(film: &Film) -> Vec<u64> {
    film.sums()
        .iter()
        .flat_map(|c| [c.red, c.green, c.blue])
        .chain(film.weights().iter().copied())
        .map(f64::to_bits)
        .collect()
}

#[test]
fn patterns_drive_roughness_and_index_as_numbers_would() {
    // A pattern of one grey everywhere is the number: the same image, to the bit.
    let uniform =
        |v: f64| format!("{{ type: stripes, colors: [[{v}, {v}, {v}], [{v}, {v}, {v}]] }}");
    let numbers = render(&textured_scene("0.5", "1.5"), 12, 8, 4);
    let patterns = render(&textured_scene(&uniform(0.5), &uniform(1.5)), 12, 8, 4);
    assert_eq!(bits(&numbers), bits(&patterns));
    // And a pattern that varies does vary the surface: stripes of polished and rough gold.
    let striped = textured_scene("{ type: stripes, colors: [[0, 0, 0], [1, 1, 1]] }", "1.5");
    let gold = &striped.world.objects[1];
    let at = |x: f64| match gold
        .material
        .physical_at(|| rayforge::point(x, 0.0, 0.0))
        .unwrap()
    {
        rayforge::shading::Physical::Conductor { alpha_u, .. } => alpha_u,
        other => panic!("{other:?}"),
    };
    assert_eq!((at(0.5), at(1.5)), (0.0, 1.0));
    assert_ne!(bits(&render(&striped, 12, 8, 4)), bits(&numbers));
}

#[test]
fn a_pattern_of_indices_needs_a_physical_material() {
    let e = rayforge_scene::load_str(
        "- add: sphere\n  material:\n    refractive-index: { type: stripes, colors: [[1, 1, 1], [2, 2, 2]] }\n",
        Path::new("scene.yml"),
    )
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("refractive-index"));
    assert!(e.message.contains("type: dielectric"), "{e}");
}
