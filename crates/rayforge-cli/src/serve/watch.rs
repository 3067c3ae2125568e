//! Noticing edits: the scene's folder is watched (with `notify`: inotify, FSEvents or
//! ReadDirectoryChangesW), and a change to the scene file, to a file whose name the scene's
//! text mentions (its models, textures, environment maps), or to a file the scene read when it
//! last loaded (a model's material library and its textures, a glTF model's buffers and
//! images) counts the files' generation up once the burst of events an editor's save makes
//! has settled.
//!
//! Whole folders are watched, not files: editors save by writing a new file and renaming it
//! over the old one, which a watch on the old file would lose.
//!
//! The scene's text (for the names it mentions) is read once at the start and once after each
//! settled change, never on an event: a folder busy with other files cost a read of the whole
//! scene per event, and a scene replaced by a link to `/dev/zero` grew the watch to 4.1 GB on
//! each. It is read as untrusted ([`scene_text`]): a regular file only, at most
//! [`rayforge_scene::MAX_SCENE_BYTES`], opened without blocking, so a FIFO swapped in for the
//! scene (which held the watch forever, and the page never followed an edit again) is passed
//! over like any file that does not read, and the next save is followed as ever.

use crate::failure::Failure;
use notify::{Event, EventKind, RecursiveMode, Watcher};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;
use tokio::sync::watch;

/// How long the files must stay quiet before a change counts: a save is several events
/// (write, rename, attributes), and one render for them is enough.
const SETTLE: Duration = Duration::from_millis(100);

/// The watch on the scene's folder; changes stop being noticed when it is dropped.
pub struct FileWatch {
    _watcher: notify::RecommendedWatcher,
}

/// The files a scene read when it last loaded (`rayforge_scene::Scene::files`), shared
/// between the renders that load it and the watch.
#[derive(Debug, Default)]
pub struct SceneFiles(Mutex<Vec<PathBuf>>);

impl SceneFiles {
    /// Remembers the files of the scene just loaded.
    pub fn set(&self, files: &[PathBuf]) {
        if let Ok(mut known) = self.0.lock() {
            known.clear();
            known.extend_from_slice(files);
        }
    }

    /// Whether `path` is one of them (by file name and its folder's name, as the event's path
    /// and the scene's may spell the same folder differently).
    fn holds(&self, path: &Path) -> bool {
        let key = |p: &Path| {
            let folder = p
                .parent()
                .and_then(Path::file_name)
                .map(|n| n.to_os_string());
            (folder, p.file_name().map(|n| n.to_os_string()))
        };
        let wanted = key(path);
        self.0
            .lock()
            .map(|known| known.iter().any(|k| key(k) == wanted))
            .unwrap_or(false)
    }
}

/// Starts watching the folder of the scene file `scene`; `changes` gets the generation of the
/// files (0 at first, one more after each settled change). A change to one of `files` counts
/// too.
pub fn start(
    scene: &Path,
    files: Arc<SceneFiles>,
    changes: watch::Sender<u64>,
) -> Result<FileWatch, Failure> {
    let folder = match scene.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let (events, received) = mpsc::channel();
    let mut watcher = notify::recommended_watcher(move |event: notify::Result<Event>| {
        // The settling thread has ended only when the server is going away.
        let _ = events.send(event);
    })
    .map_err(|e| Failure::internal(format!("cannot watch files for changes: {e}")))?;
    watcher
        .watch(&folder, RecursiveMode::Recursive)
        .map_err(|e| {
            Failure::usage(format!(
                "cannot watch `{}` for changes: {e}",
                folder.display()
            ))
        })?;
    let scene = scene.to_path_buf();
    std::thread::Builder::new()
        .name("rayforge-serve-watch".into())
        .spawn(move || settle(&scene, &files, &received, &changes))
        .map_err(|e| Failure::internal(format!("cannot start the file watch's thread: {e}")))?;
    Ok(FileWatch { _watcher: watcher })
}

