//! How much of a file a reader takes: input files are regular files of bounded size, so a
//! wrong path (a device, a pipe) or a huge file is refused in words, not read into memory.

use std::io::Read;
use std::path::Path;

/// Largest scene file (bytes). A scene is a few hundred bytes of TOML; 4 MiB leaves room for
/// comments and inline data without letting a stray multi-gigabyte file be parsed.
pub const MAX_SCENE_BYTES: u64 = 4 << 20;

/// Largest mesh file (bytes): 1 GiB, a binary STL of about 20 million triangles.
pub const MAX_MESH_BYTES: u64 = 1 << 30;

/// The bytes of the regular file at `path`, refused (`InvalidInput`) when it is a folder,
/// pipe or device, or longer than `max` bytes. The size is checked before reading and the read
/// is capped, so a file that grows meanwhile cannot exceed it either.
pub fn read_limited(path: &Path, max: u64) -> std::io::Result<Vec<u8>> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a folder, pipe or device)",
        ));
    }
    let too_big = || {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{} is larger than the {} this input may have",
                bytes(meta.len().max(max + 1)),
                bytes(max)
            ),
        )
    };
    if meta.len() > max {
        return Err(too_big());
    }
    let mut out = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?
        .take(max + 1)
        .read_to_end(&mut out)?;
    if out.len() as u64 > max {
        return Err(too_big());
    }
    Ok(out)
}

/// `n` bytes in words: "4 MiB", "1.5 GiB", "812 bytes".
pub fn bytes(n: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if n < 1024 {
        return format!("{n} bytes");
    }
    let mut x = n as f64 / 1024.0;
    let mut unit = 0;
    while x >= 1024.0 && unit + 1 < UNITS.len() {
        x /= 1024.0;
        unit += 1;
    }
    let digits = if x.fract() == 0.0 { 0 } else { 1 };
    format!("{x:.digits$} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_words() {
        assert_eq!(bytes(812), "812 bytes");
        assert_eq!(bytes(4 << 20), "4 MiB");
        assert_eq!(bytes(3 << 29), "1.5 GiB");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.toml");
        std::fs::write(&path, vec![b'#'; 2048]).unwrap();
        assert_eq!(read_limited(&path, 4096).unwrap().len(), 2048);
        let err = read_limited(&path, 1024).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
        assert!(err.to_string().contains("larger than the 1 KiB"), "{err}");
        let err = read_limited(dir.path(), 1024).unwrap_err();
        assert!(err.to_string().contains("not a regular file"), "{err}");
    }
}
