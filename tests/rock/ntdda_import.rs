//! `pbdda import-ntdda`: ntdda's text and DDAML input of a small jointed mass, written by hand
//! field by field after ntdda's readers (tests/ntdda/mass.geo, mass.ana, mass_ddaml.geo,
//! mass_ddaml.ana), imported to the scene the geometry determines.
//!
//! The mass: a 10 x 6 rectangle traced by four boundary joint lines (type 1), cut by a vertical
//! joint x = 4 and a horizontal joint y = 3 (type 2, both overshooting the outline by 0.5 as DC
//! users draw them) into four blocks: A = [0,4]x[0,3], B = [4,10]x[0,3], C = [0,4]x[3,6],
//! D = [4,10]x[3,6]. A hole point (2, 4.5) deletes C; a material line inside B gives it material
//! 2; fixed points (1, 0.5) in A and (9, 0.5) in B; load point (7, 5) and measured point (8, 5)
//! in D; a type-2 (segmented, grouted) bolt from (6, 1) to (6, 5) in the DDAML geometry.
//! Every expected number below follows from that geometry by hand; coordinates are small
//! integers and halves, exact in binary, so equality is exact.

use crate::common;
use std::path::{Path, PathBuf};
use toml::Value;

fn input(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ntdda").join(name)
}

fn import(geo: &str, ana: &str) -> Value {
    let scene = pbdda::ntdda::import(&input(geo), Some(&input(ana))).expect("the hand-written files import");
    doc(&scene.toml)
}

/// A TOML document as a table value.
fn doc(text: &str) -> Value {
    Value::Table(toml::from_str::<toml::Table>(text).expect("the written scene is TOML"))
}

fn points(v: &Value) -> Vec<[f64; 2]> {
    v.as_array()
        .expect("an array of points")
        .iter()
        .map(|p| {
            let p = p.as_array().expect("a point");
            [p[0].as_float().expect("x"), p[1].as_float().expect("y")]
        })
        .collect()
}

fn point(v: &Value) -> [f64; 2] {
    points(&Value::Array(vec![v.clone()]))[0]
}

fn tables<'a>(scene: &'a Value, key: &str) -> &'a [Value] {
    scene.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}

/// What both formats must agree on (the text format has no bolts and no load histories).
fn common(scene: &Value) {
    // [domain]: the outline of the four blocks, counter-clockwise from the lowest-left corner;
    // the overshoots (0.5 beyond the outline) close no block and vanish (DC's dc05-dc06).
    let domain = &scene["domain"];
    assert_eq!(points(&domain["vertices"]), [[0.0, 0.0], [10.0, 0.0], [10.0, 6.0], [0.0, 6.0]]);
    assert_eq!(domain["material"].as_str(), Some("mat-1"));
    assert_eq!(domain["model"].as_str(), Some("deformable"));
    assert_eq!(points(&domain["fixed_points"]), [[1.0, 0.5], [9.0, 0.5]]);

    // [[joint]]: x = 4 between A and B (its part between C and D borders the deleted C), y = 3
    // between B and D (its part between A and C likewise): two pieces, both joint type 2.
    let joints = tables(scene, "joint");
    assert_eq!(joints.len(), 2);
    assert_eq!(points(&joints[0]["points"]), [[4.0, 0.0], [4.0, 3.0]]);
    assert_eq!(points(&joints[1]["points"]), [[4.0, 3.0], [10.0, 3.0]]);
    assert!(joints.iter().all(|j| j["interface"].as_str() == Some("joint-2")));

    // [[region]]: B, the block the material line lies in (DC's dc13), takes material 2.
    let regions = tables(scene, "region");
    assert_eq!(regions.len(), 1);
    assert_eq!(points(&regions[0]["vertices"]), [[4.0, 0.0], [10.0, 0.0], [10.0, 3.0], [4.0, 3.0]]);
    assert_eq!(regions[0]["material"].as_str(), Some("mat-2"));

    // [[excavation]]: C, the block the hole point deletes.
    let holes = tables(scene, "excavation");
    assert_eq!(holes.len(), 1);
    assert_eq!(points(&holes[0]["vertices"]), [[0.0, 3.0], [4.0, 3.0], [4.0, 6.0], [0.0, 6.0]]);

    // Blocks after the hole: A (centroid (2, 1.5)), B (7, 1.5), D (7, 4.5); pbdda's cutter
    // names them by centroid y, then x: blk-1 = A, blk-2 = B, blk-3 = D.
    let monitors = tables(scene, "monitor");
    assert_eq!(monitors.len(), 1);
    assert_eq!(monitors[0]["body"].as_str(), Some("blk-3"));
    assert_eq!(point(&monitors[0]["point"]), [8.0, 5.0]);

    // [[material]]: density is ntdda's unit mass `ma` as given (analysisreader.c reads it as
    // materialProps[i][0]); young e0 and poisson u0 as given.
    let m = tables(scene, "material");
    assert_eq!(m.len(), 2);
    let f = |t: &Value, k: &str| t[k].as_float().expect(k);
    assert_eq!((f(&m[0], "density"), f(&m[0], "young"), f(&m[0], "poisson")), (2700.0, 5e9, 0.25));
    assert_eq!((f(&m[1], "density"), f(&m[1], "young"), f(&m[1], "poisson")), (2500.0, 1e9, 0.3));

    // [[interface]]: the default (joint type 1's law) and one per joint material.
    let i = tables(scene, "interface");
    assert_eq!(i.len(), 3);
    assert!(i[0].get("name").is_none());
    assert_eq!(i[1]["name"].as_str(), Some("joint-1"));
    assert_eq!(i[2]["name"].as_str(), Some("joint-2"));
    let law = |t: &Value| (f(t, "friction_angle"), f(t, "cohesion"), f(t, "tensile_strength"));
    assert_eq!(law(&i[0]), (35.0, 0.0, 0.0));
    assert_eq!(law(&i[1]), (35.0, 0.0, 0.0));
    assert_eq!(law(&i[2]), (30.0, 1e4, 5e3));

    // [time]: ntdda's maximum time step g1 and step count; [physics]: analysis type 1 is dynamic.
    assert_eq!(f(&scene["time"], "step"), 0.001);
    assert_eq!(scene["time"]["steps"].as_integer(), Some(100));
    assert_eq!(scene["time"]["adaptive"].as_bool(), Some(true));
    assert_eq!(f(&scene["physics"], "velocity_carry"), 1.0);
}

