//! The PLY loader on arbitrary bytes: an `Err` is fine, a panic, hang or overflow is not.
//! A mesh that loads must give finite mass properties without panicking.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace_geometry::mesh::{MeshOptions, read_ply};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = read_ply(data, Path::new("fuzz.ply"), &MeshOptions::default()) {
        let _ = mesh.mass_properties();
        let _ = mesh.adjacency().boundary_edges();
    }
});
