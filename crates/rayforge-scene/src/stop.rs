//! Stopping a load part-way: the flag that Ctrl-C, a termination signal or the live page's
//! cancel sets, looked at by every reader once per unit of its work (a YAML item and each part
//! it builds, an OBJ statement, a PLY element, a glTF node and primitive, a pbrt directive
//! and each shape it makes), so that a scene of millions of parts stops within one part, not
//! after the whole file. A unit is short (microseconds): no reader looks at the flag inside a
//! unit, and none checks the time.

use crate::error::SceneError;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

/// The flag a load stops at (see the [module](self)); none by default.
#[derive(Debug, Clone, Default)]
pub struct StopFlag(Option<Arc<AtomicBool>>, Option<Arc<AtomicU64>>);

impl StopFlag {
    /// Stops the load once `flag` is set (by another thread: a signal handler, a server).
    pub fn new(flag: Arc<AtomicBool>) -> Self {
        Self(Some(flag), None)
    }

    /// A flag that sets itself at the reader's `looks`-th look at it (from 1), the same on
    /// every run: what tests stop a load partway with, at a known unit, instead of by time.
    /// The library's builds that take [`StopFlag::flag`] see it once it has set itself.
    #[doc(hidden)]
    pub fn set_at_look(looks: u64) -> Self {
        Self(
            Some(Arc::new(AtomicBool::new(false))),
            Some(Arc::new(AtomicU64::new(looks))),
        )
    }

    /// Whether the flag is set (a relaxed load: nothing else is read through it).
    pub fn is_set(&self) -> bool {
        let Some(flag) = &self.0 else {
            return false;
        };
        if let Some(left) = &self.1 {
            let before = left.fetch_sub(1, Ordering::Relaxed);
            if before <= 1 {
                left.store(0, Ordering::Relaxed);
                flag.store(true, Ordering::Relaxed);
            }
        }
        flag.load(Ordering::Relaxed)
    }

    /// The flag itself, for the library's builds that stop at it (a mesh's BVH, the
    /// tessellation): `None` when nothing stops the load.
    pub fn flag(&self) -> Option<&AtomicBool> {
        self.0.as_deref()
    }

    /// `Err` with the interrupted error for `path` once the flag is set; each reader places it
    /// where it stopped.
    pub(crate) fn check(&self, path: &Path) -> Result<(), SceneError> {
        if self.is_set() {
            Err(SceneError::interrupted(path))
        } else {
            Ok(())
        }
    }
}

/// Two options are the same when they stop at the same flag (or neither at any).
impl PartialEq for StopFlag {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            _ if self.1.is_some() != other.1.is_some() => false,
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

impl Eq for StopFlag {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flag_stops_once_set_and_none_never() {
        let flag = Arc::new(AtomicBool::new(false));
        let stop = StopFlag::new(flag.clone());
        let path = Path::new("scene.yml");
        assert!(stop.check(path).is_ok());
        flag.store(true, Ordering::Relaxed);
        let e = stop.check(path).unwrap_err();
        assert!(e.interrupted, "{e}");
        assert!(StopFlag::default().check(path).is_ok());
        assert_eq!(stop, stop.clone());
        assert_ne!(stop, StopFlag::new(Arc::new(AtomicBool::new(true))));
        assert_ne!(stop, StopFlag::default());
    }

    fn set() -> StopFlag {
        StopFlag::new(Arc::new(AtomicBool::new(true)))
    }

    #[test]
    fn an_obj_model_stops_at_its_first_statement() {
        let mut text = String::new();
        for i in 0..1000 {
            text.push_str(&format!("v {i} 0 0\nv {i} 1 0\nv {i} 0 1\nf -3 -2 -1\n"));
        }
        let path = Path::new("m.obj");
        let whole = crate::obj::parse_obj_in(&text, path, 10_000, &StopFlag::default()).unwrap();
        assert_eq!(whole.groups[0].triangles.len(), 1000);
        let e = crate::obj::parse_obj_in(&text, path, 10_000, &set()).unwrap_err();
        assert!(e.interrupted, "{e}");
        assert_eq!(e.span.map(|s| (s.line, s.column)), Some((1, 1)), "{e}");
    }

    #[test]
    fn a_ply_model_stops_at_its_first_element() {
        let mut text = String::from(
            "ply\nformat ascii 1.0\nelement vertex 300\nproperty float x\nproperty float y\n\
             property float z\nelement face 100\nproperty list uchar int vertex_indices\n\
             end_header\n",
        );
        for i in 0..300 {
            text.push_str(&format!("{i} {} 0\n", i % 2));
        }
        for i in 0..100 {
            text.push_str(&format!("3 {} {} {}\n", 3 * i, 3 * i + 1, 3 * i + 2));
        }
        let path = Path::new("m.ply");
        let bytes = text.as_bytes();
        let whole = crate::ply::parse_ply_in(bytes, path, 1000, &StopFlag::default()).unwrap();
        assert_eq!(whole.face_count(), 100);
        let e = crate::ply::parse_ply_in(bytes, path, 1000, &set()).unwrap_err();
        assert!(e.interrupted, "{e}");
        assert_eq!(e.key.as_deref(), Some("vertex"), "{e}");
        // Before the first vertex's line: the header's last line.
        assert_eq!(e.span.map(|s| s.line), Some(9), "{e}");
    }
}