/// Counts a generation up for each burst of events that touches the scene's files, until the
/// watcher or every listener is gone.
fn settle(
    scene: &Path,
    files: &SceneFiles,
    received: &mpsc::Receiver<notify::Result<Event>>,
    changes: &watch::Sender<u64>,
) {
    let mut text = scene_text(scene);
    while let Ok(event) = received.recv() {
        if !touches_scene(scene, &text, files, &event) {
            continue;
        }
        // Wait for quiet: whatever else arrives meanwhile is part of the same save.
        loop {
            match received.recv_timeout(SETTLE) {
                Ok(_) => continue,
                Err(mpsc::RecvTimeoutError::Timeout) => break,
                Err(mpsc::RecvTimeoutError::Disconnected) => return,
            }
        }
        text = scene_text(scene);
        changes.send_modify(|generation| *generation += 1);
        if changes.is_closed() {
            return;
        }
    }
}

/// The scene file's text, for the names it mentions; empty when it is not a regular file of at
/// most [`rayforge_scene::MAX_SCENE_BYTES`] of UTF-8 (the render that follows says why). It is
/// opened without blocking and checked before a byte is read: opening a FIFO to read waits for
/// a writer, and a device or a link to one never ends.
fn scene_text(scene: &Path) -> String {
    let read = || -> Option<String> {
        let file = open_without_blocking(scene)?;
        let meta = file.metadata().ok()?;
        if !meta.is_file() || meta.len() > rayforge_scene::MAX_SCENE_BYTES {
            return None;
        }
        let mut text = String::new();
        // Bounded again: the file may grow while it is read.
        file.take(rayforge_scene::MAX_SCENE_BYTES)
            .read_to_string(&mut text)
            .ok()?;
        Some(text)
    };
    read().unwrap_or_default()
}

/// The file at `path` opened to read, without waiting for a FIFO's writer.
#[cfg(unix)]
fn open_without_blocking(path: &Path) -> Option<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
        .ok()
}

/// The file at `path` opened to read, if it is a regular file (elsewhere a FIFO is not opened
/// by a path the scene's folder holds).
#[cfg(not(unix))]
fn open_without_blocking(path: &Path) -> Option<std::fs::File> {
    std::fs::metadata(path)
        .ok()
        .filter(std::fs::Metadata::is_file)?;
    std::fs::File::open(path).ok()
}

/// Whether an event may change the scene: it changes content or names (not a mere read), and
/// one of its files is the scene file, is named in the scene's `text` or was read by the scene
/// when it last loaded. A watcher's own error (events lost) counts, as anything may have
/// changed.
fn touches_scene(
    scene: &Path,
    text: &str,
    files: &SceneFiles,
    event: &notify::Result<Event>,
) -> bool {
    let event = match event {
        Ok(event) => event,
        Err(_) => return true,
    };
    if matches!(event.kind, EventKind::Access(_)) {
        return false;
    }
    event
        .paths
        .iter()
        .any(|path| is_scene_file(scene, path) || mentioned(text, path) || files.holds(path))
}

/// Whether `path` is the scene file (by name: the event's path is the watched folder's
/// spelling of it, which may differ from the command line's).
fn is_scene_file(scene: &Path, path: &Path) -> bool {
    path.file_name().is_some() && path.file_name() == scene.file_name()
}

/// Whether the scene's text names the file at `path` (by its file name: the scene names it
/// relative to its folder, perhaps in a sub-folder).
fn mentioned(text: &str, path: &Path) -> bool {
    path.file_name()
        .and_then(|name| name.to_str())
        .is_some_and(|name| !name.is_empty() && text.contains(name))
}

#[cfg(test)]
mod tests {
    use super::*;
    use notify::event::{AccessKind, CreateKind, ModifyKind};

    fn event(kind: EventKind, path: &str) -> notify::Result<Event> {
        Ok(Event::new(kind).add_path(PathBuf::from(path)))
    }

