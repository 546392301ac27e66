//! The OBJ reader on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pregrasp_io::mesh_io::parse_obj;

fuzz_target!(|data: &[u8]| {
    let _ = parse_obj(data, "fuzz.obj", 1.0);
});
