//! The on-disk cache of derived collision geometry.
//!
//! Directory: `$PREGRASP_CACHE_DIR`, else `$XDG_CACHE_HOME/pregrasp`, else
//! `$HOME/.cache/pregrasp` ([`default_cache_dir`]); entries live in its `urdf-geometry/`
//! folder as `<robot>-<key>.json`, `key` the digest of every input (see
//! [`crate::geometry::load`]). An entry is JSON (`serde_json` with exact float round trip)
//! holding the algorithm version, the key and the [`UrdfGeometry`].
//!
//! Writes are atomic: the entry is written to a temporary file in the same folder, synced,
//! then renamed over the final name, so a reader sees either no entry or a whole one, even
//! with several processes deriving the same robot. Reading never fails the load: a missing,
//! unreadable, unparsable or mismatched entry is reported as such and the geometry
//! recomputed (and the entry rewritten).

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::types::UrdfGeometry;

/// The cache folder from the environment (see the module documentation); `None` when no
/// variable gives one.
pub fn default_cache_dir() -> Option<PathBuf> {
    let var = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    var("PREGRASP_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("pregrasp")))
        .or_else(|| var("HOME").map(|d| d.join(".cache").join("pregrasp")))
}

#[derive(Serialize, Deserialize)]
struct Entry {
    version: String,
    key: String,
    geometry: UrdfGeometry,
}

/// The entry file for `robot` and `key` under the cache folder `dir`.
pub fn entry_path(dir: &Path, robot: &str, key: &str) -> PathBuf {
    let name: String = robot
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    dir.join("urdf-geometry").join(format!("{name}-{key}.json"))
}

/// Largest cache entry read (bytes): an entry holds hull vertices, kilobytes per link; 64 MiB
/// is far beyond any real robot's and bounds what a planted file can make us read.
pub const MAX_ENTRY_BYTES: u64 = 64 << 20;

/// What reading an entry found.
pub(crate) enum Read {
    Hit(UrdfGeometry),
    Absent,
    /// Present but not usable; the reason.
    Bad(String),
}

/// Reads the entry at `path`, accepting it only for this `version` and `key` and with its
/// pair indices in range.
pub(crate) fn read(path: &Path, version: &str, key: &str) -> Read {
    let bytes = match pregrasp_limits::read_limited(path, MAX_ENTRY_BYTES) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Read::Absent,
        Err(e) => return Read::Bad(e.to_string()),
    };
    let entry: Entry = match serde_json::from_slice(&bytes) {
        Ok(e) => e,
        Err(e) => return Read::Bad(format!("not a cache entry: {e}")),
    };
    let g = entry.geometry;
    let n = g.links.len();
    let in_range = g.self_collision_pairs.iter().all(|&(a, b)| a < b && b < n)
        && g.excluded_pairs.iter().all(|e| e.a < e.b && e.b < n)
        && g.links.iter().all(|l| l.pieces.len() == l.elements.len());
    if entry.version != version || entry.key != key || g.key != key || !in_range {
        return Read::Bad("stale or inconsistent entry".to_string());
    }
    Read::Hit(g)
}

/// Writes the entry atomically (temporary file, sync, rename); the error says why not.
pub(crate) fn write(path: &Path, version: &str, geometry: &UrdfGeometry) -> Result<(), String> {
    let dir = path.parent().ok_or("no folder")?;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let entry = Entry {
        version: version.to_string(),
        key: geometry.key.clone(),
        geometry: geometry.clone(),
    };
    let text = serde_json::to_vec(&entry).map_err(|e| e.to_string())?;
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let tmp = dir.join(format!(".tmp-{}-{nanos}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(&text)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("{}: {e}", path.display())
    })
}
