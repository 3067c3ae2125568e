//! The path tracer's keys: `emission` and the physical material `type:` (with `metal`, `eta`,
//! `k`, `alpha`, `roughness`, `refractive-index`), and `renderer: path` with its `world:` keys.
mod support;

use rayforge::film::PixelFilter;
use rayforge::options::{
    LightSamplerKind, MirrorBallBudget, PathOptions, Roulette, SampleAllocation, SamplerKind,
    Techniques,
};
use rayforge::shading::bsdf::{metal, Coat, ConductorBase, Layers, METAL_NAMES};
use rayforge::shading::Physical;
use rayforge::{Color, Material};
use rayforge_scene::{Scene, SceneError};
use support::{assert_located, load_after_camera};

/// The material of a sphere whose material mapping holds `lines` (each indented by the caller's
/// four spaces): the first line of the mapping is line 10.
fn material(lines: &str) -> Result<Material, SceneError> {
    let body = format!("- add: sphere\n  material:\n{}", indent(lines));
    load_after_camera(&body).map(|s| s.world.objects[0].material.clone())
}

fn indent(lines: &str) -> String {
    lines.lines().map(|l| format!("    {l}\n")).collect()
}

fn physical(lines: &str) -> Option<Physical> {
    material(lines).expect("the material is read").physical
}

/// The `world:` item holding `lines`: the first is line 9.
fn world(lines: &str) -> Result<Scene, SceneError> {
    load_after_camera(&format!("- world:\n{}", indent(lines)))
}

// Emission.

#[test]
fn emission_is_a_colour_or_one_grey_number_and_black_by_default() {
    let m = material("emission: [4, 2, 0.5]").unwrap();
    assert_eq!(m.emission, Color::new(4.0, 2.0, 0.5));
    assert_eq!(
        material("emission: 3").unwrap().emission,
        Color::new(3.0, 3.0, 3.0)
    );
    assert_eq!(material("emission: 0").unwrap().emission, Color::BLACK);
    assert_eq!(material("color: [1, 0, 0]").unwrap().emission, Color::BLACK);
}

#[test]
fn emission_is_not_negative_nor_text() {
    assert_located(
        material("emission: [1, -1, 1]"),
        10,
        15,
        "emission",
        "negative",
    );
    assert_located(material("emission: -2"), 10, 15, "emission", "negative");
    assert_located(
        material("emission: bright"),
        10,
        15,
        "emission",
        "or one number",
    );
    assert_located(
        material("emission: [1, 1]"),
        10,
        15,
        "emission",
        "3 numbers",
    );
    assert_located(material("emission: .inf"), 10, 15, "emission", "finite");
}

// Material types.

#[test]
fn without_type_a_material_is_the_books() {
    assert_eq!(physical("color: [1, 0, 0]"), None);
    assert_eq!(physical("transparency: 1\nrefractive-index: 0.5"), None);
}

#[test]
fn diffuse_and_mirror_take_nothing_more() {
    assert_eq!(physical("type: diffuse"), Some(Physical::Diffuse));
    assert_eq!(
        physical("type: mirror\ncolor: [0.9, 0.9, 0.9]"),
        Some(Physical::Mirror)
    );
}

#[test]
fn a_conductor_is_polished_aluminium_by_default() {
    let (eta, k) = metal("aluminium").unwrap();
    assert_eq!(
        physical("type: conductor"),
        Some(Physical::Conductor {
            eta,
            k,
            alpha_u: 0.0,
            alpha_v: 0.0
        })
    );
}