#[test]
fn text_format_imports_the_jointed_mass() {
    let scene = import("mass.geo", "mass.ana");
    common(&scene);
    // Gravity is we / ma of material 1 (analysisreader.c: gravaccel = materialProps[1][1] /
    // materialProps[1][0]): 26487 / 2700, which rounds to the double nearest 9.81.
    assert_eq!(point(&scene["physics"]["gravity"]), [0.0, -(26487.0 / 2700.0)]);
    assert_eq!(26487.0_f64 / 2700.0, 9.81);
    // The text format has no load histories: no [[load]], and no bolts.
    assert!(tables(&scene, "load").is_empty());
    assert!(tables(&scene, "connector").is_empty());
}

#[test]
fn ddaml_format_imports_the_jointed_mass_with_bolt_and_load() {
    let scene = import("mass_ddaml.geo", "mass_ddaml.ana");
    common(&scene);
    assert_eq!(point(&scene["physics"]["gravity"]), [0.0, -9.81]);
    // The load history "0 0 -1000; 1 0 -2000" on D: the y component, its peak -2000 as the
    // force and the records over the peak as the history factors (0.5, 1).
    let loads = tables(&scene, "load");
    assert_eq!(loads.len(), 1);
    assert_eq!(loads[0]["body"].as_str(), Some("blk-3"));
    assert_eq!(point(&loads[0]["force"]), [0.0, -2000.0]);
    assert_eq!(points(&loads[0]["history"]), [[0.0, 0.5], [1.0, 1.0]]);
    // Bolt type 2 is cut at every block edge (produce_boltsegments): grouted. Its stiffness
    // k = 1e8 N/m over its length L = 4 m gives young = k L = 4e8 with area 1 (E A / L = k).
    let bolts = tables(&scene, "connector");
    assert_eq!(bolts.len(), 1);
    let b = &bolts[0];
    assert_eq!(b["kind"].as_str(), Some("bolt"));
    assert_eq!(b["grouted"].as_bool(), Some(true));
    assert_eq!(points(&b["points"]), [[6.0, 1.0], [6.0, 5.0]]);
    assert_eq!(b["young"].as_float(), Some(4e8));
    assert_eq!(b["area"].as_float(), Some(1.0));
    assert_eq!(b["strength"].as_float(), Some(2e5));
    assert_eq!(b["pretension"].as_float(), Some(1e4));
}

#[test]
fn text_and_ddaml_give_the_same_scene() {
    let (mut t, mut d) = (import("mass.geo", "mass.ana"), import("mass_ddaml.geo", "mass_ddaml.ana"));
    for s in [&mut t, &mut d] {
        let s = s.as_table_mut().expect("a table");
        s.remove("load");
        s.remove("connector");
    }
    assert_eq!(t, d);
}

