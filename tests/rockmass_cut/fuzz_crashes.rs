//! The inputs on which `cargo fuzz run cut` found the cutter failing (module header in
//! tests/rockmass_cut.rs), each a test.

use super::cut_input::{check, check_area, decode};
use pbdda::rockmass::{CutError, CutSpec, cut};

/// The blocks' total area less `expected` (the domain less the removed excavation, shoelace of
/// the input polygons, as `decode` computes it), relative to `expected`.
fn area_error(spec: &CutSpec, expected: f64) -> f64 {
    let c = cut(spec).unwrap_or_else(|e| panic!("{e}"));
    (c.blocks.iter().map(|b| b.area).sum::<f64>() - expected) / expected
}

/// Decodes a crash input: its spec and its closed-form area (the decoder's identity applies).
fn decoded(data: &[u8]) -> (CutSpec, f64) {
    let (spec, expected) = decode(data);
    (spec, expected.unwrap_or_else(|| panic!("the area identity applies to this input")))
}

/// The message of a refused cut.
fn refusal(spec: &CutSpec) -> CutError {
    match cut(spec) {
        Ok(c) => panic!("cut into {} blocks, but the cut must be refused", c.blocks.len()),
        Err(e) => e,
    }
}

/// The first crash (spade's `!previous_region.is_empty() || from == final_vertex`).
#[test]
fn crash_141367992574() {
    check(include_bytes!("../../fuzz/crashes/cut/crash-141367992574cda1dabce779d78ccd860eb82472"));
}

/// The fuzz target's area identity (header above) on the input it stopped on after 4,475
/// executions: the blocks summed to 17.57318029975338 against 17.58412627092939 for the
/// domain less the removed excavation (closed form, shoelace of the two input polygons).
#[test]
fn area_6f7d9fea10b3() {
    check(include_bytes!("../../fuzz/crashes/cut/area-6f7d9fea10b36ae87f22a0a0c8b8ceb903537f5c"));
}

/// Every input of the kept fuzz corpus (fuzz/corpus/cut) cuts or is refused with an error
/// naming its input (spacing, block limit, ...), never by the panic guard around the
/// triangulation (`CutError::Degenerate` "triangulation failed"); a cut passes the area
/// identity above.
#[test]
fn the_fuzz_corpus_never_reaches_the_panic_guard() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/cut");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap_or_else(|e| panic!("{e}")).path())
        .collect();
    files.sort();
    assert!(!files.is_empty());
    for f in files {
        let (spec, expected) = decode(&std::fs::read(&f).unwrap_or_else(|e| panic!("{e}")));
        match cut(&spec) {
            Ok(c) => check_area(&spec, &c, expected),
            Err(pbdda::rockmass::CutError::Degenerate { message, .. })
                if message.contains("triangulation failed") =>
            {
                panic!("{}: {message}", f.display())
            }
            Err(_) => {}
        }
    }
}

/// A removed excavation, an 18-gon of radius 0.078 m (edges 2 r sin(10 deg) = 2.714e-2 m), with
/// min_edge 2.793e-2 m: every edge is shorter than the merge distance, so its corners would all
/// merge and the excavation vanish (the blocks once summed to the domain, 154.01742, against
/// 153.97799). The cut is refused, naming the excavation and its first edge (math note §12.8).
/// With min_edge 0.01 m (below the edges) it cuts, and the blocks sum to the domain less the
/// 18-gon (closed form, shoelace) to 1e-12 relative: no corner of either outline moves (the
/// merges are of crossings onto corners, along the outline), so only the rounding of the
/// shoelace sums over coordinates of 10 m (1e-16 relative each) remains.
#[test]
fn area_1796cfb766be() {
    let (mut spec, expected) =
        decoded(include_bytes!("../../fuzz/crashes/cut/area-1796cfb766be7d9b665c5fb7089d4e7f7162ea1f"));
    match refusal(&spec) {
        CutError::Excavation { excavation: 1, message } => {
            assert!(message.contains("edge vertices[0]-vertices[1] is 2.714e-2 m long"), "{message}");
            assert!(message.contains("shorter than the merge distance 2.793e-2 m"), "{message}");
        }
        e => panic!("{e}"),
    }
    spec.min_edge = 0.01;
    assert!(area_error(&spec, expected).abs() < 1e-12);
}

