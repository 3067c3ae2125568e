//! `rayforge slurm SCENE -o OUT --tasks N [RENDER FLAGS…] [-- SBATCH OPTIONS…]`: a render
//! spread over a Slurm cluster as a job array of slices and a merge job that waits for them.
//!
//! Everything a task would refuse is refused here first, before anything is submitted: the
//! render flags are parsed by `rayforge render`'s own parser with the `--slice` a task gets,
//! and the scene is read and the first slice's part header made, as a task makes it. Then the
//! scripts ([`crate::slurm_script`]) are written, atomically, into `OUT.slurm/` beside the
//! image, with the directories of the parts and the logs (Slurm does not create a log's
//! directory), and submitted from there: the array with `sbatch --parsable`, then the merge
//! with `--dependency=afterok:<array>`. Submitting the same command again after a failure
//! re-runs only the slices whose parts are missing or damaged, as a complete part is kept.
//!
//! An animation (`--frames A..B` among the render flags, `-o` a numbered name) is shared out
//! instead: task I renders every N-th frame from the I-th, each whole to its own image, and
//! there is no merge job (a frame already written is skipped, so a re-run costs nothing).

use crate::args::{Cli, Command as Subcommand, SlurmArgs};
use crate::atomic_write::{check_writable, write_atomically};
use crate::failure::Failure;
use crate::format::ImageFormat;
use crate::part_file::PART_AOVS;
use crate::settings::RenderSettings;
use crate::slice::{Cut, Slice, MAX_SLICES};
use crate::slice_render;
use crate::slurm_script::{quote, Plan, LOG_DIR, MERGE_SCRIPT, PARTS_LIST, SLICES_SCRIPT};
use clap::Parser;
use rayforge_scene::clip_to;
use std::ffi::OsString;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};
use std::process::Command;

/// How many characters of sbatch's error output a failure quotes at most (it can be long,
/// and its first lines say what is wrong).
const QUOTED_STDERR_CHARS: usize = 1000;

/// The bytes a part holds per pixel of each film: three sums and a weight, 64-bit floats.
const PART_BYTES_PER_PIXEL: u64 = 32;

/// Runs the slurm command.
pub fn run(args: &SlurmArgs) -> Result<(), Failure> {
    if args.tasks == 0 || args.tasks > MAX_SLICES {
        return Err(Failure::usage(format!(
            "--tasks must be from 1 to {MAX_SLICES}, found {}",
            args.tasks
        )));
    }
    let (render_flags, sbatch) = flags(args)?;
    ImageFormat::from_path(&args.output)?;
    check_writable(&args.output)?;
    let output = absolute_output(&args.output)?;
    let scene = std::fs::canonicalize(&args.scene)
        .map_err(|e| Failure::usage(format!("cannot read `{}`: {e}", args.scene.display())))?;
    let rayforge = std::env::current_exe()
        .and_then(std::fs::canonicalize)
        .map_err(|e| Failure::internal(format!("cannot find the running rayforge: {e}")))?;
    let dir = job_dir(&output);
    let parts = dir.join("parts");
    let frames = render_flags
        .iter()
        .any(|f| f == "--frames" || f.starts_with("--frames="));
    let target = if frames {
        output.clone()
    } else {
        parts.join("part-0.part")
    };
    // A cut image is denoised by the merge, from the AOVs its slices keep.
    let (render_flags, merge_companions) = if frames {
        (render_flags.to_vec(), Vec::new())
    } else {
        merge_companions(render_flags)
    };
    let render_flags = &render_flags[..];
    let (settings, slice) = task_settings(args, render_flags, &scene, &target)?;
    if frames {
        return submit_frames(
            args,
            &settings,
            &rayforge,
            &scene,
            &output,
            &dir,
            render_flags,
            &sbatch,
        );
    }
    let header = slice_render::plan(&settings, &slice)?;
    let plan = Plan {
        rayforge: utf8(&rayforge)?,
        scene: utf8(&scene)?,
        output: utf8(&output)?,
        parts: utf8(&parts)?,
        parts_list: utf8(&dir.join(PARTS_LIST))?,
        tasks: args.tasks,
        cut: slice.cut,
        render_flags: render_flags.to_vec(),
        merge_flags: [merge_flags(&settings), merge_companions].concat(),
        threads_given: settings.threads.is_some(),
        frames: false,
    };
    for needed in [&parts, &dir.join(LOG_DIR)] {
        std::fs::create_dir_all(needed)
            .map_err(|e| Failure::usage(format!("cannot create `{}`: {e}", needed.display())))?;
    }
    write_atomically(&dir.join(SLICES_SCRIPT), plan.slices_script().as_bytes())?;
    write_atomically(&dir.join(PARTS_LIST), plan.parts_list().as_bytes())?;
    write_atomically(&dir.join(MERGE_SCRIPT), plan.merge_script().as_bytes())?;
    let last = args.tasks - 1;
    if args.dry_run {
        let options: String = sbatch.iter().map(|o| format!("{} ", quote(o))).collect();
        println!(
            "wrote `{}`, `{MERGE_SCRIPT}` and `{PARTS_LIST}` beside it; nothing submitted. To \
             submit them:",
            dir.join(SLICES_SCRIPT).display()
        );
        println!("  cd {} &&", quote(&utf8(&dir)?));
        println!("  array=$(sbatch --parsable {options}{SLICES_SCRIPT}) &&");
        println!("  sbatch --parsable {options}--dependency=afterok:${{array%%;*}} {MERGE_SCRIPT}");
    } else {
        let (array, merge) = submit_both(&dir, &sbatch)?;
        println!(
            "slices: job array {array}, tasks 0-{last}, logs in `{}`",
            dir.join(LOG_DIR).display()
        );
        println!("merge:  job {merge}, once every slice has succeeded (afterok:{array})");
    }
    let pixels = header.width as u64 * header.height as u64;
    // The image's film, and the AOVs' beside it when the parts keep them.
    let films = if header.aovs { 1 + PART_AOVS as u64 } else { 1 };
    let part_bytes = (films * PART_BYTES_PER_PIXEL).saturating_mul(pixels);
    let all_parts = match slice.cut {
        Cut::Rows => part_bytes,
        Cut::Samples => part_bytes.saturating_mul(args.tasks),
    };
    println!(
        "parts:  `{}` to `{}`, {} in all",
        plan.part(0),
        plan.part(last),
        megabytes(all_parts)
    );
    println!("image:  `{}`", output.display());
    Ok(())
}

