//! `rayforge render --slice I/N` and `rayforge merge`: a render cut into slices and merged is
//! the render done in one process, byte for byte when cut by rows (every renderer and lighting
//! model, any N, any thread count) and within the stated bound when cut by samples; merge
//! refuses parts that are missing, duplicated, of another render, damaged or cut short; a
//! complete part is not rendered again; `auto/N` reads the scheduler's index.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository's root, where the scenes are.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `rayforge` binary, with neither scheduler's index in its environment (the tests may
/// themselves run inside a Slurm job or a Kubernetes Indexed Job).
fn rayforge() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX");
    command
}

/// `rayforge render <scene> -o <out> -q <args…>`.
fn render(scene: &Path, out: &Path, args: &[&str]) -> Output {
    rayforge()
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .args(args)
        .output()
        .unwrap()
}

/// `rayforge merge <parts…> -o <out> -q`.
fn merge(parts: &[PathBuf], out: &Path) -> Output {
    rayforge()
        .arg("merge")
        .args(parts)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .output()
        .unwrap()
}

/// `rayforge merge <parts…> --scene <scene> -o <out> -q`: the scene named for its canvas
/// items, which the merge draws from it.
fn merge_scene(parts: &[PathBuf], scene: &Path, out: &Path) -> Output {
    rayforge()
        .arg("merge")
        .args(parts)
        .arg("--scene")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .output()
        .unwrap()
}

