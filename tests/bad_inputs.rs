//! The corpus of bad inputs in `tests/bad_inputs/`: every scene (`.toml`) and gmsh mesh
//! (`.msh`) there is invalid, and its `.expect` sidecar lists, one a line, fragments that the
//! error must contain (the key path and the message the validation rule promises; for files
//! named in the fragment, the file and line). Each input must be rejected with an error, not a
//! panic, and without hanging: a reader that takes longer than `HANG` seconds on a few-line
//! file is stuck (the budget is far above any real parse, so this is not a speed test).
//! A 200k-vertex self-intersecting polygon, generated here, must be rejected too (the former
//! all-pairs simplicity check took over a minute on it).

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

const HANG: u64 = 60;

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

/// The error text of reading `path` as a scene or a mesh; fails the test on Ok, panic or hang.
fn rejection(path: &Path) -> String {
    let (tx, rx) = mpsc::channel();
    let p = path.to_path_buf();
    std::thread::spawn(move || {
        let result = std::panic::catch_unwind(|| match p.extension().and_then(|e| e.to_str()) {
            Some("msh") => pbdda::mesh::Mesh::read(&p).map(|_| ()).map_err(|e| e.to_string()),
            _ => pbdda::scene::load(&p).map(|_| ()).map_err(|e| e.to_string()),
        });
        let _ = tx.send(result);
    });
    match rx.recv_timeout(Duration::from_secs(HANG)) {
        Ok(Ok(Err(message))) => message,
        Ok(Ok(Ok(()))) => panic!("{}: accepted, but it is a bad input", path.display()),
        Ok(Err(_)) => panic!("{}: the reader panicked", path.display()),
        Err(_) => panic!("{}: not rejected within {HANG} s (hang)", path.display()),
    }
}

#[test]
fn every_bad_input_gets_its_message() {
    let mut inputs: Vec<PathBuf> = std::fs::read_dir(corpus())
        .expect("tests/bad_inputs")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml" || e == "msh"))
        .collect();
    inputs.sort();
    // the issue asks for at least 50; the corpus has 111 scenes and 10 meshes
    assert_eq!(inputs.len(), 121, "corpus size changed: update this count");
    let mut failures = Vec::new();
    for path in &inputs {
        let expect = std::fs::read_to_string(path.with_extension("expect"))
            .unwrap_or_else(|_| panic!("{}: no .expect sidecar", path.display()));
        let message = rejection(path);
        for fragment in expect.lines().filter(|l| !l.is_empty()) {
            if !message.contains(fragment) {
                failures.push(format!("{}: missing `{fragment}` in: {message}", path.display()));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A 200k-gon: a circle with one vertex pulled across to the far side, so that its two edges
/// cross the opposite arc. The simplicity check (a sweep, O(N log N)) must find a crossing.
#[test]
fn huge_self_intersecting_polygon_is_rejected() {
    let n = 200_000;
    let mut text = String::from(
        "[scene]\nname = \"big\"\n[time]\nstep = 0.01\nsteps = 1\n[[material]]\nname = \"m\"\n\
         density = 1000.0\n[[body]]\nname = \"p\"\nshape = \"polygon\"\nmaterial = \"m\"\nvertices = [",
    );
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        let (x, y) = if i == 10 { (-2.0, 0.0) } else { (a.cos(), a.sin()) };
        text.push_str(&format!("[{x:?}, {y:?}],"));
    }
    text.push_str("]\n");
    let dir = std::env::temp_dir().join(format!("pbdda-bad-inputs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("big.toml");
    std::fs::write(&path, text).expect("write");
    let message = rejection(&path);
    assert!(message.contains("body[0].vertices: the polygon intersects itself"), "{message}");
    std::fs::remove_dir_all(&dir).expect("cleanup");
}
