//! A glTF model's buffers and other resources: the GLB's binary chunk, `data:` URIs, and
//! files beside the model (inside the scene's folder, within the model size limit).

use super::paths::error;
use crate::error::SceneError;
use crate::files::{read_bounded, Folder};
use crate::obj::MAX_MODEL_BYTES;
use base64::Engine;
use std::path::{Path, PathBuf};

/// The bytes of every buffer, in the file's order, each at least as long as it says.
pub(crate) type Buffers = Vec<Vec<u8>>;

/// Reads every buffer of `gltf` (the model file at `path`), taking the GLB's binary chunk.
pub(crate) fn load(
    path: &Path,
    gltf: &mut ::gltf::Gltf,
    folder: &Folder,
) -> Result<Buffers, SceneError> {
    let mut blob = gltf.blob.take();
    let mut out = Vec::new();
    for buffer in gltf.buffers() {
        let at = format!("buffers[{}]", buffer.index());
        let bytes = match buffer.source() {
            ::gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                error(
                    path,
                    &at,
                    "the buffer is the GLB's binary chunk, which the file lacks",
                )
            })?,
            ::gltf::buffer::Source::Uri(uri) => resource(path, &format!("{at}.uri"), uri, folder)?,
        };
        if bytes.len() < buffer.length() {
            return Err(error(
                path,
                format!("{at}.byteLength"),
                format!(
                    "the buffer says it holds {} bytes, but its data has {}",
                    buffer.length(),
                    bytes.len()
                ),
            ));
        }
        out.push(bytes);
    }
    for view in gltf.views() {
        let end = view.offset().checked_add(view.length());
        let size = out.get(view.buffer().index()).map_or(0, Vec::len);
        if end.is_none_or(|end| end > size) {
            return Err(error(
                path,
                format!("bufferViews[{}]", view.index()),
                format!(
                    "the view reaches past the end of its buffer ({} bytes from {}, in {size})",
                    view.length(),
                    view.offset()
                ),
            ));
        }
    }
    Ok(out)
}

/// The bytes a URI names: a `data:` URI's own (base64), or a file beside the model.
pub(crate) fn resource(
    path: &Path,
    at: &str,
    uri: &str,
    folder: &Folder,
) -> Result<Vec<u8>, SceneError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((header, data)) = rest.split_once(',') else {
            return Err(error(path, at, "the data URI has no `,` before its data"));
        };
        if !header.ends_with(";base64") {
            return Err(error(
                path,
                at,
                "only base64 data URIs are read (`;base64,`)",
            ));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(data.trim())
            .map_err(|e| error(path, at, format!("the data URI's base64 is damaged: {e}")));
    }
    let file = beside(path, uri).ok_or_else(|| {
        error(
            path,
            at,
            format!("`{}` is not a relative file name", crate::error::clip(uri)),
        )
    })?;
    folder.check(&file).map_err(|e| error(path, at, e))?;
    read_bounded(&file, MAX_MODEL_BYTES)
        .map_err(|e| error(path, at, format!("cannot read `{}`: {e}", file.display())))
}

/// The file a relative URI names beside the model at `path` (percent escapes decoded);
/// `None` for an absolute URI of another scheme.
fn beside(path: &Path, uri: &str) -> Option<PathBuf> {
    if uri.contains("://") || uri.starts_with('/') {
        return None;
    }
    let mut bytes = Vec::with_capacity(uri.len());
    let raw = uri.as_bytes();
    let mut i = 0;
    while i < raw.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            raw[i],
            raw.get(i + 1).and_then(|&b| hex(b)),
            raw.get(i + 2).and_then(|&b| hex(b)),
        ) {
            (b'%', Some(h), Some(l)) => {
                bytes.push((h * 16 + l) as u8);
                i += 3;
            }
            (b, _, _) => {
                bytes.push(b);
                i += 1;
            }
        }
    }
    let name = String::from_utf8(bytes).ok()?;
    Some(path.parent().unwrap_or(Path::new(".")).join(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_uris_are_decoded_beside_the_model() {
        let model = Path::new("/scenes/models/box.gltf");
        assert_eq!(
            beside(model, "tex%20ture/a%2Bb.png"),
            Some(PathBuf::from("/scenes/models/tex ture/a+b.png"))
        );
        assert_eq!(beside(model, "https://example.com/a.bin"), None);
        assert_eq!(beside(model, "/etc/passwd"), None);
    }
}
