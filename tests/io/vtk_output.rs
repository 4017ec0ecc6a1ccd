//! ParaView output (scene-format "Outputs", VTK data table): short runs of the paper examples
//! write `vtk/scene.pvd` and one `.vtu` per written step; each file is read back (by the
//! reader below, from the layout VTK's XML format gives base64 appended data: the base64 of a
//! UInt64 byte count and the values, at the `offset` of each `DataArray` after the `_` that
//! opens the data) and compared with the CSVs written in the same run, and read again by vtkio (a VTK
//! reader that is not ours) to the same points, cells and arrays. VTK's own reader and meshio
//! read every example's files in `.ci/run` (`scripts/check-vtu.py`, Python).
//!
//! Where the expected numbers come from:
//! - cell and point counts: the contract (one cell per body, one line per contact row of
//!   contacts.csv and per connector row of connectors.csv at that step, one triangle per mesh
//!   element on the mesh's nodes) and the display tessellation (64-gon disks, rings as a
//!   keyhole polygon on 2 × 64 points, polygons by their vertex count in the scene); every example is run;
//! - values: the CSV columns of the same step, parsed back. Both files are written from the
//!   same f64 (CSV in shortest round-trip form, VTK as binary f64), so they must agree
//!   exactly;
//! - a disk's display 64-gon is symmetric about its centre: the mean of its vertices is the
//!   centroid to rounding (1e-12 relative is a few hundred ulps of 64 additions);
//! - contact lines join the two bodies' sides: in the static §7.1 heap (the bodies stay put
//!   to 1e-9 m, tests/paper/paper_7_1_disk_heap.rs) each end of a disk–disk line lies on its
//!   disk's circle, |end − centre| = R to 1e-8 m (motion plus the solver's gap accuracy).

use pbdda::geometry::{Vec2, polygon_moments};
use pbdda::model::Model;
use pbdda::output::connectors::ConnectorWriter;
use pbdda::output::csv::CsvWriter;
use pbdda::output::results::{Table, write_geometry};
use pbdda::output::vtk::VtkWriter;
use pbdda::world::World;
use std::path::{Path, PathBuf};

/// VTK cell type codes, from VTK's file format documentation (restated, not taken from the
/// writer, so that a wrong code there fails here).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CellType {
    Line = 3,
    Triangle = 5,
    Polygon = 7,
}

impl CellType {
    fn of(code: f64) -> CellType {
        let all = [CellType::Line, CellType::Triangle, CellType::Polygon];
        all.into_iter().find(|&t| t as u8 as f64 == code).unwrap_or_else(|| panic!("cell type {code}"))
    }
}

/// The value of attribute `key` in the XML tag `tag`.
fn attribute<'a>(tag: &'a str, key: &str) -> &'a str {
    let at = tag.find(&format!(" {key}=\"")).unwrap_or_else(|| panic!("no {key} in {tag}")) + key.len() + 3;
    &tag[at..at + tag[at..].find('"').expect("closing quote")]
}

/// One array of a `.vtu` file: its section (`PointData`, `CellData`, `Points`, `Cells`), name
/// and values.
type Array = (String, String, Vec<f64>);

