//! A command's output files: all or nothing, never over a device or an input.
//!
//! A command declares every path it may write before it does any work ([`Outputs::declare`]),
//! so a path it cannot write is refused before minutes of planning, and then stages the bytes
//! of each ([`Outputs::write`]). Nothing named is touched until [`Outputs::commit`]; an
//! [`Outputs`] dropped without it (an error, exit 1) removes its temporary files and any folder
//! it created, and leaves every named path as it was.
//!
//! What a path may name:
//! - a regular file, or nothing yet (its folder must exist, or be made by
//!   [`Outputs::declare_creating_dirs`]): written to a temporary file in the same folder at
//!   declaration time and renamed over the path at commit, so a reader never sees half a file;
//!   a symbolic link is followed, the file it names is replaced and the link stays;
//! - a character device or a FIFO (`/dev/null`, `/dev/stdout`, a named pipe): written through
//!   at commit, never replaced by a file;
//! - anything else (a folder, a socket, a block device, a dangling link) is refused;
//! - so is a file declared twice, or a file the command reads ([`Outputs::reading`]).

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// Why an output cannot be written. Every message starts with the path as the user gave it.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{path}: cannot write: {error}")]
    Io { path: String, error: std::io::Error },
    #[error("{path}: {why}; give the path of a file")]
    NotAFile { path: String, why: &'static str },
    #[error("{path}: is also an input of this command ({what}); write the output elsewhere")]
    IsInput { path: String, what: String },
    #[error("{path}: given for two outputs; give each output its own path")]
    Twice { path: String },
    #[error("{path}: the folder {folder} does not exist")]
    NoFolder { path: String, folder: String },
}

/// One declared output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputId(usize);

/// How an output reaches its path.
enum Sink {
    /// A file: staged in `temp` (beside `target`, the path with links followed), renamed at
    /// commit; `written` once [`Outputs::write`] filled it.
    File {
        target: PathBuf,
        temp: NamedTempFile,
        written: bool,
    },
    /// A character device or FIFO: its bytes, written through at commit.
    Stream {
        target: PathBuf,
        bytes: Option<Vec<u8>>,
    },
}

struct Entry {
    /// The path as given, for messages.
    shown: String,
    /// The absolute path with links followed (or, for a file not there yet, its folder's).
    key: PathBuf,
    sink: Sink,
}

/// The outputs of one command (see the module documentation).
#[derive(Default)]
pub struct Outputs {
    entries: Vec<Entry>,
    /// Absolute paths (links followed) of the command's inputs, with what each is.
    inputs: Vec<(PathBuf, String)>,
    /// Folders made by [`Outputs::declare_creating_dirs`], outermost first.
    made_dirs: Vec<PathBuf>,
}

impl Outputs {
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Records that the command reads `path` (`what`: "the scene", "the mesh", …): declaring it
    /// as an output is then refused. A path that does not exist is ignored.
    pub fn reading(&mut self, path: &Path, what: &str) -> &mut Outputs {
        if let Ok(key) = std::fs::canonicalize(path) {
            self.inputs.push((key, what.to_string()));
        }
        self
    }

    /// Declares `path` as an output; its folder must exist.
    pub fn declare(&mut self, path: &Path) -> Result<OutputId, OutputError> {
        self.declare_inner(path, false)
    }

    /// Declares `path` as an output, making its folder (and any missing parent) if needed; the
    /// folders made are removed again unless the outputs are committed.
    pub fn declare_creating_dirs(&mut self, path: &Path) -> Result<OutputId, OutputError> {
        self.declare_inner(path, true)
    }

