//! Noticing edits: the scene's folder is watched (with `notify`: inotify, FSEvents or
//! ReadDirectoryChangesW), and a change to the scene file, to a file whose name the scene's
//! text mentions (its models, textures, environment maps), or to a file the scene read when it
//! last loaded (a model's material library and its textures, a glTF model's buffers and
//! images) counts the files' generation up once the burst of events an editor's save makes
//! has settled.
//!
//! Whole folders are watched, not files: editors save by writing a new file and renaming it
//! over the old one, which a watch on the old file would lose.

use crate::failure::Failure;
use notify::{Event, EventKind, RecursiveMode, Watcher};
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
    while let Ok(event) = received.recv() {
        if !touches_scene(scene, files, &event) {
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
        changes.send_modify(|generation| *generation += 1);
        if changes.is_closed() {
            return;
        }
    }
}

/// Whether an event may change the scene: it changes content or names (not a mere read), and
/// one of its files is the scene file, is named in the scene's text or was read by the scene
/// when it last loaded. A watcher's own error (events lost) counts, as anything may have
/// changed.
fn touches_scene(scene: &Path, files: &SceneFiles, event: &notify::Result<Event>) -> bool {
    let event = match event {
        Ok(event) => event,
        Err(_) => return true,
    };
    if matches!(event.kind, EventKind::Access(_)) {
        return false;
    }
    let text = std::fs::read_to_string(scene).unwrap_or_default();
    event
        .paths
        .iter()
        .any(|path| is_scene_file(scene, path) || mentioned(&text, path) || files.holds(path))
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
        let files = SceneFiles::default();
        let modify = EventKind::Modify(ModifyKind::Any);
        let here = |name: &str| dir.path().join(name).display().to_string();
        let touches = |e: &notify::Result<Event>| touches_scene(&scene, &files, e);
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
}