    #[test]
    fn edits_of_the_scene_and_its_files_count() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let scene = dir.path().join("scene.yml");
        std::fs::write(&scene, "- add: obj\n  file: models/teapot.obj\n").expect("written");
        let text = scene_text(&scene);
        let files = SceneFiles::default();
        let modify = EventKind::Modify(ModifyKind::Any);
        let here = |name: &str| dir.path().join(name).display().to_string();
        let touches = |e: &notify::Result<Event>| touches_scene(&scene, &text, &files, e);
        assert!(touches(&event(modify, &here("scene.yml"))));
        assert!(touches(&event(
            EventKind::Create(CreateKind::File),
            &here("models/teapot.obj")
        )));
        assert!(!touches(&event(modify, &here("notes.txt"))));
        assert!(!touches(&event(
            EventKind::Access(AccessKind::Any),
            &here("scene.yml")
        )));
        assert!(touches(&Err(notify::Error::generic("lost"))));
        // The model's material library is not named in the scene's text: it counts once the
        // scene has loaded and said it read it.
        let library = here("models/teapot.mtl");
        assert!(!touches(&event(modify, &library)));
        files.set(&[
            dir.path().join("models/teapot.obj"),
            dir.path().join("models/teapot.mtl"),
        ]);
        assert!(touches(&event(modify, &library)));
    }

    /// Makes a FIFO at `path`.
    #[cfg(unix)]
    fn fifo(path: &Path) {
        use std::os::unix::ffi::OsStrExt;
        let name = std::ffi::CString::new(path.as_os_str().as_bytes()).expect("a path");
        // SAFETY: `name` is a NUL-terminated path that lives across the call.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0, "mkfifo");
    }

    /// Runs `f` on a thread of its own, failing (not hanging) if it has not returned within a
    /// minute: what it waits for, a FIFO's writer, never comes.
    fn within_a_minute<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
        let (sent, received) = mpsc::channel();
        std::thread::spawn(move || {
            let _ = sent.send(f());
        });
        received
            .recv_timeout(Duration::from_secs(60))
            .expect("returned without waiting for a FIFO's writer")
    }

    /// The finding: the watch read the whole scene on every event, whatever it was (a link to
    /// `/dev/zero` grew it to 4.1 GB), and blocked for ever opening a FIFO.
    #[cfg(unix)]
    #[test]
    fn the_scene_text_is_read_only_from_a_bounded_regular_file() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let plain = dir.path().join("scene.yml");
        std::fs::write(&plain, "- add: sphere\n").expect("written");
        assert_eq!(scene_text(&plain), "- add: sphere\n");
        let pipe = dir.path().join("pipe.yml");
        fifo(&pipe);
        let zero = dir.path().join("zero.yml");
        std::os::unix::fs::symlink("/dev/zero", &zero).expect("a link");
        let huge = dir.path().join("huge.yml");
        std::fs::File::create(&huge)
            .and_then(|f| f.set_len(rayforge_scene::MAX_SCENE_BYTES + 1))
            .expect("a sparse file");
        for path in [pipe, zero, huge, dir.path().to_path_buf()] {
            let shown = path.display().to_string();
            assert_eq!(within_a_minute(move || scene_text(&path)), "", "{shown}");
        }
    }

    /// Waits (a minute at most) for the files' generation to reach `wanted`.
    fn generation_reaches(changes: &watch::Receiver<u64>, wanted: u64) {
        let deadline = std::time::Instant::now() + Duration::from_secs(60);
        while *changes.borrow() < wanted {
            assert!(
                std::time::Instant::now() < deadline,
                "the watch did not reach generation {wanted}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The finding: a FIFO swapped in for the scene held the watch, and the page never followed
    /// a later edit. Now the swap is one change and the next save another.
    #[cfg(unix)]
    #[test]
    fn a_fifo_swapped_in_for_the_scene_leaves_later_edits_followed() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let scene = dir.path().join("scene.yml");
        std::fs::write(&scene, "- add: sphere\n").expect("written");
        let (generation, changes) = watch::channel(0);
        let _watch = start(&scene, Arc::default(), generation).expect("watches");
        let pipe = dir.path().join("pipe");
        fifo(&pipe);
        std::fs::rename(&pipe, &scene).expect("the FIFO swapped in");
        generation_reaches(&changes, 1);
        let saved = dir.path().join("saved.tmp");
        std::fs::write(&saved, "- add: cube\n").expect("written");
        let seen = *changes.borrow();
        std::fs::rename(&saved, &scene).expect("saved over the FIFO");
        generation_reaches(&changes, seen + 1);
    }
}