/// An animation over the cluster: the job array alone, task I rendering its share of the
/// frames to their images (see the [module](self)).
#[allow(clippy::too_many_arguments)]
fn submit_frames(
    args: &SlurmArgs,
    settings: &RenderSettings,
    rayforge: &Path,
    scene: &Path,
    output: &Path,
    dir: &Path,
    render_flags: &[String],
    sbatch: &[String],
) -> Result<(), Failure> {
    let (first, last_frame) = settings
        .frames
        .ok_or_else(|| Failure::internal("an animation without its frames"))?;
    let frames = last_frame - first + 1;
    if args.tasks > frames {
        return Err(Failure::usage(format!(
            "--tasks {} is more than the animation's {frames} frames: give at most {frames}",
            args.tasks
        )));
    }
    if let Some(cut) = args.slice_by {
        if Cut::from_arg(Some(cut)) != Cut::Rows {
            return Err(Failure::usage(
                "--slice-by samples cannot share out an animation: each task renders whole frames",
            ));
        }
    }
    let plan = Plan {
        rayforge: utf8(rayforge)?,
        scene: utf8(scene)?,
        output: utf8(output)?,
        parts: String::new(),
        parts_list: String::new(),
        tasks: args.tasks,
        cut: Cut::Rows,
        render_flags: render_flags.to_vec(),
        merge_flags: Vec::new(),
        threads_given: settings.threads.is_some(),
        frames: true,
    };
    let logs = dir.join(LOG_DIR);
    std::fs::create_dir_all(&logs)
        .map_err(|e| Failure::usage(format!("cannot create `{}`: {e}", logs.display())))?;
    write_atomically(&dir.join(SLICES_SCRIPT), plan.slices_script().as_bytes())?;
    let last = args.tasks - 1;
    if args.dry_run {
        let options: String = sbatch.iter().map(|o| format!("{} ", quote(o))).collect();
        println!(
            "wrote `{}`; nothing submitted. To submit it:",
            dir.join(SLICES_SCRIPT).display()
        );
        println!(
            "  cd {} && sbatch --parsable {options}{SLICES_SCRIPT}",
            quote(&utf8(dir)?)
        );
    } else {
        let array = submit(dir, sbatch, &[], SLICES_SCRIPT, "the job array")?;
        println!(
            "frames: job array {array}, tasks 0-{last}, logs in `{}`",
            logs.display()
        );
    }
    println!(
        "images: frames {first} to {last_frame} as `{}`, task I rendering every {}-th from frame {first} + I",
        output.display(),
        args.tasks
    );
    Ok(())
}

