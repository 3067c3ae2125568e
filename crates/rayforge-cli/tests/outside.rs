//! `rayforge render` reads the files a scene names only from inside the scene's folder unless
//! `--allow-outside` is given (issue 21, finding 9): a model named `../../secret.obj` was read,
//! and the error display showed the lines around a bad line of whatever file it named.

use std::path::Path;
use std::process::{Command, Output};

fn render(scene: &Path, output: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(output)
        .args(["--width", "4", "--height", "4", "--quiet"])
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn a_model_outside_the_scenes_folder_needs_allow_outside() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("scene");
    std::fs::create_dir(&dir).unwrap();
    // A file outside with a bad line next to a secret: its lines must never be shown.
    std::fs::write(
        root.path().join("secret.obj"),
        "# password: hunter2\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv x\n",
    )
    .unwrap();
    let scene = dir.join("scene.yml");
    std::fs::write(
        &scene,
        "- add: camera\n  width: 4\n  height: 4\n  field-of-view: 1\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n- add: obj\n  file: ../secret.obj\n",
    )
    .unwrap();
    let image = dir.join("out.png");
    let out = render(&scene, &image, &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("scene.yml:9:9"), "{stderr}");
    assert!(stderr.contains("outside the scene's folder"), "{stderr}");
    assert!(stderr.contains("--allow-outside"), "{stderr}");
    assert!(!stderr.contains("hunter2"), "{stderr}");
    assert!(!image.exists());
    // Allowed, the model is read (and its bad line is an error in it, as in any model).
    let out = render(&scene, &image, &["--allow-outside"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("secret.obj:6:3"), "{stderr}");
    std::fs::write(
        root.path().join("secret.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let out = render(&scene, &image, &["--allow-outside"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(image.exists());
}
