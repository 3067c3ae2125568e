//! The two batch scripts `rayforge slurm` writes: the job array whose task I renders slice I,
//! and the merge job that joins the parts once every slice has succeeded.
//!
//! The scripts are plain `sh`, self-contained and readable, so that a user can submit them by
//! hand, re-run one slice (`sbatch --array=5 slices.sh`) or copy them as a starting point.
//! Every path in a command is absolute and shell-quoted (the tasks run on other nodes, from
//! whatever directory); the `#SBATCH` lines name only paths relative to the scripts' directory,
//! which is where they are submitted from, because sbatch's own parsing of those lines is not
//! a shell's and a path with a space or a `%` would be misread there.

use crate::slice::Cut;

/// The directory of the tasks' logs, in the scripts' directory (their `#SBATCH` lines name it
/// relative to it).
pub const LOG_DIR: &str = "logs";

/// The file name of the job array's script.
pub const SLICES_SCRIPT: &str = "slices.sh";

/// The file name of the merge job's script.
pub const MERGE_SCRIPT: &str = "merge.sh";

/// The file name of the list of part files the merge job reads (`rayforge merge --list`).
pub const PARTS_LIST: &str = "parts.list";

/// What the scripts need to know, every path absolute and valid UTF-8.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plan {
    /// The rayforge executable the tasks run (the one running now).
    pub rayforge: String,
    /// The scene file.
    pub scene: String,
    /// The image the merge writes.
    pub output: String,
    /// The directory of the part files.
    pub parts: String,
    /// The list of part files (`PARTS_LIST` in the scripts' directory).
    pub parts_list: String,
    /// How many slices (array tasks).
    pub tasks: u64,
    /// How the render is cut.
    pub cut: Cut,
    /// The render flags, given to every task as they are.
    pub render_flags: Vec<String>,
    /// The flags the merge reads the scene with (for its canvas items), as the tasks read it:
    /// `--allow-outside` and `--max-triangles` when the render flags give them.
    pub merge_flags: Vec<String>,
    /// Whether the render flags set the thread count; if not, a task takes Slurm's
    /// `--cpus-per-task` when it is given.
    pub threads_given: bool,
    /// Whether the render is an animation (`--frames`): task I then renders its share of the
    /// frames whole, straight to their numbered images, and there is nothing to merge.
    pub frames: bool,
}

impl Plan {
    /// The part file of slice `index` (as the tasks and the merge name it).
    pub fn part(&self, index: u64) -> String {
        format!("{}/{}", self.parts, part_name(&index.to_string()))
    }

    /// The job array's script: task I renders slice I to its part file.
    pub fn slices_script(&self) -> String {
        let last = self.tasks - 1;
        let target = if self.frames {
            quote(&self.output)
        } else {
            format!(
                "{}/{}",
                quote(&self.parts),
                part_name("\"$SLURM_ARRAY_TASK_ID\"")
            )
        };
        let mut command = vec![
            quote(&self.rayforge),
            "render".to_string(),
            quote(&self.scene),
            "-o".to_string(),
            target,
            "--slice".to_string(),
            format!("auto/{}", self.tasks),
            "--slice-by".to_string(),
            self.cut.name().to_string(),
        ];
        if !self.threads_given {
            // Without it, rayforge would start a thread per core of the node, however many
            // CPUs Slurm gave the task: tasks sharing a node would fight over its cores.
            command.push("${SLURM_CPUS_PER_TASK:+--threads=$SLURM_CPUS_PER_TASK}".to_string());
        }
        command.extend(self.render_flags.iter().map(|f| quote(f)));
        let what = if self.frames {
            "its share of the animation's frames (every\n# {tasks}-th from the I-th), each to its own image. A frame already written is skipped"
        } else {
            "slice I of {tasks} of the scene\n# to its part file. A task whose part is already complete renders nothing"
        }
        .replace("{tasks}", &self.tasks.to_string());
        format!(
            "#!/bin/sh
# Written by `rayforge slurm`: task I of this job array renders {what}, so a requeued or
# re-submitted task costs a scene load. Re-run some tasks by hand, from this directory:
#   sbatch --array=3,5 {SLICES_SCRIPT}
#SBATCH --job-name=rayforge-slices
#SBATCH --array=0-{last}
#SBATCH --requeue
#SBATCH --open-mode=append
#SBATCH --output={LOG_DIR}/slice-%a.log
set -eu
exec {command}
",
            command = command.join(" ")
        )
    }