fn ok(output: &Output) {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The error message of a failed run (exit 2: bad input).
fn refused(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    stderr
}

/// Renders `scene` in `n` slices cut by `cut` into `dir` with `args`, and returns the parts.
fn slices(scene: &Path, dir: &Path, n: u64, cut: &str, args: &[&str]) -> Vec<PathBuf> {
    (0..n)
        .map(|i| {
            let part = dir.join(format!("{cut}-{n}-{i}.part"));
            let slice = format!("{i}/{n}");
            let mut all = vec!["--slice", &slice, "--slice-by", cut];
            all.extend_from_slice(args);
            ok(&render(scene, &part, &all));
            part
        })
        .collect()
}

/// Renders `scene` (under `scenes/`) with `args` in one process and in 1, 2, 3 and 7 row slices,
/// with 1 and 2 threads, to `ext`, and checks every merged image is the same bytes.
fn region_slices_match(scene: &str, args: &[&str], ext: &str) {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes").join(scene);
    let one = dir.path().join(format!("one.{ext}"));
    ok(&render(&scene, &one, args));
    let expected = std::fs::read(&one).unwrap();
    for threads in ["1", "2"] {
        let mut args = args.to_vec();
        args.extend_from_slice(&["--threads", threads]);
        for n in [1, 2, 3, 7] {
            let parts = slices(&scene, dir.path(), n, "rows", &args);
            let merged = dir.path().join(format!("merged-{threads}-{n}.{ext}"));
            ok(&merge_scene(&parts, &scene, &merged));
            assert!(
                std::fs::read(&merged).unwrap() == expected,
                "{}: {n} slices with {threads} threads differ from one render",
                scene.display()
            );
        }
    }
}

#[test]
fn row_slices_of_the_phong_ray_tracer_are_the_same_bytes() {
    // Odd sizes: the slices have unequal numbers of rows, and 7 slices of 11 rows.
    let args = ["--width", "15", "--height", "11", "--spp", "4"];
    region_slices_match("trtc/ch11-reflection-refraction.yml", &args, "pfm");
}

#[test]
fn row_slices_of_the_flat_and_cgfs_models_are_the_same_bytes() {
    let args = ["--width", "14", "--height", "13"];
    region_slices_match("cgfs/raytracer-01.yml", &args, "pfm");
    region_slices_match("cgfs/transparency.yml", &args, "pfm");
}

#[test]
fn row_slices_of_the_optics_model_are_the_same_bytes_after_its_exposure() {
    // The exposure divides by the brightest sample of all slices, and fills the pixels no
    // sample reached from their neighbours, across the slices' rows.
    let args = ["--width", "14", "--height", "13"];
    region_slices_match("fundamentals/spheroid.yml", &args, "png");
    region_slices_match("fundamentals/polyhedra.yml", &args, "pfm");
}

#[test]
fn row_slices_of_the_rasterizer_are_the_same_bytes_canvas_items_included() {
    let args = ["--width", "15", "--height", "11", "--renderer", "raster"];
    region_slices_match("trtc/ch11-reflection-refraction.yml", &args, "pfm");
    // A book stage with a canvas triangle drawn over the image, which merge draws too.
    region_slices_match(
        "cgfs/raster-04.yml",
        &["--width", "20", "--height", "20"],
        "png",
    );
}

#[test]
fn row_slices_of_the_path_tracer_are_the_same_bytes() {
    let args = ["--width", "9", "--height", "11", "--spp", "6"];
    region_slices_match("pbr/cornell.yml", &args, "pfm");
    let mut gaussian = args.to_vec();
    gaussian.extend_from_slice(&["--filter", "gaussian"]);
    region_slices_match("pbr/cornell.yml", &gaussian, "png");
}

#[test]
fn row_slices_of_the_rasterizer_that_skip_bands_of_tiles_are_the_same_bytes() {
    // 70 rows are three bands of the rasterizer's 32-row tiles; in 40 slices, slice 0 has rows
    // 0 and 40 (bands 0 and 1, band 2 not drawn) and slice 35 row 35 alone (band 1).
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/trtc/ch11-reflection-refraction.yml");
    let args = ["--width", "9", "--height", "70", "--renderer", "raster"];
    let one = dir.path().join("one.pfm");
    ok(&render(&scene, &one, &args));
    let parts = slices(&scene, dir.path(), 40, "rows", &args);
    let merged = dir.path().join("merged.pfm");
    ok(&merge(&parts, &merged));
    assert!(std::fs::read(&merged).unwrap() == std::fs::read(&one).unwrap());
}

/// Each pixel's sums (red, green, blue) and weight of a part's film, from the part file's
/// documented layout: the header's length at byte 12, the film after the header and its
/// checksum, 45 bytes of film header, then 4 × f64 per pixel.
fn part_pixels(part: &Path) -> Vec<[f64; 4]> {
    let bytes = std::fs::read(part).unwrap();
    let header = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let film = &bytes[24 + header..];
    assert_eq!(&film[..8], b"RAYFILM\n");
    film[45..film.len() - 4]
        .chunks_exact(32)
        .map(|p| std::array::from_fn(|i| f64::from_le_bytes(p[i * 8..][..8].try_into().unwrap())))
        .collect()
}

/// The bound docs/distributed.md states for sample slices of `spp` samples: each sum within
/// 2·γ(spp) of the one-process film's, relatively, with γ(n) = n·u / (1 − n·u), u = 2⁻⁵³.
fn sample_bound(spp: u64) -> f64 {
    let nu = spp as f64 * f64::EPSILON / 2.0;
    2.0 * nu / (1.0 - nu)
}

#[test]
fn sample_slices_of_the_path_tracer_agree_within_the_stated_bound() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/pbr/cornell.yml");
    for (filter, spp) in [("box", 24u64), ("tent", 13)] {
        let spp_text = spp.to_string();
        // Slices share samples evenly; so must the one-process render they are held to.
        let args = [
            "--width",
            "8",
            "--height",
            "7",
            "--spp",
            &spp_text,
            "--filter",
            filter,
            "--sample-allocation",
            "uniform",
        ];
        // One slice of all samples is the one-process film (merged bit for bit, below).
        let whole = slices(&scene, dir.path(), 1, "samples", &args);
        let expected = part_pixels(&whole[0]);
        let one = dir.path().join(format!("one-{filter}.png"));
        ok(&render(&scene, &one, &args));
        let merged_one = dir.path().join(format!("merged-1-{filter}.png"));
        ok(&merge(&whole, &merged_one));
        assert_eq!(
            std::fs::read(&merged_one).unwrap(),
            std::fs::read(&one).unwrap()
        );
        for n in [2, 3, 7] {
            let mut threads = args.to_vec();
            threads.extend_from_slice(&["--threads", if n == 3 { "1" } else { "2" }]);
            let parts = slices(&scene, dir.path(), n, "samples", &threads);
            // The merge's sums: each part's added in slice order to −0.0.
            let mut sums = vec![[-0.0f64; 4]; expected.len()];
            for part in &parts {
                for (sum, p) in sums.iter_mut().zip(part_pixels(part)) {
                    for (s, v) in sum.iter_mut().zip(p) {
                        *s += v;
                    }
                }
            }
            let bound = sample_bound(spp);
            for (i, (m, e)) in sums.iter().zip(&expected).enumerate() {
                for c in 0..4 {
                    let diff = (m[c] - e[c]).abs();
                    assert!(
                        diff <= bound * e[c].abs(),
                        "{filter}, {n} slices, pixel {i} channel {c}: {} against {}",
                        m[c],
                        e[c]
                    );
                }
                if filter == "box" {
                    // Whole numbers of samples: the weights are exact in any order.
                    assert_eq!(m[3], e[3], "pixel {i}");
                }
            }
            // On this scene the 8-bit images are the same bytes.
            let merged = dir.path().join(format!("merged-{n}-{filter}.png"));
            ok(&merge(&parts, &merged));
            assert_eq!(
                std::fs::read(&merged).unwrap(),
                std::fs::read(&one).unwrap(),
                "{filter}, {n} slices"
            );
        }
    }
}

