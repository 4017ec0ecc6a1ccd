//! The block `(K̄⁻¹)_SS` of a meshed block's step matrix over the DOFs its contacts touch
//! (math note §9.3), built from the factor's forward solves along the elimination tree
//! (`SparseFactor::inverse_block`), against the same block from full solves of the unit vectors
//! (`SparseFactor::inverse_block_by_solves`, forward and backward with the whole factor).
//!
//! The matrix is the step matrix K̄ = K + 2M/dt² of `generate::PressedBlock` (the mesh of
//! `benches/mesh.rs`, E 1e10 Pa, dt 0.01), S the DOFs of its bottom row of nodes (the floor's
//! contacts) and of its top nodes under the disk. Both ways use the same factor and differ only
//! in how they round: the tolerance 1e-12 of the block's largest entry is the issue's
//! "same answers to 1e-12".

use pbdda::cluster::SparseFactor;
use pbdda::generate::PressedBlock;
use pbdda::mesh::body::MeshBody;

/// K̄ of the `nx` × `nx / 2` pressed block, factorized, and its contact DOFs: the bottom row,
/// then the top nodes within 0.1 m of the middle.
fn factor_and_contact_dofs(nx: usize) -> (SparseFactor, Vec<usize>, Vec<usize>) {
    let block = PressedBlock::benchmark(nx);
    let model = block.model();
    let pbdda::model::Shape::Mesh(shape) = &model.bodies[1].shape else { panic!("the block is a mesh") };
    let elastic = pbdda::body::constitutive(1e10, 0.25, model.physics.plane);
    let fe = MeshBody::new(shape, 2500.0, elastic, [0.0; 3], Default::default(), 0.0);
    let mut factor = SparseFactor::new(fe.ndof());
    factor.factorize(&fe.step_triplets(block.dt)).expect("K̄ is SPD");
    let nodes = &shape.mesh.nodes;
    let dofs = |keep: &dyn Fn(f64, f64) -> bool| -> Vec<usize> {
        (0..nodes.len()).filter(|&i| keep(nodes[i].x, nodes[i].y)).flat_map(|i| [2 * i, 2 * i + 1]).collect()
    };
    let bottom = dofs(&|_, y| y == 0.0);
    let top = dofs(&|x, y| y == block.height && (x - 0.5 * block.width).abs() < 0.1);
    (factor, bottom, top)
}

/// Largest difference between two blocks, relative to the largest entry of the reference.
fn relative_difference(block: &[f64], reference: &[f64]) -> f64 {
    let scale = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    block.iter().zip(reference).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

/// The pressed block of `nx` × `nx / 2` cells: the bottom row's DOFs asked first, then all
/// contact DOFs in another order (the top's join the kept block). Both answers equal the full
/// solves' within 1e-12 of the largest entry, and the block is exactly symmetric.
fn check_block(nx: usize, supernodal: bool, counts: (usize, usize)) {
    let (factor, bottom, top) = factor_and_contact_dofs(nx);
    assert_eq!(factor.is_supernodal(), supernodal);
    assert_eq!((bottom.len(), top.len()), counts);
    let first = factor.inverse_block(&bottom);
    assert!(relative_difference(&first, &factor.inverse_block_by_solves(&bottom)) < 1e-12);
    let all: Vec<usize> = top.iter().chain(bottom.iter().rev()).copied().collect();
    let block = factor.inverse_block(&all);
    assert!(relative_difference(&block, &factor.inverse_block_by_solves(&all)) < 1e-12);
    let m = all.len();
    for i in 0..m {
        for j in 0..i {
            assert_eq!(block[i * m + j], block[j * m + i]);
        }
    }
}

/// 60 × 30 cells (3,782 DOF): faer factors it simplicially (one column per group). 61 bottom
/// nodes; top nodes at x = 2 ± k/15 m within 0.1 m of the middle: k = -1..1.
#[test]
fn simplicial_factor_matches_full_solves() {
    check_block(60, false, (122, 6));
}

/// 140 × 70 cells (20,022 DOF): a supernodal factor. 141 bottom nodes; top nodes at
/// x = 2 ± 4k/140 m within 0.1 m: k = -3..3.
#[test]
fn supernodal_factor_matches_full_solves() {
    check_block(140, true, (282, 14));
}

/// The bench's own matrix: the 316 × 158 block (100,806 DOF), its 634 bottom-row DOFs and the
/// top's 30, within 1e-12 of the largest entry: the size the fast path is for (the full solves
/// of the reference take most of this test's time).
#[test]
fn slow_bench_matrix_matches_full_solves() {
    let (factor, bottom, top) = factor_and_contact_dofs(316);
    assert!(factor.is_supernodal());
    assert_eq!((bottom.len(), top.len()), (634, 30));
    let all: Vec<usize> = bottom.iter().chain(&top).copied().collect();
    let block = factor.inverse_block(&all);
    assert!(relative_difference(&block, &factor.inverse_block_by_solves(&all)) < 1e-12);
}
