//! Fuzz target: the scene reader must return `Ok` or a `SceneError`, never panic or hang,
//! whatever the bytes (invalid UTF-8 included, as `scene::load` would see them). A scene it
//! accepts must also build a world and take its first step without a panic (an error is fine):
//! bounded to small scenes (12 bodies, 12 connectors, 2,000 mesh nodes) and a capped solver so
//! that one input stays well under a second in the instrumented build (the 3,200-node Hertz
//! mesh takes 0.27 s for one step in release and more than 10 s under ASan: a timeout that is
//! no hang).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let parsed = match std::str::from_utf8(data) {
        Ok(text) => pbdda::scene::parse(text, "fuzz.toml"),
        Err(_) => pbdda::scene::parse_bytes(data, "fuzz.toml"),
    };
    if let Ok(mut model) = parsed {
        let mesh_nodes: usize = (model.bodies.iter())
            .map(|b| match &b.shape {
                pbdda::model::Shape::Mesh(m) => m.mesh.nodes.len(),
                _ => 0,
            })
            .sum();
        if model.bodies.len() <= 12 && model.connectors.len() <= 12 && mesh_nodes <= 2_000 {
            model.solver.max_iterations = model.solver.max_iterations.min(500);
            model.time.max_halvings = model.time.max_halvings.min(2);
            let _ = pbdda::world::World::new(model).step();
        }
    }
});