#[test]
fn a_conductor_names_its_metal_or_gives_eta_and_k() {
    let (eta, k) = metal("gold").unwrap();
    assert_eq!(
        physical("type: conductor\nmetal: gold\nalpha: 0.2"),
        Some(Physical::Conductor {
            eta,
            k,
            alpha_u: 0.2,
            alpha_v: 0.2
        })
    );
    for name in METAL_NAMES {
        let (eta, k) = metal(name).unwrap();
        assert_eq!(
            physical(&format!("type: conductor\nmetal: {name}")),
            Some(Physical::Conductor {
                eta,
                k,
                alpha_u: 0.0,
                alpha_v: 0.0
            })
        );
    }
    assert_eq!(
        physical("type: conductor\neta: [0.2, 0.4, 1.5]\nk: [3, 2.5, 2]\nroughness: 0.5"),
        Some(Physical::Conductor {
            eta: Color::new(0.2, 0.4, 1.5),
            k: Color::new(3.0, 2.5, 2.0),
            alpha_u: 0.25,
            alpha_v: 0.25
        })
    );
}

#[test]
fn dielectrics_and_plastic_default_to_index_one_and_a_half_and_smooth() {
    assert_eq!(
        physical("type: dielectric"),
        Some(Physical::Dielectric {
            eta: 1.5,
            alpha_u: 0.0,
            alpha_v: 0.0
        })
    );
    assert_eq!(
        physical("type: thin-dielectric"),
        Some(Physical::ThinDielectric { eta: 1.5 })
    );
    assert_eq!(
        physical("type: plastic"),
        Some(Physical::Plastic {
            eta: 1.5,
            alpha: 0.0
        })
    );
}

#[test]
fn dielectrics_and_plastic_take_the_refractive_index_and_a_width() {
    assert_eq!(
        physical("type: dielectric\nrefractive-index: 1.33\nalpha: 0.1"),
        Some(Physical::Dielectric {
            eta: 1.33,
            alpha_u: 0.1,
            alpha_v: 0.1
        })
    );
    assert_eq!(
        physical("type: thin-dielectric\nrefractive-index: 1.2"),
        Some(Physical::ThinDielectric { eta: 1.2 })
    );
    assert_eq!(
        physical("refractive-index: 2\ntype: plastic\nroughness: 0.3"),
        Some(Physical::Plastic {
            eta: 2.0,
            alpha: 0.3 * 0.3
        })
    );
    // The book's keys are read as before beside a type.
    let m = material("type: dielectric\nrefractive-index: 1.33\ntransparency: 0.5").unwrap();
    assert_eq!((m.refractive_index, m.transparency), (1.33, 0.5));
}

#[test]
fn an_unknown_type_lists_the_types() {
    let e = assert_located(
        material("type: metal"),
        10,
        11,
        "type",
        "unknown material type",
    );
    assert!(
        e.message
            .contains("diffuse, conductor, dielectric, thin-dielectric, plastic, mirror"),
        "{e}"
    );
    assert_located(material("type: [1]"), 10, 11, "type", "expected a name");
}

#[test]
fn an_unknown_metal_lists_the_metals() {
    let e = assert_located(
        material("type: conductor\nmetal: unobtainium"),
        11,
        12,
        "metal",
        "unknown metal `unobtainium`",
    );
    assert!(e.message.contains(&METAL_NAMES.join(", ")), "{e}");
}

#[test]
fn keys_of_another_type_are_errors_naming_the_key() {
    assert_located(
        material("type: dielectric\nmetal: gold"),
        11,
        5,
        "metal",
        "does not apply to `type: dielectric`",
    );
    assert_located(
        material("type: plastic\nk: [1, 1, 1]"),
        11,
        5,
        "k",
        "does not apply to `type: plastic`",
    );
    assert_located(
        material("type: thin-dielectric\nalpha: 0.1"),
        11,
        5,
        "alpha",
        "does not apply to `type: thin-dielectric`",
    );
    assert_located(
        material("type: mirror\nroughness: 0.1"),
        11,
        5,
        "roughness",
        "does not apply",
    );
    assert_located(
        material("metal: gold\ntype: diffuse"),
        10,
        5,
        "metal",
        "does not apply to `type: diffuse`",
    );
}

