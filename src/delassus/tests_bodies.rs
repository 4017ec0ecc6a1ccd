//! The body form's product in halves (`BodyPart::apply` over the halves of `split`, math note §3.3).

use super::*;
use crate::body::Body;
use crate::cluster::Flexibility;
use crate::dofs::DofMap;
use crate::geometry::{Vec2, cw};
use crate::jacobian::Piece;
use crate::model::{BodyModel, BodySpec, Material, Plane, Shape};

/// Whether a and b have the same length and the same bits entry by entry.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The largest |x| of v (0 for an empty v).
fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Disks of radius 0.5 in a row, one apart, of the given models: the bodies, their DOF map and
/// flexibility (each disk its own cluster).
fn disks(models: &[BodyModel]) -> (Vec<Body>, DofMap, Flexibility) {
    let material = Material { name: "m".into(), density: 2.0, young: Some(1e8), poisson: Some(0.3) };
    let bodies: Vec<Body> = (0..models.len())
        .map(|i| {
            let shape = Shape::Disk { center: Vec2::new(i as f64, 0.0), radius: 0.5 };
            Body::new(&BodySpec::at_rest(format!("b{i}"), shape, models[i], false), &material, Plane::Stress)
        })
        .collect();
    let map = DofMap::new(&bodies, &[]);
    let mut flex = Flexibility::new(false);
    flex.refresh(&map, &bodies, &[], 0.01, 0.0).expect("K̃ is SPD");
    (bodies, map, flex)
}

/// `n` rigid disks ([`disks`]), each in body form, with the body form's blocks.
fn rigid_disks(n: usize) -> (Vec<Body>, DofMap, Flexibility, Arc<Blocks>) {
    let (bodies, map, flex) = disks(&vec![BodyModel::Rigid; n]);
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
/// B v (v = 1/4) summed as the segments' (the same bits), stay frames where they come in row
/// order and are pushed as their segments otherwise (contact 0 pushed last; contacts 5,249 to
/// 5,328 after 5,329), side by side with the frames: 10,499, 10,498, 10,419 and 10,500 frames.
/// The part reads frames and segments in push order: cut at the middle frame (5,249; 5,209 of
/// the late order, whose 80 contacts of segments all lie above its row; 5,250 with the wall),
/// and not at all with contact 0's segments, pushed last below every row; with the segments'
/// diagonal bit for bit and products equal to the segments' to 1e-12. The response K̃⁻¹ Bᵀ z (`BodyPart::response`) has the bits of B's
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
    // the order, the wall, the segments' cut (segment, its row), the frames' (frame, its row)
    let orders = [
        (in_order(), false, Some((21_000, 10_500)), 10_499, Some((5_249, 10_498))),
        ((1..n - 1).chain([0]).collect(), false, None, 10_498, None),
        (late, false, Some((21_320, 10_660)), 10_419, Some((5_209, 10_418))),
        (in_order(), true, Some((21_002, 10_502)), 10_500, Some((5_250, 10_500))),
    ];
    for (order, with_wall, cut, frames, frame_cut) in orders {
        let split = cut.map(|(segs, row)| Cut { frames: 0, segs, row });
        let frame_split = frame_cut.map(|(frames, row)| Cut { frames, segs: 0, row });
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
        assert!(same_bits(&q, &q_framed), "split {split:?}: B v");
        assert_eq!(framed.frames().len(), frames, "split {split:?}: framed");
        assert_eq!(framed.len(), jac.len());
        let same_segments = framed.segments().iter().zip(jac.segments()).all(|(a, b)| {
            (a.row(), a.cluster(), a.dofs()) == (b.row(), b.cluster(), b.dofs())
                && same_bits(framed.vals(a), jac.vals(b))
        });
        assert!(same_segments, "split {split:?}: the frames' segments");
        products_match(&jac, &framed, &blocks, (split, frame_split), &flex, &map);
    }
}

