//! Files from outside as the command meets them (issue 44, findings 4 to 8): a named pipe
//! where a file is expected, a part file forged to make the merge read elsewhere, outputs that
//! would replace an input or a file that is not a part, the Slurm merge's list of parts, and
//! half floats past their range. Each gets its documented answer (docs/reliability.md) at
//! once: a command that would block on a pipe is caught by a generous deadline, not timed.
#![cfg(unix)]
#[path = "support/scratch.rs"]
mod scratch;

use scratch::{render, stderr, Dir};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A small scene with canvas items (the book's shaded triangle, drawn by the rasterizer and
/// over the image by the merge).
fn overlay_scene(d: &Dir) -> PathBuf {
    d.file(
        "tri.yml",
        "- world:\n    renderer: raster\n    background: [1, 1, 1]
- add: camera\n  width: 12\n  height: 10\n  viewport: [1, 1]\n  distance: 1
- add: canvas-triangle\n  points: [[-5, -4], [5, 1], [1, 5]]\n  color: [0, 1, 0]\n",
    )
}

/// A small scene without canvas items, for the ray tracer.
fn plain_scene(d: &Dir) -> PathBuf {
    d.file(
        "plain.yml",
        "- add: camera\n  width: 8\n  height: 6\n  field-of-view: 1\n  from: [0, 0, -5]
  to: [0, 0, 0]\n  up: [0, 1, 0]
- add: light\n  at: [-10, 10, -10]\n  intensity: [1, 1, 1]
- add: sphere\n",
    )
}

/// Runs `command`, killing it (and failing) if it has not ended in a minute: what a command
/// blocked on a named pipe would do forever. A refusal takes milliseconds.
fn within_a_minute(command: &mut Command) -> Output {
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("still running after a minute: {command:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn rayforge() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_rayforge"));
    command
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX");
    command
}

/// `rayforge merge ARGS…`.
fn merge(args: &[&Path]) -> Command {
    let mut command = rayforge();
    command.arg("merge").args(args);
    command
}

/// Makes a named pipe at `path`.
fn fifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

/// The message of a refusal (exit 2).
fn refused(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    err
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}

/// Renders slice `i` of `n` of `scene` to `dir/part-i.part`.
fn part(d: &Dir, scene: &Path, i: u64, n: u64) -> PathBuf {
    let part = d.path(&format!("part-{i}.part"));
    ok(&render(
        scene,
        &part,
        &["--slice", &format!("{i}/{n}"), "-q"],
    ));
    part
}

#[test]
fn a_named_pipe_as_a_part_is_refused_at_once() {
    let d = Dir::new();
    let scene = plain_scene(&d);
    let good = part(&d, &scene, 0, 2);
    let pipe = d.path("part-1.part");
    fifo(&pipe);
    let out = d.path("out.png");
    let err = refused(&within_a_minute(&mut merge(&[
        &good,
        &pipe,
        "-o".as_ref(),
        &out,
    ])));
    assert!(
        err.contains("cannot read the part") && err.contains("it is a named pipe"),
        "{err}"
    );
    assert!(!out.exists());
    assert!(!d.path("out.png.rayforge-lock").exists());
}

#[test]
fn a_named_pipe_as_the_checkpoint_to_resume_is_refused_and_the_lock_released() {
    let d = Dir::new();
    let scene = plain_scene(&d);
    let out = d.path("out.png");
    fifo(&d.path("out.png.rayforge-checkpoint"));
    let mut command = rayforge();
    command.arg("render").arg(&scene).arg("-o").arg(&out);
    let err = refused(&within_a_minute(command.args(["--resume", "-q"])));
    assert!(
        err.contains("cannot resume from") && err.contains("it is a named pipe"),
        "{err}"
    );
    assert!(!out.exists());
    assert!(
        !d.path("out.png.rayforge-lock").exists(),
        "the lock is left"
    );
}

#[test]
fn a_slice_to_a_named_pipe_or_a_file_that_is_not_a_part_is_refused_without_force() {
    let d = Dir::new();
    let scene = plain_scene(&d);
    let pipe = d.path("pipe.part");
    fifo(&pipe);
    let mut command = rayforge();
    command.arg("render").arg(&scene).arg("-o").arg(&pipe);
    let err = refused(&within_a_minute(command.args(["--slice", "0/2"])));
    assert!(err.contains("is there and is not a part file"), "{err}");
    assert!(err.contains("--force"), "{err}");

    let image = d.file("photo.png", "not a part: a photograph");
    let err = refused(&render(&scene, &image, &["--slice", "0/2"]));
    assert!(err.contains("is there and is not a part file"), "{err}");
    assert_eq!(std::fs::read(&image).unwrap(), b"not a part: a photograph");
    ok(&render(
        &scene,
        &image,
        &["--slice", "0/2", "--force", "-q"],
    ));
    assert!(std::fs::read(&image).unwrap().starts_with(b"RAYPART\n"));

    // The scene itself is never replaced, --force or not.
    for force in [&[][..], &["--force"][..]] {
        let mut args = vec!["--slice", "0/2"];
        args.extend_from_slice(force);
        let err = refused(&render(&scene, &scene, &args));
        assert!(
            err.contains("it is the scene file") && err.contains("an input of this command"),
            "{err}"
        );
    }
    assert!(std::fs::read_to_string(&scene)
        .unwrap()
        .contains("add: sphere"));
}

