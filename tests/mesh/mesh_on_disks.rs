//! A meshed block landing on frictional disks, the case that made MPRGP's fallback try NSGS
//! before PC (math note §4.8, "MPRGP's fallbacks").
//!
//! The block (2 m × 1 m, 8 × 4 squares of two triangles, E = 1e10 Pa, density 1, so 2 kg) is
//! released at rest 0.02 m above a row of four rigid disks (radius 0.5, μ = 0.6) between walls:
//! `DiskPile::benchmark(4, 1)` (g = 9.81 m/s², dt = 1/60 s, tolerance 1e-6). It falls, lands on
//! the middle disks, and bounces: the step reverses an impacting contact's normal velocity
//! exactly (math note §1.3, solve 2), so the block rises back to where it was released, lands
//! again, and so on, once every 14 steps.
//!
//! The landing steps pose a frictional problem whose box moves with its normal forces: MPRGP's
//! and PC's passes at fixed friction bounds (§4.3) did not settle on them (step 4 ended at a
//! residual of 6.2e-5 after 21,338 iterations, with PC's hand-over), while NSGS, which takes
//! each contact's friction bound at the current iterate, solves them in about a thousand
//! sweeps. Checked: every one of 29 steps converges to the tolerance, and both apexes
//! (steps 13 and 27, where the block's velocity changes sign) lie within 1e-6 m of the release
//! height: each landing may leave the block off the exact reversal by the gap part of the
//! residual's tolerance, 1e-6 times the scene's feature length (at most the disks' radius, so
//! 5e-7 m; math note §4.9), and two landings come before the second apex.

use crate::common;

use pbdda::generate::{DiskPile, PressedBlock};
use pbdda::geometry::Vec2;
use pbdda::model::{BodyModel, BodySpec, MeshShape, Shape};
use pbdda::world::World;

#[test]
fn meshed_block_lands_on_frictional_disks() {
    let mut model = DiskPile::benchmark(4, 1).model();
    for m in &mut model.materials {
        m.young = Some(1e10);
    }
    let block =
        PressedBlock { nx: 8, ny: 4, width: 2.0, height: 1.0, load: 0.0, dt: 0.01, factor_drift: 0.0 };
    let mut mesh = block.mesh();
    mesh.nodes.iter_mut().for_each(|p| *p += Vec2::new(0.5, 1.02)); // the disks' tops at y = 1
    let shape = Shape::Mesh(Box::new(MeshShape { mesh, fixed_nodes: Vec::new(), rollers: Vec::new() }));
    model.bodies.push(BodySpec::at_rest("block", shape, BodyModel::Deformable, false));
    let tolerance = model.solver.tolerance;
    let mut world = World::new(model);
    let release = world.bodies.last().expect("the block").centroid.y;
    let mut heights = Vec::new();
    common::run(&mut world, 29, |world, r| {
        common::assert_converged(r, tolerance);
        heights.push(world.bodies.last().expect("the block").centroid.y);
    });
    for apex in [13, 27] {
        let is_top = heights[apex] > heights[apex - 1] && heights[apex] > heights[apex + 1];
        assert!(
            is_top && (heights[apex] - release).abs() < 1e-6,
            "step {apex}: {} vs {release}",
            heights[apex]
        );
    }
}