/// A joint polyline that closes a thin triangle (its long sides 1.8e-3 rad apart) whose sides
/// meet the domain's outline 2.294e-2 m apart, below min_edge 2.500e-2 m. Merging the two
/// crossings pinches the triangle off the block around it: that block's outline touches itself
/// at the merged vertex around a clockwise loop of 6.998e-2 m2 (the triangle), which, dropped,
/// made the blocks overlap (100.15302 against the domain's 100.08304). The cut is refused
/// (math note §12.8). With min_edge 0.01 m (below 2.294e-2) it cuts into the triangle and the
/// rest, and the blocks sum to the domain (no excavation; closed form, shoelace) to 1e-12
/// relative, as above.
#[test]
fn area_82b682ccdc23() {
    let (mut spec, expected) =
        decoded(include_bytes!("../../fuzz/crashes/cut/area-82b682ccdc23c91ffb3aa4034c0a3bbe5e313848"));
    assert!(spec.excavations.is_empty());
    match refusal(&spec) {
        CutError::Degenerate { message, .. } => {
            assert!(message.contains("pinches off a hole of area 6.998e-2 m2"), "{message}")
        }
        e => panic!("{e}"),
    }
    spec.min_edge = 0.01;
    assert!(area_error(&spec, expected).abs() < 1e-12);
}

/// A kept excavation (an 18-gon of 3.417 m2) whose corner reaches 1.0e-3 m past the domain's
/// outline, with min_edge 0.05 m: the two crossings of its edges with the outline,
/// 1.244e-2 m apart, merge, and the block around it would hold it as a hole pinched at that
/// point; dropped, that loop made the blocks sum to 83.50286 against 80.08555 (the domain less
/// the removed 11-gon). The cut is refused (math note §12.8). With min_edge 0.01 m it cuts, and
/// the blocks sum to the domain less the removed 11-gon (closed form, shoelace; the kept one's
/// part beyond the outline lies outside the domain) to 1e-12 relative, as above.
#[test]
fn area_4cd97f3d936e() {
    let (mut spec, expected) =
        decoded(include_bytes!("../../fuzz/crashes/cut/area-4cd97f3d936e4c7adf2f96cb8e76830281079979"));
    match refusal(&spec) {
        CutError::Degenerate { message, .. } => {
            assert!(message.contains("pinches off a hole of area 3.417e0 m2"), "{message}")
        }
        e => panic!("{e}"),
    }
    spec.min_edge = 0.01;
    assert!(area_error(&spec, expected).abs() < 1e-12);
}

/// A joint passing 1.04e-3 m from a corner of a kept triangle (0.4127 m2) inside the domain, with
/// min_edge 0.041 m: the corner takes the joint's two crossings with the triangle's edges, and the
/// block beside it would hold the triangle as a hole pinched at that corner; dropped, that loop
/// made the blocks sum to 143.15297 against 142.74024. The cut is refused (math note §12.8).
/// With min_edge 1e-4 m it cuts without a merge, and the blocks sum to the domain less the
/// removed 17-gon (closed form, shoelace) to 1e-12 relative, as above.
#[test]
fn area_0134ee0417e4() {
    let (mut spec, expected) =
        decoded(include_bytes!("../../fuzz/crashes/cut/area-0134ee0417e4d0c2a629976e34f20b0294d14b22"));
    match refusal(&spec) {
        CutError::Degenerate { message, .. } => {
            assert!(message.contains("pinches off a hole of area 4.127e-1 m2"), "{message}")
        }
        e => panic!("{e}"),
    }
    spec.min_edge = 1e-4;
    assert!(area_error(&spec, expected).abs() < 1e-12);
}