/// The arrays of a `.vtu` file with base64 appended data, as f64, and the piece's point and
/// cell counts.
fn read_vtu(path: &Path) -> (Vec<Array>, usize, usize) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let open = b"<AppendedData encoding=\"base64\">";
    let at = bytes.windows(open.len()).position(|w| w == open).expect("base64 appended data");
    let head = std::str::from_utf8(&bytes[..at]).expect("UTF-8 header");
    assert!(head.contains("byte_order=\"LittleEndian\" header_type=\"UInt64\""), "{head}");
    let data = at + open.len() + bytes[at + open.len()..].iter().position(|&b| b == b'_').expect("_") + 1;
    let piece = &head[head.find("<Piece ").expect("piece")..];
    let count = |key| attribute(piece, key).parse::<usize>().expect("count");
    let (mut arrays, mut section) = (Vec::new(), "");
    for tag in head.split('<').map(|t| t.split('>').next().unwrap_or("")) {
        let name = tag.split([' ', '/']).next().unwrap_or("");
        if ["PointData", "CellData", "Points", "Cells"].contains(&name) {
            section = name;
        }
        if name != "DataArray" {
            continue;
        }
        assert_eq!(attribute(tag, "format"), "appended", "{tag}");
        if section == "Cells" && attribute(tag, "Name") != "types" {
            // VTK's vtkIdType is signed, and meshio casts ids to a signed type: unsigned ids fail there
            assert!(["Int32", "Int64"].contains(&attribute(tag, "type")), "signed ids: {tag}");
        }
        let start = data + attribute(tag, "offset").parse::<usize>().expect("offset");
        let block = decode_block(&bytes[start..]);
        let values: Vec<f64> = match attribute(tag, "type") {
            "Float64" => block.chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect(),
            "Int32" => block.chunks(4).map(|c| i32::from_le_bytes(c.try_into().unwrap()) as f64).collect(),
            "Int64" => block.chunks(8).map(|c| i64::from_le_bytes(c.try_into().unwrap()) as f64).collect(),
            "UInt8" => block.iter().map(|&b| b as f64).collect(),
            other => panic!("type {other}"),
        };
        let components: usize = attribute(tag, "NumberOfComponents").parse().expect("components");
        assert_eq!(values.len() % components, 0, "{tag}");
        arrays.push((section.to_string(), attribute(tag, "Name").to_string(), values));
    }
    (arrays, count("NumberOfPoints"), count("NumberOfCells"))
}

/// One appended block: base64 of its UInt64 byte count and its values, encoded together (VTK's
/// layout for uncompressed appended data); the values' bytes.
fn decode_block(text: &[u8]) -> Vec<u8> {
    use base64::Engine;
    let b64 = base64::engine::general_purpose::STANDARD;
    let head = b64.decode(&text[..12]).expect("base64 block header");
    let len = u64::from_le_bytes(head[..8].try_into().unwrap()) as usize;
    let chars = (8 + len).div_ceil(3) * 4;
    let block = b64.decode(&text[..chars]).expect("base64 block");
    assert_eq!(block.len(), 8 + len, "block length");
    block[8..].to_vec()
}

fn example(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(name);
    pbdda::scene::load(&path).unwrap_or_else(|e| panic!("example {name} does not load: {e}"))
}

/// Runs `steps` steps of an example, writing CSVs, geometry and VTK as `pbdda run` does.
fn run(name: &str, steps: usize, every: usize) -> (PathBuf, World) {
    run_model(name, example(name), steps, every)
}

fn run_model(name: &str, mut model: Model, steps: usize, every: usize) -> (PathBuf, World) {
    model.time.steps = steps;
    model.output.every = every;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("vtk_{name}"));
    let mut world = World::new(model);
    let mut csv = CsvWriter::create(&dir, every, steps, true).expect("csv writer");
    let mut lines = ConnectorWriter::create(&dir, &world, true).expect("connector writer");
    write_geometry(&dir, &world).expect("geometry");
    let mut vtk = VtkWriter::create(&dir, &world).expect("vtk writer");
    for _ in 0..steps {
        let rec = world.step().unwrap_or_else(|e| panic!("{e}"));
        csv.write_step(&world, &rec).expect("csv step");
        lines.write_step(&world, &rec).expect("connectors step");
        vtk.write_step(&world, &rec).expect("vtk step");
    }
    (dir, world)
}

/// One read-back step: points, cells (point ids), types and named cell arrays.
struct Step {
    points: Vec<Vec2>,
    cells: Vec<Vec<usize>>,
    types: Vec<CellType>,
    arrays: Vec<(String, Vec<f64>)>,
    /// Point data `displacement` (mesh nodes), empty when absent.
    displacement: Vec<f64>,
}