#[test]
fn ignored_fields_are_listed_one_line_each() {
    let scene = pbdda::ntdda::import(&input("mass.geo"), Some(&input("mass.ana"))).expect("imports");
    // per block material: initial stress, strain, velocity (3 x 2); g2; penalty; e00; the load
    // point without a history: 10 lines, each also a comment line of the scene.
    assert_eq!(scene.ignored.len(), 10);
    for line in &scene.ignored {
        assert!(scene.toml.contains(&format!("#   {line}\n")), "{line}");
    }
    assert!(scene.ignored.iter().any(|l| l.contains("mass.geo:18: load point 1")));
}

/// Writes `text` to a scratch file named `name` and imports it (with `ana` if given). Each call
/// has a folder of its own: the tests run in parallel and several use the same file names.
fn import_text(name: &str, text: &str, ana: Option<(&str, &str)>) -> Result<pbdda::ntdda::Import, String> {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ntdda_import").join(call.to_string());
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let geo = dir.join(name);
    std::fs::write(&geo, text).expect("write");
    let ana = ana.map(|(n, t)| {
        let p = dir.join(n);
        std::fs::write(&p, t).expect("write");
        p
    });
    pbdda::ntdda::import(&geo, ana.as_deref()).map_err(|e| e.to_string())
}

fn fails(name: &str, text: &str, ana: Option<(&str, &str)>, expect: &str) {
    let err = import_text(name, text, ana).expect_err("malformed input is refused");
    assert!(err.contains(expect), "got `{err}`, expected `{expect}`");
}

const GOOD_ANA: &str = "1\n10\n1\n1\n0.01\n0.001\n2700 26487 5e9 0.25 0 0 0 0 0 0 0 0 0\n30 0 0\n";

#[test]
fn malformed_inputs_name_file_line_and_field() {
    // a letter where joint line 2's y1 belongs (line 10)
    let geo = "0.01\n4 0\n0\n0\n0\n0\n0\n0\n0 0 1 0 1\n1 x 1 1 1\n1 1 0 1 1\n0 1 0 0 1\n";
    fails("letter.geo", geo, None, "letter.geo:10: joint line 2: y1: expected a number, found `x`");
    // the file ends inside joint line 4
    let geo = "0.01\n4 0\n0\n0\n0\n0\n0\n0\n0 0 1 0 1\n1 0 1 1 1\n1 1 0 1 1\n0 1\n";
    fails("short.geo", geo, None, "short.geo:12: joint line 4: x2: the file ends before this field");
    // bolts in the text format, which has no bolt lines
    fails("bolts.geo", "0.01\n4 0\n0\n2\n0\n0\n0\n0\n", None, "bolts.geo:4: number of bolts: 2 bolts");
    // more boundary lines than joint lines
    fails("bound.geo", "0.01\n2 3\n0\n0\n0\n0\n0\n0\n", None, "bound.geo:2: number of boundary lines");
    // a joint type the analysis has no material for (type 2, one joint material)
    let geo = "0.01\n4 0\n0\n0\n0\n0\n0\n0\n0 0 1 0 1\n1 0 1 1 2\n1 1 0 1 1\n0 1 0 0 1\n";
    fails("type.geo", geo, Some(("type.ana", GOOD_ANA)), "type.geo:10: joint line: type: joint type 2");
    // a measured point in no block
    let geo = "0.01\n4 0\n0\n0\n0\n0\n1\n0\n0 0 1 0 1\n1 0 1 1 1\n1 1 0 1 1\n0 1 0 0 1\n5 5\n";
    fails("outside.geo", geo, None, "outside.geo:13: measured point 1: lies in no block");
    // joint lines that close no block
    fails(
        "open.geo",
        "0.01\n2 0\n0\n0\n0\n0\n0\n0\n0 0 1 0 1\n1 0 1 1 1\n",
        None,
        "open.geo:9: joint lines: the joint lines close no block",
    );
    // analysis type 2, and a time step of zero
    let ana = "2\n10\n1\n1\n0.01\n0.001\n";
    let square = "0.01\n4 0\n0\n0\n0\n0\n0\n0\n0 0 1 0 1\n1 0 1 1 1\n1 1 0 1 1\n0 1 0 0 1\n";
    fails(
        "sq.geo",
        square,
        Some(("kind.ana", ana)),
        "kind.ana:1: analysis type: expected 0 (static) or 1 (dynamic), found 2",
    );
    let ana = "1\n10\n1\n1\n0.01\n0\n";
    fails("sq.geo", square, Some(("dt.ana", ana)), "dt.ana:6: maximum time step g1: must be > 0");
}

