//! The body form's product in halves (`BodyPart::apply` over the halves of `split`, math note §3.3).

use super::*;
use crate::body::Body;
use crate::cluster::Flexibility;
use crate::dofs::DofMap;
use crate::geometry::{Vec2, cw};
use crate::model::{BodyModel, BodySpec, Material, Plane, Shape};

/// `n` rigid disks of radius 0.5 in a row, one apart, each in body form: the bodies, their DOF
/// map and flexibility, and the body form's blocks.
fn rigid_disks(n: usize) -> (Vec<Body>, DofMap, Flexibility, Arc<Blocks>) {
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
    (bodies, map, flex, blocks)
}

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
/// added to. Every order packs into contact frames (`frames.rs`; the wall's contact into one of
/// one body), whose products and diagonal have the bits of the segments'. The response K̃⁻¹ Bᵀ z
/// (`BodyPart::response`) has the bits of B's transpose product and the flexibility's solves
/// where there is no cut (the same sums in the same order), and equals them to 1e-12 of its
/// largest entry over the halves (a body with segments on both sides adds two partial sums),
/// with the same bits on one thread and two and over frames or segments.
#[test]
fn products_split_only_where_no_row_straddles() {
    let n = 10_500;
    let (bodies, map, flex, blocks) = rigid_disks(n);
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
        for (row, dir) in [(0, Vec2::x()), (1, cw(Vec2::x()))] {
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
        let part = BodyPart::new(&jac, Arc::clone(&blocks), &mut diagonal, &mut Vec::new());
        assert_eq!(part.split, split);
        assert!(part.frames.is_some(), "split {split}: frames");
        // the same part over the segments
        let plain = BodyPart {
            frames: None,
            ..BodyPart::new(&jac, Arc::clone(&blocks), &mut vec![0.0; jac.rows], &mut Vec::new())
        };
        let mut serial = vec![0.0; jac.rows];
        part.add_diagonal(&jac, 0..jac.segments().len(), &mut serial, 0);
        assert!(
            diagonal.iter().zip(&serial).all(|(a, b)| a.to_bits() == b.to_bits()),
            "split {split}: diagonal"
        );
        let z: Vec<f64> = (0..jac.rows).map(|r| ((r * 37) % 101) as f64 / 101.0 - 0.3).collect();
        // adding to zeros, or clearing a vector of NaN first (a row it missed would stay NaN)
        let on = |part: &BodyPart, threads: usize, clear: bool| {
            let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
            let mut out = vec![if clear { f64::NAN } else { 0.0 }; jac.rows];
            pool.install(|| part.apply(&jac, &z, &mut out, clear));
            out
        };
        let (got, w) = (on(&part, 2, false), super::super::assemble(&jac, &flex, &map));
        let same = |a: &[f64]| a.iter().zip(&got).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same(&on(&part, 1, false)), "split {split}: threads");
        assert!(same(&on(&part, 1, true)) && same(&on(&part, 2, true)), "split {split}: clearing");
        assert!(same(&on(&plain, 2, false)) && same(&on(&plain, 1, true)), "split {split}: segments");
        response_matches_the_transpose_product(&part, &plain, &jac, &z, &flex, &map);
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

/// The response checks of `products_split_only_where_no_row_straddles` (see there).
fn response_matches_the_transpose_product(
    part: &BodyPart,
    plain: &BodyPart,
    jac: &Jacobian,
    z: &[f64],
    flex: &Flexibility,
    map: &DofMap,
) {
    let mut want = vec![0.0; map.total()];
    jac.transpose_apply(z, |_| true, &mut want);
    flex.solve_in_place(map, &mut want);
    let on = |part: &BodyPart, threads: usize| {
        let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
        let mut out = vec![0.0; map.total()];
        assert!(pool.install(|| part.response(jac, z, &mut out)), "every segment on a body");
        out
    };
    let got = on(part, 2);
    let bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(bits(&on(part, 1), &got) && bits(&on(plain, 2), &got), "split {}: response bits", part.split);
    if part.split == 0 {
        assert!(bits(&got, &want), "response without halves");
    }
    let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(
        got.iter().zip(&want).all(|(a, b)| (a - b).abs() <= 1e-12 * scale),
        "split {}: response",
        part.split
    );
}

/// With a body outside the body form, its segments are not the body part's: it gives no response
/// (out untouched), and the caller takes B's transpose product. Two disks, one contact.
#[test]
fn no_response_unless_every_segment_is_on_a_body() {
    let (bodies, map, flex, _) = rigid_disks(2);
    let mut jac = Jacobian::with_rows(1);
    for (body, sign) in [(0, 1.0), (1, -1.0)] {
        jac.push(0, body, 3 * body, 3, bodies[body].shape_row(Vec2::new(0.5, 0.0), Vec2::x()) * sign);
    }
    let blocks = Arc::new(Blocks::new(&flex, &map, &[true, false]));
    let part = BodyPart::new(&jac, blocks, &mut [0.0; 1], &mut Vec::new());
    let mut out = vec![f64::NAN; map.total()];
    assert!(!part.response(&jac, &[1.0], &mut out));
    assert!(out.iter().all(|x| x.is_nan()));
}

/// Contact frames (`frames::pack`) only where each frame gives back its segments' entries bit
/// for bit and the body's K̃⁻¹ lies where the frames' diagonal reads it: a contact between two
/// rigid bodies (rows n and cw(n) on A, the same negated on B, each with its own moment arms)
/// and one on a single body pack (6 segments into 2 frames). Each of these stops the packing
/// at its first segment (the count is the segments packed before it): a tangent row that is not
/// cw(n) (6), a rolling contact (8: its rows n and t on A still make a frame of one body, and
/// its rolling row stops it), a deformable body's segment of four entries (6), a contact cut
/// after its first segment (6), a body whose K̃⁻¹ is not at three times its first DOF (4). Where
/// the Jacobian stops packing, `BodyPart::new` adds the rest of diag(W) from the segments: the
/// bits of `add_diagonal` over all of them.
#[test]
fn frames_only_where_they_give_back_every_entry() {
    let n = Vec2::new(0.6, -0.8);
    let (na, nb) = ([n.x, n.y, 0.3], [-n.x, -n.y, -0.2]);
    let (ta, tb) = ([cw(n).x, cw(n).y, 0.5], [-cw(n).x, -cw(n).y, 0.7]);
    // contact rows 0, 1 between bodies at DOFs 0 and 3, rows 2, 3 on the body at DOF 6 alone
    let good = |jac: &mut Jacobian| {
        for (row, start, vals) in [(0, 0, na), (1, 0, ta), (0, 3, nb), (1, 3, tb), (2, 6, na), (3, 6, ta)] {
            jac.push_slice(row, start / 3, start, &vals);
        }
    };
    let jacobian = |extra: &dyn Fn(&mut Jacobian)| {
        let mut jac = Jacobian::with_rows(7);
        good(&mut jac);
        extra(&mut jac);
        jac
    };
    let dense = |s: &Segment| s.cluster() * 3 == s.start();
    let packed = |jac: &Jacobian, dense: &dyn Fn(&Segment) -> bool| {
        // into the storage of an earlier step (two frames), which pack clears
        let (mut frames, mut earlier) = (Vec::new(), Jacobian::with_rows(4));
        good(&mut earlier);
        assert_eq!(frames::pack(&earlier, earlier.segments(), |_| true, &mut frames, |_| {}), 6);
        (frames::pack(jac, jac.segments(), dense, &mut frames, |_| {}), frames.len())
    };
    let none: &dyn Fn(&mut Jacobian) = &|_| {}; // no more segments
    assert_eq!(packed(&jacobian(none), &dense), (6, 2));
    type Extra<'a> = &'a dyn Fn(&mut Jacobian);
    let cases: [(Extra, usize); 4] = [
        (&|jac| [(4, n), (5, n)].iter().for_each(|&(r, d)| jac.push_slice(r, 0, 0, &[d.x, d.y, 0.1])), 6),
        (
            &|jac| {
                for (start, sign, (nv, tv)) in [(0, 1.0, (na, ta)), (3, -1.0, (nb, tb))] {
                    [(4, nv), (5, tv), (6, [0.0, 0.0, sign])]
                        .iter()
                        .for_each(|(r, v)| jac.push_slice(*r, start / 3, start, v));
                }
            },
            8,
        ),
        (
            &|jac| {
                jac.push_slice(4, 3, 9, &[n.x, n.y, 0.1, 0.2]);
                jac.push_slice(5, 3, 9, &[cw(n).x, cw(n).y, 0.1, 0.2]);
            },
            6,
        ),
        (&|jac| jac.push_slice(4, 0, 0, &na), 6),
    ];
    let (_, _, _, blocks) = rigid_disks(3);
    for (i, (extra, count)) in cases.iter().enumerate() {
        let jac = jacobian(*extra);
        assert_eq!(packed(&jac, &dense).0, *count, "case {i}");
        if i == 2 {
            continue; // (four DOFs: not one of these rigid disks')
        }
        let mut diagonal = vec![0.0; jac.rows];
        let part = BodyPart::new(&jac, Arc::clone(&blocks), &mut diagonal, &mut Vec::new());
        let mut serial = vec![0.0; jac.rows];
        part.add_diagonal(&jac, 0..jac.segments().len(), &mut serial, 0);
        assert!(part.frames.is_none(), "case {i}: frames");
        assert!(diagonal.iter().zip(&serial).all(|(a, b)| a.to_bits() == b.to_bits()), "case {i}: diagonal");
    }
    assert_eq!(packed(&jacobian(none), &|s: &Segment| s.start() != 6).0, 4, "not dense");
}