#[test]
fn a_render_never_writes_over_a_file_its_scene_reads() {
    let d = Dir::new();
    // The scene's own environment map as the output: it would be replaced by the render.
    let map = d.path("sky.pfm");
    let mut sky = b"PF\n2 2\n-1.0\n".to_vec();
    (0..12).for_each(|_| sky.extend_from_slice(&1.0f32.to_le_bytes()));
    std::fs::write(&map, sky).unwrap();
    let scene = d.file(
        "sky.yml",
        "- world:\n    renderer: path\n    environment: {file: sky.pfm}
- add: camera\n  width: 4\n  height: 3\n  field-of-view: 1\n  from: [0, 0, -5]
  to: [0, 0, 0]\n  up: [0, 1, 0]\n",
    );
    let before = std::fs::read(&map).unwrap();
    let err = refused(&render(&scene, &map, &["--spp", "1"]));
    assert!(err.contains("it is a file the scene reads"), "{err}");
    assert_eq!(std::fs::read(&map).unwrap(), before);
}

#[test]
fn merge_never_writes_over_its_own_inputs() {
    let d = Dir::new();
    let scene = plain_scene(&d);
    let parts: Vec<PathBuf> = (0..2).map(|i| part(&d, &scene, i, 2)).collect();
    // A part named as if it were an image: `-o` names it.
    let named = d.path("part-1.pfm");
    std::fs::rename(&parts[1], &named).unwrap();
    let before = std::fs::read(&named).unwrap();
    let o = merge(&[&parts[0], &named, "-o".as_ref(), &named])
        .output()
        .unwrap();
    let err = refused(&o);
    assert!(
        err.contains("it is the part") && err.contains("part-1.pfm"),
        "{err}"
    );
    assert_eq!(std::fs::read(&named).unwrap(), before);
    // Through a link, the same file.
    let link = d.path("link.pfm");
    std::os::unix::fs::symlink(&named, d.path("link.part")).unwrap();
    std::fs::hard_link(&named, &link).unwrap();
    let o = merge(&[&parts[0], &d.path("link.part"), "-o".as_ref(), &link])
        .output()
        .unwrap();
    assert!(refused(&o).contains("an input of this command"));
    assert_eq!(std::fs::read(&named).unwrap(), before);
}

#[test]
fn merge_reads_parts_from_a_list_as_from_its_arguments() {
    let d = Dir::new();
    let scene = plain_scene(&d);
    let parts: Vec<PathBuf> = (0..3).map(|i| part(&d, &scene, i, 3)).collect();
    let by_args = d.path("args.pfm");
    let mut args: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    args.extend([Path::new("-o"), &by_args]);
    ok(&merge(&args).arg("-q").output().unwrap());
    // Relative names from the list's folder, in any order, a blank line between.
    let list = d.file("parts.list", "part-2.part\n\npart-0.part\npart-1.part\n");
    let by_list = d.path("list.pfm");
    ok(&merge(&["--list".as_ref(), &list, "-o".as_ref(), &by_list])
        .arg("-q")
        .output()
        .unwrap());
    assert!(std::fs::read(&by_list).unwrap() == std::fs::read(&by_args).unwrap());
    // The list is an input like the parts (named here as an image might be), and a pipe is
    // no list.
    let odd = d.file("list.pfm", "part-2.part\npart-0.part\npart-1.part\n");
    let o = merge(&["--list".as_ref(), &odd, "-o".as_ref(), &odd])
        .output()
        .unwrap();
    assert!(refused(&o).contains("it is the list of parts"));
    assert!(std::fs::read_to_string(&odd)
        .unwrap()
        .starts_with("part-2.part"));
    let pipe = d.path("pipe.list");
    fifo(&pipe);
    let err = refused(&within_a_minute(&mut merge(&[
        "--list".as_ref(),
        &pipe,
        "-o".as_ref(),
        &by_list,
    ])));
    assert!(err.contains("it is a named pipe"), "{err}");
}