const XML_HEAD: &str = "<?xml version=\"1.0\"?>\n<DDA>\n<Geometry>\n<Edgenodedist distance=\"0.01\"/>\n";

#[test]
fn malformed_ddaml_names_file_line_and_field() {
    // a joint with three numbers (line 6)
    let geo = format!(
        "{XML_HEAD}<Jointlist>\n<Joint type=\"1\"> 0 0 1 </Joint>\n</Jointlist>\n</Geometry>\n</DDA>\n"
    );
    fails("three.geo", &geo, None, "three.geo:6: Jointlist/Joint: needs 4 numbers, found 3");
    // a joint without its type (ntdda segfaults on it)
    let geo = format!("{XML_HEAD}<Jointlist>\n<Joint> 0 0 1 0 </Joint>\n</Jointlist>\n</Geometry>\n</DDA>\n");
    fails("notype.geo", &geo, None, "notype.geo:6: Joint@type: the attribute is missing");
    // a tag left open
    let geo =
        format!("{XML_HEAD}<Jointlist>\n<Joint type=\"1\"> 0 0 1 0\n</Jointlist>\n</Geometry>\n</DDA>\n");
    fails("open.geo", &geo, None, "open.geo:7: XML:");
    // no <Geometry>
    fails(
        "nogeo.geo",
        "<?xml version=\"1.0\"?>\n<DDA>\n</DDA>\n",
        None,
        "nogeo.geo:2: Geometry: <DDA> has no <Geometry> element",
    );
    // an analysis without Numtimesteps, and a load history whose count disagrees
    let square = format!(
        "{XML_HEAD}<Jointlist>\n{}</Jointlist>\n</Geometry>\n</DDA>\n",
        ["0 0 1 0", "1 0 1 1", "1 1 0 1", "0 1 0 0"]
            .map(|j| format!("<Joint type=\"1\">{j}</Joint>\n"))
            .concat()
    );
    let ana = "<?xml version=\"1.0\"?>\n<DDA>\n<Analysis>\n<Maxtimestep maxtimestep=\"0.01\"/>\n</Analysis>\n</DDA>\n";
    fails(
        "sq.geo",
        &square,
        Some(("nosteps.ana", ana)),
        "nosteps.ana:3: Numtimesteps: <Analysis> has no <Numtimesteps",
    );
    let ana = "<?xml version=\"1.0\"?>\n<DDA>\n<Analysis>\n<Numtimesteps timesteps=\"5\"/>\n<Maxtimestep maxtimestep=\"0.01\"/>\n\
               <Loadpointlist>\n<Loadpoint numpoints=\"3\">0 1 0; 1 1 0;</Loadpoint>\n</Loadpointlist>\n</Analysis>\n</DDA>\n";
    fails(
        "sq.geo",
        &square,
        Some(("count.ana", ana)),
        "count.ana:7: Loadpoint@numpoints: says 3 records, the element has 2",
    );
}

