//! A glTF file's buffers and images, read without trusting it: a URI is a `data:` URI or a
//! relative path that stays inside the file's folder (no absolute paths, no other schemes, no
//! `..` out of the folder, no symbolic link out of it), and every byte range is checked
//! against the data it points into before anything slices it.

use std::path::{Component, Path, PathBuf};

/// The bytes a URI names, or a message saying why there are none.
pub fn read_uri(uri: &str, folder: &Path) -> Result<Vec<u8>, String> {
    if uri.starts_with("data:") {
        // The gltf crate decodes base64 data URIs (with no base folder it reads nothing else).
        let source = gltf::buffer::Source::Uri(uri);
        return gltf::buffer::Data::from_source(source, None)
            .map(|d| d.0)
            .map_err(|e| format!("its data URI does not decode: {e}"));
    }
    let path = relative_path(uri)?;
    let full = folder.join(&path);
    // A symbolic link inside the folder may still point out of it.
    let (real, real_folder) = match (full.canonicalize(), folder.canonicalize()) {
        (Ok(r), Ok(f)) => (r, f),
        (Err(e), _) | (_, Err(e)) => return Err(format!("{}: {e}", full.display())),
    };
    if !real.starts_with(&real_folder) {
        return Err(format!(
            "{} resolves to {}, outside the glTF file's folder: refused",
            full.display(),
            real.display()
        ));
    }
    std::fs::read(&real).map_err(|e| format!("{}: {e}", full.display()))
}

/// A URI reference as a path below the folder: percent-decoded, relative, never above it.
fn relative_path(uri: &str) -> Result<PathBuf, String> {
    // A scheme is letters, digits, + - . before the first ':' (RFC 3986); a drive letter
    // (C:) is one too, and as absolute as a path.
    if let Some((scheme, _)) = uri.split_once(':')
        && !scheme.contains('/')
    {
        return Err(format!(
            "URI '{uri}' has the scheme '{scheme}:'; only data: URIs and paths relative to the glTF file are read"
        ));
    }
    let decoded = urlencoding::decode(uri)
        .map_err(|_| format!("URI '{uri}' does not percent-decode to UTF-8"))?;
    let path = Path::new(decoded.as_ref());
    let mut depth = 0usize;
    for c in path.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            Component::ParentDir => {
                return Err(format!(
                    "URI '{uri}' leads out of the glTF file's folder: refused"
                ));
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(format!(
                    "URI '{uri}' is an absolute path; glTF URIs are relative to the file: refused"
                ));
            }
        }
    }
    if depth == 0 {
        return Err(format!("URI '{uri}' names no file"));
    }
    Ok(path.to_path_buf())
}

/// Every buffer's bytes, in document order: the GLB's binary chunk or a URI's data, each at
/// least as long as the buffer says (a shorter one is a truncated file).
pub fn read_buffers(
    document: &gltf::Document,
    folder: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, String> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let what = match buffer.name() {
            Some(n) => format!("buffer {} ('{n}')", buffer.index()),
            None => format!("buffer {}", buffer.index()),
        };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| format!("{what} is the GLB binary chunk, but the file has none"))?,
            gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, folder).map_err(|e| format!("{what}: {e}"))?
            }
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "{what} has {} bytes but declares {} (a truncated file?)",
                data.len(),
                buffer.length()
            ));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// The bytes of a buffer view, checked against its buffer.
pub fn view_bytes<'b>(
    view: &gltf::buffer::View<'_>,
    buffers: &'b [Vec<u8>],
) -> Result<&'b [u8], String> {
    let data = &buffers[view.buffer().index()];
    view.offset()
        .checked_add(view.length())
        .and_then(|end| data.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "buffer view {} spans bytes {}..{} of buffer {}, which has {}",
                view.index(),
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index(),
                data.len()
            )
        })
}

/// An image's encoded bytes (from a buffer view or a URI), and a name for messages.
pub fn image_bytes(
    image: &gltf::Image<'_>,
    folder: &Path,
    buffers: &[Vec<u8>],
) -> Result<Vec<u8>, String> {
    match image.source() {
        gltf::image::Source::View { view, .. } => view_bytes(&view, buffers).map(<[u8]>::to_vec),
        gltf::image::Source::Uri { uri, .. } => read_uri(uri, folder),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_stay_inside_the_folder() {
        assert_eq!(
            relative_path("textures/a%20b.png").unwrap(),
            PathBuf::from("textures/a b.png")
        );
        assert_eq!(
            relative_path("textures/../b.bin").unwrap(),
            PathBuf::from("textures/../b.bin")
        );
        for bad in [
            "../secret.bin",
            "a/../../b.bin",
            "/etc/passwd",
            "file:///etc/passwd",
            "http://example.com/a.bin",
            "C:/a.bin",
            "%2e%2e/x.bin",
            ".",
            "%FF.bin",
        ] {
            assert!(relative_path(bad).is_err(), "{bad} was accepted");
        }
    }
}