#[test]
fn physical_keys_without_a_type_are_errors() {
    let e = assert_located(material("alpha: 0.1"), 10, 5, "alpha", "add a `type:`");
    assert!(e.message.contains("conductor"), "{e}");
    assert_located(
        material("color: [1, 1, 1]\nmetal: gold"),
        11,
        5,
        "metal",
        "add a `type:`",
    );
    assert_located(material("eta: [1, 1, 1]"), 10, 5, "eta", "add a `type:`");
}

#[test]
fn alpha_and_roughness_together_are_an_error() {
    assert_located(
        material("type: conductor\nalpha: 0.1\nroughness: 0.2"),
        12,
        5,
        "roughness",
        "not both",
    );
    assert_located(
        material("type: dielectric\nroughness: 0.2\nalpha: 0.1"),
        12,
        5,
        "alpha",
        "not both",
    );
}

#[test]
fn alpha_and_roughness_lie_between_zero_and_one() {
    assert_located(
        material("type: conductor\nalpha: 1.5"),
        11,
        12,
        "alpha",
        "between 0",
    );
    assert_located(
        material("type: plastic\nroughness: -0.1"),
        11,
        16,
        "roughness",
        "between 0",
    );
    assert_located(
        material("type: plastic\nalpha: rough"),
        11,
        12,
        "alpha",
        "expected a number",
    );
    assert_eq!(
        physical("type: conductor\nalpha: 1"),
        Some(Physical::Conductor {
            eta: metal("aluminium").unwrap().0,
            k: metal("aluminium").unwrap().1,
            alpha_u: 1.0,
            alpha_v: 1.0
        })
    );
}

#[test]
fn a_conductor_index_is_a_metal_or_eta_and_k_together() {
    assert_located(
        material("type: conductor\neta: [1, 1, 1]"),
        11,
        5,
        "eta",
        "needs `k`",
    );
    assert_located(
        material("type: conductor\nk: [1, 1, 1]"),
        11,
        5,
        "k",
        "needs `eta`",
    );
    assert_located(
        material("type: conductor\nmetal: gold\neta: [1, 1, 1]\nk: [1, 1, 1]"),
        12,
        5,
        "eta",
        "not both",
    );
    assert_located(
        material("type: conductor\neta: [1, 0, 1]\nk: [1, 1, 1]"),
        11,
        10,
        "eta",
        "positive",
    );
    assert_located(
        material("type: conductor\neta: [1, 1, 1]\nk: [1, -1, 1]"),
        12,
        8,
        "k",
        "negative",
    );
    assert_located(
        material("type: conductor\neta: 1\nk: [1, 1, 1]"),
        11,
        10,
        "eta",
        "expected a list",
    );
}

#[test]
fn a_physical_refractive_index_lies_between_one_and_nine() {
    assert_located(
        material("type: dielectric\nrefractive-index: 0.5"),
        11,
        23,
        "refractive-index",
        "between 1 and 9",
    );
    assert_located(
        material("refractive-index: 10\ntype: thin-dielectric"),
        10,
        23,
        "refractive-index",
        "between 1 and 9",
    );
    assert_located(
        material("type: plastic\nrefractive-index: 0.9"),
        11,
        23,
        "refractive-index",
        "between 1 and 9",
    );
}

// Through defines.

const DEFINES: &str = "- define: gold
  value:
    type: conductor
    metal: gold
    emission: 2
- define: brushed-gold
  extend: gold
  value:
    roughness: 0.5
- define: glass
  value:
    type: dielectric
    refractive-index: 1.4
- define: frosted
  extend: glass
  value:
    alpha: 0.3
- define: plain
  extend: glass
  value:
    type: diffuse
";

fn defined(name: &str) -> Material {
    load_after_camera(&format!("{DEFINES}- add: sphere\n  material: {name}\n"))
        .expect("the scene loads")
        .world
        .objects[0]
        .material
        .clone()
}

