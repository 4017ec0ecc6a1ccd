//! A bolt pattern on an excavation removed at a stage (scene-format "Rock masses", `stage` on
//! `[[excavation]]` and `[[bolt_pattern]]`). Until its stage the excavation's blocks are in the
//! model, and the pattern's bolts start on the boundary they share with the rock. Expected
//! (scene-format, bolt positions): floor(L / spacing) + 1 bolts for the boundary length L in the
//! range; each bolt's first anchor is held by the rock block just outside the excavation (the
//! wedge of examples/tunnel_insitu.toml: its bolts run from the wedge into the fixed rock above),
//! never by one of the excavation's own blocks, whether the bolts are grouted (segments) or
//! end-anchored.

/// The example with its pattern's `grouted` set to `grouted`.
fn tunnel(grouted: bool) -> pbdda::model::Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tunnel_insitu.toml");
    let text = std::fs::read_to_string(path).expect("example");
    assert!(text.contains("\ngrouted = true\n"));
    let text = text.replace("\ngrouted = true\n", &format!("\ngrouted = {grouted}\n"));
    pbdda::scene::parse(&text, "tunnel.toml").unwrap_or_else(|e| panic!("grouted = {grouted}: {e}"))
}

#[test]
fn pattern_bolts_on_a_staged_excavation_start_in_the_rock() {
    // the 24-gon of radius 3 between polar angles 80° and 100°: the crown vertex at 90° and two
    // pieces of its neighbouring edges, each 3 sin 15° / sin 97.5° long (law of sines in the
    // triangle centre, 90° vertex, ray at 80°); spacing 0.347627 m
    let half = 3.0 * 10f64.to_radians().sin() / (180.0f64 - 10.0 - 82.5).to_radians().sin();
    let bolts = (2.0 * half / 0.347627).floor() as usize + 1;
    assert_eq!(bolts, 4);
    for grouted in [true, false] {
        let m = tunnel(grouted);
        let dug: Vec<usize> = m.excavations.iter().flat_map(|e| e.bodies.clone()).collect();
        assert_eq!(dug.len(), 3, "the tunnel's blocks (the J1 and J2 traces through it cut it in three)");
        assert_eq!(m.connectors.len(), bolts, "grouted = {grouted}");
        for c in &m.connectors {
            assert!(
                !dug.contains(&c.bodies[0]) && !dug.contains(&c.bodies[1]),
                "{} is held by the tunnel's blocks",
                c.name
            );
            assert!(
                !m.bodies[c.bodies[0]].fixed && m.bodies[c.bodies[1]].fixed,
                "{}: wedge to fixed rock",
                c.name
            );
        }
    }
}
