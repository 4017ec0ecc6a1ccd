//! Fuzz target: the gmsh reader must return `Ok` or a `MeshError`, never panic or hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = pbdda::mesh::Mesh::parse("fuzz.msh", data);
});