#[test]
fn defined_materials_carry_the_new_keys_and_extend_them() {
    let (eta, k) = metal("gold").unwrap();
    let gold = defined("gold");
    assert_eq!(
        gold.physical,
        Some(Physical::Conductor {
            eta,
            k,
            alpha_u: 0.0,
            alpha_v: 0.0
        })
    );
    assert_eq!(gold.emission, Color::new(2.0, 2.0, 2.0));
    let brushed = defined("brushed-gold");
    assert_eq!(
        brushed.physical,
        Some(Physical::Conductor {
            eta,
            k,
            alpha_u: 0.25,
            alpha_v: 0.25
        })
    );
    assert_eq!(brushed.emission, Color::new(2.0, 2.0, 2.0));
    assert_eq!(
        defined("frosted").physical,
        Some(Physical::Dielectric {
            eta: 1.4,
            alpha_u: 0.3,
            alpha_v: 0.3
        })
    );
    // Overriding the type keeps the book's refractive index, which a diffuse surface ignores.
    assert_eq!(defined("plain").physical, Some(Physical::Diffuse));
}

#[test]
fn an_extension_must_fit_the_type_it_inherits() {
    // `metal` comes from `gold` (line 11), which `shiny-glass` re-types as a dielectric.
    let e = load_after_camera(&format!(
        "{DEFINES}- define: shiny-glass\n  extend: gold\n  value:\n    type: dielectric\n- add: sphere\n  material: shiny-glass\n"
    ))
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("metal"), "{e}");
    assert_eq!(e.span.unwrap().line, 11, "{e}");
    assert!(
        e.message.contains("does not apply to `type: dielectric`"),
        "{e}"
    );
}

// The `world:` item.

#[test]
fn renderer_path_gives_the_path_tracers_defaults() {
    let scene = world("renderer: path").unwrap();
    assert_eq!(scene.path, Some(PathOptions::default()));
    assert_eq!(
        scene.path.unwrap().max_depth,
        PathOptions::DEFAULT_MAX_DEPTH
    );
    assert_eq!((scene.raster, scene.max_depth), (None, None));
    for other in ["renderer: ray", "renderer: raster", "lighting: phong"] {
        assert_eq!(world(other).unwrap().path, None, "{other}");
    }
    assert_eq!(load_after_camera("").unwrap().path, None);
}

#[test]
fn the_path_tracers_keys_are_read() {
    let scene = world(
        "renderer: path\nsampler: independent\nfilter: tent\nfilter-radius: 2\nseed: 42\nroulette-depth: 5\nmax-depth: 10",
    )
    .unwrap();
    assert_eq!(
        scene.path,
        Some(PathOptions {
            sampler: SamplerKind::Independent,
            filter: PixelFilter::Tent { radius: 2.0 },
            max_depth: 10,
            roulette_depth: 5,
            roulette: Roulette::Learned,
            seed: 42,
            allocation: SampleAllocation::ByNoise,
            light_sampler: LightSamplerKind::Auto,
            techniques: Techniques::default(),
            roulette_predictions: true,
        })
    );
    for (name, kind) in [
        ("uniform", LightSamplerKind::Uniform),
        ("power", LightSamplerKind::Power),
        ("bvh", LightSamplerKind::Bvh),
        ("auto", LightSamplerKind::Auto),
    ] {
        let scene = world(&format!("renderer: path\nlight-sampler: {name}")).unwrap();
        assert_eq!(scene.path.unwrap().light_sampler, kind);
    }
    // `max-depth` is still given to the other renderers' setting too.
    assert_eq!(scene.max_depth, Some(10));
    let path = |lines: &str| {
        world(&format!("renderer: path\n{lines}"))
            .unwrap()
            .path
            .unwrap()
    };
    assert_eq!(path("sampler: sobol").sampler, SamplerKind::Sobol);
    assert_eq!(path("filter: box").filter, PixelFilter::Box);
    assert_eq!(
        path("filter: tent").filter,
        PixelFilter::Tent { radius: 1.5 }
    );
    assert_eq!(
        path("filter: gaussian").filter,
        PixelFilter::Gaussian { radius: 1.5 }
    );
    assert_eq!(
        path("filter-radius: 8\nfilter: gaussian").filter,
        PixelFilter::Gaussian { radius: 8.0 }
    );
    assert_eq!(path("seed: 0").seed, 0);
    assert_eq!(path("seed: 9007199254740992").seed, 1 << 53);
    assert_eq!(path("max-depth: 0").max_depth, 0);
    assert_eq!(path("roulette-depth: 1").roulette_depth, 1);
    assert_eq!(path("roulette-scale: auto").roulette, Roulette::Learned);
    assert_eq!(path("roulette-scale: 1").roulette, Roulette::Scale(1.0));
    assert_eq!(path("roulette-scale: 0.25").roulette, Roulette::Scale(0.25));
    assert_eq!(path("roulette-scale: 64").roulette, Roulette::Scale(64.0));
    assert_eq!(
        path("sample-allocation: by-noise").allocation,
        SampleAllocation::ByNoise
    );
    assert_eq!(
        path("sample-allocation: uniform").allocation,
        SampleAllocation::Uniform
    );
    assert_eq!(path("seed: 1").allocation, SampleAllocation::ByNoise);
    assert!(!path("roulette-predictions: false").roulette_predictions);
    assert!(path("roulette-predictions: true").roulette_predictions);
    assert!(path("seed: 1").roulette_predictions);
}

