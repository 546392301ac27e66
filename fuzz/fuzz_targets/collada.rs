//! The mesh reader on arbitrary bytes named `m.dae`: the COLLADA check
//! (`geometry::collada::validate`), then mesh-loader on what passes it.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use nalgebra::Isometry3;
use pregrasp_urdf::geometry::mesh::parse;

fuzz_target!(|data: &[u8]| {
    let _ = parse(data, Path::new("m.dae"), [1.0; 3], &Isometry3::identity());
});
