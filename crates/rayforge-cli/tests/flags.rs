//! One meaning per flag across renderers: limits are those of the renderer that draws the
//! scene (the scene's own `renderer:` counts), a flag for a technique the renderer lacks is
//! refused, a guard it cannot exceed is ignored with a warning, the two adaptive features have
//! names of their own, `--spp N` is N samples per pixel in the ray tracer and the path
//! tracer alike, and a warning that holds for every frame of `--frames` is said once.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A camera looking at nothing: every camera ray misses, so the rays counted are the camera's.
const EMPTY: &str = "
- add: camera
  width: 3
  height: 2
  field-of-view: 0.8
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

/// The scene's own choice of renderer.
fn choosing(renderer: &str) -> String {
    format!("{EMPTY}- world:\n    renderer: {renderer}\n")
}

struct Dir(tempfile::TempDir);

impl Dir {
    fn new() -> Self {
        Dir(tempfile::tempdir().unwrap())
    }

    fn file(&self, name: &str, text: &str) -> PathBuf {
        let path = self.0.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }
}

fn render(scene: &Path, out: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .args(args)
        .output()
        .expect("runs rayforge")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Renders and expects success; returns stderr.
#[track_caller]
fn accepted(scene: &Path, out: &Path, args: &[&str]) -> String {
    let o = render(scene, out, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    assert!(out.exists(), "{args:?} wrote no image");
    stderr(&o)
}

/// Renders and expects a usage error (exit 2) that says each of `words`; nothing written.
#[track_caller]
fn refused(scene: &Path, out: &Path, args: &[&str], words: &[&str]) {
    let o = render(scene, out, args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: `{w}` not in: {err}");
    }
    assert!(!out.exists(), "{args:?} wrote an image");
}

#[test]
fn a_scene_that_selects_the_path_tracer_takes_the_path_tracers_sample_limit() {
    let d = Dir::new();
    let path = d.file("path.yml", &choosing("path"));
    let err = accepted(&path, &d.path("a.pfm"), &["--spp", "8192"]);
    assert!(err.contains("at 8192 spp"), "{err}");
    // Past the path tracer's own limit, the refusal names the flag, value, limit, renderer.
    refused(
        &path,
        &d.path("b.pfm"),
        &["--spp", "2000000"],
        &[
            "--spp 2000000",
            "more than 1048576",
            "the path tracer (the scene's `renderer: path`)",
        ],
    );
    // The same count on the ray tracer, the default or the command line's choice.
    let ray = d.file("ray.yml", EMPTY);
    refused(
        &ray,
        &d.path("c.pfm"),
        &["--spp", "8192"],
        &[
            "--spp 8192",
            "more than 4096",
            "the ray tracer (the default renderer)",
            "the path tracer's limit is 1048576",
        ],
    );
    refused(
        &path,
        &d.path("d.pfm"),
        &["--spp", "8192", "--renderer", "ray"],
        &[
            "--spp 8192",
            "more than 4096",
            "the ray tracer (--renderer ray)",
        ],
    );
    refused(
        &path,
        &d.path("e.pfm"),
        &["--spp", "0"],
        &["--spp must be at least 1"],
    );
}

/// `EMPTY` with the camera's `samples: N`, and the scene's own renderer when given.
fn sampled(samples: u32, renderer: Option<&str>) -> String {
    let camera = EMPTY.replace(
        "  up: [0, 1, 0]",
        &format!("  up: [0, 1, 0]\n  samples: {samples}"),
    );
    match renderer {
        Some(r) => format!("{camera}- world:\n    renderer: {r}\n"),
        None => camera,
    }
}

#[test]
fn the_cameras_samples_take_the_limit_of_the_renderer_that_draws_the_scene() {
    let d = Dir::new();
    // Past the ray tracer's 4096, the path tracer's scene takes them...
    let path = d.file("path.yml", &sampled(8192, Some("path")));
    let err = accepted(&path, &d.path("a.pfm"), &["-q"]);
    assert!(err.is_empty(), "{err}");
    let err = accepted(&path, &d.path("b.pfm"), &[]);
    assert!(err.contains("at 8192 spp"), "{err}");
    // ...and the ray tracer refuses them, the command line's choice or the scene's, at the
    // key (file, line 9, column 12), naming the renderer and the limits.
    refused(
        &path,
        &d.path("c.pfm"),
        &["--renderer", "ray"],
        &[
            "path.yml:9:12: `samples`: 8192 samples per pixel is more than 4096",
            "the ray tracer (--renderer ray)",
            "the path tracer's limit is 1048576",
        ],
    );
    let ray = d.file("ray.yml", &sampled(8192, None));
    refused(
        &ray,
        &d.path("d.pfm"),
        &[],
        &[
            "ray.yml:9:12: `samples`",
            "more than 4096, the most the ray tracer (the default renderer) takes",
        ],
    );
    // The command line's path tracer takes the ray-traced scene's count; `--spp` replaces it.
    let err = accepted(&ray, &d.path("e.pfm"), &["--renderer", "path"]);
    assert!(err.contains("at 8192 spp"), "{err}");
    accepted(&ray, &d.path("f.pfm"), &["--spp", "2", "-q"]);
    // At the limit, the ray tracer takes it; past the path tracer's, the reader refuses.
    let most = d.file("most.yml", &sampled(4096, None));
    let err = accepted(&most, &d.path("g.pfm"), &["--width", "1", "--height", "1"]);
    assert!(!err.contains("error"), "{err}");
    let past = d.file("past.yml", &sampled((1 << 20) + 1, Some("path")));
    refused(
        &past,
        &d.path("h.pfm"),
        &[],
        &[
            "past.yml:9:12: `samples`: 1048577 samples per pixel is more than 1048576, the most \
             the path tracer takes",
        ],
    );
}

#[test]
fn the_depth_limit_is_the_renderers() {
    let d = Dir::new();
    let path = d.file("path.yml", &choosing("path"));
    let ray = d.file("ray.yml", EMPTY);
    accepted(&path, &d.path("a.pfm"), &["--max-depth", "1024", "-q"]);
    accepted(&ray, &d.path("b.pfm"), &["--max-depth", "64", "-q"]);
    refused(
        &ray,
        &d.path("c.pfm"),
        &["--max-depth", "100"],
        &[
            "--max-depth 100",
            "more than 64",
            "the ray tracer (the default renderer)",
            "the path tracer's limit is 1024",
        ],
    );
    accepted(
        &ray,
        &d.path("d.pfm"),
        &["--max-depth", "100", "--renderer", "path", "-q"],
    );
    refused(
        &path,
        &d.path("e.pfm"),
        &["--max-depth", "2000"],
        &[
            "--max-depth 2000",
            "more than 1024",
            "the path tracer (the scene's `renderer: path`)",
        ],
    );
}

#[test]
fn a_whitted_scene_refuses_the_path_tracers_flags_and_a_path_scene_the_ray_tracers() {
    let d = Dir::new();
    let ray = d.file("ray.yml", EMPTY);
    for flag in [
        &["--seed", "3"][..],
        &["--sample-allocation", "uniform"],
        &["--roulette-scale", "2"],
    ] {
        refused(
            &ray,
            &d.path("a.pfm"),
            flag,
            &[flag[0], "applies to the path tracer"],
        );
    }
    let path = d.file("path.yml", &choosing("path"));
    for (flag, value) in [
        ("--bailout", "0.1"),
        ("--adaptive-aa", "0.1"),
        ("--subsample", "0.1"),
        ("--trace-pixel", "1,1"),
    ] {
        refused(
            &path,
            &d.path("b.pfm"),
            &[flag, value],
            &[
                &format!("{flag} applies to the ray tracer, not to the path tracer (the scene's `renderer: path`)"),
            ],
        );
    }
    refused(
        &path,
        &d.path("c.pfm"),
        &["--bailout", "0"],
        &["Russian roulette (--roulette-scale)"],
    );
    // The rasterizer traces no rays: the ray tracer's techniques are refused there too.
    let raster = d.file("raster.yml", &choosing("raster"));
    for (flag, value) in [
        ("--bailout", "0.1"),
        ("--subsample", "0.1"),
        ("--trace-pixel", "0,0"),
    ] {
        refused(
            &raster,
            &d.path("d.png"),
            &[flag, value],
            &[&format!("{flag} applies to the ray tracer, not to the rasterizer (the scene's `renderer: raster`)")],
        );
    }
    refused(
        &raster,
        &d.path("e.png"),
        &["--spp", "4"],
        &["the rasterizer does not anti-alias"],
    );
    // The ray tracer takes all of them.
    accepted(
        &ray,
        &d.path("f.pfm"),
        &["--bailout", "0.1", "--subsample", "0.1", "-q"],
    );
}

#[test]
fn guards_a_renderer_cannot_exceed_are_ignored_with_a_warning() {
    let d = Dir::new();
    let path = d.file("path.yml", &choosing("path"));
    let err = accepted(&path, &d.path("a.pfm"), &["--max-rays-per-sample", "1000"]);
    assert!(
        err.contains(
            "warning: --max-rays-per-sample is ignored: the path tracer (the scene's `renderer: \
             path`) follows one path a sample"
        ),
        "{err}"
    );
    let err = accepted(&path, &d.path("b.pfm"), &["--max-raster-triangles", "1000"]);
    assert!(
        err.contains("warning: --max-raster-triangles is ignored: the path tracer"),
        "{err}"
    );
    let raster = d.file("raster.yml", &choosing("raster"));
    let err = accepted(
        &raster,
        &d.path("c.png"),
        &["--max-depth", "3", "--max-rays-per-sample", "9"],
    );
    for expected in [
        "warning: --max-depth is ignored: the rasterizer (the scene's `renderer: raster`) follows no reflections or refractions",
        "warning: --max-rays-per-sample is ignored: the rasterizer (the scene's `renderer: raster`) traces no rays",
    ] {
        assert!(err.contains(expected), "{expected}: {err}");
    }
    // --quiet prints nothing but errors; the ray tracer uses the guard and says nothing.
    let err = accepted(&raster, &d.path("d.png"), &["--max-depth", "3", "-q"]);
    assert!(err.is_empty(), "{err}");
    let ray = d.file("ray.yml", EMPTY);
    let err = accepted(&ray, &d.path("e.pfm"), &["--max-rays-per-sample", "1000"]);
    assert!(!err.contains("warning"), "{err}");
}

#[test]
fn a_warning_that_holds_for_every_frame_is_said_once() {
    let d = Dir::new();
    // A guard the path tracer ignores, and a key the scene reads by its old name.
    let scene = d.file(
        "frames.yml",
        &format!("{}    sample-allocation: adaptive\n", choosing("path")),
    );
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(d.path("f-%02d.pfm"))
        .args([
            "--frames",
            "0..2",
            "--spp",
            "1",
            "--max-rays-per-sample",
            "9",
        ])
        .output()
        .unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    for frame in ["f-00.pfm", "f-01.pfm", "f-02.pfm"] {
        assert!(d.path(frame).exists(), "{frame}: {err}");
    }
    assert_eq!(err.matches("path traced").count(), 3, "{err}");
    for warning in [
        "warning: --max-rays-per-sample is ignored",
        "old name of `by-noise`",
    ] {
        assert_eq!(err.matches(warning).count(), 1, "{warning}: {err}");
    }
}

/// The camera rays of an image of the empty scene, from the ray tracer's summary.
fn rays_in(summary: &str) -> &str {
    let start = summary.find('(').expect("a ray count") + 1;
    let end = summary[start..].find(" rays)").expect("a ray count") + start;
    &summary[start..end]
}

#[test]
fn spp_is_the_samples_per_pixel_for_both_renderers() {
    let d = Dir::new();
    let ray = d.file("ray.yml", EMPTY);
    // 3 × 2 pixels, every camera ray a miss: the rays are the samples.
    for (spp, rays) in [("5", "30"), ("4", "24"), ("7", "42"), ("1", "6")] {
        let err = accepted(&ray, &d.path(&format!("r{spp}.pfm")), &["--spp", spp]);
        assert_eq!(rays_in(&err), rays, "--spp {spp}: {err}");
    }
    let path = d.file("path.yml", &choosing("path"));
    let err = accepted(&path, &d.path("p.pfm"), &["--spp", "5"]);
    assert!(err.contains("at 5 spp"), "{err}");
    // The camera's `samples` means the same.
    let five = d.file(
        "five.yml",
        &EMPTY.replace("  up: [0, 1, 0]", "  up: [0, 1, 0]\n  samples: 5"),
    );
    let err = accepted(&five, &d.path("s.pfm"), &[]);
    assert_eq!(rays_in(&err), "30", "{err}");
}

#[test]
fn spp_and_the_scenes_samples_give_the_same_image() {
    // A scene with edges, so that where the rays go shows in the pixels.
    let d = Dir::new();
    let sphere = format!(
        "{EMPTY}- add: light\n  at: [-10, 10, -10]\n  intensity: [1, 1, 1]\n- add: sphere\n  material:\n    color: [1, 0, 0]\n"
    );
    for n in ["5", "9"] {
        let by_scene = d.file(
            &format!("s{n}.yml"),
            &sphere.replace(
                "  up: [0, 1, 0]",
                &format!("  up: [0, 1, 0]\n  samples: {n}"),
            ),
        );
        let plain = d.file(&format!("p{n}.yml"), &sphere);
        let (a, b) = (d.path(&format!("a{n}.pfm")), d.path(&format!("b{n}.pfm")));
        accepted(&by_scene, &a, &["-q"]);
        accepted(&plain, &b, &["-q", "--spp", n]);
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{n}"
        );
    }
}

#[test]
fn the_two_adaptive_features_have_names_of_their_own_and_the_old_ones_warn() {
    let d = Dir::new();
    let ray = d.file("ray.yml", EMPTY);
    let new = d.path("new.pfm");
    let err = accepted(&ray, &new, &["--adaptive-aa", "0.1"]);
    assert!(!err.contains("warning"), "{err}");
    let old = d.path("old.pfm");
    let err = accepted(&ray, &old, &["--adaptive", "0.1"]);
    assert!(
        err.contains("warning: --adaptive is the old name of --adaptive-aa"),
        "{err}"
    );
    assert_eq!(std::fs::read(&new).unwrap(), std::fs::read(&old).unwrap());
    refused(
        &ray,
        &d.path("both.pfm"),
        &["--adaptive", "0.1", "--adaptive-aa", "0.1"],
        &["--adaptive is its old name"],
    );
    let path = d.file("path.yml", &choosing("path"));
    let err = accepted(
        &path,
        &d.path("p.pfm"),
        &["--sample-allocation", "by-noise"],
    );
    assert!(!err.contains("warning"), "{err}");
    let err = accepted(
        &path,
        &d.path("q.pfm"),
        &["--sample-allocation", "adaptive"],
    );
    assert!(
        err.contains("warning: `--sample-allocation adaptive` is the old name of `--sample-allocation by-noise`"),
        "{err}"
    );
    let old_key = d.file(
        "old-key.yml",
        &format!("{}    sample-allocation: adaptive\n", choosing("path")),
    );
    let err = accepted(&old_key, &d.path("k.pfm"), &[]);
    assert!(err.contains("old name of `by-noise`"), "{err}");
}

#[test]
fn the_help_names_the_new_spellings_only() {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args(["render", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("--adaptive-aa <THRESHOLD>"), "{help}");
    assert!(
        !help.contains("--adaptive <"),
        "the old name is hidden: {help}"
    );
    assert!(help.contains("by-noise"), "{help}");
    assert!(!help.contains("adaptive (each"), "{help}");
}

#[test]
fn the_help_names_the_layers_the_viewer_is_sent() {
    let o = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args(["render", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    // A flag's long help, from its name to the blank line before the next flag.
    let flag = |name: &str| {
        let at = help.find(name).unwrap_or_else(|| panic!("{name}: {help}"));
        let rest = &help[at + name.len()..];
        rest[..rest.find("\n\n").unwrap_or(rest.len())].to_string()
    };
    let server = flag("--display-server <HOST:PORT>");
    let layers = ["albedo", "normal", "depth", "samples", "noisy", "denoised"];
    for layer in layers {
        let named = format!("`{layer}`");
        assert!(
            server.contains(&named),
            "--display-server names {named}: {server}"
        );
    }
    let denoise = flag("--denoise\n");
    assert!(
        denoise.contains("`denoised`") && denoise.contains("`noisy`"),
        "{denoise}"
    );
}

/// Three lamps of differing power over a floor, for the path tracer; `light` is the scene's
/// `light-sampler` line, if any.
fn lamps(light: &str) -> String {
    let mut text = format!(
        "- world:\n    renderer: path\n    background: [0, 0, 0]\n{light}\
         - add: camera\n  width: 6\n  height: 4\n  field-of-view: 1.2\n\
         \x20 from: [0, 3, 3]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n\
         - add: rectangle\n  material: {{ type: diffuse, color: [0.6, 0.6, 0.6] }}\n\
         \x20 transform: [[scale, 3, 1, 3]]\n"
    );
    for (x, bright) in [(-1.0, 1.0), (0.0, 8.0), (1.0, 30.0)] {
        text += &format!(
            "- add: sphere\n  material: {{ type: diffuse, color: [0, 0, 0], \
             emission: [{bright}, {bright}, {bright}] }}\n  \
             transform: [[scale, 0.1, 0.1, 0.1], [translate, {x}, 1, 0]]\n"
        );
    }
    text
}

#[test]
fn the_light_sampler_flag_picks_the_sampler_and_refuses_another_name() {
    let d = Dir::new();
    let plain = d.file("lamps.yml", &lamps(""));
    let image = |scene: &Path, name: &str, args: &[&str]| {
        let out = d.path(name);
        accepted(scene, &out, &[&["-q", "--spp", "4"], args].concat());
        std::fs::read(out).unwrap()
    };
    let mut images = Vec::new();
    for name in ["uniform", "power", "bvh"] {
        let flagged = image(&plain, &format!("{name}.pfm"), &["--light-sampler", name]);
        // The flag gives the image of the scene's own key.
        let key = d.file(
            &format!("{name}.yml"),
            &lamps(&format!("    light-sampler: {name}\n")),
        );
        assert_eq!(
            flagged,
            image(&key, &format!("{name}-key.pfm"), &[]),
            "{name}"
        );
        images.push(flagged);
    }
    // Three samplers, three images (the same seed, lights picked with other odds).
    assert_ne!(images[0], images[1]);
    assert_ne!(images[1], images[2]);
    assert_ne!(images[0], images[2]);
    // Three lamps are too few for the tree: `auto` picks by power, and the flag overrides
    // the scene's key.
    assert_eq!(
        image(&plain, "auto.pfm", &["--light-sampler", "auto"]),
        images[1]
    );
    let keyed = d.file("keyed.yml", &lamps("    light-sampler: uniform\n"));
    assert_eq!(
        image(&keyed, "over.pfm", &["--light-sampler", "bvh"]),
        images[2]
    );
    refused(
        &plain,
        &d.path("bad.pfm"),
        &["--light-sampler", "tree"],
        &[
            "invalid value 'tree' for '--light-sampler <NAME>'",
            "[possible values: uniform, power, bvh, auto]",
        ],
    );
    refused(
        &d.file("ray.yml", EMPTY),
        &d.path("ray.pfm"),
        &["--light-sampler", "bvh"],
        &["--light-sampler", "applies to the path tracer"],
    );
}

#[test]
fn the_sphere_cones_flag_samples_the_balls_as_the_scenes_key_does() {
    let d = Dir::new();
    let image = |scene: &Path, name: &str, args: &[&str]| {
        let out = d.path(name);
        accepted(scene, &out, &[&["-q", "--spp", "4"], args].concat());
        std::fs::read(out).unwrap()
    };
    let plain = d.file("balls.yml", &lamps(""));
    let keyed = d.file("by-area.yml", &lamps("    sphere-cones: off\n"));
    let cones = image(&plain, "cones.pfm", &[]);
    let by_area = image(&plain, "area.pfm", &["--sphere-cones", "off"]);
    // The ball lamps sampled another way: another image from the same seed.
    assert_ne!(cones, by_area);
    // The flag gives the image of the scene's key, and overrides it.
    assert_eq!(by_area, image(&keyed, "key.pfm", &[]));
    assert_eq!(cones, image(&keyed, "over.pfm", &["--sphere-cones", "on"]));
}

#[test]
fn the_equiangular_flag_samples_the_fog_as_the_scenes_key_does() {
    let d = Dir::new();
    let image = |scene: &Path, name: &str, args: &[&str]| {
        let out = d.path(name);
        accepted(scene, &out, &[&["-q", "--spp", "4"], args].concat());
        std::fs::read(out).unwrap()
    };
    // The ball lamps in a box of fog.
    let fog = "- medium: fog\n  sigma-s: 0.5\n\
               - add: cube\n  material: interface\n  interior: fog\n\
               \x20 transform: [[scale, 2, 1.5, 2]]\n";
    let plain = d.file("fog.yml", &(lamps("") + fog));
    let keyed = d.file("off.yml", &(lamps("    equiangular: off\n") + fog));
    let on = image(&plain, "on.pfm", &[]);
    let off = image(&plain, "off.pfm", &["--equiangular", "off"]);
    // Points drawn towards the lamps: another image from the same seed.
    assert_ne!(on, off);
    // The flag gives the image of the scene's key, and overrides it.
    assert_eq!(off, image(&keyed, "key.pfm", &[]));
    assert_eq!(on, image(&keyed, "over.pfm", &["--equiangular", "on"]));
}

#[test]
fn the_path_tracers_technique_switches_are_its_flags() {
    let d = Dir::new();
    let path = d.file("path.yml", &choosing("path"));
    let ray = d.file("ray.yml", EMPTY);
    let switches = [
        "--next-event",
        "--mis",
        "--roulette",
        "--glass-split",
        "--mirror-balls",
        "--sphere-cones",
        "--equiangular",
    ];
    for (i, flag) in switches.iter().enumerate() {
        for value in ["on", "off"] {
            accepted(
                &path,
                &d.path(&format!("{i}{value}.pfm")),
                &[flag, value, "-q"],
            );
        }
        refused(
            &path,
            &d.path("bad.pfm"),
            &[flag, "maybe"],
            &["invalid value 'maybe'", flag],
        );
        refused(
            &ray,
            &d.path("ray.pfm"),
            &[flag, "off"],
            &[flag, "applies to the path tracer"],
        );
    }
    accepted(
        &path,
        &d.path("budget.pfm"),
        &["--mirror-ball-cap", "5", "--mirror-ball-cull", "0", "-q"],
    );
    refused(
        &path,
        &d.path("cap.pfm"),
        &["--mirror-ball-cap", "0"],
        &["--mirror-ball-cap takes at least 1"],
    );
    accepted(
        &path,
        &d.path("lights.pfm"),
        &["--equiangular-lights", "3", "-q"],
    );
    for count in ["0", "17"] {
        refused(
            &path,
            &d.path("bad-lights.pfm"),
            &["--equiangular-lights", count],
            &["--equiangular-lights takes from 1 to 16"],
        );
    }
    refused(
        &ray,
        &d.path("ray.pfm"),
        &["--equiangular-lights", "3"],
        &["--equiangular-lights", "applies to the path tracer"],
    );
    for cull in ["1", "1.5"] {
        refused(
            &path,
            &d.path("cull.pfm"),
            &["--mirror-ball-cull", cull],
            &["--mirror-ball-cull takes a share of the sky's light from 0 to below 1"],
        );
    }
    refused(
        &path,
        &d.path("roulette.pfm"),
        &["--roulette", "off", "--roulette-scale", "2"],
        &["--roulette-scale scales the roulette that --roulette off turns off"],
    );
    // A scene's `roulette: off` with the flag's scale: the scene's switch is named.
    let off = d.file(
        "off.yml",
        &format!("{}    roulette: off\n", choosing("path")),
    );
    refused(
        &off,
        &d.path("scale.pfm"),
        &["--roulette-scale", "2"],
        &["the scene's `roulette: off`"],
    );
    accepted(
        &off,
        &d.path("on.pfm"),
        &["--roulette", "on", "--roulette-scale", "2", "-q"],
    );
}

#[test]
fn a_path_scenes_max_depth_takes_the_limit_of_the_renderer_that_draws_it() {
    let d = Dir::new();
    let path = d.file(
        "deep.yml",
        &format!("{}    max-depth: 500\n", choosing("path")),
    );
    // The path tracer follows 500 bounces...
    accepted(&path, &d.path("a.pfm"), &["-q", "--spp", "1"]);
    // ...the ray tracer at most 64: refused at the key (line 11, column 16), naming both.
    refused(
        &path,
        &d.path("b.pfm"),
        &["--renderer", "ray"],
        &[
            "deep.yml:11:16: `max-depth`: 500 bounces is more than 64",
            "the ray tracer (--renderer ray)",
            "the path tracer's limit is 1024",
        ],
    );
    // `--max-depth` replaces the key.
    accepted(
        &path,
        &d.path("c.pfm"),
        &["--renderer", "ray", "--max-depth", "5", "-q"],
    );
}
