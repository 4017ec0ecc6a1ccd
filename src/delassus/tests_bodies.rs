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
/// added to. The same contacts pushed as contact frames (`jacobian::Frame`), with their share of
/// B v (v = 1/4) summed as the segments' (the same bits), stay frames where
/// they come in row order (contact order, with or without the wall) and turn into their
/// segments otherwise; framed, the part reads the frames, cut at the middle frame (5,249 and
/// 5,250 with the wall), with the segments' diagonal bit for bit and products equal to the
/// segments' to 1e-12. The response K̃⁻¹ Bᵀ z (`BodyPart::response`) has the bits of B's
/// transpose product and the flexibility's solves where there is no cut (the same sums in the
/// same order), and equals them to 1e-12 of its largest entry over the halves (a body with
/// segments on both sides adds two partial sums), with the same bits on one thread and two.
#[test]
fn products_split_only_where_no_row_straddles() {
    let n = 10_500;
    let (bodies, map, flex, blocks) = rigid_disks(n);
    let v = vec![0.25; 3 * n];
    let rows = |k: usize, first: usize| {
        let normal = Vec2::new(-1.0, -0.1 * (k % 3) as f64).normalize();
        let x = Vec2::new(k as f64 + 0.5, 0.0);
        let row = |body: usize, sign| [normal, cw(normal)].map(|dir| bodies[body].rigid_row(x, dir, sign));
        (first + 2 * k, row(k, 1.0), row(k + 1, -1.0))
    };
    // contact k between disks k and k + 1 at rows first + 2k, + 1, as segments or as a frame
    let contact = |jac: &mut Jacobian, k: usize, first: usize, framed: bool, q: &mut [f64]| {
        let (r, [na, ta], [nb, tb]) = rows(k, first);
        if framed {
            let frame = Frame::new(r, 3 * k, na, ta).with_second(3 * k + 3, nb, tb);
            return jac.push_frame(frame, [k, k + 1], &v, q);
        }
        for (body, [n, t]) in [(k, [na, ta]), (k + 1, [nb, tb])] {
            jac.push_apply(r, body, 3 * body, &n, &v, q);
            jac.push_apply(r + 1, body, 3 * body, &t, &v, q);
        }
    };
    let wall = |jac: &mut Jacobian, framed: bool, q: &mut [f64]| {
        let [rn, rt] =
            [Vec2::x(), cw(Vec2::x())].map(|dir| bodies[0].rigid_row(Vec2::new(-0.5, 0.0), dir, 1.0));
        if framed {
            return jac.push_frame(Frame::new(0, 0, rn, rt), [0, 0], &v, q);
        }
        jac.push_apply(0, 0, 0, &rn, &v, q);
        jac.push_apply(1, 0, 0, &rt, &v, q);
    };
    let late = (0..5_249).chain([5_329]).chain(5_249..5_329).chain(5_330..n - 1).collect();
    let in_order = || (0..n - 1).collect::<Vec<_>>();
    let orders = [
        (in_order(), false, 21_000, Some(5_249)),
        ((1..n - 1).chain([0]).collect(), false, 0, None),
        (late, false, 21_320, None),
        (in_order(), true, 21_002, Some(5_250)),
    ];
    for (order, with_wall, split, frame_split) in orders {
        let first = if with_wall { 2 } else { 0 };
        let build = |framed: bool| {
            let mut jac = Jacobian::with_rows(first + 2 * (n - 1));
            let mut q = vec![0.0; jac.rows];
            if with_wall {
                wall(&mut jac, framed, &mut q);
            }
            order.iter().for_each(|&k| contact(&mut jac, k, first, framed, &mut q));
            (jac, q)
        };
        let ((jac, q), (framed, q_framed)) = (build(false), build(true));
        assert!(q.iter().zip(&q_framed).all(|(a, b)| a.to_bits() == b.to_bits()), "split {split}: B v");
        assert_eq!(framed.frames().is_some(), frame_split.is_some(), "split {split}: framed");
        assert_eq!(framed.len(), jac.len());
        let same_segments = framed.segments().iter().zip(jac.segments()).all(|(a, b)| {
            (a.row(), a.cluster(), a.dofs()) == (b.row(), b.cluster(), b.dofs())
                && framed.vals(a).iter().zip(jac.vals(b)).all(|(x, y)| x.to_bits() == y.to_bits())
        });
        assert!(same_segments, "split {split}: the frames' segments");
        let mut diagonal = vec![0.0; jac.rows];
        let part = BodyPart::new(&jac, Arc::clone(&blocks), &mut diagonal);
        assert_eq!((part.split, part.framed), (split, false));
        let mut serial = vec![0.0; jac.rows];
        part.add_diagonal(&jac, 0..jac.segments().len(), &mut serial, 0);
        let bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(bits(&diagonal, &serial), "split {split}: diagonal");
        let z: Vec<f64> = (0..jac.rows).map(|r| ((r * 37) % 101) as f64 / 101.0 - 0.3).collect();
        // adding to zeros, or clearing a vector of NaN first (a row it missed would stay NaN)
        let on = |part: &BodyPart, jac: &Jacobian, threads: usize, clear: bool| {
            let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
            let mut out = vec![if clear { f64::NAN } else { 0.0 }; jac.rows];
            pool.install(|| part.apply(jac, &z, &mut out, clear));
            out
        };
        let (got, w) = (on(&part, &jac, 2, false), super::super::assemble(&jac, &flex, &map));
        assert!(bits(&on(&part, &jac, 1, false), &got), "split {split}: threads");
        assert!(
            bits(&on(&part, &jac, 1, true), &got) && bits(&on(&part, &jac, 2, true), &got),
            "split {split}: clearing"
        );
        response_matches_the_transpose_product(&part, &jac, &z, &flex, &map);
        let want: Vec<f64> = w.outer_iterator().map(|row| row.iter().map(|(c, v)| v * z[c]).sum()).collect();
        let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let dmax = diagonal.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (r, d) in diagonal.iter().enumerate() {
            let wrr = w.get(r, r).copied().unwrap_or(0.0);
            assert!((d - wrr).abs() <= 1e-12 * dmax, "split {split}, diagonal {r}: {d} vs {wrr}");
        }
        let near = |a: &[f64]| a.iter().zip(&want).all(|(a, b)| (a - b).abs() <= 1e-12 * scale);
        assert!(near(&got), "split {split}: W z");
        let Some(at) = frame_split else { continue };
        let mut diagonal_f = vec![0.0; jac.rows];
        let part = BodyPart::new(&framed, Arc::clone(&blocks), &mut diagonal_f);
        assert_eq!((part.split, part.framed), (at, true));
        assert!(bits(&diagonal_f, &diagonal), "split {split}: the frames' diagonal");
        let got = on(&part, &framed, 2, false);
        assert!(bits(&on(&part, &framed, 1, true), &got), "split {split}: the frames' threads");
        assert!(near(&got), "split {split}: the frames' W z");
        response_matches_the_transpose_product(&part, &framed, &z, &flex, &map);
    }
}