impl Step {
    fn read(path: &Path) -> Step {
        let (arrays, np, nc) = read_vtu(path);
        let take = |section: &str, name: &str| {
            arrays.iter().find(|(s, n, _)| s == section && n == name).map(|(_, _, v)| v.clone())
        };
        let p = take("Points", "Points").expect("points");
        assert_eq!(p.len(), 3 * np);
        let points = p.chunks(3).map(|c| Vec2::new(c[0], c[1])).collect();
        let (connectivity, offsets) =
            (take("Cells", "connectivity").unwrap(), take("Cells", "offsets").unwrap());
        let mut start = 0;
        let cells: Vec<Vec<usize>> = offsets
            .iter()
            .map(|&end| {
                let c = connectivity[start..end as usize].iter().map(|&i| i as usize).collect();
                start = end as usize;
                c
            })
            .collect();
        let types: Vec<CellType> = take("Cells", "types").unwrap().into_iter().map(CellType::of).collect();
        assert_eq!((cells.len(), types.len()), (nc, nc));
        let displacement = take("PointData", "displacement").unwrap_or_default();
        let arrays = arrays.into_iter().filter(|(s, _, _)| s == "CellData").map(|(_, n, v)| (n, v)).collect();
        let step = Step { points, cells, types, arrays, displacement };
        step.same_as_vtkio(path);
        step
    }

    /// vtkio, a VTK reader that is not ours, reads `path` to the same points, cells and cell
    /// arrays (values compared exactly: both decode the same bytes).
    fn same_as_vtkio(&self, path: &Path) {
        use vtkio::model::{Attribute, DataArray, DataSet, Vtk};
        let vtk = Vtk::import(path).unwrap_or_else(|e| panic!("vtkio, {}: {e:?}", path.display()));
        let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else { panic!("not a grid") };
        assert_eq!(pieces.len(), 1);
        let piece = pieces.into_iter().next().unwrap().into_loaded_piece_data(None).expect("piece");
        let points: Vec<f64> = piece.points.cast_into().expect("points");
        let ours: Vec<f64> = self.points.iter().flat_map(|p| [p.x, p.y, 0.0]).collect();
        assert_eq!(points, ours, "vtkio points");
        let (connectivity, offsets) = piece.cells.cell_verts.into_xml();
        let ends: Vec<usize> =
            self.cells.iter().scan(0, |n, c| Some(*n + c.len()).inspect(|e| *n = *e)).collect();
        assert_eq!(offsets.iter().map(|&o| o as usize).collect::<Vec<_>>(), ends, "vtkio offsets");
        let ids: Vec<usize> = self.cells.iter().flatten().copied().collect();
        assert_eq!(connectivity.iter().map(|&i| i as usize).collect::<Vec<_>>(), ids, "vtkio connectivity");
        assert_eq!(piece.data.cell.len(), self.arrays.len(), "vtkio cell arrays");
        for a in &piece.data.cell {
            let Attribute::DataArray(DataArray { name, data, .. }) = a else { panic!("field data") };
            let values: Vec<f64> = data.clone().cast_into().expect("numbers");
            assert_eq!(values, self.array(name), "vtkio {name}");
        }
    }

    fn array(&self, name: &str) -> &[f64] {
        &self.arrays.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no cell array `{name}`")).1
    }
}

/// Rows of a CSV table at one step, as (column -> text) lookups.
fn rows_at(t: &Table, step: usize) -> Vec<Vec<String>> {
    let s = t.col("step").expect("step column");
    t.rows.iter().filter(|(_, r)| r[s] == step.to_string()).map(|(_, r)| r.clone()).collect()
}

fn num(t: &Table, row: &[String], key: &str) -> f64 {
    let c = t.col(key).expect("column");
    if row[c].is_empty() { 0.0 } else { row[c].parse().expect("number") }
}