#[test]
fn samples_cannot_cut_the_ray_tracer_or_more_slices_than_samples() {
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("p.part");
    let scene = repo().join("scenes/trtc/ch07-world.yml");
    let m = refused(&render(
        &scene,
        &part,
        &[
            "--width",
            "8",
            "--height",
            "8",
            "--slice",
            "0/2",
            "--slice-by",
            "samples",
        ],
    ));
    assert!(
        m.contains("stratified grid") && m.contains("--slice-by rows"),
        "{m}"
    );
    let m = refused(&render(
        &repo().join("scenes/pbr/cornell.yml"),
        &part,
        &[
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "2",
            "--slice",
            "0/3",
            "--slice-by",
            "samples",
        ],
    ));
    assert!(
        m.contains("cannot cut 2 samples per pixel into 3 slices"),
        "{m}"
    );
    assert!(!part.exists());
}

/// A scene of its own in `dir` (a copy of chapter 7's world, `extra` appended), and its parts
/// in 3 row slices.
fn own_scene_parts(dir: &Path, name: &str, extra: &str) -> (PathBuf, Vec<PathBuf>) {
    let text = std::fs::read_to_string(repo().join("scenes/trtc/ch07-world.yml")).unwrap();
    let scene = dir.join(format!("{name}.yml"));
    std::fs::write(&scene, text + extra).unwrap();
    let parts_dir = dir.join(name);
    std::fs::create_dir(&parts_dir).unwrap();
    let parts = slices(
        &scene,
        &parts_dir,
        3,
        "rows",
        &["--width", "10", "--height", "8"],
    );
    (scene, parts)
}

#[test]
fn merge_names_missing_and_duplicated_slices() {
    let dir = tempfile::tempdir().unwrap();
    let (_, parts) = own_scene_parts(dir.path(), "a", "");
    let out = dir.path().join("out.png");
    let m = refused(&merge(&parts[..1], &out));
    assert!(m.contains("2 of the 3 slices are missing: 1, 2"), "{m}");
    let twice = [parts[0].clone(), parts[1].clone(), parts[1].clone()];
    let m = refused(&merge(&twice, &out));
    assert!(m.contains("slice 1/3 is given twice"), "{m}");
    assert!(!out.exists());
}