    fn declare_inner(&mut self, path: &Path, make_dirs: bool) -> Result<OutputId, OutputError> {
        let shown = path.display().to_string();
        let io = |error| OutputError::Io {
            path: shown.clone(),
            error,
        };
        let not_a_file = |why| OutputError::NotAFile {
            path: shown.clone(),
            why,
        };
        let (key, stream) = match std::fs::metadata(path) {
            Ok(meta) => {
                let kind = meta.file_type();
                let stream = is_stream(&kind);
                if meta.is_dir() {
                    return Err(not_a_file("is a folder"));
                }
                if !(meta.is_file() || stream) {
                    return Err(not_a_file(
                        "is a socket or block device, not a file, character device or pipe",
                    ));
                }
                (std::fs::canonicalize(path).map_err(io)?, stream)
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                if std::fs::symlink_metadata(path).is_ok() {
                    return Err(not_a_file("is a symbolic link to nothing"));
                }
                let name = path
                    .file_name()
                    .ok_or_else(|| not_a_file("names no file"))?;
                let folder = match path.parent() {
                    Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                    _ => PathBuf::from("."),
                };
                if !folder.is_dir() {
                    if make_dirs && !folder.exists() {
                        self.make_dirs(&folder).map_err(io)?;
                    } else {
                        return Err(OutputError::NoFolder {
                            path: shown,
                            folder: folder.display().to_string(),
                        });
                    }
                }
                (
                    std::fs::canonicalize(&folder).map_err(io)?.join(name),
                    false,
                )
            }
            Err(e) => return Err(io(e)),
        };
        if let Some((_, what)) = self.inputs.iter().find(|(k, _)| *k == key) {
            return Err(OutputError::IsInput {
                path: shown,
                what: what.clone(),
            });
        }
        // Several outputs may stream into one device (`/dev/null`); a file holds only one.
        if !stream && self.entries.iter().any(|e| e.key == key) {
            return Err(OutputError::Twice { path: shown });
        }
        let sink = if stream {
            Sink::Stream {
                target: key.clone(),
                bytes: None,
            }
        } else {
            let folder = key.parent().unwrap_or(Path::new("."));
            let temp = tempfile::Builder::new()
                .prefix(".pregrasp-")
                .suffix(".tmp")
                .tempfile_in(folder)
                .map_err(io)?;
            Sink::File {
                target: key.clone(),
                temp,
                written: false,
            }
        };
        self.entries.push(Entry { shown, key, sink });
        Ok(OutputId(self.entries.len() - 1))
    }

    /// Makes `folder` and its missing parents, remembering each one made.
    fn make_dirs(&mut self, folder: &Path) -> std::io::Result<()> {
        let mut missing = Vec::new();
        let mut at = Some(folder);
        while let Some(dir) = at {
            if dir.as_os_str().is_empty() || dir.exists() {
                break;
            }
            missing.push(dir.to_path_buf());
            at = dir.parent();
        }
        for dir in missing.into_iter().rev() {
            std::fs::create_dir(&dir)?;
            self.made_dirs.push(dir);
        }
        Ok(())
    }

    /// Stages the whole content of output `id` (a second call replaces the first).
    pub fn write(&mut self, id: OutputId, content: &[u8]) -> Result<(), OutputError> {
        let entry = &mut self.entries[id.0];
        let io = |error| OutputError::Io {
            path: entry.shown.clone(),
            error,
        };
        match &mut entry.sink {
            Sink::File { temp, written, .. } => {
                let file = temp.as_file_mut();
                file.set_len(0).map_err(io)?;
                std::io::Seek::rewind(file).map_err(io)?;
                file.write_all(content).map_err(io)?;
                file.flush().map_err(io)?;
                *written = true;
            }
            Sink::Stream { bytes, .. } => *bytes = Some(content.to_vec()),
        }
        Ok(())
    }

    /// The path of output `id` as it was given.
    pub fn shown(&self, id: OutputId) -> &str {
        &self.entries[id.0].shown
    }

