//! The body form's product in halves (`BodyPart::halves`, math note §3.3).

use super::*;
use crate::body::Body;
use crate::geometry::{Vec2, cw};
use crate::model::{BodyModel, BodySpec, Material, Plane, Shape};

/// The halves' cut (`BodyPart::split`) on a row of 10,500 rigid disks, each touching the
/// next (2 rows and 4 segments per contact, 41,996 segments): pushed in contact order, the
/// first segment at or past half (20,998) whose row is above every earlier one is contact
/// 5,250's first, segment 21,000 (20,998 and 20,999 are contact 5,249's rows on its second
/// body). With contact 0 pushed last, rows 0 and 1 come after every cut: no split, and the
/// serial product runs. With contact 5,329 pushed in 5,249's place (then 5,249–5,328, then the
/// rest in order), its rows 10,658 and 10,659, among the first half's segments, are above all
/// the rows up to contact 5,330's: the cut is that contact's first segment, 21,320, farther
/// past half than `split_of` reads row by row (`CUT_WINDOW`). With a contact on disk 0 alone
/// (a wall's: rows 0 and 1, two segments) pushed first and the others' rows two higher, half
/// (20,999) falls on contact 5,249's second segment, whose row is above every earlier one but
/// not at or below the later ones (its third segment is on the row below): the cut is contact
/// 5,250's first segment, 21,002 (the first rule found none there). diag(W), added over the
/// halves on both cores, has the bits of one pass over all segments, and equals the assembled
/// W's diagonal to 1e-12. Both products equal the assembled W's to 1e-12 of the largest
/// |W z| (the same terms summed in another order), and give the same bits on one thread and
/// on two (the calling thread with one micropool worker: the determinism contract). Cleared
/// first (`clear`, each half its own rows), a vector of NaN gets the same bits as zeros
/// added to.
#[test]
fn products_split_only_where_no_row_straddles() {
    let n = 10_500;
    let material = Material { name: "m".into(), density: 2.0, young: Some(1e8), poisson: Some(0.3) };
    let bodies: Vec<Body> = (0..n)
        .map(|i| {
            let spec = BodySpec::at_rest(
                format!("b{i}"),
                Shape::Disk { center: Vec2::new(i as f64, 0.0), radius: 0.5 },
                BodyModel::Rigid,
                false,
            );
            Body::new(&spec, &material, Plane::Stress)
        })
        .collect();
    let map = DofMap::new(&bodies, &[]);
    let mut flex = Flexibility::new(false);
    flex.refresh(&map, &bodies, &[], 0.01, 0.0).expect("K̃ is SPD");
    let blocks = Arc::new(Blocks::new(&flex, &map, &vec![true; n]));
    // contact k between disks k and k + 1 at rows first + 2k, + 1
    let contact = |jac: &mut Jacobian, k: usize, first: usize| {
        let normal = Vec2::new(-1.0, -0.1 * (k % 3) as f64).normalize();
        let x = Vec2::new(k as f64 + 0.5, 0.0);
        for (body, sign) in [(k, 1.0), (k + 1, -1.0)] {
            for (row, dir) in [(first + 2 * k, normal), (first + 2 * k + 1, cw(normal))] {
                jac.push(row, body, 3 * body, 3, bodies[body].shape_row(x, dir) * sign);
            }
        }
    };
    let wall = |jac: &mut Jacobian| {
        let x = Vec2::new(-0.5, 0.0);
        for (row, dir) in [(0, Vec2::x()), (1, Vec2::y())] {
            jac.push(row, 0, 0, 3, bodies[0].shape_row(x, dir));
        }
    };
    let late = (0..5_249).chain([5_329]).chain(5_249..5_329).chain(5_330..n - 1).collect();
    let in_order = || (0..n - 1).collect::<Vec<_>>();
    let orders = [
        (in_order(), false, 21_000),
        ((1..n - 1).chain([0]).collect(), false, 0),
        (late, false, 21_320),
        (in_order(), true, 21_002),
    ];
    for (order, with_wall, split) in orders {
        let mut jac = Jacobian::default();
        let first = if with_wall { 2 } else { 0 };
        jac.reset(first + 2 * (n - 1));
        if with_wall {
            wall(&mut jac);
        }
        order.iter().for_each(|&k| contact(&mut jac, k, first));
        let mut diagonal = vec![0.0; jac.rows];
        let part = BodyPart::new(&jac, Arc::clone(&blocks), &mut diagonal);
        assert_eq!(part.split, split);
        let mut serial = vec![0.0; jac.rows];
        part.add_diagonal(&jac, 0..jac.segments().len(), &mut serial, 0);
        assert!(
            diagonal.iter().zip(&serial).all(|(a, b)| a.to_bits() == b.to_bits()),
            "split {split}: diagonal"
        );
        let z: Vec<f64> = (0..jac.rows).map(|r| ((r * 37) % 101) as f64 / 101.0 - 0.3).collect();
        // adding to zeros, or clearing a vector of NaN first (a row it missed would stay NaN)
        let on = |threads: usize, clear: bool| {
            let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
            let mut out = vec![if clear { f64::NAN } else { 0.0 }; jac.rows];
            pool.install(|| part.apply(&jac, &z, &mut out, clear));
            out
        };
        let (got, w) = (on(2, false), super::super::assemble(&jac, &flex, &map));
        let same = |a: &[f64]| a.iter().zip(&got).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same(&on(1, false)), "split {split}: threads");
        assert!(same(&on(1, true)) && same(&on(2, true)), "split {split}: clearing");
        let want: Vec<f64> = w.outer_iterator().map(|row| row.iter().map(|(c, v)| v * z[c]).sum()).collect();
        let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let dmax = diagonal.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (r, d) in diagonal.iter().enumerate() {
            let wrr = w.get(r, r).copied().unwrap_or(0.0);
            assert!((d - wrr).abs() <= 1e-12 * dmax, "split {split}, diagonal {r}: {d} vs {wrr}");
        }
        for r in 0..jac.rows {
            assert!(
                (got[r] - want[r]).abs() <= 1e-12 * scale,
                "split {split}, row {r}: {} vs {}",
                got[r],
                want[r]
            );
        }
    }
}