#[test]
fn merge_refuses_parts_of_another_scene_or_other_settings() {
    let dir = tempfile::tempdir().unwrap();
    let (_, a) = own_scene_parts(dir.path(), "a", "");
    let (_, b) = own_scene_parts(dir.path(), "b", "\n# another scene\n");
    let out = dir.path().join("out.png");
    let m = refused(&merge(&[a[0].clone(), b[1].clone(), a[2].clone()], &out));
    assert!(
        m.contains("not slices of the same render") && m.contains("scene files differ"),
        "{m}"
    );
    assert!(m.contains("b/rows-3-1.part"), "{m}");
    let (scene, _) = own_scene_parts(dir.path(), "c", "");
    let deeper = dir.path().join("deeper.part");
    let args = [
        "--width",
        "10",
        "--height",
        "8",
        "--max-depth",
        "1",
        "--slice",
        "1/3",
    ];
    ok(&render(&scene, &deeper, &args));
    let m = refused(&merge(&[a[0].clone(), deeper, a[2].clone()], &out));
    assert!(m.contains("settings differ"), "{m}");
    assert!(!out.exists());
}

#[test]
fn merge_refuses_parts_rendered_against_another_version_of_a_file_the_scene_reads() {
    // The fingerprint covers the model the scene reads, not only the scene's text: a slice
    // rendered after the model changed does not merge with the others.
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("tri.obj");
    let triangle = |y: f64| format!("v -1 0 0\nv 1 0 0\nv 0 {y} 0\nf 1 2 3\n");
    std::fs::write(&model, triangle(1.0)).unwrap();
    let (scene, parts) = own_scene_parts(dir.path(), "m", "\n- add: obj\n  file: tri.obj\n");
    std::fs::write(&model, triangle(2.0)).unwrap();
    let later = dir.path().join("later.part");
    let args = ["--width", "10", "--height", "8", "--slice", "1/3"];
    ok(&render(&scene, &later, &args));
    let out = dir.path().join("out.png");
    let m = refused(&merge(&[parts[0].clone(), later, parts[2].clone()], &out));
    assert!(m.contains("scene files differ"), "{m}");
    // The same model as when the slices were rendered: they merge.
    std::fs::write(&model, triangle(1.0)).unwrap();
    ok(&merge(&parts, &out));
}

#[test]
fn merge_refuses_damaged_truncated_and_foreign_files_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, parts) = own_scene_parts(dir.path(), "a", "");
    let out = dir.path().join("out.png");
    let good = std::fs::read(&parts[1]).unwrap();
    let damaged = dir.path().join("damaged.part");
    let mut bytes = good.clone();
    let last = bytes.len() - 10;
    bytes[last] ^= 1;
    std::fs::write(&damaged, &bytes).unwrap();
    let m = refused(&merge(&[parts[0].clone(), damaged, parts[2].clone()], &out));
    assert!(
        m.contains("damaged.part` is not a usable part file: its film is damaged"),
        "{m}"
    );
    let truncated = dir.path().join("truncated.part");
    std::fs::write(&truncated, &good[..good.len() - 100]).unwrap();
    let m = refused(&merge(
        &[parts[0].clone(), truncated, parts[2].clone()],
        &out,
    ));
    assert!(
        m.contains("truncated.part` is not a usable part file: it is truncated"),
        "{m}"
    );
    let image = dir.path().join("image.png");
    ok(&render(&scene, &image, &["--width", "4", "--height", "4"]));
    let m = refused(&merge(&[parts[0].clone(), image, parts[2].clone()], &out));
    assert!(
        m.contains("image.png` is not a usable part file: it is not a rayforge part"),
        "{m}"
    );
    assert!(!out.exists());
}