/// Checks every written step of a run against its CSVs; returns the steps checked.
fn check_run(dir: &Path, world: &World, written: &[usize]) -> Vec<Step> {
    let pvd = std::fs::read_to_string(dir.join("vtk/scene.pvd")).expect("scene.pvd");
    let bodies = Table::read(&dir.join("bodies.csv")).expect("bodies.csv");
    let contacts = Table::read(&dir.join("contacts.csv")).expect("contacts.csv");
    let connectors =
        dir.join("connectors.csv").exists().then(|| Table::read(&dir.join("connectors.csv")).expect("csv"));
    let listed = pvd.matches("<DataSet ").count();
    assert_eq!(listed, written.len(), "scene.pvd lists the written steps:\n{pvd}");
    let mut out = Vec::new();
    for &s in written {
        let (b, c) = (rows_at(&bodies, s), rows_at(&contacts, s));
        // a row may carry extra digits of the same value (docs/scene-format.md, "Row layout")
        let time: f64 = b[0][bodies.col("time").unwrap()].parse().expect("time");
        let time = pbdda::output::csv::Num(time);
        let entry = format!("timestep=\"{time}\" group=\"\" part=\"0\" file=\"step_{s:06}.vtu\"");
        assert!(pvd.contains(&entry), "scene.pvd has no entry `{entry}`:\n{pvd}");
        let step = Step::read(&dir.join(format!("vtk/step_{s:06}.vtu")));
        let nb = world.bodies.len();
        let lines = connectors.as_ref().map_or(0, |t| rows_at(t, s).len());
        let meshes = world.bodies.iter().filter_map(|b| b.mesh.as_ref());
        let (triangles, nodes) =
            meshes.fold((0, 0), |(t, n), fe| (t + fe.triangles.len(), n + fe.nodes.len()));
        assert_eq!(
            step.cells.len(),
            nb + c.len() + lines + triangles,
            "step {s}: one cell per body, contact, connector and mesh triangle"
        );
        let body_points: usize = world
            .bodies
            .iter()
            .map(|b| match &b.outline {
                pbdda::body::Outline::Disk { .. } => 64,
                pbdda::body::Outline::Ring { .. } => 128,
                pbdda::body::Outline::Polygon { vertices, .. } => vertices.len(),
            })
            .sum();
        assert_eq!(step.points.len(), body_points + 2 * (c.len() + lines) + nodes, "step {s}: points");
        for name in [
            "body",
            "kind",
            "velocity",
            "rotation",
            "stress",
            "strain",
            "normal_force",
            "shear_force",
            "state",
            "axial_force",
            "plastic_strain",
        ] {
            let per_cell = if ["velocity", "stress", "strain"].contains(&name) { 3 } else { 1 };
            assert_eq!(step.array(name).len(), per_cell * step.cells.len(), "{name} has a value per cell");
        }
        check_bodies(&step, &bodies, &b, world, s);
        check_contacts(&step, &contacts, &c, nb, s);
        if let Some(t) = &connectors {
            // connector lines follow the contacts, in connectors.csv order
            for (k, row) in rows_at(t, s).iter().enumerate() {
                let cell = nb + c.len() + k;
                assert_eq!(step.types[cell], CellType::Line);
                assert_eq!(
                    step.array("axial_force")[cell],
                    num(t, row, "axial_force"),
                    "step {s} connector {k}"
                );
                let state = match row[t.col("state").unwrap()].as_str() {
                    "intact" => 4.0,
                    "broken" => 5.0,
                    "yielding" => 6.0,
                    other => panic!("connector state {other}"),
                };
                assert_eq!(step.array("state")[cell], state, "step {s} connector {k} state");
                let plastic = num(t, row, "plastic_strain");
                assert_eq!(step.array("plastic_strain")[cell], plastic, "step {s} connector {k}");
                // the line runs from anchor to anchor, as the CSV's anchor columns give them
                let ends = [step.points[step.cells[cell][0]], step.points[step.cells[cell][1]]];
                let anchors = [
                    Vec2::new(num(t, row, "anchor_a_x"), num(t, row, "anchor_a_y")),
                    Vec2::new(num(t, row, "anchor_b_x"), num(t, row, "anchor_b_y")),
                ];
                assert_eq!(ends, anchors, "step {s} connector {k}: line ends are the anchors");
            }
        }
        if triangles > 0 {
            assert_eq!(step.displacement.len(), 3 * step.points.len(), "step {s}: displacement per point");
        }
        out.push(step);
    }
    out
}