    /// The merge job's script: the parts of every slice, named one a line in the list file
    /// the merge reads (so that a part missing is named by the merge, a part left from a
    /// render cut otherwise is not taken, and no argument list grows with the task count),
    /// joined into the image; the scene is named for its canvas items.
    pub fn merge_script(&self) -> String {
        let mut command = vec![
            quote(&self.rayforge),
            "merge".to_string(),
            "--list".to_string(),
            quote(&self.parts_list),
            "--scene".to_string(),
            quote(&self.scene),
        ];
        command.extend(self.merge_flags.iter().map(|f| quote(f)));
        command.extend(["-o".to_string(), quote(&self.output)]);
        format!(
            "#!/bin/sh
# Written by `rayforge slurm`: joins the {tasks} parts that {PARTS_LIST} names into the image
# once every slice has succeeded (it is submitted with --dependency=afterok:<the slices' job
# array>; if a slice fails, Slurm cancels it: submit the same `rayforge slurm` command again).
#SBATCH --job-name=rayforge-merge
#SBATCH --kill-on-invalid-dep=yes
#SBATCH --open-mode=append
#SBATCH --output={LOG_DIR}/merge.log
set -eu
exec {command}
",
            tasks = self.tasks,
            command = command.join(" "),
        )
    }

    /// The list of part files the merge reads: every slice's, one a line, in slice order.
    pub fn parts_list(&self) -> String {
        (0..self.tasks).map(|i| self.part(i) + "\n").collect()
    }
}

/// The file name of a part, its index given as shell text.
fn part_name(index: &str) -> String {
    format!("part-{index}.part")
}

/// `text` as one word for `sh`: as it is when it holds only characters the shell leaves alone,
/// else in single quotes (inside which nothing is special but the quote itself).
pub fn quote(text: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_@%+=:,./-".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan() -> Plan {
        Plan {
            rayforge: "/opt/ray forge/rayforge".into(),
            scene: "/data/scene.yml".into(),
            output: "/data/out/frame.exr".into(),
            parts: "/data/out/frame.exr.slurm/parts".into(),
            parts_list: "/data/out/frame.exr.slurm/parts.list".into(),
            tasks: 4,
            cut: Cut::Samples,
            render_flags: vec!["--spp".into(), "64".into(), "--seed".into(), "it's".into()],
            merge_flags: vec!["--allow-outside".into()],
            threads_given: false,
            frames: false,
        }
    }

    #[test]
    fn an_animation_task_renders_its_frames_to_the_numbered_images() {
        let plan = Plan {
            output: "/data/out/frame-%04d.png".into(),
            cut: Cut::Rows,
            frames: true,
            ..plan()
        };
        let script = plan.slices_script();
        assert!(
            script.contains(" -o /data/out/frame-%04d.png --slice auto/4"),
            "{script}"
        );
        assert!(!script.contains("parts"), "{script}");
    }

    #[test]
    fn words_the_shell_would_split_or_expand_are_quoted() {
        assert_eq!(quote("/a/b-c_d.yml"), "/a/b-c_d.yml");
        assert_eq!(quote(""), "''");
        assert_eq!(quote("a b"), "'a b'");
        assert_eq!(quote("$HOME*"), "'$HOME*'");
        assert_eq!(quote("it's"), r"'it'\''s'");
    }

    #[test]
    fn the_array_script_runs_slice_i_of_n_for_task_i() {
        let script = plan().slices_script();
        assert!(script.contains("#SBATCH --array=0-3\n"), "{script}");
        assert!(script.contains("#SBATCH --requeue\n"), "{script}");
        assert!(
            script.contains(
                "exec '/opt/ray forge/rayforge' render /data/scene.yml -o \
                 /data/out/frame.exr.slurm/parts/part-\"$SLURM_ARRAY_TASK_ID\".part \
                 --slice auto/4 --slice-by samples \
                 ${SLURM_CPUS_PER_TASK:+--threads=$SLURM_CPUS_PER_TASK} --spp 64 --seed 'it'\\''s'\n"
            ),
            "{script}"
        );
    }

    #[test]
    fn threads_given_are_not_overridden() {
        let plan = Plan {
            threads_given: true,
            ..plan()
        };
        assert!(!plan.slices_script().contains("SLURM_CPUS_PER_TASK"));
    }

    #[test]
    fn the_merge_script_reads_every_part_from_the_list() {
        let script = plan().merge_script();
        assert!(
            script.ends_with(
                "\nexec '/opt/ray forge/rayforge' merge --list \
                 /data/out/frame.exr.slurm/parts.list --scene /data/scene.yml --allow-outside \
                 -o /data/out/frame.exr\n"
            ),
            "{script}"
        );
        assert_eq!(
            plan().part(2),
            "/data/out/frame.exr.slurm/parts/part-2.part"
        );
        let list = plan().parts_list();
        let names: Vec<&str> = list.lines().collect();
        assert_eq!(names.len(), 4);
        assert_eq!(names[3], "/data/out/frame.exr.slurm/parts/part-3.part");
    }
}