/// Forges `part`'s header to name `scene` as its scene file, its checksums made right again
/// (they find damage, not forgery).
fn forge_scene_path(part: &Path, scene: &str) -> Vec<u8> {
    let bytes = std::fs::read(part).unwrap();
    let header_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let fields = &bytes[16..16 + header_len];
    // The fields before the scene's path: 5 u64s, the cut, 4 u64s, development, overlay and
    // AOVs (format 3).
    let fixed = 5 * 8 + 1 + 4 * 8 + 3;
    let old_len = u32::from_le_bytes(fields[fixed..fixed + 4].try_into().unwrap()) as usize;
    let mut new_fields = fields[..fixed].to_vec();
    new_fields.extend_from_slice(&(scene.len() as u32).to_le_bytes());
    new_fields.extend_from_slice(scene.as_bytes());
    new_fields.extend_from_slice(&fields[fixed + 4 + old_len..]);
    let mut forged = bytes[..12].to_vec();
    forged.extend_from_slice(&(new_fields.len() as u32).to_le_bytes());
    forged.extend_from_slice(&new_fields);
    forged.extend_from_slice(&[0; 8]);
    forged.extend_from_slice(&bytes[16 + header_len + 8..]);
    rayforge_cli::untrusted::with_part_checksums_repaired(&forged)
}

#[test]
fn merge_opens_no_path_a_part_names_and_reads_the_scene_the_user_names() {
    let d = Dir::new();
    let scene = overlay_scene(&d);
    let parts: Vec<PathBuf> = (0..2).map(|i| part(&d, &scene, i, 2)).collect();
    // A secret outside anything the user named, and a named pipe: a forged part names each.
    let secret = d.file("secret.txt", "root:$6$the-secret-hash:19000:0:99999:7:::\n");
    let pipe = d.path("pipe.yml");
    fifo(&pipe);
    let out = d.path("out.png");
    for named in [&secret, &pipe] {
        let forged = d.path("forged.part");
        std::fs::write(
            &forged,
            forge_scene_path(&parts[1], named.to_str().unwrap()),
        )
        .unwrap();
        let o = within_a_minute(&mut merge(&[&parts[0], &forged, "-o".as_ref(), &out]));
        let err = refused(&o);
        assert!(err.contains("name it with --scene"), "{err}");
        assert!(!err.contains("the-secret-hash"), "{err}");
        // Named by the user, the true scene: the forged path is shown, never opened.
        let o = within_a_minute(&mut merge(&[
            &parts[0],
            &forged,
            "--scene".as_ref(),
            &scene,
            "-o".as_ref(),
            &out,
            "-q".as_ref(),
        ]));
        ok(&o);
    }
    // The user's scene is read under the merge's own rules: a pipe is refused at once, and
    // another file is refused by the fingerprint, its text never shown.
    let err = refused(&within_a_minute(&mut merge(&[
        &parts[0],
        &parts[1],
        "--scene".as_ref(),
        &pipe,
        "-o".as_ref(),
        &out,
    ])));
    assert!(err.contains("it is a named pipe"), "{err}");
    let other = d.file(
        "other.yml",
        &std::fs::read_to_string(&scene)
            .unwrap()
            .replace("[0, 1, 0]", "[1, 0, 0]"),
    );
    let err = refused(
        &merge(&[
            &parts[0],
            &parts[1],
            "--scene".as_ref(),
            &other,
            "-o".as_ref(),
            &out,
        ])
        .output()
        .unwrap(),
    );
    assert!(
        err.contains("is not the one the slices were rendered from"),
        "{err}"
    );
}

#[test]
fn half_floats_past_65504_are_written_as_65504_not_infinity() {
    let d = Dir::new();
    // A light of 10^7 on a white sphere: most lit values are far past the half's range.
    let scene = d.file(
        "bright.yml",
        "- add: camera\n  width: 16\n  height: 16\n  field-of-view: 0.8\n  from: [0, 0, -5]
  to: [0, 0, 0]\n  up: [0, 1, 0]
- add: light\n  at: [-10, 10, -10]\n  intensity: [1e7, 1e7, 1e7]
- add: sphere\n  material: {color: [1, 1, 1]}\n",
    );
    let out = d.path("bright.exr");
    ok(&render(&scene, &out, &["--exr-half", "-q"]));
    use exr::prelude::{read_all_flat_layers_from_file, FlatSamples};
    let image = read_all_flat_layers_from_file(&out).unwrap();
    let mut saturated = 0;
    for channel in &image.layer_data[0].channel_data.list {
        let FlatSamples::F16(values) = &channel.sample_data else {
            panic!("not half floats");
        };
        assert!(values
            .iter()
            .all(|v| v.is_finite() && v.to_f32() <= 65504.0));
        saturated += values.iter().filter(|v| v.to_f32() == 65504.0).count();
    }
    assert!(saturated > 100, "only {saturated} values saturated");
}