fn check_bodies(step: &Step, t: &Table, rows: &[Vec<String>], world: &World, s: usize) {
    let (vel, rot, stress, strain) =
        (step.array("velocity"), step.array("rotation"), step.array("stress"), step.array("strain"));
    for (i, row) in rows.iter().enumerate() {
        let b = &world.bodies[i];
        assert_eq!(row[t.col("body").unwrap()], b.name, "bodies.csv order is world order");
        assert_eq!(step.array("body")[i], i as f64);
        assert_eq!(
            [vel[3 * i], vel[3 * i + 1]],
            [num(t, row, "vx"), num(t, row, "vy")],
            "{} velocity",
            b.name
        );
        assert_eq!(rot[i], num(t, row, "rotation"), "{} rotation at step {s}", b.name);
        for (k, key) in ["stress_x", "stress_y", "stress_xy"].iter().enumerate() {
            assert_eq!(stress[3 * i + k], num(t, row, key), "{} {key}", b.name);
        }
        for (k, key) in ["strain_x", "strain_y", "strain_xy"].iter().enumerate() {
            assert_eq!(strain[3 * i + k], num(t, row, key), "{} {key}", b.name);
        }
        let (x, y) = (num(t, row, "x"), num(t, row, "y"));
        let pts: Vec<Vec2> = step.cells[i].iter().map(|&k| step.points[k]).collect();
        let centre = match &b.outline {
            pbdda::body::Outline::Polygon { .. } => {
                assert_eq!(step.types[i], CellType::Polygon);
                polygon_moments(&pts).centroid
            }
            pbdda::body::Outline::Disk { .. } => {
                assert_eq!(step.types[i], CellType::Polygon);
                pts.iter().sum::<Vec2>() / pts.len() as f64
            }
            pbdda::body::Outline::Ring { .. } => {
                assert_eq!(step.types[i], CellType::Polygon);
                // the keyhole: 64 outer ids, the first again, 64 inner ids, the inner first again
                assert_eq!(pts.len(), 130);
                assert_eq!((pts[0], pts[65]), (pts[64], pts[129]));
                pts[..64].iter().chain(&pts[65..129]).sum::<Vec2>() / 128.0
            }
        };
        let scale = b.reach.max(x.abs()).max(y.abs());
        assert!(
            (centre - Vec2::new(x, y)).norm() <= 1e-12 * scale,
            "step {s}: {} cell centroid {centre:?} vs bodies.csv ({x}, {y})",
            b.name
        );
    }
}

fn check_contacts(step: &Step, t: &Table, rows: &[Vec<String>], nb: usize, s: usize) {
    let (pn, pt, state) = (step.array("normal_force"), step.array("shear_force"), step.array("state"));
    let codes = ["open", "stick", "slide", "bonded"];
    for (k, row) in rows.iter().enumerate() {
        let cell = nb + k;
        assert_eq!(step.types[cell], CellType::Line);
        assert_eq!(pn[cell], num(t, row, "normal_force"), "step {s} contact {k} normal force");
        assert_eq!(pt[cell], num(t, row, "shear_force"), "step {s} contact {k} shear force");
        let st = &row[t.col("state").unwrap()];
        assert_eq!(codes[state[cell] as usize], st, "step {s} contact {k} state");
        let c = Vec2::new(num(t, row, "x"), num(t, row, "y"));
        let n = Vec2::new(num(t, row, "nx"), num(t, row, "ny"));
        let g = num(t, row, "gap");
        let ends = [step.points[step.cells[cell][0]], step.points[step.cells[cell][1]]];
        let scale = c.norm().max(1.0);
        for (end, want) in ends.iter().zip([c - n * (g / 2.0), c + n * (g / 2.0)]) {
            assert!(
                (end - want).norm() <= 1e-12 * scale,
                "step {s} contact {k}: end {end:?}, expected {want:?}"
            );
        }
    }
}

/// Each end of every contact line lies on its disk's circle to `tol` (bodies not disks are
/// skipped): the B end first, then the A end.
fn check_line_ends(dir: &Path, world: &World, step: &Step, s: usize, tol: f64) -> usize {
    let contacts = Table::read(&dir.join("contacts.csv")).unwrap();
    let rows = rows_at(&contacts, s);
    let nb = world.bodies.len();
    let mut checked = 0;
    for (k, row) in rows.iter().enumerate() {
        let ends = [step.points[step.cells[nb + k][0]], step.points[step.cells[nb + k][1]]];
        let names = [&row[contacts.col("body_b").unwrap()], &row[contacts.col("body_a").unwrap()]];
        for (end, name) in ends.iter().zip(names) {
            let b = world.bodies.iter().find(|b| &b.name == name).expect("body");
            if let pbdda::body::Outline::Disk { radius } = b.outline {
                let d = (end - b.centroid).norm() - radius;
                assert!(d.abs() < tol, "contact {k}: the end on {name} is {d:e} m off its circle");
                checked += 1;
            }
        }
    }
    checked
}

