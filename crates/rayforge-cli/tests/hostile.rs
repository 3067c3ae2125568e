//! Hostile input through the command (the reliability issue's findings): errors whose column
//! is past 65 535 or that quote megabytes of input, ray trees that would never end, frames the
//! rasterizer could not hold, and `--trace-pixel` on a tree of millions of rays. Each gets a
//! clear error (or a bounded answer) in bounded time and output.
#[path = "support/scratch.rs"]
mod scratch;

use scratch::{render, stderr, Dir};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const CAMERA: &str = "
- add: camera
  width: 4
  height: 3
  field-of-view: 1.0
  from: [0, 0, 0]
  to: [0, 0, 1]
  up: [0, 1, 0]
- add: light
  at: [0, 2, 0]
  intensity: [1, 1, 1]
";

/// A glass cube inside a mirror cube, the camera inside both: each ray that meets the glass
/// splits in two and none leaves, so one camera ray is a tree of 2^depth rays.
fn mirror_box(lighting: &str) -> String {
    format!(
        "- world:\n    lighting: {lighting}\n{CAMERA}
- add: cube
  transform: [[scale, 5, 5, 5]]
  material: {{ color: [0.2, 0.2, 0.2], reflective: 1 }}
- add: cube
  transform: [[scale, 3, 3, 3]]
  material: {{ reflective: 0.5, transparency: 0.5, refractive-index: 1.5 }}
"
    )
}

#[test]
fn an_error_past_column_65535_is_shown_without_a_panic() {
    let d = Dir::new();
    let scene = d.file(
        "long.yml",
        &format!(
            "{CAMERA}- add: sphere\n  material: {{ color: [1, 1, 1], {}bogus: 1 }}\n",
            " ".repeat(70_000)
        ),
    );
    let o = render(&scene, &d.path("out.png"), &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(":13:70033: `bogus`: unknown key"), "{err}");
    // The line is shown cut to a window around the error, with its real line number.
    assert!(err.contains("13 │ …"), "{err}");
    assert!(err.len() < 4_000, "{} bytes of stderr", err.len());
    assert!(!d.path("out.png").exists());
}

#[test]
fn a_name_of_megabytes_is_quoted_in_part() {
    let d = Dir::new();
    let name = "m".repeat(5_000_000);
    let scene = d.file(
        "name.yml",
        &format!("{CAMERA}- add: sphere\n  material: {name}\n"),
    );
    let o = render(&scene, &d.path("out.png"), &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err.contains("is not defined"),
        "{}",
        &err[..err.len().min(2000)]
    );
    assert!(err.contains("bytes left out"));
    assert!(err.len() < 4_000, "{} bytes of stderr", err.len());
}