/// Submits the job array, then the merge after it, and returns their job ids. If the merge
/// cannot be submitted, the slices already are: the error says how to cancel them or submit
/// the merge by hand.
fn submit_both(dir: &Path, sbatch: &[String]) -> Result<(String, String), Failure> {
    let array = submit(dir, sbatch, &[], SLICES_SCRIPT, "the slices' job array")?;
    let dependency = format!("--dependency=afterok:{array}");
    let merge =
        submit(dir, sbatch, &[&dependency], MERGE_SCRIPT, "the merge job").map_err(|failure| {
            match failure {
                Failure::Input(why) => Failure::usage(format!(
                    "{why}. The slices were submitted as job {array}: cancel them with \
                 `scancel {array}`, or submit the merge by hand from `{}`: \
                 sbatch {dependency} {MERGE_SCRIPT}",
                    dir.display()
                )),
                other => other,
            }
        })?;
    Ok((array, merge))
}

/// The flags the merge job reads the scene with, as the tasks read it.
fn merge_flags(settings: &RenderSettings) -> Vec<String> {
    let mut flags = Vec::new();
    if settings.allow_outside {
        flags.push("--allow-outside".to_string());
    }
    if settings.max_triangles != rayforge_scene::DEFAULT_MAX_TRIANGLES {
        flags.extend([
            "--max-triangles".to_string(),
            settings.max_triangles.to_string(),
        ]);
    }
    flags
}

/// The render flags the slices of a cut image get, and the flags the merge adds for them:
/// `--denoise` is the merge's (a denoiser must see the whole image), the slices keeping the
/// albedo and normals that guide it (`--aovs`); `--aovs` is both, the slices keeping the AOVs
/// and the merge writing them.
fn merge_companions(render: &[String]) -> (Vec<String>, Vec<String>) {
    let denoise = render.iter().any(|f| f == "--denoise");
    let aovs = render.iter().any(|f| f == "--aovs");
    let mut tasks: Vec<String> = render
        .iter()
        .filter(|f| *f != "--denoise")
        .cloned()
        .collect();
    let mut merge = Vec::new();
    if aovs {
        merge.push("--aovs".to_string());
    } else if denoise {
        tasks.push("--aovs".to_string());
    }
    if denoise {
        merge.push("--denoise".to_string());
    }
    (tasks, merge)
}

/// The render flags and the sbatch options. Once the render flags have begun, clap hands every
/// word that follows to them, `--` included (the sbatch options are its own only when no
/// render flag is given), so the render flags are cut at their first `--`; rayforge slurm's
/// own options found among them were given after a render flag, and are refused, named.
fn flags(args: &SlurmArgs) -> Result<(&[String], Vec<String>), Failure> {
    let (render, sbatch) = match args.render_flags.iter().position(|f| f == "--") {
        Some(at) => (&args.render_flags[..at], &args.render_flags[at + 1..]),
        None => (&args.render_flags[..], &[][..]),
    };
    let given = |f: &String, flag: &str| *f == flag || f.starts_with(&format!("{flag}="));
    for flag in render {
        if given(flag, "--slice") {
            return Err(Failure::usage(format!(
                "`{flag}`: rayforge slurm gives each task its slice; say how many with --tasks"
            )));
        }
        let own = ["--tasks", "--dry-run", "--slice-by", "--output"];
        if flag == "-o" || own.iter().any(|own| given(flag, own)) {
            return Err(Failure::usage(format!(
                "`{flag}` comes after a render flag: give rayforge slurm's own options (-o, \
                 --tasks, --slice-by, --dry-run) before the render flags"
            )));
        }
    }
    Ok((render, [sbatch, &args.sbatch[..]].concat()))
}

