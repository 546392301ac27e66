//! The scene parser on arbitrary text: an error or a scene, never a panic or a hang.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use pregrasp_io::scene::Scene;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = Scene::from_str(text, Path::new("fuzz.toml"));
    }
});