/// The product checks of `products_split_only_where_no_row_straddles` (see there) on B pushed
/// as segments (`jac`) and as frames (`framed`), with the cuts each should get.
fn products_match(
    jac: &Jacobian,
    framed: &Jacobian,
    blocks: &Arc<Blocks>,
    (split, frame_split): (Option<Cut>, Option<Cut>),
    flex: &Flexibility,
    map: &DofMap,
) {
    let mut diagonal = vec![0.0; jac.rows];
    let part = BodyPart::new(jac, Arc::clone(blocks), &mut diagonal);
    assert_eq!(part.split, split);
    let mut serial = vec![0.0; jac.rows];
    part.add_diagonal(jac, 0..jac.segments().len(), &mut serial, 0);
    assert!(same_bits(&diagonal, &serial), "split {split:?}: diagonal");
    let z: Vec<f64> = (0..jac.rows).map(|r| ((r * 37) % 101) as f64 / 101.0 - 0.3).collect();
    // adding to zeros, or clearing a vector of NaN first (a row it missed would stay NaN)
    let on = |part: &BodyPart, jac: &Jacobian, threads: usize, clear: bool| {
        let pool = micropool::ThreadPoolBuilder::default().num_threads(threads - 1).build();
        let mut out = vec![if clear { f64::NAN } else { 0.0 }; jac.rows];
        pool.install(|| part.apply(jac, &z, &mut out, clear));
        out
    };
    let (got, w) = (on(&part, jac, 2, false), super::super::assemble(jac, flex, map));
    assert!(same_bits(&on(&part, jac, 1, false), &got), "split {split:?}: threads");
    assert!(
        same_bits(&on(&part, jac, 1, true), &got) && same_bits(&on(&part, jac, 2, true), &got),
        "split {split:?}: clearing"
    );
    response_matches_the_transpose_product(&part, jac, &z, flex, map);
    let want: Vec<f64> = w.outer_iterator().map(|row| row.iter().map(|(c, v)| v * z[c]).sum()).collect();
    let scale = max_abs(&want);
    let dmax = max_abs(&diagonal);
    for (r, d) in diagonal.iter().enumerate() {
        let wrr = w.get(r, r).copied().unwrap_or(0.0);
        assert!((d - wrr).abs() <= 1e-12 * dmax, "split {split:?}, diagonal {r}: {d} vs {wrr}");
    }
    let near = |a: &[f64]| a.iter().zip(&want).all(|(a, b)| (a - b).abs() <= 1e-12 * scale);
    assert!(near(&got), "split {split:?}: W z");
    let mut diagonal_f = vec![0.0; jac.rows];
    let part = BodyPart::new(framed, Arc::clone(blocks), &mut diagonal_f);
    assert_eq!(part.split, frame_split);
    assert!(same_bits(&diagonal_f, &diagonal), "split {split:?}: the frames' diagonal");
    let got = on(&part, framed, 2, false);
    assert!(same_bits(&on(&part, framed, 1, true), &got), "split {split:?}: the frames' threads");
    assert!(near(&got), "split {split:?}: the frames' W z");
    response_matches_the_transpose_product(&part, framed, &z, flex, map);
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
    assert!(same_bits(&on(1), &got), "split {:?}: response threads", part.split);
    if part.split.is_none() {
        assert!(same_bits(&got, &want), "response without halves");
    }
    let scale = max_abs(&want);
    assert!(
        got.iter().zip(&want).all(|(a, b)| (a - b).abs() <= 1e-12 * scale),
        "split {:?}: response",
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

/// B as contact frames (`Jacobian::push_frame`) and segments side by side: two frames (a
/// contact between rigid bodies at rows 0 and 1, a contact on one body at rows 2 and 3), a
/// segment of four entries at row 4 and a third frame at rows 5 and 6 (pushed in that order:
/// three runs, `Jacobian::pieces`) give the segments of pushing all as segments, in push order,
/// with the same entries (a negation is exact), both as `segments` makes them and once turned
/// into segments (`unframe`). A frame pushed below the last frame's row is pushed as its
/// segments (frames out of row order, in their push order), and sorting by row sorts the
/// segments. B v summed as the frames are pushed has the segments' bits.
#[test]
fn frames_and_segments_side_by_side() {
    let n = Vec2::new(0.6, -0.8);
    let (na, nb) = ([n.x, n.y, 0.3], [-n.x, -n.y, -0.2]);
    let (ta, tb) = ([cw(n).x, cw(n).y, 0.5], [-cw(n).x, -cw(n).y, 0.7]);
    let frames =
        [Frame::new(0, 0, na, ta).with_second(3, nb, tb), Frame::new(2, 6, na, ta), Frame::new(5, 0, nb, tb)];
    let deformable: &[f64] = &[n.x, n.y, 0.1, 0.2];
    let segments = [
        (0, 0, &na[..]),
        (1, 0, &ta),
        (0, 3, &nb),
        (1, 3, &tb),
        (2, 6, &na),
        (3, 6, &ta),
        (4, 3, deformable),
    ];
    let last = [(5, 0, &nb[..]), (6, 0, &tb)];
    let v: Vec<f64> = (0..9).map(|i| 0.1 * i as f64 - 0.3).collect();
    let same = |a: &Jacobian, b: &Jacobian| {
        a.len() == b.len()
            && a.segments().iter().zip(b.segments()).all(|(s, t)| {
                (s.row(), s.cluster(), s.dofs()) == (t.row(), t.cluster(), t.dofs())
                    && same_bits(a.vals(s), b.vals(t))
            })
    };
    let as_segments = |all: &[(usize, usize, &[f64])]| {
        let (mut jac, mut q) = (Jacobian::with_rows(7), vec![0.0; 7]);
        all.iter().for_each(|&(row, start, vals)| jac.push_apply(row, start / 3, start, vals, &v, &mut q));
        (jac, q)
    };
    let clusters = [[0, 1], [2, 2], [0, 0]];
    let push = |jac: &mut Jacobian, q: &mut [f64], k: usize| jac.push_frame(frames[k], clusters[k], &v, q);
    let (mut mixed, mut q) = (Jacobian::with_rows(7), vec![0.0; 7]);
    push(&mut mixed, &mut q, 0);
    push(&mut mixed, &mut q, 1);
    mixed.push_apply(4, 1, 3, deformable, &v, &mut q);
    push(&mut mixed, &mut q, 2);
    let (want, q_want) = as_segments(&[&segments[..], &last].concat());
    assert_eq!((mixed.frames().len(), mixed.own_segments().len(), mixed.len()), (3, 1, 9));
    let pieces: Vec<Piece> = mixed.pieces().collect();
    assert_eq!(pieces, [Piece::Frames(0..2), Piece::Segments(0..1), Piece::Frames(2..3)]);
    assert!(same(&mixed, &want), "made from the frames");
    assert!(same_bits(&q, &q_want), "B v");
    let mut unframed = mixed.clone();
    unframed.unframe();
    assert_eq!((unframed.frames().len(), unframed.own_segments().len()), (0, 9));
    assert!(same(&unframed, &want), "unframed");
    let (mut late, mut q) = (Jacobian::with_rows(7), vec![0.0; 7]);
    push(&mut late, &mut q, 1);
    push(&mut late, &mut q, 0);
    assert_eq!((late.frames().len(), late.own_segments().len()), (1, 4));
    let (want, _) = as_segments(&[&segments[4..6], &segments[..4]].concat());
    assert!(same(&late, &want), "out of row order");
    let (mut want, _) = as_segments(&[&segments[4..6], &segments[..4]].concat());
    late.sort_by_row();
    want.sort_by_row();
    assert!(late.frames().is_empty() && same(&late, &want), "sorted");
}

/// The body form over a rigid disk, three deformable ones (4 DOFs each) and a rigid one in a
/// row (DOFs at 0, 3, 7, 11 and 15: not `Blocks::dense`, so a frame's bodies are found by their
/// clusters; the last rigid disk is body 4, where its first DOF over 3, the dense rule, would
/// name body 5), with a wall contact on each rigid disk as a frame and the four disk-disk
/// contacts as segments (wall, contacts, wall: runs of frames and segments in turn), against the
/// same B pushed as segments only: the diagonal, W z, the response K̃⁻¹ Bᵀ z and the row bounds
/// have the same bits (the same terms in the same order; the frames give each entry bit for
/// bit), and W z equals the assembled W's to 1e-12 of its largest entry (another order).
#[test]
fn frames_read_beside_a_deformable_body() {
    let (rigid, deformable) = (BodyModel::Rigid, BodyModel::Deformable);
    let models = [rigid, deformable, deformable, deformable, rigid];
    let (count, rows) = (models.len(), 2 * models.len() + 2);
    let (bodies, map, flex) = disks(&models);
    let blocks = Arc::new(Blocks::new(&flex, &map, &vec![true; count]));
    let starts: Vec<usize> = (0..count).map(|b| map.range(b).start).collect();
    assert!(!blocks.dense && starts == [0, 3, 7, 11, 15], "{starts:?}, dense {}", blocks.dense);
    let v: Vec<f64> = (0..map.total()).map(|i| 0.1 * i as f64 - 0.3).collect();
    let build = |framed: bool| {
        let (mut jac, mut q) = (Jacobian::with_rows(rows), vec![0.0; rows]);
        // a wall contact on rigid disk b at rows r, r + 1, pushing on it along +x or -x
        let wall = |jac: &mut Jacobian, q: &mut [f64], b: usize, r: usize, dir: f64| {
            let (n, x) = (Vec2::new(dir, 0.1).normalize(), Vec2::new(b as f64 - 0.5 * dir, 0.0));
            let [rn, rt] = [n, cw(n)].map(|d| bodies[b].rigid_row(x, d, 1.0));
            let start = map.range(b).start;
            match framed {
                true => jac.push_frame(Frame::new(r, start, rn, rt), [b, b], &v, q),
                false => {
                    [rn, rt].iter().enumerate().for_each(|(k, e)| jac.push_apply(r + k, b, start, e, &v, q))
                }
            }
        };
        wall(&mut jac, &mut q, 0, 0, 1.0);
        for (k, (a, b)) in (0..count - 1).map(|a| (a, a + 1)).enumerate() {
            let x = Vec2::new(a as f64 + 0.5, 0.0);
            for (r, dir) in [(2 + 2 * k, Vec2::x()), (3 + 2 * k, cw(Vec2::x()))] {
                for (body, sign) in [(a, 1.0), (b, -1.0)] {
                    let row = bodies[body].shape_row(x, dir) * sign;
                    let range = map.range(body);
                    jac.push_apply(r, body, range.start, &row.as_slice()[..range.len()], &v, &mut q);
                }
            }
        }
        wall(&mut jac, &mut q, count - 1, rows - 2, -1.0);
        (jac, q)
    };
    let ((framed, q_framed), (plain, q)) = (build(true), build(false));
    assert_eq!((framed.frames().len(), plain.frames().len(), framed.len(), plain.len()), (2, 0, 20, 20));
    assert!(same_bits(&q_framed, &q), "B v");
    let (mut d_framed, mut d) = (vec![0.0; rows], vec![0.0; rows]);
    let part_framed = BodyPart::new(&framed, Arc::clone(&blocks), &mut d_framed);
    let part = BodyPart::new(&plain, Arc::clone(&blocks), &mut d);
    assert!(same_bits(&d_framed, &d) && d.iter().all(|&x| x > 0.0), "diagonal");
    let z: Vec<f64> = (0..rows).map(|r| 0.3 - 0.1 * r as f64).collect();
    let product = |part: &BodyPart, jac: &Jacobian| {
        let mut out = vec![0.0; rows];
        part.apply(jac, &z, &mut out, true);
        out
    };
    let got = product(&part_framed, &framed);
    assert!(same_bits(&got, &product(&part, &plain)), "W z");
    let w = super::super::assemble(&plain, &flex, &map);
    let want: Vec<f64> = w.outer_iterator().map(|row| row.iter().map(|(c, x)| x * z[c]).sum()).collect();
    let scale = max_abs(&want);
    assert!(got.iter().zip(&want).all(|(a, b)| (a - b).abs() <= 1e-12 * scale), "W z against W");
    let response = |part: &BodyPart, jac: &Jacobian| {
        let mut out = vec![0.0; map.total()];
        assert!(part.response(jac, &z, &mut out));
        out
    };
    assert!(same_bits(&response(&part_framed, &framed), &response(&part, &plain)), "response");
    let sc: Vec<f64> = (0..rows).map(|r| 1.0 + 0.25 * r as f64).collect();
    let bounds = |part: &BodyPart, jac: &Jacobian| {
        let mut out = vec![0.0; rows];
        part.row_bounds(jac, &sc, &mut out);
        out
    };
    assert!(same_bits(&bounds(&part_framed, &framed), &bounds(&part, &plain)), "row bounds");
}

/// The body form's blocks brought up to date in place (`Blocks::update`): on a rigid disk, a
/// deformable one and a rigid one, the deformable disk strained (its K̃ follows its geometry,
/// so the flexibility's next refresh replaces its factor and only its) gives blocks equal bit
/// for bit to new ones made from the refreshed flexibility (`Blocks::new`): K̃⁻¹ and R of
/// every body, and the stamps. The kept blocks' layout holds (`same_layout`), and the
/// update copies the deformable disk's block, not the others' (their K̃⁻¹ unchanged).
#[test]
fn blocks_updated_in_place_equal_new_ones() {
    let (mut bodies, map, mut flex) = disks(&[BodyModel::Rigid, BodyModel::Deformable, BodyModel::Rigid]);
    let mut kept = Blocks::new(&flex, &map, &[true; 3]);
    let before = kept.kinv.clone();
    let mut strain = crate::body::Dofs::zeros();
    strain[3] = 0.01;
    bodies[1].apply_increment(&strain);
    flex.refresh(&map, &bodies, &[], 0.01, 0.0).expect("K̃ is SPD");
    assert!(kept.same_layout(&map, &[true; 3]) && kept.stamps != flex.stamps());
    assert!(kept.update(&flex));
    let new = Blocks::new(&flex, &map, &[true; 3]);
    assert!(
        same_bits(&kept.kinv, &new.kinv) && same_bits(&kept.root, &new.root) && kept.stamps == new.stamps
    );
    let changed: Vec<usize> = (0..3)
        .filter(|&b| {
            let (at, n) = (kept.square[b], kept.n[b]);
            !same_bits(&before[at..at + n * n], &kept.kinv[at..at + n * n])
        })
        .collect();
    assert_eq!(changed, [1]);
}

/// Disks ([`disks`]'s row and material) of the given models, the first `joined` each bolted to
/// the next (E = 1e8 Pa, A = 0.01 m²) into one cluster, the rest alone: the bodies, their DOF
/// map and flexibility.
fn bolted(models: &[BodyModel], joined: usize) -> (Vec<Body>, DofMap, Flexibility) {
    let (bodies, _, _) = disks(models);
    let (couplings, pairs) = crate::cluster::bolted_row(&bodies, joined);
    let map = DofMap::new(&bodies, &pairs);
    let mut flex = Flexibility::new(false);
    flex.refresh(&map, &bodies, &couplings, 0.01, 0.0).expect("K̃ is SPD");
    (bodies, map, flex)
}

/// A cluster of several bodies in body form: rigid, rigid, deformable and rigid disks bolted
/// into a chain (13 DOFs, a dense closed form) beside a rigid disk alone, with a wall contact
/// at each end and a contact between each two neighbours (the chain's three have both segments
/// of each row on the chain's cluster). The diagonal and W z equal the assembled W's to 1e-12
/// of their largest entries (the same terms in another order). The row bounds of Ŵ = S W S
/// (S = diag(W)^-1/2, the solver's scaling) bound ‖Ŵ‖ from above, and xᵀŴx <= Σ_r b_r x_r² for
/// three vectors x, as `row_bounds` promises. They are also within a factor √13 + 1 of ‖Ŵ‖: a
/// row's bound is the sum of its clusters' λ_c, each Gershgorin's bound of an n_c × n_c matrix
/// M_c whose largest eigenvalue is ‖Ŵ_c‖ <= ‖Ŵ‖ (Ŵ is the sum of its clusters' PSD parts), and
/// Gershgorin's bound of a symmetric matrix is within √n_c of its norm. Taking a row's two
/// segments on the chain one by one instead of summed would give tens of times ‖Ŵ‖ here, the
/// bolts' small relative compliance setting the inner rows' scale (math note §3.3).
#[test]
fn joined_cluster_in_body_form() {
    let (rigid, deformable) = (BodyModel::Rigid, BodyModel::Deformable);
    let models = [rigid, rigid, deformable, rigid, rigid];
    let (count, rows) = (models.len(), 2 * models.len() + 2);
    let (bodies, map, flex) = bolted(&models, 4);
    assert_eq!((map.clusters(), map.cluster_range(0).len()), (2, 13));
    let blocks = Arc::new(Blocks::new(&flex, &map, &[true, true]));
    assert_eq!((blocks.n.clone(), blocks.joined.clone()), (vec![13, 3], vec![true, false]));
    let (mut jac, v, mut q) = (Jacobian::with_rows(rows), vec![0.0; map.total()], vec![0.0; rows]);
    let mut push = |jac: &mut Jacobian, r: usize, x: Vec2, dir: Vec2, body: usize, sign: f64| {
        let row = bodies[body].shape_row(x, dir) * sign;
        let range = map.range(body);
        let cluster = map.cluster_of(body).expect("a moving body");
        jac.push_apply(r, cluster, range.start, &row.as_slice()[..range.len()], &v, &mut q);
    };
    for (r, dir) in [(0, Vec2::x()), (1, cw(Vec2::x()))] {
        push(&mut jac, r, Vec2::new(-0.5, 0.0), dir, 0, 1.0);
        push(&mut jac, rows - 2 + r, Vec2::new(count as f64 - 0.5, 0.0), -dir, count - 1, 1.0);
    }
    for (k, a) in (0..count - 1).enumerate() {
        let x = Vec2::new(a as f64 + 0.5, 0.0);
        for (r, dir) in [(2 + 2 * k, Vec2::x()), (3 + 2 * k, cw(Vec2::x()))] {
            push(&mut jac, r, x, dir, a, 1.0);
            push(&mut jac, r, x, dir, a + 1, -1.0);
        }
    }
    let w = super::super::assemble(&jac, &flex, &map);
    let dense = nalgebra::DMatrix::from_fn(rows, rows, |i, j| w.get(i, j).copied().unwrap_or(0.0));
    let mut diagonal = vec![0.0; rows];
    let part = BodyPart::new(&jac, Arc::clone(&blocks), &mut diagonal);
    let near = |a: &[f64], b: &[f64]| {
        let scale = max_abs(b);
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * scale)
    };
    assert!(near(&diagonal, dense.diagonal().as_slice()), "diagonal {diagonal:?}");
    let z: Vec<f64> = (0..rows).map(|r| 0.3 - 0.1 * r as f64).collect();
    let mut got = vec![0.0; rows];
    part.apply(&jac, &z, &mut got, true);
    assert!(near(&got, (&dense * nalgebra::DVector::from_column_slice(&z)).as_slice()), "W z");
    let sc: Vec<f64> = diagonal.iter().map(|d| 1.0 / d.sqrt()).collect();
    let scaled = nalgebra::DMatrix::from_fn(rows, rows, |i, j| sc[i] * dense[(i, j)] * sc[j]);
    let norm = scaled.symmetric_eigenvalues().max();
    let mut bounds = vec![0.0; rows];
    part.row_bounds(&jac, &sc, &mut bounds);
    let largest = bounds.iter().copied().fold(0.0, f64::max);
    assert!(norm <= largest && largest <= (13f64.sqrt() + 1.0) * norm, "{largest} against ‖Ŵ‖ = {norm}");
    for x in [z.clone(), vec![1.0; rows], (0..rows).map(|r| (r as f64).sin()).collect()] {
        let x = nalgebra::DVector::from_vec(x);
        let form = x.dot(&(&scaled * &x));
        let bound: f64 = bounds.iter().zip(x.iter()).map(|(b, x)| b * x * x).sum();
        assert!(form <= bound * (1.0 + 1e-12), "{form} > {bound}");
    }
}