#[test]
fn the_old_name_of_the_allocation_by_noise_is_read_with_a_warning() {
    let scene = world("renderer: path\nsample-allocation: adaptive").unwrap();
    assert_eq!(scene.path.unwrap().allocation, SampleAllocation::ByNoise);
    let [warning] = &scene.warnings[..] else {
        panic!("one warning, not {:?}", scene.warnings);
    };
    let text = warning.to_string();
    assert!(text.contains("sample-allocation"), "{text}");
    assert!(text.contains("by-noise"), "{text}");
    let quiet = world("renderer: path\nsample-allocation: by-noise").unwrap();
    assert!(quiet.warnings.is_empty(), "{:?}", quiet.warnings);
}

#[test]
fn a_path_scene_may_go_deeper_than_a_ray_traced_one() {
    let deep = world("renderer: path\nmax-depth: 1024").unwrap();
    assert_eq!(deep.path.unwrap().max_depth, 1024);
    assert_located(
        world("max-depth: 65"),
        9,
        16,
        "max-depth",
        "the limit 64 of the ray tracer",
    );
}

#[test]
fn the_path_tracers_keys_need_renderer_path() {
    for key in [
        "sampler: sobol",
        "filter: box",
        "filter-radius: 1",
        "seed: 1",
        "roulette-depth: 2",
        "roulette-scale: 2",
        "sample-allocation: by-noise",
        "roulette-predictions: false",
    ] {
        let name = key.split(':').next().unwrap();
        assert_located(world(key), 9, 5, name, "add `renderer: path`");
        assert_located(
            world(&format!("renderer: raster\n{key}")),
            10,
            5,
            name,
            "applies to the path tracer",
        );
    }
    // And the rasterizer's keys are not the path tracer's.
    assert_located(
        world("renderer: path\nwireframe: true"),
        10,
        5,
        "wireframe",
        "add `renderer: raster`",
    );
}

#[test]
fn an_unknown_renderer_lists_path() {
    assert_located(
        world("renderer: photon"),
        9,
        15,
        "renderer",
        "expected ray, raster or path",
    );
}