#[test]
fn disk_heap_time_series_matches_csvs_and_lines_join_the_disks() {
    // 5 steps, every 2nd written: steps 2, 4 and the last, 5
    let (dir, world) = run("7_1_disk_heap.toml", 5, 2);
    let steps = check_run(&dir, &world, &[2, 4, 5]);
    let rows = rows_at(&Table::read(&dir.join("contacts.csv")).unwrap(), 5);
    assert_eq!(rows.len(), 3, "the heap has three contacts (Table 1)");
    // d1-d2 both ends, d2-d3 both ends, d3 end of d3-floor
    assert_eq!(check_line_ends(&dir, &world, &steps[2], 5, 1e-8), 5);
}

/// An open contact with a real gap: the §7.1 heap with d1 lifted by 0.2 m (within the
/// default contact threshold, a tenth of the 10 m radius). d1 falls from rest under g = 10:
/// after 5 steps of 1 ms it moves 5e-5 m per step, and the line's ends (start-of-step contact
/// point ± end-of-step gap / 2) lie on the circles to that motion; 1e-4 m tolerance, while
/// ends swapped or misplaced would be 0.2 m off.
#[test]
fn open_contact_line_spans_the_gap() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_1_disk_heap.toml");
    let text = std::fs::read_to_string(&path).expect("example");
    assert_eq!(text.matches("center = [0.0, 50.0]").count(), 1);
    let lifted = text.replace("center = [0.0, 50.0]", "center = [0.0, 50.2]");
    let model = pbdda::scene::parse(&lifted, "lifted.toml").expect("lifted heap");
    let (dir, world) = run_model("lifted_heap", model, 5, 1);
    let steps = check_run(&dir, &world, &[1, 2, 3, 4, 5]);
    let contacts = Table::read(&dir.join("contacts.csv")).unwrap();
    let gap = num(&contacts, &rows_at(&contacts, 5)[2], "gap");
    assert!((gap - 0.2).abs() < 1e-3, "d1-d2 is the third contact, open by about 0.2 m: {gap}");
    assert_eq!(check_line_ends(&dir, &world, &steps[4], 5, 1e-4), 5);
}

/// Every scene of `examples/`, 4 steps written every 2nd (steps 2 and 4): the files read back
/// with the counts of the contract (bodies, contacts, connectors, mesh triangles and nodes), the
/// arrays of the contract, and the values of the CSVs of the same run (`check_run`).
#[test]
fn every_example_time_series_matches_its_csvs() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("examples/")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert_eq!(names.len(), 28, "{names:?}");
    for name in &names {
        // a directory of its own: the other tests run some of these examples at the same time
        let (out, world) = run_model(&format!("every_{name}"), example(name), 4, 2);
        assert_eq!(check_run(&out, &world, &[2, 4]).len(), 2, "{name}");
    }
}

#[test]
fn ring_in_frame_time_series_matches_csvs() {
    let (dir, world) = run("7_3_ring_in_frame.toml", 4, 1);
    check_run(&dir, &world, &[1, 2, 3, 4]);
}

#[test]
fn block_staircase_time_series_matches_csvs() {
    let (dir, world) = run("7_2_block_staircase.toml", 3, 1);
    check_run(&dir, &world, &[1, 2, 3]);
}

#[test]
fn deformable_staircase_writes_stress_and_strain() {
    let (dir, world) = run("7_2_block_staircase_deformable.toml", 3, 1);
    let steps = check_run(&dir, &world, &[1, 2, 3]);
    // the deformable blocks carry a non-zero stress after loading (else the check is empty)
    let stress = steps[2].array("stress");
    assert!(stress.iter().any(|s| *s != 0.0), "some deformable block is stressed");
}

#[test]
fn pvd_is_valid_before_the_first_step() {
    let model = example("7_1_disk_heap.toml");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("vtk_empty");
    let world = World::new(model);
    let w = VtkWriter::create(&dir, &world).expect("vtk writer");
    let text = std::fs::read_to_string(w.pvd_path()).expect("pvd");
    assert_eq!(text.matches("<DataSet ").count(), 0);
    assert!(text.contains("<Collection>") && text.contains("</VTKFile>"));
}

