//! Bounded input: what pregrasp reads from files is checked before it is parsed.
//!
//! * [`read_limited`]: the bytes of a **regular** file of at most a given size. A folder, FIFO,
//!   socket or device (`/dev/zero`) is refused without being opened — opening a FIFO blocks
//!   until a writer comes, reading a character device never ends — and the size is checked
//!   before reading and again while reading, so a file that grows meanwhile cannot exceed it.
//! * [`xml`]: an XML document's depth and node count checked by a non-recursive reader
//!   (roxmltree keeps an explicit parent stack), so that the recursive readers behind the
//!   URDF and COLLADA parsers only ever see documents they can walk without overflowing the
//!   stack.
//!
//! The limits each input has are constants next to its reader: [`MAX_DESCRIPTION_BYTES`] and
//! [`MAX_COLLISION_MESH_BYTES`] here for robot descriptions, the scene and mesh limits in
//! `pregrasp-io`.

pub mod xml;

use std::io::Read;
use std::path::Path;

/// Largest robot description (URDF) read: 16 MiB. The descriptions of real arms are 10–500 KB
/// (a xacro-expanded humanoid about 1 MB); a 300 MB file is not a description.
pub const MAX_DESCRIPTION_BYTES: u64 = 16 << 20;

/// Largest collision mesh a description may name: 128 MiB, a binary STL of 2.8 million
/// triangles. Collision meshes of real arms are 10 KB–5 MB.
pub const MAX_COLLISION_MESH_BYTES: u64 = 128 << 20;

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

/// [`read_limited`] as UTF-8 text (`InvalidData` when it is not).
pub fn read_text_limited(path: &Path, max: u64) -> std::io::Result<String> {
    String::from_utf8(read_limited(path, max)?).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        )
    })
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

    #[cfg(unix)]
    #[test]
    fn a_character_device_is_refused_unread() {
        let err = read_limited(Path::new("/dev/zero"), 1 << 30).unwrap_err();
        assert!(err.to_string().contains("not a regular file"), "{err}");
    }

    #[test]
    fn text_that_is_not_utf8_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.urdf");
        std::fs::write(&path, b"<robot\xff>").unwrap();
        let err = read_text_limited(&path, 1024).unwrap_err();
        assert!(err.to_string().contains("not UTF-8 text (byte 6)"), "{err}");
    }
}