#[test]
fn bad_path_tracer_values_are_errors_naming_the_key() {
    let path = |lines: &str| world(&format!("renderer: path\n{lines}"));
    assert_located(
        path("sampler: halton"),
        10,
        14,
        "sampler",
        "sobol or independent",
    );
    assert_located(
        path("filter: mitchell"),
        10,
        13,
        "filter",
        "box, tent or gaussian",
    );
    assert_located(
        path("filter: box\nfilter-radius: 2"),
        11,
        5,
        "filter-radius",
        "box filter has no radius",
    );
    assert_located(
        path("filter-radius: 2"),
        10,
        5,
        "filter-radius",
        "needs `filter: tent`",
    );
    for radius in ["0", "-1", "8.5"] {
        assert_located(
            path(&format!("filter: tent\nfilter-radius: {radius}")),
            11,
            20,
            "filter-radius",
            "at most 8",
        );
    }
    assert_located(path("seed: -1"), 10, 11, "seed", "whole number");
    assert_located(path("seed: 1.5"), 10, 11, "seed", "whole number");
    assert_located(path("seed: 1e20"), 10, 11, "seed", "whole number");
    assert_located(
        path("roulette-depth: 0"),
        10,
        21,
        "roulette-depth",
        "at least 1",
    );
    assert_located(
        path("max-depth: 1025"),
        10,
        16,
        "max-depth",
        "the limit 1024 of the path tracer",
    );
    assert_located(
        path("light-sampler: tree"),
        10,
        20,
        "light-sampler",
        "expected `uniform`, `power`, `bvh` or `auto`, found `tree`",
    );
    assert_located(
        path("roulette-predictions: off"),
        10,
        27,
        "roulette-predictions",
        "expected true or false",
    );
    assert_located(
        path("sample-allocation: even"),
        10,
        24,
        "sample-allocation",
        "expected `by-noise`, `by-noise-trusted` or `uniform`, found `even`",
    );
    for bad in ["0.2", "65", "-1", "nan", "often", "[1, 2]"] {
        assert_located(
            path(&format!("roulette-scale: {bad}")),
            10,
            21,
            "roulette-scale",
            "`auto` or a number from 0.25 to 64",
        );
    }
}

