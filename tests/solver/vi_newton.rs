//! The semismooth Newton method (`[solver] method = "newton"`, math note §4.16): KKT of the
//! Coulomb QVI on random three-disk rows, and a sliding mass of blocks against the closed form
//! of a body sliding down an incline.

use crate::common;
use crate::vi_support;

use pbdda::vi::{BlockLaw, BoundRule, Method, Problem, Solver};
use pbdda::world::World;
use vi_support::*;

/// Coulomb friction without cohesion as a contact law (math note §4.7): the same bounds as
/// `vi_support::Coulomb` with c = 0, and their closed form, which Newton differentiates.
struct Law {
    mu: f64,
}

impl BoundRule for Law {
    fn block_bounds(&self, k: usize, z: &[f64], lo: &mut [f64], hi: &mut [f64]) {
        Coulomb { mu: self.mu, c: 0.0 }.block_bounds(k, z, lo, hi);
    }

    fn block_law(&self, _k: usize, _z: &[f64]) -> Option<BlockLaw> {
        Some(BlockLaw { tension: 0.0, a: [0.0; 2], b: [self.mu, 0.0], a_open: [0.0; 2] })
    }
}

/// 200 random three-disk rows (`disk_row`: random radii, densities, velocities; μ in
/// [0.1, 1]), cold started. Expected: converged, with the KKT conditions of the QVI at the
/// answer (`check_coulomb`, whose tolerances derive from the residual eps = 1e-10 in its
/// header), whether Newton answers or hands over to the mprgp chain (math note §4.16; it
/// hands over on one of these 200).
#[test]
fn newton_meets_the_coulomb_kkt_conditions_on_random_disk_rows() {
    let eps = 1e-10;
    let mut rng = Rng::new(7);
    for case in 0..200 {
        let (w, q) = disk_row(&mut rng);
        let mu = rng.range(0.1, 1.0);
        let law = Law { mu };
        let mut solver = Solver::new().with_method(Method::Newton);
        let mut z = vec![0.0; q.len()];
        let wc = to_csr(&w);
        let rep =
            solver.solve(&Problem { w: &wc, q: &q, blocks: &pairs(q.len()) }, &law, &mut z, &opts(eps, true));
        assert!(rep.converged && rep.residual <= eps, "case {case}: {rep:?}");
        if let Err(e) = check_coulomb(&w, &q, &Coulomb { mu, c: 0.0 }, &z, eps) {
            panic!("case {case} (mu {mu}): {e}");
        }
    }
}

/// A mass of 3 × 4 rigid blocks (1 × 0.5 m, density 2500) on a fixed base, gravity tilted by
/// a = 35° (the base is the incline), friction 0.5 on the base and 0.9 between blocks: the
/// mass slides as one body (0.9 > tan a' for every interface it needs to hold), so every block
/// moves by g (sin a − cos a tan φ) t² / 2, tan φ = 0.5, exactly in DDA's time scheme
/// (constant acceleration: d = v dt + a dt² / 2, math note §1.1). Tolerance: 1e-10 of the
/// distance, the solver tolerance (1e-12) times the ratio of the mass's weight to its friction
/// force, with margin for 50 steps of rounding.
#[test]
fn sliding_mass_moves_by_the_closed_form() {
    let (a, g, mu, dt, steps) = (35f64.to_radians(), 9.81, 0.5, 1e-3, 50);
    let mut s = format!(
        "[scene]\nname = \"sliding mass\"\n[time]\nstep = {dt}\nsteps = {steps}\n[physics]\n\
         gravity = [{}, {}]\n[solver]\ntolerance = 1e-12\nmethod = \"newton\"\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\n[[material]]\nname = \"base\"\n\
         density = 2500.0\n[[interface]]\nfriction = 0.9\n[[interface]]\n\
         materials = [\"rock\", \"base\"]\nfriction = {mu}\n",
        g * a.sin(),
        -g * a.cos()
    );
    common::scenes::rectangle(&mut s, "base", -1.0, -1.0, 60.0, 0.0, "material = \"base\"\nfixed = true");
    for j in 0..3 {
        for i in 0..4 {
            let (x, y) = (i as f64, 0.5 * j as f64);
            common::scenes::rectangle(
                &mut s,
                &format!("b{j}_{i}"),
                x,
                y,
                x + 1.0,
                y + 0.5,
                "material = \"rock\"",
            );
        }
    }
    let model = pbdda::scene::parse(&s, "sliding_mass.toml").expect("valid scene");
    let mut world = World::new(model);
    let start: Vec<_> = world.bodies.iter().map(|b| b.centroid).collect();
    common::run(&mut world, steps, |_, rec| common::assert_converged(rec, 1e-12));
    let t = steps as f64 * dt;
    let exact = g * (a.sin() - a.cos() * mu) * t * t / 2.0;
    for (b, s0) in world.bodies.iter().zip(&start).skip(1) {
        let (dx, dy) = (b.centroid.x - s0.x, b.centroid.y - s0.y);
        assert!(
            (dx - exact).abs() <= 1e-10 * exact && dy.abs() <= 1e-10 * exact,
            "{}: {dx} {dy} vs {exact}",
            b.name
        );
    }
}