#[test]
fn a_complete_part_is_kept_and_a_damaged_one_rendered_again() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, parts) = own_scene_parts(dir.path(), "a", "");
    let args = ["--width", "10", "--height", "8", "--slice", "1/3"];
    let render_again = || {
        rayforge()
            .arg("render")
            .arg(&scene)
            .arg("-o")
            .arg(&parts[1])
            .args(args)
            .output()
            .unwrap()
    };
    let before = std::fs::metadata(&parts[1]).unwrap().modified().unwrap();
    let again = render_again();
    ok(&again);
    let said = String::from_utf8_lossy(&again.stderr);
    assert!(
        said.contains("is already complete; nothing to render"),
        "{said}"
    );
    assert_eq!(
        std::fs::metadata(&parts[1]).unwrap().modified().unwrap(),
        before
    );
    // Cut short (a disk that filled up, a copy interrupted): replaced by a whole part.
    let good = std::fs::read(&parts[1]).unwrap();
    std::fs::write(&parts[1], &good[..good.len() / 2]).unwrap();
    let again = render_again();
    ok(&again);
    let said = String::from_utf8_lossy(&again.stderr);
    assert!(
        said.contains("note: replacing") && said.contains("truncated"),
        "{said}"
    );
    assert_eq!(std::fs::read(&parts[1]).unwrap(), good);
}

#[test]
fn auto_takes_the_index_from_slurm_or_kubernetes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/trtc/ch07-world.yml");
    let size = ["--width", "9", "--height", "7"];
    let one = dir.path().join("one.pfm");
    ok(&render(&scene, &one, &size));
    let auto = |variable: &str, index: &str, part: &Path| {
        rayforge()
            .env(variable, index)
            .arg("render")
            .arg(&scene)
            .arg("-o")
            .arg(part)
            .args(["-q", "--slice", "auto/2"])
            .args(size)
            .output()
            .unwrap()
    };
    let parts = [dir.path().join("0.part"), dir.path().join("1.part")];
    ok(&auto("SLURM_ARRAY_TASK_ID", "0", &parts[0]));
    ok(&auto("JOB_COMPLETION_INDEX", "1", &parts[1]));
    let merged = dir.path().join("merged.pfm");
    ok(&merge(&parts, &merged));
    assert_eq!(
        std::fs::read(&merged).unwrap(),
        std::fs::read(&one).unwrap()
    );
    let m = refused(&auto(
        "SLURM_ARRAY_TASK_ID",
        "2",
        &dir.path().join("x.part"),
    ));
    assert!(
        m.contains("SLURM_ARRAY_TASK_ID is 2, past the last slice, 1"),
        "{m}"
    );
    let without = render(&scene, &dir.path().join("x.part"), &["--slice", "auto/2"]);
    let m = refused(&without);
    assert!(
        m.contains("SLURM_ARRAY_TASK_ID")
            && m.contains("JOB_COMPLETION_INDEX")
            && m.contains("neither is set"),
        "{m}"
    );
}

#[test]
fn a_slice_refuses_flags_it_cannot_honour() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/trtc/ch07-world.yml");
    let part = dir.path().join("p.part");
    let m = refused(&render(&scene, &part, &["--slice", "0/2", "--resume"]));
    assert!(m.contains("--resume cannot be used with --slice"), "{m}");
    let m = refused(&render(&scene, &part, &["--slice", "2/2"]));
    assert!(m.contains("must be below N"), "{m}");
    let m = refused(&render(&scene, &part, &["--slice-by", "rows"]));
    assert!(m.contains("--slice"), "{m}");
}

/// `rayforge render <scene> -o <out> -q <args…>` with its address space limited to `kib` KiB
/// (`ulimit -v`): memory it allocates, or reserves before rendering, past that is refused.
#[cfg(target_os = "linux")]
fn render_within(kib: u64, scene: &Path, out: &Path, args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .args(args)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap()
}