#[test]
fn a_right_handed_camera_puts_forward_cross_up_on_the_image_right() {
    let yaml = "- add: camera\n  width: 11\n  height: 11\n  field-of-view-degrees: 60\n  handedness: right\n  from: [0, 0, 3.9]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n";
    let scene = rayforge_scene::load_str(yaml, std::path::Path::new("camera.yml")).unwrap();
    // Looking down −z with +y up, forward × up is +x: the rightmost pixel looks that way.
    let right = scene.camera.ray_for_pixel(10, 5).direction;
    assert!(right.x > 0.0, "{right:?}");
    let yaml = yaml.replace("handedness: right", "handedness: up");
    let err = rayforge_scene::load_str(&yaml, std::path::Path::new("camera.yml"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("handedness") && err.contains("camera.yml:5:"),
        "{err}"
    );
}

#[test]
fn emission_side_and_two_sided_are_read() {
    let yaml = "- add: cube\n  material:\n    emission: 0.2\n    emission-side: back\n    two-sided: false\n- add: camera\n  width: 2\n  height: 2\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n";
    let scene = rayforge_scene::load_str(yaml, std::path::Path::new("sides.yml")).unwrap();
    let m = &scene.world.objects[0].material;
    assert_eq!(m.emission_side, rayforge::shading::EmissionSide::Back);
    assert!(!m.two_sided);
    let bad = yaml.replace("emission-side: back", "emission-side: inside");
    let err = rayforge_scene::load_str(&bad, std::path::Path::new("sides.yml"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("sides.yml:4:") && err.contains("emission side"),
        "{err}"
    );
}

#[test]
fn the_techniques_are_switched_on_and_off() {
    let on = world("renderer: path").unwrap().path.unwrap().techniques;
    assert_eq!(on, Techniques::default());
    assert!(on.next_event && on.mis && on.roulette && on.glass_split && on.mirror_balls);
    assert!(on.sphere_cones && on.equiangular);
    assert_eq!(on.mirror_ball_budget, MirrorBallBudget::default());
    let off = world(
        "renderer: path\nnext-event: off\nmis: off\nroulette: off\nglass-split: off\nmirror-balls: off\nmirror-ball-cap: 7\nmirror-ball-cull: 0.25\nsphere-cones: off\nequiangular: off\nequiangular-lights: 3",
    )
    .unwrap()
    .path
    .unwrap()
    .techniques;
    assert_eq!(
        off,
        Techniques {
            next_event: false,
            mis: false,
            roulette: false,
            glass_split: false,
            mirror_balls: false,
            mirror_ball_budget: MirrorBallBudget { cap: 7, cull: 0.25 },
            sphere_cones: false,
            equiangular: false,
            equiangular_lights: 3,
        }
    );
    // Each switch on its own, in either spelling.
    for (key, value, get) in [
        (
            "next-event",
            "false",
            (|t: Techniques| t.next_event) as fn(Techniques) -> bool,
        ),
        ("mis", "off", |t| t.mis),
        ("roulette", "off", |t| t.roulette),
        ("glass-split", "false", |t| t.glass_split),
        ("mirror-balls", "off", |t| t.mirror_balls),
        ("sphere-cones", "false", |t| t.sphere_cones),
        ("equiangular", "off", |t| t.equiangular),
    ] {
        let t = world(&format!("renderer: path\n{key}: {value}"))
            .unwrap()
            .path
            .unwrap()
            .techniques;
        assert!(!get(t), "{key}");
        let others = Techniques::default();
        assert_eq!(
            [
                t.next_event,
                t.mis,
                t.roulette,
                t.glass_split,
                t.mirror_balls,
                t.sphere_cones,
                t.equiangular
            ]
            .iter()
            .filter(|on| !**on)
            .count(),
            1,
            "{key}"
        );
        let t = world(&format!("renderer: path\n{key}: on")).unwrap();
        assert_eq!(t.path.unwrap().techniques, others, "{key}");
    }
}

#[test]
fn bad_technique_keys_are_located() {
    let path = |line: &str| world(&format!("renderer: path\n{line}"));
    for key in [
        "next-event",
        "mis",
        "roulette",
        "glass-split",
        "mirror-balls",
        "sphere-cones",
    ] {
        let column = key.len() + 7;
        assert_located(
            path(&format!("{key}: maybe")),
            10,
            column,
            key,
            "expected `on` or `off`, found `maybe`",
        );
        assert_located(
            path(&format!("{key}: 1")),
            10,
            column,
            key,
            "expected `on` or `off`, found the number 1",
        );
        // Another renderer's scene is told what the key belongs to.
        assert_located(
            world(&format!("{key}: off")),
            9,
            5,
            key,
            "applies to the path tracer",
        );
    }
    // The equiangular lights: at least 1, at most the arrays' 16.
    for bad in ["0", "17", "2.5"] {
        assert_located(
            path(&format!("equiangular-lights: {bad}")),
            10,
            25,
            "equiangular-lights",
            if bad == "17" {
                "from 1 to 16"
            } else {
                "at least 1"
            },
        );
    }
    assert_located(
        world("equiangular-lights: 3"),
        9,
        5,
        "equiangular-lights",
        "applies to the path tracer",
    );
    assert_located(
        path("mirror-ball-cap: 0"),
        10,
        22,
        "mirror-ball-cap",
        "at least 1",
    );
    for bad in ["1", "-0.1", "2"] {
        assert_located(
            path(&format!("mirror-ball-cull: {bad}")),
            10,
            23,
            "mirror-ball-cull",
            "from 0 to below 1",
        );
    }
    assert_located(
        path("mirror-ball-cull: many"),
        10,
        23,
        "mirror-ball-cull",
        "number",
    );
    assert_located(
        path("roulette: off\nroulette-scale: 2"),
        11,
        5,
        "roulette-scale",
        "`roulette: off` turns off",
    );
}

#[test]
fn anisotropic_widths_are_read_per_tangent() {
    let (eta, k) = metal("gold").unwrap();
    assert_eq!(
        physical("type: conductor\nmetal: gold\nalpha-u: 0.1\nalpha-v: 0.4"),
        Some(Physical::Conductor {
            eta,
            k,
            alpha_u: 0.1,
            alpha_v: 0.4
        })
    );
    assert_eq!(
        physical("type: dielectric\nroughness-u: 0.5\nroughness-v: 0.2"),
        Some(Physical::Dielectric {
            eta: 1.5,
            alpha_u: 0.25,
            alpha_v: 0.2 * 0.2
        })
    );
    assert_located(
        material("type: conductor\nalpha-u: 0.1"),
        11,
        5,
        "alpha-u",
        "needs `alpha-u` and `alpha-v`",
    );
    assert_located(
        material("type: conductor\nalpha: 0.1\nalpha-v: 0.2"),
        12,
        5,
        "alpha-v",
        "not both",
    );
    assert_located(
        material("type: conductor\nalpha-u: 0.1\nroughness-v: 0.2"),
        12,
        5,
        "roughness-v",
        "one of each kind",
    );
    assert_located(
        material("type: plastic\nalpha-u: 0.1\nalpha-v: 0.1"),
        11,
        5,
        "alpha-u",
        "does not apply",
    );
}

#[test]
fn coated_materials_take_the_layers_with_pbrt_defaults() {
    assert_eq!(
        physical("type: coated-diffuse"),
        Some(Physical::CoatedDiffuse {
            coat: Coat::smooth(1.5),
            layers: Layers::PBRT_DEFAULT
        })
    );
    assert_eq!(
        physical(
            "type: coated-diffuse\nrefractive-index: 1.3\nroughness: 0.5\nthickness: 0.2\n\
             medium-albedo: [0.5, 0.4, 0.3]\nmedium-g: -0.3\nwalk-depth: 20\nwalk-samples: 4"
        ),
        Some(Physical::CoatedDiffuse {
            coat: Coat {
                eta: 1.3,
                alpha_u: 0.25,
                alpha_v: 0.25
            },
            layers: Layers {
                thickness: 0.2,
                albedo: Color::new(0.5, 0.4, 0.3),
                g: -0.3,
                max_depth: 20,
                samples: 4
            }
        })
    );
    let (eta, k) = metal("copper").unwrap();
    assert_eq!(
        physical("type: coated-conductor\nmetal: copper\nalpha: 0.1\nbase-alpha-u: 0.2\nbase-alpha-v: 0.3"),
        Some(Physical::CoatedConductor {
            coat: Coat {
                eta: 1.5,
                alpha_u: 0.1,
                alpha_v: 0.1
            },
            base: ConductorBase {
                eta,
                k,
                alpha_u: 0.2,
                alpha_v: 0.3
            },
            layers: Layers::PBRT_DEFAULT
        })
    );
    assert_located(
        material("type: coated-diffuse\nthickness: 0"),
        11,
        16,
        "thickness",
        "above 0",
    );
    assert_located(
        material("type: coated-diffuse\nmedium-g: 1"),
        11,
        15,
        "medium-g",
        "between -1 and 1",
    );
    assert_located(
        material("type: coated-diffuse\nwalk-depth: 1000"),
        11,
        17,
        "walk-depth",
        "at most",
    );
    assert_located(
        material("type: coated-diffuse\nbase-alpha: 0.1"),
        11,
        5,
        "base-alpha",
        "coated-conductor",
    );
}

#[test]
fn diffuse_transmission_takes_two_shares() {
    assert_eq!(
        physical("type: diffuse-transmission"),
        Some(Physical::DiffuseTransmission {
            reflectance: Color::new(0.25, 0.25, 0.25),
            transmittance: Color::new(0.25, 0.25, 0.25)
        })
    );
    assert_eq!(
        physical("type: diffuse-transmission\nreflectance: 0.5\ntransmittance: [0.1, 0.2, 0.3]"),
        Some(Physical::DiffuseTransmission {
            reflectance: Color::new(0.5, 0.5, 0.5),
            transmittance: Color::new(0.1, 0.2, 0.3)
        })
    );
    assert_located(
        material("type: diffuse-transmission\ntransmittance: 1.5"),
        11,
        20,
        "transmittance",
        "from 0 to 1",
    );
    assert_located(
        material("type: conductor\nreflectance: 0.5"),
        11,
        5,
        "reflectance",
        "diffuse-transmission",
    );
}