/// The settings and slice of the first task, from `rayforge render`'s own parser and checks,
/// so that flags a task would refuse are refused now, in the words `rayforge render` uses.
fn task_settings(
    args: &SlurmArgs,
    render_flags: &[String],
    scene: &Path,
    output: &Path,
) -> Result<(RenderSettings, Slice), Failure> {
    let mut argv: Vec<OsString> = vec!["rayforge".into(), "render".into(), scene.into()];
    argv.extend(["-o".into(), output.into()]);
    argv.extend(["--slice".into(), format!("0/{}", args.tasks).into()]);
    if let Some(cut) = args.slice_by {
        argv.extend(["--slice-by".into(), Cut::from_arg(Some(cut)).name().into()]);
    }
    argv.extend(render_flags.iter().map(OsString::from));
    let render = match Cli::try_parse_from(argv) {
        Ok(Cli {
            command: Subcommand::Render(render),
        }) => render,
        Ok(_) => {
            return Err(Failure::internal(
                "the render flags parsed as another command",
            ))
        }
        Err(e) => {
            let message = e.to_string();
            let first = message.lines().next().unwrap_or_default();
            return Err(Failure::usage(format!(
                "the render flags {render_flags:?} are not `rayforge render`'s: {}",
                first.trim_start_matches("error: ")
            )));
        }
    };
    let settings = RenderSettings::from_args(render)?;
    let slice = settings
        .slice
        .ok_or_else(|| Failure::internal("the first task's settings have no slice"))?;
    Ok((settings, slice))
}

/// `OUT.slurm`, beside the image: where the scripts, the parts and the logs go.
fn job_dir(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".slurm");
    PathBuf::from(name)
}

/// The image's absolute path (its directory exists: [`check_writable`] has said so).
fn absolute_output(output: &Path) -> Result<PathBuf, Failure> {
    let name = output
        .file_name()
        .ok_or_else(|| Failure::usage(format!("`{}` does not name a file", output.display())))?;
    let dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let dir = std::fs::canonicalize(dir)
        .map_err(|e| Failure::usage(format!("cannot find `{}`: {e}", dir.display())))?;
    Ok(dir.join(name))
}

/// A path as the scripts' text, which must be able to name it exactly.
fn utf8(path: &Path) -> Result<String, Failure> {
    path.to_str().map(str::to_string).ok_or_else(|| {
        Failure::usage(format!(
            "`{}` is not valid UTF-8, so a batch script cannot name it",
            path.display()
        ))
    })
}

/// Submits `script` (in `dir`, the working directory of its jobs) with `sbatch --parsable`,
/// the user's options, then `ours`, and returns the job's id; `what` names it in errors.
fn submit(
    dir: &Path,
    options: &[String],
    ours: &[&str],
    script: &str,
    what: &str,
) -> Result<String, Failure> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .args(options)
        .args(ours)
        .arg(script)
        .current_dir(dir)
        .output()
        .map_err(|e| match e.kind() {
            ErrorKind::NotFound => Failure::usage(format!(
                "cannot submit {what}: sbatch was not found on the PATH (run rayforge slurm on \
                 a machine of the Slurm cluster, or give --dry-run to write the scripts only)"
            )),
            _ => Failure::usage(format!("cannot run sbatch to submit {what}: {e}")),
        })?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(Failure::usage(format!(
            "sbatch refused {what} ({}): {}",
            output.status,
            clip_to(stderr.trim(), QUOTED_STDERR_CHARS)
        )));
    }
    job_id(&stdout).ok_or_else(|| {
        Failure::usage(format!(
            "sbatch submitted {what} but printed `{}`, not a job id",
            clip_to(stdout.trim(), QUOTED_STDERR_CHARS)
        ))
    })
}

/// The job id in `sbatch --parsable`'s output: `ID` or `ID;CLUSTER`.
fn job_id(stdout: &str) -> Option<String> {
    let id = stdout.trim().split(';').next()?;
    (!id.is_empty() && id.bytes().all(|b| b.is_ascii_digit())).then(|| id.to_string())
}

/// `bytes` in megabytes (or kilobytes, when below one), for the weight of the parts.
fn megabytes(bytes: u64) -> String {
    if bytes < 1_000_000 {
        format!("{:.0} kB", bytes as f64 / 1e3)
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parsable_job_id_is_read_with_or_without_its_cluster() {
        assert_eq!(job_id("1234\n").as_deref(), Some("1234"));
        assert_eq!(job_id("77;cluster\n").as_deref(), Some("77"));
        assert_eq!(job_id("Submitted batch job 5\n"), None);
        assert_eq!(job_id(""), None);
    }

    #[test]
    fn the_job_directory_is_beside_the_image() {
        assert_eq!(job_dir(Path::new("/a/b.png")), Path::new("/a/b.png.slurm"));
    }
}