#[test]
fn a_ray_tree_that_never_ends_is_stopped_by_the_ray_budget_in_every_model() {
    let d = Dir::new();
    for (lighting, extra) in [("cgfs", &[][..]), ("phong", &["--bailout", "0"][..])] {
        let scene = d.file("box.yml", &mirror_box(lighting));
        let out = d.path("box.png");
        let started = Instant::now();
        let mut args = vec!["--max-depth", "64", "--max-rays-per-sample", "50000"];
        args.extend(extra);
        let o = render(&scene, &out, &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{lighting}: {err}");
        assert!(err.contains("error: pixel ("), "{lighting}: {err}");
        assert!(
            err.contains("more than 50000 rays") && err.contains("--max-rays-per-sample"),
            "{lighting}: {err}"
        );
        assert!(!out.exists(), "{lighting}");
        assert!(started.elapsed() < Duration::from_secs(60), "{lighting}");
        let _ = std::fs::remove_file(d.path("box.png.rayforge-checkpoint"));
    }
}

#[test]
fn shares_of_light_past_one_are_refused_where_they_are_written() {
    let d = Dir::new();
    for (material, key) in [
        ("reflective: 5", "reflective"),
        ("transparency: 5", "transparency"),
        ("opacity: -1", "opacity"),
        ("gloss: [5, 5, 5]", "gloss"),
    ] {
        let scene = d.file(
            "shares.yml",
            &format!("{CAMERA}- add: sphere\n  material: {{ {material} }}\n"),
        );
        let o = render(&scene, &d.path("out.png"), &[]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{material}: {err}");
        assert!(
            err.contains("shares.yml:13:") && err.contains(&format!("`{key}`")),
            "{material}: {err}"
        );
        assert!(err.contains("share of light from 0 to 1"), "{err}");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn an_interrupt_stops_a_render_inside_one_pixel() {
    let d = Dir::new();
    let scene = d.file("box.yml", &mirror_box("cgfs"));
    let out = d.path("box.png");
    // Each pixel is a tree of 2^64 rays and the budget is far away: only the stop flag,
    // looked at inside the pixel, can end this render.
    let mut child = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .args(["render", "--max-depth", "64", "--max-rays-per-sample"])
        .arg("100000000000")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Signalled only once it catches SIGINT (before that the signal would kill it outright,
    // not ask it to stop); no row can finish meanwhile, however long that takes.
    wait_until_it_catches_sigint(child.id());
    let signalled = Instant::now();
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        // A guard against a hang: the stop is looked at every few samples.
        assert!(
            signalled.elapsed() < Duration::from_secs(60),
            "still running 60 s after SIGINT"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(130));
    assert!(!out.exists());
}

/// Ctrl-C while a scene of 300,000 parts is read (about 16 MB; seconds to read in a debug
/// build): the reading stops part-way, at the line it reached, and the command exits 130
/// having written nothing. The handler is installed just before the reading starts, and the
/// signal sent once it is: the place named must be well before the file's end.
#[cfg(target_os = "linux")]
#[test]
fn an_interrupt_stops_the_reading_of_a_huge_scene() {
    let d = Dir::new();
    let mut text = String::from(CAMERA);
    for i in 0..300_000 {
        text.push_str(&format!(
            "- add: sphere\n  transform: [[translate, {i}, 0, 9]]\n"
        ));
    }
    let lines = text.lines().count();
    let scene = d.file("huge.yml", &text);
    let out = d.path("huge.png");
    let child = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_until_it_catches_sigint(child.id());
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(!out.exists());
    let at = err
        .split("stopped while reading the scene at ")
        .nth(1)
        .unwrap_or_else(|| panic!("not stopped while reading: {err}"));
    let line: usize = at
        .split(':')
        .nth(1)
        .and_then(|l| l.parse().ok())
        .unwrap_or_else(|| panic!("no line: {err}"));
    assert!(line < lines / 2, "stopped at line {line} of {lines}: {err}");
    assert!(err.contains("nothing was written"), "{err}");
}

/// Waits until the process `pid` has a handler for SIGINT (its `SigCgt` mask in
/// `/proc/PID/status` holds the signal), the observable sign that its Ctrl-C handler is
/// installed; the deadline is a guard against a hang, not a measure of speed.
#[cfg(target_os = "linux")]
fn wait_until_it_catches_sigint(pid: u32) {
    const SIGINT_BIT: u64 = 1 << (2 - 1);
    let status = format!("/proc/{pid}/status");
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let text = std::fs::read_to_string(&status).unwrap_or_else(|e| panic!("{status}: {e}"));
        let caught = text
            .lines()
            .find_map(|l| l.strip_prefix("SigCgt:"))
            .map(|mask| u64::from_str_radix(mask.trim(), 16).expect("a hexadecimal mask"))
            .expect("a SigCgt line");
        if caught & SIGINT_BIT != 0 {
            return;
        }
        assert!(Instant::now() < deadline, "no SIGINT handler after 60 s");
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn a_frame_the_rasterizer_could_not_hold_is_refused_at_once() {
    let d = Dir::new();
    let spheres: String = (0..64)
        .map(|i| format!("- add: sphere\n  transform: [[translate, {i}, 0, 10]]\n"))
        .collect();
    let scene = d.file("spheres.yml", &format!("{CAMERA}{spheres}"));
    let started = Instant::now();
    let o = render(
        &scene,
        &d.path("out.png"),
        &["--renderer", "raster", "--sphere-divisions", "4096"],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--max-raster-triangles"), "{err}");
    // Refused before any sphere is built: building them (64 meshes of 33 million triangles)
    // would take far longer than this guard, however slow the machine.
    assert!(started.elapsed() < Duration::from_secs(60));
    assert!(!d.path("out.png").exists());
}

#[test]
fn trace_pixel_on_a_tree_of_millions_of_rays_prints_a_bounded_record() {
    let d = Dir::new();
    let scene = d.file("box.yml", &mirror_box("cgfs"));
    let o = render(
        &scene,
        &d.path("out.png"),
        &[
            "--trace-pixel",
            "1,1",
            "--max-depth",
            "64",
            "--max-rays-per-sample",
            "300000",
        ],
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("more events, not shown"),
        "{}",
        &out[out.len().saturating_sub(500)..]
    );
    assert!(out.contains("stopped: this camera ray led to more than 300000 rays"));
    assert!(
        out.lines().count() < 100_100,
        "{} lines",
        out.lines().count()
    );
    // The render that follows stops at the same budget.
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[cfg(target_os = "linux")]
#[test]
fn an_output_in_a_directory_that_takes_no_files_is_not_called_missing() {
    let d = Dir::new();
    let scene = d.file("s.yml", &format!("{CAMERA}- add: sphere\n"));
    let o = render(&scene, Path::new("/proc/out.png"), &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("the directory takes no new files"), "{err}");
    let o = render(&scene, &d.path("missing/out.png"), &[]);
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
}

/// A scene with old Mac line endings (a carriage return alone ends each line, as YAML reads
/// it): the excerpt shows the line the message names, under the same number (it counted only
/// line feeds, and showed 3:15 under a message that said 9:15).
#[test]
fn an_error_in_a_file_of_carriage_returns_shows_the_line_it_names() {
    let d = Dir::new();
    let text = format!("{CAMERA}- add: sphere\n  material: {{ colr: 1 }}\n").replace('\n', "\r");
    let scene = d.file("mac.yml", &text);
    let o = render(&scene, &d.path("out.png"), &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("mac.yml:13:15: `colr`"), "{err}");
    assert!(err.contains("13 │   material: { colr: 1 }"), "{err}");
    assert!(err.contains("12 │ - add: sphere"), "{err}");
}

/// Renders `scene` under one limit, `[flag, value]`, and checks the refusal: exit status 2, an
/// error naming the flag and the place `at` (`file:line:`), and no image written.
fn refused_at(scene: &Path, out: &Path, limit: &[&str; 2], at: &str) {
    let o = render(scene, out, &["-q", limit[0], limit[1]]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(limit[0]), "{err}");
    assert!(err.contains(at), "{err}");
    assert!(!out.exists());
}

#[test]
fn the_pbrt_readers_limits_are_flags() {
    let d = Dir::new();
    let scene = d.file(
        "s.pbrt",
        "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 3\nCamera \
         \"perspective\"\nSampler \"independent\" \"integer pixelsamples\" 1\nWorldBegin\n\
         Shape \"sphere\" \"float radius\" 2\n",
    );
    let out = d.path("s.png");
    refused_at(&scene, &out, &["--max-pbrt-values", "3"], "s.pbrt:5:");
    let o = render(&scene, &out, &["-q", "--max-pbrt-include-depth", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--max-pbrt-include-depth must be at least 1"));
    let o = render(&scene, &out, &["-q", "--max-pbrt-radiances", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--max-pbrt-radiances must be at least 1"));
    let o = render(&scene, &out, &["-q", "--max-pbrt-values", "4"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A grid or cloud medium too dense to track a ray through (each unit of its optical depth a
/// step of tracking) is refused at its directive under `--max-optical-depth`, and the flag
/// takes only a finite number above 0.
#[test]
fn a_medium_past_the_optical_depth_limit_is_refused_where_it_is_made() {
    let d = Dir::new();
    let scene = d.file(
        "s.pbrt",
        "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 3\nCamera \
         \"perspective\"\nSampler \"independent\" \"integer pixelsamples\" 1\nWorldBegin\n\
         MakeNamedMedium \"c\" \"string type\" \"cloud\" \"rgb sigma_s\" [1000 1000 1000]\n",
    );
    let out = d.path("s.png");
    // σs 1000 over the unit cube: up to 1000 √3 ≈ 1732 across.
    refused_at(&scene, &out, &["--max-optical-depth", "1000"], "s.pbrt:5:");
    for bad in ["0", "-1", "NaN", "inf"] {
        let flag = format!("--max-optical-depth={bad}");
        let o = render(&scene, &out, &["-q", &flag]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            stderr(&o).contains("--max-optical-depth must be a finite number above 0"),
            "{bad}: {}",
            stderr(&o)
        );
    }
    let o = render(&scene, &out, &["-q", "--max-optical-depth", "2000"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Without `-o`, a pbrt scene's film names the image; the film is read under the flags the
/// scene is read under: `--allow-outside` for a film in an included file outside the scene's
/// folder, `--max-pbrt-include-depth` for one included 40 files deep. The film was read with
/// the default limits and the folder rule whatever the flags, so both were refused before the
/// render began.
#[test]
fn a_pbrt_films_default_output_is_read_under_the_users_flags() {
    let d = Dir::new();
    std::fs::create_dir(d.path("scene")).unwrap();
    let film = "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 3 \
                \"string filename\" \"room.pfm\"\n";
    let rest = "Camera \"perspective\"\nSampler \"independent\" \"integer pixelsamples\" 1\n\
                WorldBegin\nShape \"sphere\" \"float radius\" 2\n";
    d.file("film.pbrt", film);
    d.file("scene/s.pbrt", &format!("Include \"../film.pbrt\"\n{rest}"));
    let run = |scene: &str, extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_rayforge"))
            .current_dir(d.path(""))
            .args(["render", scene, "-q"])
            .args(extra)
            .output()
            .expect("runs")
    };
    let o = run("scene/s.pbrt", &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--allow-outside"), "{}", stderr(&o));
    let o = run("scene/s.pbrt", &["--allow-outside"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.path("room.pfm").is_file());
    std::fs::remove_file(d.path("room.pfm")).unwrap();

    for i in 1..40 {
        d.file(
            &format!("scene/i{i}.pbrt"),
            &format!("Include \"i{}.pbrt\"\n", i + 1),
        );
    }
    d.file("scene/i40.pbrt", film);
    d.file("scene/deep.pbrt", &format!("Include \"i1.pbrt\"\n{rest}"));
    let o = run("scene/deep.pbrt", &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--max-pbrt-include-depth"),
        "{}",
        stderr(&o)
    );
    let o = run("scene/deep.pbrt", &["--max-pbrt-include-depth", "64"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.path("room.pfm").is_file());
}

/// Ctrl-C on a scene of expensive rays (the finding: a stop looked at every 4,096 rays came
/// seconds late where each ray meets thousands of objects): 20,000 spheres in one place, whose
/// boxes no hierarchy can part, so that every ray into them tests them all. The top row sees
/// the sky alone (its rays miss their box); the bottom row's rays meet the pile, and cost a
/// hundred times as much. Two threads; `--pause-after-rows 1` holds the worker of the first
/// row finished (the cheap one) there, so that the signal comes while the other is inside
/// the bottom row, whatever the machine's speed. The render reports the work it did: the top
/// row's 8 × 4096 samples and only part of the bottom row's (a stop looked at only between
/// rows would have finished the row, and so the image), asserted by count, not by time.
#[cfg(target_os = "linux")]
#[test]
fn an_interrupt_stops_a_render_of_expensive_rays_inside_its_row() {
    use std::io::{BufRead, BufReader};
    let d = Dir::new();
    let mut text = String::from(
        "- add: camera\n  width: 8\n  height: 2\n  field-of-view: 0.5\n  from: [0, 0, 0]\n  \
         to: [0, 0, 1]\n  up: [0, 1, 0]\n",
    );
    for _ in 0..20_000 {
        text.push_str(
            "- add: sphere\n  transform: [[scale, 2, 0.2, 1], [translate, 0, -0.26, 8]]\n",
        );
    }
    let scene = d.file("pile.yml", &text);
    let out = d.path("pile.pfm");
    let mut child = Command::new(env!("CARGO_BIN_EXE_rayforge"))
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .args([
            "--renderer",
            "path",
            "--spp",
            "4096",
            "--sample-allocation",
            "uniform",
        ])
        .args(["--roulette", "off", "--max-depth", "4", "--threads", "2"])
        .args(["--pause-after-rows", "1"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let mut said = String::new();
    // The paused render waits for the signal; the stream ends only if it ended first.
    for line in lines.by_ref() {
        let line = line.unwrap();
        said.push_str(&line);
        said.push('\n');
        if line.contains("paused after 1 rows") {
            break;
        }
    }
    assert!(said.contains("paused after 1 rows"), "{said}");
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    for line in lines {
        said.push_str(&line.unwrap());
        said.push('\n');
    }
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{said}");
    assert!(said.contains("1 of 2 rows are saved"), "{said}");
    assert!(!out.exists());
    let samples: u64 = said
        .split("(stopped after ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no work reported: {said}"));
    let row = 8 * 4096;
    assert!(
        (row..2 * row).contains(&samples),
        "{samples} samples: not the top row and part of the bottom one: {said}"
    );
}
