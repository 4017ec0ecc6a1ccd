//! Paper §7.10 (Figure 39): two star-shaped blocks and nine disks joined by ten springs drop onto a
//! large fixed disk (`examples/7_10_particle_chain.toml`; the paper does not give the spacing,
//! star size, density or friction, so the example chooses them and says so).
//!
//! Checks, from conservation of energy: the springs start unstretched (no pretension) and the only
//! external force is gravity, so with contacts that do no net work (math note §10.1) and a time
//! scheme that can only dissipate (Newmark γ = 1, math note §1.1), the kinetic energy can never
//! exceed the potential energy released, Σ m_i g (y_i(0) − y_i(t)). The bound is checked at every
//! step with a margin of 1e-9 of the energy released plus 1e-9 J (round-off of the sums). Every step
//! converges and no pair starts a step penetrating deeper than 5 % of the contact threshold (the
//! run log's penetration warning); the middle disk ends on top of the big disk. The chain does not
//! come fully to rest in the 15 s simulated (it keeps rocking with about a tenth of its peak kinetic
//! energy), so "on top" is checked to 1 cm, half a percent of the disk's radius.

use pbdda::world::{Warning, World};

#[test]
fn chain_never_gains_energy_and_lands_on_the_disk() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_10_particle_chain.toml");
    let mut world = World::new(pbdda::scene::load(&path).expect("scene"));
    let g = 10.0;
    let y0: Vec<f64> = world.bodies.iter().map(|b| b.centroid.y).collect();
    let mut max_ke: f64 = 0.0;
    for _ in 0..world.model.time.steps {
        let rec = world.step().expect("step");
        assert!(rec.converged, "step {}: residual {}", rec.step, rec.residual);
        let penetration = rec.warnings.iter().find(|w| matches!(w, Warning::Penetration { .. }));
        assert!(penetration.is_none(), "{penetration:?}");
        let released: f64 = world
            .bodies
            .iter()
            .zip(&y0)
            .filter(|(b, _)| !b.fixed)
            .map(|(b, y)| b.mass * g * (y - b.centroid.y))
            .sum();
        assert!(
            rec.kinetic_energy <= released * (1.0 + 1e-9) + 1e-9,
            "step {}: kinetic energy {} above the energy released {released}",
            rec.step,
            rec.kinetic_energy
        );
        max_ke = max_ke.max(rec.kinetic_energy);
    }
    // the middle disk p5 lies on the big disk (R = 8, r = 2): centre 10 m from its centre
    let p5 = world.bodies.iter().find(|b| b.name == "p5").expect("p5");
    let distance = p5.centroid.norm();
    assert!((distance - 10.0).abs() < 1e-2, "p5 at {distance} m from the big disk's centre");
    eprintln!("peak kinetic energy {max_ke:.4e} J");
}