/// The command line writes the scene the library makes and lists the ignored fields on stderr;
/// a malformed file is an error message and a failure exit, not a panic.
#[test]
fn command_line_writes_the_scene_and_lists_what_it_ignores() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ntdda_cli_mass.toml");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["import-ntdda"])
        .args([input("mass.geo"), input("mass.ana")])
        .arg("--out")
        .arg(&out)
        .output()
        .expect("pbdda runs");
    assert!(run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    let lib = pbdda::ntdda::import(&input("mass.geo"), Some(&input("mass.ana"))).expect("imports");
    assert_eq!(stderr.lines().filter(|l| l.starts_with("ignored: ")).count(), lib.ignored.len());
    let written = std::fs::read_to_string(&out).expect("the scene is written");
    assert_eq!(doc(&written), doc(&lib.toml));

    let bad = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ntdda_cli_bad.geo");
    std::fs::write(&bad, "0.01\n4 zero\n").expect("write");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_pbdda"))
        .args(["import-ntdda"])
        .arg(&bad)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("pbdda runs");
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    // without spaces: a long temporary path may itself be broken across lines
    let flat = common::one_line(&stderr).replace(' ', "");
    assert!(flat.contains("ntdda_cli_bad.geo:2:numberofboundarylines"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// ntdda's own pushblock geometry layout (a block on a base, every joint line overshooting by
/// 0.01-0.02 as drawn in ntdda's example): two blocks, the base [10,50]x[10,20] (centroid y 15)
/// and the small block [15,20]x[20,25] (y 22.5); the outline has 8 corners.
#[test]
fn overshooting_lines_close_the_blocks_they_draw() {
    let joints = [
        "10 9.98 10 20.01",
        "9.98 20 50.01 20",
        "50 20.01 50 9.98",
        "50.01 10 9.98 10",
        "15 19.99 15 25.01",
        "14.99 25 20.01 25",
        "20 25.01 20 19.99",
    ];
    let geo = format!(
        "{XML_HEAD}<Jointlist>\n{}</Jointlist>\n<Measuredpointlist><Point>17.5 22.5</Point></Measuredpointlist>\n</Geometry>\n</DDA>\n",
        joints.map(|j| format!("<Joint type=\"1\">{j}</Joint>\n")).concat()
    );
    let scene = import_text("push.geo", &geo, None).expect("imports");
    assert!(scene.toml.contains("close 2 blocks"), "{}", scene.toml);
    let v = doc(&scene.toml);
    assert_eq!(
        points(&v["domain"]["vertices"]),
        [
            [10.0, 10.0],
            [50.0, 10.0],
            [50.0, 20.0],
            [20.0, 20.0],
            [20.0, 25.0],
            [15.0, 25.0],
            [15.0, 20.0],
            [10.0, 20.0]
        ]
    );
    // the shared edge y = 20 from 15 to 20 is the one interior joint piece
    assert_eq!(tables(&v, "joint").len(), 1);
    assert_eq!(points(&tables(&v, "joint")[0]["points"]), [[15.0, 20.0], [20.0, 20.0]]);
    assert_eq!(tables(&v, "monitor")[0]["body"].as_str(), Some("blk-2"));
}

/// The imported scene loads with pbdda's scene reader, whose cutter (src/rockmass) makes the
/// blocks the import's own arrangement found: A, B and D (C is excavated), named blk-1, blk-2,
/// blk-3 by centroid y then x, so the names the import wrote for the monitor and the load (blk-3)
/// are the block holding their points. The fixed points fix A and B; B has material 2; the
/// grouted bolt crosses one block edge (y = 3), so it is one segment joining B and D.
#[test]
fn imported_scene_loads_into_the_expected_blocks() {
    let text =
        pbdda::ntdda::import(&input("mass_ddaml.geo"), Some(&input("mass_ddaml.ana"))).expect("imports");
    let model = pbdda::scene::parse(&text.toml, "mass.toml").expect("the imported scene loads");
    let names: Vec<&str> = model.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["blk-1", "blk-2", "blk-3"]);
    let at = |x: f64, y: f64| pbdda::geometry::Vec2::new(x, y);
    for (b, p) in model.bodies.iter().zip([at(2.0, 1.5), at(7.0, 1.5), at(7.0, 4.5)]) {
        assert!(b.shape.contains(p), "{} holds {p:?}", b.name);
    }
    let fixed: Vec<bool> = model.bodies.iter().map(|b| b.fixed).collect();
    assert_eq!(fixed, [true, true, false]);
    let materials: Vec<&str> =
        model.bodies.iter().map(|b| model.materials[b.material].name.as_str()).collect();
    assert_eq!(materials, ["mat-1", "mat-2", "mat-1"]);
    assert_eq!(model.monitors[0].body, 2);
    assert_eq!(model.loads.len(), 1);
    assert_eq!(model.loads[0].body, 2);
    assert_eq!(model.connectors.len(), 1);
    let mut joined = model.connectors[0].bodies;
    joined.sort_unstable();
    assert_eq!(joined, [1, 2]);
    // the text format's scene: the same three blocks
    let text = pbdda::ntdda::import(&input("mass.geo"), Some(&input("mass.ana"))).expect("imports");
    assert_eq!(pbdda::scene::parse(&text.toml, "mass.toml").expect("loads").bodies.len(), 3);
}

/// The example (examples/ntdda_import/slope.toml, written by the command) loads: its joint lines
/// close four blocks (below/above the bedding joint, either side of x = 14), and the fixed line
/// along the base from x = 3 fixes the two below the bedding joint, blk-1 and blk-2 (centroid y
/// 1.53 each for the wedges y < 0.4 x - 1, against 4.3 and 7.0 above it).
#[test]
fn example_slope_loads() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ntdda_import/slope.toml");
    let model = pbdda::scene::load(&path).expect("the example loads");
    assert_eq!(model.bodies.len(), 4);
    let fixed: Vec<bool> = model.bodies.iter().map(|b| b.fixed).collect();
    assert_eq!(fixed, [true, true, false, false]);
    let written = std::fs::read_to_string(&path).expect("read");
    let fresh = pbdda::ntdda::import(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ntdda_import/slope.geo"),
        Some(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ntdda_import/slope.ana")),
    )
    .expect("imports");
    assert_eq!(doc(&written), doc(&fresh.toml));
}
