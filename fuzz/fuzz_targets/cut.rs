//! Fuzz target: the block cutter must return `Ok` or a `CutError`, never panic or hang; on `Ok`
//! the blocks' areas obey the identity of `cut_input` (shared with tests/rockmass_cut.rs).
#![no_main]

mod cut_input;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (spec, expected) = cut_input::decode(data);
    if let Ok(c) = pbdda::rockmass::cut(&spec) {
        cut_input::check_area(&spec, &c, expected);
    }
});