/// `[output] vtk` (scene format: "vtk = true ... (default true)"): absent is true, `false` is
/// read, and a value of the wrong type is an error naming the key and its line.
#[test]
fn output_vtk_key() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_1_disk_heap.toml");
    let text = std::fs::read_to_string(&path).expect("example");
    assert!(!text.contains("[output]"), "the example sets no [output] table");
    let parse = |extra: &str| pbdda::scene::parse(&format!("{text}\n[output]\n{extra}\n"), "s.toml");
    assert!(pbdda::scene::parse(&text, "s.toml").expect("example").output.vtk);
    assert!(parse("every = 2").expect("every only").output.vtk);
    assert!(!parse("vtk = false").expect("vtk off").output.vtk);
    let err = parse("vtk = 1").expect_err("vtk = 1 is not a boolean").to_string();
    let line = text.lines().count() + 3;
    assert!(err.contains("vtk") && err.contains(&format!("s.toml:{line}")), "{err}");
}

/// The connector and mesh hooks write cells a VTK reader reads back: a square of two
/// triangles (4 nodes, displacement as point data) and one connector line; counts and values
/// are the ones put in.
#[test]
fn connector_and_mesh_hooks_write_readable_cells() {
    use pbdda::output::vtk::{CellValues, Grid, LineCell, MeshCells, add_lines, add_mesh};
    let mut grid = Grid::default();
    let line =
        CellValues { kind: 20, state: 4, axial_force: 1.5e4, body: 0, body_b: 1, ..CellValues::default() };
    add_lines(&mut grid, &[LineCell { a: Vec2::new(0.0, 0.0), b: Vec2::new(2.0, 1.0), values: line }]);
    let nodes = vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
    let mesh = MeshCells {
        body: 2,
        displacement: nodes.iter().map(|p| p * 1e-3).collect(),
        nodes,
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        stress: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
        strain: vec![[0.0; 3]; 2],
    };
    add_mesh(&mut grid, &mesh);
    assert_eq!((grid.num_cells(), grid.num_points()), (3, 6));
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hooks.vtu");
    let mut file = std::io::BufWriter::new(std::fs::File::create(&path).expect("create"));
    grid.write_vtu(&mut file).expect("write");
    std::io::Write::flush(&mut file).expect("flush");
    drop(file);
    let step = Step::read(&path);
    assert_eq!(step.cells, vec![vec![0, 1], vec![2, 3, 4], vec![2, 4, 5]]);
    assert_eq!(step.types, vec![CellType::Line, CellType::Triangle, CellType::Triangle]);
    assert_eq!(step.array("axial_force"), &[1.5e4, 0.0, 0.0]);
    assert_eq!(step.array("kind"), &[20.0, 30.0, 30.0]);
    assert_eq!(step.array("stress"), &[0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    let d = &step.displacement;
    // the line's two points have none; node 2 (1, 1) moved by 1e-3 (1, 1)
    assert_eq!(&d[..6], &[0.0; 6]);
    assert_eq!(&d[3 * 4..3 * 5], &[1e-3, 1e-3, 0.0]);
}

/// A block (1 m x 1 m, density 1000: m g = 1e4 N per metre with g = 10) hangs from a fixed
/// ceiling by one vertical bolt from (0, 0) on the ceiling to (0, -2) on the block's top
/// (E = 200 GPa, A = 5e-4 m^2: EA/l = 5e7 N/m), with `extra` bolt keys. Static analysis
/// (`velocity_carry = 0`) with dt = 0.1 s: the mass term 2m/dt² = 2e5 N/m is 0.4 % of EA/l, so
/// step 1 already loads the bolt with 99.6 % of the weight.
fn hanging_bolt(name: &str, extra: &str, steps: usize) -> (PathBuf, World) {
    let text = format!(
        r#"
[scene]
name = "{name}"
[time]
step = 0.1
steps = {steps}
[physics]
gravity = [0.0, -10.0]
velocity_carry = 0.0
[[material]]
name = "steel"
density = 1000.0
[[body]]
name = "ceiling"
shape = "polygon"
vertices = [[-2.0, 0.0], [2.0, 0.0], [2.0, 1.0], [-2.0, 1.0]]
material = "steel"
fixed = true
[[body]]
name = "block"
shape = "polygon"
vertices = [[-0.5, -3.0], [0.5, -3.0], [0.5, -2.0], [-0.5, -2.0]]
material = "steel"
[[connector]]
name = "bolt"
kind = "bolt"
points = [[0.0, 0.0], [0.0, -2.0]]
bodies = ["ceiling", "block"]
young = 2.0e11
area = 5.0e-4
{extra}
"#
    );
    let model = pbdda::scene::parse(&text, "hanging.toml").unwrap_or_else(|e| panic!("{e:?}"));
    run_model(name, model, steps, 1)
}

/// A bolt of strength 5 kN holding the 10 kN block breaks in step 1 (connectors.csv: one row,
/// `broken`, at step 1, then none). Its line is in step 1's file only, with state 5 (the
/// legend), the force it broke at (the CSV's `axial_force`, above the 5 kN strength) and its
/// ends on the CSV's anchors; anchor a is on the fixed ceiling, so it is exactly the scene's
/// (0, 0). Steps 2 and 3 have no connector cell (`check_run` counts the cells).
#[test]
fn broken_bolt_line_is_written_once_with_its_state() {
    let (dir, world) = hanging_bolt("broken_bolt", "strength = 5.0e3", 3);
    let steps = check_run(&dir, &world, &[1, 2, 3]);
    let t = Table::read(&dir.join("connectors.csv")).expect("connectors.csv");
    assert_eq!(t.rows.len(), 1, "one row: the break");
    let row = &t.rows[0].1;
    assert_eq!(
        (row[t.col("step").unwrap()].as_str(), row[t.col("state").unwrap()].as_str()),
        ("1", "broken")
    );
    let force = num(&t, row, "axial_force");
    assert!(force > 5e3, "broke above its strength: {force}");
    let cell = world.bodies.len() + rows_at(&Table::read(&dir.join("contacts.csv")).unwrap(), 1).len();
    assert_eq!(steps[0].array("state")[cell], 5.0);
    assert_eq!(steps[0].array("axial_force")[cell], force);
    assert_eq!(steps[0].points[steps[0].cells[cell][0]], Vec2::new(0.0, 0.0));
    assert_eq!(steps[1].cells.len(), steps[0].cells.len() - 1, "no line after the break");
}

/// A bolt with yield force 5 kN under the 10 kN block yields from step 1 and stays at its yield
/// force while the block falls (math note §6.1: the active set holds N = Y exactly; 1e-6
/// relative for the solver), its plastic strain growing: each step's line has state 6, the
/// CSV's force and plastic strain, and runs from the fixed anchor (0, 0) to the block's anchor,
/// whose drop below (0, -2) is the block centre's drop (the block does not turn: the bolt and
/// gravity act on one vertical line through its centroid; 1e-12 m).
#[test]
fn yielding_bolt_line_carries_state_and_plastic_strain() {
    let (dir, world) = hanging_bolt("yielding_bolt", "yield_force = 5.0e3", 3);
    let steps = check_run(&dir, &world, &[1, 2, 3]);
    let t = Table::read(&dir.join("connectors.csv")).expect("connectors.csv");
    assert_eq!(t.rows.len(), 3);
    let mut last_plastic = 0.0;
    for (k, (_, row)) in t.rows.iter().enumerate() {
        assert_eq!(row[t.col("state").unwrap()], "yielding", "step {}", k + 1);
        let n = num(&t, row, "axial_force");
        assert!((n - 5e3).abs() <= 1e-6 * 5e3, "step {}: force {n}", k + 1);
        let plastic = num(&t, row, "plastic_strain");
        assert!(plastic > last_plastic, "step {}: plastic strain {plastic} grows", k + 1);
        last_plastic = plastic;
    }
    let contacts = Table::read(&dir.join("contacts.csv")).unwrap();
    let bodies = Table::read(&dir.join("bodies.csv")).unwrap();
    for (k, step) in steps.iter().enumerate() {
        let cell = world.bodies.len() + rows_at(&contacts, k + 1).len();
        assert_eq!(step.array("state")[cell], 6.0);
        let ends = [step.points[step.cells[cell][0]], step.points[step.cells[cell][1]]];
        assert_eq!(ends[0], Vec2::new(0.0, 0.0));
        let drop = -2.5 - num(&bodies, &rows_at(&bodies, k + 1)[1], "y");
        assert!((ends[1] - Vec2::new(0.0, -2.0 - drop)).norm() < 1e-12, "step {}: {:?}", k + 1, ends[1]);
    }
}
