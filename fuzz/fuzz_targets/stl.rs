//! The STL reader (binary and ASCII) on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pregrasp_io::mesh_io::parse_stl;

fuzz_target!(|data: &[u8]| {
    let _ = parse_stl(data, "fuzz.stl", 1.0);
});