#[test]
#[cfg(target_os = "linux")]
fn a_row_slice_of_a_poster_holds_its_rows_not_the_whole_film() {
    // A 2000 × 100 000 image: its film alone is 6.4 GB, what each slice held before. In 1000
    // slices by rows, each has 100 rows (6.4 MB of film) and is rendered, with every
    // renderer, within 1 GiB of address space, the program and its threads included; a slice
    // of it by samples, which holds every row, is refused there before rendering.
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "2000", "--height", "100000", "--threads", "2"];
    let gib = 1 << 20;
    let scenes = [
        ("trtc/ch07-world.yml", "ray", "--max-depth"),
        ("trtc/ch07-world.yml", "raster", "--sphere-divisions"),
        ("pbr/cornell.yml", "path", "--spp"),
    ];
    for (scene, renderer, cheap) in scenes {
        let part = dir.path().join(format!("{renderer}.part"));
        let mut args = vec!["--slice", "999/1000", "--renderer", renderer, cheap, "4"];
        args.extend_from_slice(&size);
        ok(&render_within(
            gib,
            &repo().join("scenes").join(scene),
            &part,
            &args,
        ));
        assert_eq!(part_pixels(&part).len(), 2000 * 100, "{renderer}");
    }
    let part = dir.path().join("samples.part");
    let mut args = vec!["--slice", "0/2", "--slice-by", "samples", "--spp", "2"];
    args.extend_from_slice(&size);
    let m = refused(&render_within(
        gib,
        &repo().join("scenes/pbr/cornell.yml"),
        &part,
        &args,
    ));
    assert!(
        m.contains("not enough memory for a slice of 100000 rows of a 2000×100000 render"),
        "{m}"
    );
    assert!(!part.exists());
}

#[test]
fn a_slice_of_an_image_too_large_to_merge_is_refused_before_rendering() {
    // 2^29 pixels: --max-pixels lets one process try, but the merge holds the whole image's
    // film and reads images of at most 2^28 pixels.
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("p.part");
    let args = [
        "--width",
        "32768",
        "--height",
        "16384",
        "--max-pixels",
        "1000000000",
        "--slice",
        "0/64",
    ];
    let m = refused(&render(
        &repo().join("scenes/trtc/ch07-world.yml"),
        &part,
        &args,
    ));
    assert!(
        m.contains(
            "a 32768×16384 image has more than 268435456 pixels, the most `rayforge merge` joins"
        ),
        "{m}"
    );
    assert!(!part.exists());
}

/// `rayforge merge <parts…> -o <out> -q <args…>`.
fn merge_with(parts: &[PathBuf], out: &Path, args: &[&str]) -> Output {
    rayforge()
        .arg("merge")
        .args(parts)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .args(args)
        .output()
        .unwrap()
}

/// The files `--aovs` writes beside `out.png`.
const AOV_FILES: [&str; 4] = ["albedo.png", "normal.png", "depth.pfm", "samples.pfm"];

#[test]
fn row_slices_with_aovs_merge_into_the_render_s_aovs_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/pbr/cornell.yml");
    let args = [
        "--renderer",
        "path",
        "--width",
        "9",
        "--height",
        "7",
        "--spp",
        "3",
        "--aovs",
    ];
    // OpenEXR holds the AOVs as layers of the one file; PNG has them beside it.
    for ext in ["exr", "png"] {
        let one = dir.path().join(format!("one.{ext}"));
        ok(&render(&scene, &one, &args));
        let parts = slices(&scene, dir.path(), 3, "rows", &args);
        let merged = dir.path().join(format!("merged.{ext}"));
        ok(&merge_with(&parts, &merged, &["--aovs"]));
        assert!(std::fs::read(&merged).unwrap() == std::fs::read(&one).unwrap());
        if ext == "png" {
            for file in AOV_FILES {
                let read = |stem: &str| std::fs::read(dir.path().join(format!("{stem}.{file}")));
                assert!(
                    read("merged").unwrap() == read("one").unwrap(),
                    "{file} differs"
                );
            }
        }
    }
    // Without --aovs the merge writes the image alone, the same image.
    let plain = dir.path().join("plain.png");
    ok(&merge(
        &slices(&scene, dir.path(), 3, "rows", &args),
        &plain,
    ));
    assert!(std::fs::read(&plain).unwrap() == std::fs::read(dir.path().join("one.png")).unwrap());
    assert!(!dir.path().join("plain.albedo.png").exists());
}

