//! Reading text input files: UTF-8, with the line of the first invalid byte in the error (a
//! plain `read_to_string` says only "stream did not contain valid UTF-8").

use std::path::Path;

/// Reads `path` as UTF-8. Invalid UTF-8 is an `InvalidData` error naming the line and column
/// (1-based, column in bytes) of the first bad byte.
pub fn read_utf8(path: &Path) -> std::io::Result<String> {
    let bytes = std::fs::read(path)?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
        let col = valid.len() - valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1) + 1;
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("line {line}, column {col}: not valid UTF-8 text; save the file as UTF-8"),
        )
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn invalid_utf8_names_its_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.txt");
        std::fs::write(&path, b"ok\nab\xffc\n").unwrap();
        let e = super::read_utf8(&path).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
        assert!(e.to_string().starts_with("line 2, column 3:"), "{e}");
    }
}