    /// Writes every staged output to its path — streams first, then the files renamed into
    /// place — and returns the paths written, as given. Declared outputs never written are
    /// left alone.
    pub fn commit(mut self) -> Result<Vec<String>, OutputError> {
        let entries = std::mem::take(&mut self.entries);
        let mut done = Vec::new();
        for e in &entries {
            if let Sink::Stream {
                target,
                bytes: Some(bytes),
            } = &e.sink
            {
                let io = |error| OutputError::Io {
                    path: e.shown.clone(),
                    error,
                };
                // No truncation and no creation: a device or pipe is written into, as `>` would.
                let mut f: File = OpenOptions::new().write(true).open(target).map_err(io)?;
                f.write_all(bytes).map_err(io)?;
                f.flush().map_err(io)?;
                done.push(e.shown.clone());
            }
        }
        for e in entries {
            if let Sink::File {
                target,
                temp,
                written: true,
            } = e.sink
            {
                let io = |error| OutputError::Io {
                    path: e.shown.clone(),
                    error,
                };
                // Temporary files are created owner-only; the result is an ordinary file.
                #[cfg(unix)]
                {
                    use std::os::unix::fs::PermissionsExt;
                    temp.as_file()
                        .set_permissions(std::fs::Permissions::from_mode(0o644))
                        .map_err(io)?;
                }
                temp.persist(&target).map_err(|e| io(e.error))?;
                done.push(e.shown);
            }
        }
        self.made_dirs.clear();
        Ok(done)
    }
}

impl Drop for Outputs {
    /// Uncommitted: the temporary files go with their entries; the folders made are removed
    /// (innermost first) where they are empty again.
    fn drop(&mut self) {
        self.entries.clear();
        for dir in self.made_dirs.iter().rev() {
            let _ = std::fs::remove_dir(dir);
        }
    }
}

/// A character device or FIFO: written through, never replaced.
fn is_stream(kind: &std::fs::FileType) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        kind.is_char_device() || kind.is_fifo()
    }
    #[cfg(not(unix))]
    {
        let _ = kind;
        false
    }
}

/// Writes `content` to `path` as the one output of a command (see [`Outputs`]).
pub fn write_one(path: &Path, content: &[u8]) -> Result<(), OutputError> {
    let mut out = Outputs::new();
    let id = out.declare(path)?;
    out.write(id, content)?;
    out.commit().map(drop)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_is_written_until_commit_and_nothing_stays_without_it() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.json");
        std::fs::write(&a, "old").unwrap();
        let b = dir.path().join("new/deeper/b.svg");
        {
            let mut out = Outputs::new();
            let ia = out.declare(&a).unwrap();
            let ib = out.declare_creating_dirs(&b).unwrap();
            out.write(ia, b"new a").unwrap();
            out.write(ib, b"new b").unwrap();
            assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
        }
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
        assert!(
            !dir.path().join("new").exists(),
            "a folder made stays behind"
        );
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "a temporary file stays behind");

        let mut out = Outputs::new();
        let ia = out.declare(&a).unwrap();
        let ib = out.declare_creating_dirs(&b).unwrap();
        out.write(ia, b"new a").unwrap();
        out.write(ib, b"new b").unwrap();
        out.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
    }

    #[test]
    fn the_same_file_twice_or_an_input_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.toml");
        std::fs::write(&scene, "x").unwrap();
        let mut out = Outputs::new();
        out.reading(&scene, "the scene");
        let err = out.declare(&scene).unwrap_err();
        assert!(
            err.to_string()
                .contains("input of this command (the scene)"),
            "{err}"
        );
        out.declare(&dir.path().join("o.json")).unwrap();
        let again = dir.path().join(".").join("o.json");
        let err = out.declare(&again).unwrap_err();
        assert!(err.to_string().contains("two outputs"), "{err}");
        let err = out.declare(dir.path()).unwrap_err();
        assert!(err.to_string().contains("is a folder"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_followed_and_stays_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.json");
        std::fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.json");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_one(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
    }

    #[cfg(unix)]
    #[test]
    fn a_character_device_stays_a_device() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        write_one(null, b"into the void").unwrap();
        let mut out = Outputs::new();
        out.declare(null).unwrap();
        out.declare(null).unwrap();
        assert!(std::fs::metadata(null)
            .unwrap()
            .file_type()
            .is_char_device());
    }
}