/// The response checks of `products_split_only_where_no_row_straddles` (see there).
fn response_matches_the_transpose_product(
    part: &BodyPart,
    jac: &Jacobian,
    z: &[f64],
    flex: &Flexibility,
    map: &DofMap,
) {
    let mut want = vec![0.0; map.total()];
    jac.transpose_apply(z, |_| true, &mut want);
    flex.solve_in_place(map, &mut want);
    let on = |threads: usize| {
        let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
        let mut out = vec![0.0; map.total()];
        assert!(pool.install(|| part.response(jac, z, &mut out)), "every segment on a body");
        out
    };
    let got = on(2);
    let bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(bits(&on(1), &got), "split {}: response threads", part.split);
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
    let part = BodyPart::new(&jac, blocks, &mut [0.0; 1]);
    let mut out = vec![f64::NAN; map.total()];
    assert!(!part.response(&jac, &[1.0], &mut out));
    assert!(out.iter().all(|x| x.is_nan()));
}

/// B as contact frames (`Jacobian::push_frame`) until a segment comes: two frames (a contact
/// between rigid bodies at rows 0 and 1, a contact on one body at rows 2 and 3), then a segment
/// of four entries, give the segments of pushing all as segments, in push order, with the same
/// entries (a negation is exact); so do frames pushed out of row order (in their push order),
/// and sorting by row (the segments' sort). While framed, `segments` makes the same segments
/// from the frames. The body form reads the frames only when every cluster is a rigid body in
/// body form laid out as the frames read it (`Blocks::dense`): with one disk outside the body
/// form it reads the segments: the diagonal of the other two disks' rows (0 and 1), and none on
/// disk 2's (2 and 3).
#[test]
fn frames_turn_into_their_segments() {
    let n = Vec2::new(0.6, -0.8);
    let (na, nb) = ([n.x, n.y, 0.3], [-n.x, -n.y, -0.2]);
    let (ta, tb) = ([cw(n).x, cw(n).y, 0.5], [-cw(n).x, -cw(n).y, 0.7]);
    let frames = [Frame::new(0, 0, na, ta).with_second(3, nb, tb), Frame::new(2, 6, na, ta)];
    let segments = [(0, 0, na), (1, 0, ta), (0, 3, nb), (1, 3, tb), (2, 6, na), (3, 6, ta)];
    let v: Vec<f64> = (0..9).map(|i| 0.1 * i as f64 - 0.3).collect();
    let same = |a: &Jacobian, b: &Jacobian| {
        a.len() == b.len()
            && a.segments().iter().zip(b.segments()).all(|(s, t)| {
                (s.row(), s.cluster(), s.dofs()) == (t.row(), t.cluster(), t.dofs())
                    && a.vals(s).iter().zip(b.vals(t)).all(|(x, y)| x.to_bits() == y.to_bits())
            })
    };
    let as_segments = |extra: &[(usize, usize, &[f64])]| {
        let mut jac = Jacobian::with_rows(5);
        for &(row, start, vals) in &segments {
            jac.push_slice(row, start / 3, start, &vals);
        }
        extra.iter().for_each(|&(row, start, vals)| jac.push_slice(row, start / 3, start, vals));
        jac
    };
    let as_frames = |order: &[usize]| {
        let (mut jac, mut q) = (Jacobian::with_rows(5), vec![0.0; 5]);
        order.iter().for_each(|&k| jac.push_frame(frames[k], [2 * k, 1 + k], &v, &mut q));
        (jac, q)
    };
    let (mut framed, q) = as_frames(&[0, 1]);
    assert_eq!(framed.frames().map(<[Frame]>::len), Some(2));
    assert!(same(&framed, &as_segments(&[])), "made from the frames");
    // B v as push_apply sums it
    let mut want = vec![0.0; 5];
    let mut plain = Jacobian::with_rows(5);
    for &(row, start, vals) in &segments {
        plain.push_apply(row, start / 3, start, &vals, &v, &mut want);
    }
    assert!(q.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()), "B v");
    let deformable: &[f64] = &[n.x, n.y, 0.1, 0.2];
    framed.push_slice(4, 1, 3, deformable);
    assert!(framed.frames().is_none() && same(&framed, &as_segments(&[(4, 3, deformable)])), "a segment");
    let (late, _) = as_frames(&[1, 0]);
    let mut want = Jacobian::with_rows(5);
    for &(row, start, vals) in segments[4..].iter().chain(&segments[..4]) {
        want.push_slice(row, start / 3, start, &vals);
    }
    assert!(late.frames().is_none() && same(&late, &want), "out of row order");
    let ((mut sorted, _), mut want) = (as_frames(&[0, 1]), as_segments(&[]));
    sorted.sort_by_row();
    want.sort_by_row();
    assert!(sorted.frames().is_none() && same(&sorted, &want), "sorted");
    let (_, map, flex, blocks) = rigid_disks(3);
    let partial = Arc::new(Blocks::new(&flex, &map, &[true, true, false]));
    let (framed, _) = as_frames(&[0, 1]);
    let diagonal = |blocks: Arc<Blocks>, reads_frames: bool| {
        let mut diagonal = vec![0.0; 5];
        let part = BodyPart::new(&framed, blocks, &mut diagonal);
        assert_eq!(part.framed, reads_frames);
        diagonal
    };
    // the segments' diagonal (`add_diagonal`) over all three disks in body form
    let mut serial = vec![0.0; 5];
    let all = BodyPart::new(&as_segments(&[]), Arc::clone(&blocks), &mut [0.0; 5]);
    all.add_diagonal(&framed, 0..framed.len(), &mut serial, 0);
    let bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(bits(&diagonal(blocks, true), &serial), "the frames' diagonal");
    // disk 2 (the second frame's rows 2 and 3) outside the body form adds nothing there
    assert!(bits(&diagonal(partial, false), &[serial[0], serial[1], 0.0, 0.0, 0.0]), "partial");
    assert!(serial[..4].iter().all(|&d| d > 0.0));
}