#[test]
fn sample_slices_with_aovs_count_every_pixel_s_samples_once() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/pbr/cornell.yml");
    let args = [
        "--renderer",
        "path",
        "--width",
        "5",
        "--height",
        "4",
        "--spp",
        "7",
        "--aovs",
    ];
    let one = dir.path().join("one.png");
    ok(&render(&scene, &one, &args));
    let parts = slices(&scene, dir.path(), 3, "samples", &args);
    let merged = dir.path().join("merged.png");
    ok(&merge_with(&parts, &merged, &["--aovs"]));
    // Counts are whole numbers, summed exactly: the one-process render's, 7 a pixel (not
    // 7 / 3, as the three parts' weights of 1 would make them if added).
    let samples = |stem: &str| std::fs::read(dir.path().join(format!("{stem}.samples.pfm")));
    assert!(samples("merged").unwrap() == samples("one").unwrap());
}

#[test]
fn merge_refuses_aovs_the_parts_do_not_hold_and_a_mix_of_parts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("scenes/pbr/cornell.yml");
    let path = [
        "--renderer",
        "path",
        "--width",
        "4",
        "--height",
        "2",
        "--spp",
        "1",
    ];
    let plain = slices(&scene, dir.path(), 2, "rows", &path);
    let out = dir.path().join("out.png");
    let m = refused(&merge_with(&plain, &out, &["--aovs"]));
    assert!(
        m.contains("the parts hold no AOVs; render the slices with --aovs"),
        "{m}"
    );
    // A part with AOVs beside one without: not slices of one render.
    let with: Vec<&str> = path.iter().copied().chain(["--aovs"]).collect();
    let part = dir.path().join("aovs-1.part");
    ok(&render(
        &scene,
        &part,
        &[&["--slice", "1/2"][..], &with].concat(),
    ));
    let m = refused(&merge(&[plain[0].clone(), part], &out));
    assert!(
        m.contains("rendered without --aovs and the other with"),
        "{m}"
    );
    // The ray tracer's parts have no AOVs to write or image to denoise.
    let ray = repo().join("scenes/trtc/ch07-world.yml");
    let parts = slices(
        &ray,
        dir.path(),
        1,
        "rows",
        &["--width", "4", "--height", "2"],
    );
    for flag in ["--aovs", "--denoise"] {
        let m = refused(&merge_with(&parts, &out, &[flag]));
        assert!(
            m.contains(&format!("{flag} is for path-traced images")),
            "{m}"
        );
    }
    assert!(!out.exists());
}

#[test]
fn a_part_of_format_version_2_still_merges() {
    // Written by rayforge before parts could hold AOVs: the one slice, by samples, of a 4×3
    // path-traced Cornell box of 2 samples a pixel.
    let dir = tempfile::tempdir().unwrap();
    let part =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/parts/v2-path-samples.part");
    let out = dir.path().join("out.pfm");
    ok(&merge(std::slice::from_ref(&part), &out));
    let pfm = std::fs::read(&out).unwrap();
    assert!(pfm.starts_with(b"PF\n4 3\n"), "{:?}", &pfm[..8]);
    let m = refused(&merge_with(&[part], &out, &["--aovs"]));
    assert!(m.contains("the parts hold no AOVs"), "{m}");
}
