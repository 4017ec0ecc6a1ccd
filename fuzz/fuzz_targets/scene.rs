//! Fuzz target: the scene reader must return `Ok` or a `SceneError`, never panic or hang,
//! whatever the bytes (invalid UTF-8 included, as `scene::load` would see them).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match std::str::from_utf8(data) {
        Ok(text) => {
            let _ = pbdda::scene::parse(text, "fuzz.toml");
        }
        Err(_) => {
            let _ = pbdda::scene::parse_bytes(data, "fuzz.toml");
        }
    }
});
