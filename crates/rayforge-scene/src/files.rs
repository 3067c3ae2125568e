//! Reading a file a scene names, within a limit: below both the scene file's reader and the
//! asset readers (models, images), so that neither has to import the other for it.

use std::io::Read;
use std::path::Path;

/// Reads a whole file of at most `limit` bytes; the error is the reason, for the caller to
/// put in context. Refuses what is not a regular file (a directory, `/dev/zero`, a pipe that
/// would never end) and stops reading past the limit, so neither a huge file nor an endless
/// device can take all memory.
pub(crate) fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err("it is not a regular file".into());
    }
    if meta.len() > limit {
        return Err(format!("it is {} bytes; the limit is {limit}", meta.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!("it grew past the limit of {limit} bytes"));
    }
    Ok(bytes)
}
