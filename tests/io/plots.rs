//! `plot_results` and `render_step` on every example (issue 9 acceptance: "`pbdda plot` and
//! `pbdda render` produce non-empty PNGs of the stated size for every example"): each example
//! runs 3 steps (its own `steps` overridden), writing CSVs and geometry as `pbdda run` does;
//! the PNGs are decoded with the `png` crate.
//!
//! Expected numbers: the PNG width and height are the requested size; the set of figures is
//! fixed by the data (energy and solver always, the two monitor figures exactly when the
//! scene has monitors, one contact figure per body among the first four met in contacts.csv);
//! "non-empty" means drawn on: the picture has pixels that are not the white background (a
//! blank canvas has none), and the scene picture has the body fill colour of render.rs.

use pbdda::model::Model;
use pbdda::output::csv::CsvWriter;
use pbdda::output::plot::{PlotOptions, plot_results};
use pbdda::output::render::render_step;
use pbdda::output::results::{ResultsError, write_geometry};
use pbdda::world::World;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Width, height and RGB(A) pixels of a PNG file.
fn decode(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png frame");
    let channels = info.color_type.samples();
    let pixels = buf[..info.buffer_size()].chunks(channels).map(|c| [c[0], c[1], c[2]]).collect();
    (info.width, info.height, pixels)
}

fn drawn_pixels(pixels: &[[u8; 3]]) -> usize {
    pixels.iter().filter(|p| **p != [255, 255, 255]).count()
}

fn run(name: &str, model: Model, steps: usize) -> (PathBuf, World, BTreeSet<String>) {
    let mut model = model;
    model.time.steps = steps;
    model.output.every = 1;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("plots_{name}"));
    let mut world = World::new(model);
    let mut csv = CsvWriter::create(&dir, 1, steps, true).expect("csv writer");
    write_geometry(&dir, &world).expect("geometry");
    let mut in_contact: Vec<String> = Vec::new();
    for _ in 0..steps {
        let rec = world.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        csv.write_step(&world, &rec).expect("csv step");
        for c in &rec.contacts {
            for b in [c.body_a, c.body_b] {
                let n = &world.bodies[b].name;
                if !in_contact.contains(n) && in_contact.len() < 4 {
                    in_contact.push(n.clone());
                }
            }
        }
    }
    (dir, world, in_contact.into_iter().collect())
}

fn check_example(file: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(file);
    let model = pbdda::scene::load(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
    let has_monitors = !model.monitors.is_empty();
    let (dir, world, contact_bodies) = run(file.trim_end_matches(".toml"), model, 3);
    let opts = PlotOptions { size: (640, 480), ..PlotOptions::default() };
    let out = dir.join("plots");
    let written = plot_results(&dir, &out, &opts).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mut expected: BTreeSet<String> = ["energy", "solver"].iter().map(|s| s.to_string()).collect();
    if has_monitors {
        expected.extend(["monitor_paths".to_string(), "monitor_displacements".to_string()]);
    }
    expected.extend(contact_bodies.iter().map(|b| format!("contact_forces_{b}")));
    let pngs: BTreeSet<String> = written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(pngs, expected, "{file}: figures");
    assert_eq!(written.len(), 2 * expected.len(), "{file}: a PNG and an SVG per figure");
    for p in written.iter().filter(|p| p.extension().is_some_and(|e| e == "png")) {
        let (w, h, px) = decode(p);
        assert_eq!((w, h), (640, 480), "{}", p.display());
        assert!(drawn_pixels(&px) > 0, "{} is blank", p.display());
    }
    for p in written.iter().filter(|p| p.extension().is_some_and(|e| e == "svg")) {
        let text = std::fs::read_to_string(p).expect("svg");
        assert!(text.contains("width=\"640\"") && text.contains("<polyline"), "{}", p.display());
    }
    let picture = render_step(&dir, None, &dir.join("scene.png"), (800, 600)).expect("render");
    let (w, h, px) = decode(&picture);
    assert_eq!((w, h), (800, 600), "{file}: picture size");
    let fills = [[175, 175, 175], [150, 200, 150], [140, 180, 230]];
    assert!(px.iter().any(|p| fills.contains(p)), "{file}: no body drawn");
    // an explicit written step renders too; a step never written is a typed error
    render_step(&dir, Some(1), &dir.join("scene_1.png"), (320, 240)).expect("render step 1");
    let err = render_step(&dir, Some(99), &dir.join("scene_99.png"), (320, 240)).expect_err("step 99");
    assert!(matches!(err, ResultsError::NoStep { step: 99, first: 1, last: 3, .. }), "{err}");
    assert_eq!(world.step_index, 3);
    let bad = PlotOptions { bodies: vec!["no_such_body".into()], ..opts };
    let err = plot_results(&dir, &out, &bad).expect_err("unknown body");
    assert!(matches!(&err, ResultsError::UnknownBody { name, .. } if name == "no_such_body"), "{err}");
}

#[test]
fn slow_every_example_plots_and_renders() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("examples")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    files.sort();
    // the loop must cover the paper's scenes (and every other example beside them)
    let paper = files.iter().filter(|f| f.starts_with("7_")).count();
    assert_eq!(
        paper, 13,
        "examples/ holds the thirteen scenes of the paper's §7.1-7.10 (§7.9 on a meshed block)"
    );
    for f in &files {
        check_example(f);
    }
}

#[test]
fn missing_results_name_the_file() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plots_nothing");
    std::fs::create_dir_all(&dir).unwrap();
    let err = plot_results(&dir, &dir.join("plots"), &PlotOptions::default()).expect_err("no steps.csv");
    assert!(err.to_string().contains("steps.csv"), "{err}");
    let err = render_step(&dir, None, &dir.join("x.png"), (100, 100)).expect_err("no geometry.csv");
    assert!(err.to_string().contains("geometry.csv"), "{err}");
}

/// A results folder still being written: the last step of bodies.csv has only some of its
/// rows, the last line not even finished. The default picture is then the last complete step
/// (the §7.1 heap has 4 bodies; 3 steps written, so step 2), and rendering works.
#[test]
fn running_folder_renders_the_last_complete_step() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/7_1_disk_heap.toml");
    let model = pbdda::scene::load(&path).expect("example");
    let (dir, world, _) = run("running_heap", model, 3);
    assert_eq!(world.bodies.len(), 4);
    let bodies = dir.join("bodies.csv");
    let text = std::fs::read_to_string(&bodies).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1 + 3 * 4, "header and 4 rows per step");
    lines.truncate(lines.len() - 2);
    std::fs::write(&bodies, format!("{}\n3,0.003,d", lines.join("\n"))).unwrap();
    let table = pbdda::output::results::Table::read(&bodies).expect("partial table");
    assert_eq!(table.rows.len(), 10, "the unfinished line is dropped");
    assert_eq!(pbdda::output::results::pick_step(&table, None, 4).expect("a complete step"), 2);
    let picture = render_step(&dir, None, &dir.join("scene.png"), (300, 200)).expect("render");
    assert_eq!(decode(&picture).0, 300);
}

/// Runs a scene text for `steps` steps writing everything `pbdda run` writes (CSVs,
/// connectors.csv, geometry, VTK), every step.
fn run_all(name: &str, text: &str, steps: usize) -> PathBuf {
    use pbdda::output::connectors::ConnectorWriter;
    use pbdda::output::vtk::VtkWriter;
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(format!("{name}.toml"));
    let mut model =
        pbdda::scene::parse(text, &file.display().to_string()).unwrap_or_else(|e| panic!("{e:?}"));
    model.time.steps = steps;
    model.output.every = 1;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("plots_{name}"));
    let mut world = World::new(model);
    let mut csv = CsvWriter::create(&dir, 1, steps, true).expect("csv writer");
    let mut lines = ConnectorWriter::create(&dir, &world, true).expect("connector writer");
    write_geometry(&dir, &world).expect("geometry");
    let mut vtk = VtkWriter::create(&dir, &world).expect("vtk writer");
    for _ in 0..steps {
        let rec = world.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        csv.write_step(&world, &rec).expect("csv step");
        lines.write_step(&world, &rec).expect("connectors step");
        vtk.write_step(&world, &rec).expect("vtk step");
    }
    dir
}

/// A 2 m x 1 m cap on fixed rock (no gravity) held by two vertical bolts through it at x = -0.5
/// and x = 0.5, each from (x, 0.9) in the cap to (x, -1.5) in the rock, pretensioned to
/// `pretension` (math note §6: the rigid blocks cannot come closer, so each bolt keeps its
/// pretension); `extra` is appended to the second bolt, `time` replaces the `[time]` table
/// (default: 2 steps of 1 ms).
fn two_bolts(pretension: [f64; 2], extra: &str, time: Option<&str>) -> String {
    let bolt = |x: f64, p: f64, more: &str| {
        format!(
            "[[connector]]\nkind = \"bolt\"\npoints = [[{x}, 0.9], [{x}, -1.5]]\nyoung = 2.0e11\narea = 5.0e-4\n\
             pretension = {p}\n{more}\n"
        )
    };
    format!(
        "[scene]\nname = \"two bolts\"\n{}\n[solver]\ntolerance = 1e-10\n\
         [[material]]\nname = \"rock\"\ndensity = 2600.0\n[[interface]]\nname = \"joint\"\nmaterials = [\"rock\", \"rock\"]\nfriction = 0.5\n\
         [[body]]\nname = \"rock\"\nshape = \"polygon\"\nvertices = [[-3.0, -2.0], [3.0, -2.0], [3.0, 0.0], [-3.0, 0.0]]\n\
         material = \"rock\"\nfixed = true\n\
         [[body]]\nname = \"cap\"\nshape = \"polygon\"\nvertices = [[-1.0, 0.0], [1.0, 0.0], [1.0, 1.0], [-1.0, 1.0]]\n\
         material = \"rock\"\n{}{}",
        time.unwrap_or("[time]\nstep = 0.001\nsteps = 2"),
        bolt(-0.5, pretension[0], ""),
        bolt(0.5, pretension[1], extra)
    )
}

/// Bolts are drawn from anchor to anchor in the colour of their force: the pixel at the middle
/// of each bolt's anchor-to-anchor segment (from connectors.csv's anchor columns, placed by the
/// picture's own map) has the colour map's colour of its force in the legend's range, 0 to the
/// largest force (20 kN and 50 kN pretension: the map's 0.4 and its top, red). The middles lie
/// 0.3 m inside the rock, where a centroid-to-centroid line (the cap's centroid to the rock's)
/// would not pass. The colour bar's top pixel row has the top colour too.
#[test]
fn bolts_are_drawn_anchor_to_anchor_in_the_colour_of_their_force() {
    use pbdda::output::render::{Range, colour_map, connector_lines, render_view};
    let dir = run_all("two_bolts", &two_bolts([2.0e4, 5.0e4], "", None), 2);
    let lines = connector_lines(&dir, 2).expect("connector rows");
    assert_eq!(lines.len(), 2);
    for (l, p) in lines.iter().zip([2.0e4, 5.0e4]) {
        assert!((l.force - p).abs() < 1e-3 * p, "bolt force {} keeps its pretension {p}", l.force);
    }
    let (png, view) = render_view(&dir, Some(2), &dir.join("bolts.png"), (800, 600)).expect("render");
    let (w, _, px) = decode(&png);
    let pixel = |(x, y): (i32, i32)| px[y as usize * w as usize + x as usize];
    let range = Range::of(lines.iter().map(|l| l.force), Some(0.0));
    assert_eq!((range.lo, range.hi), (0.0, lines[1].force));
    for l in &lines {
        let c = range.colour(l.force);
        let mid = view.px((l.a + l.b) / 2.0);
        assert_eq!(pixel(mid), [c.0, c.1, c.2], "bolt of {} N at its middle {mid:?}", l.force);
    }
    let top = colour_map(1.0);
    assert_eq!([top.0, top.1, top.2], [210, 30, 30], "the map's top is red");
    assert!(px.contains(&[top.0, top.1, top.2]), "the colour bar is drawn");
}

/// The cap pulled off the rock by an upward g = 10 (52 kN per metre), static analysis with dt =
/// 0.1 s (the mass term 2m/dt² = 1e6 N/m is 2 % of a bolt's EA/l = 4.2e7 N/m, so step 1 is
/// near the static split, 26 kN per bolt): the second bolt, of strength 10 kN, breaks in step 1.
/// In the pictures of step 1 and of step 2 (it broke before: drawn where it broke) its middle
/// has the magenta cross of a broken bolt; the connector force plot marks the break with the same colour, and the plot of a
/// run without a break has no pixel of it.
#[test]
fn broken_bolts_are_marked_in_render_and_plot() {
    use pbdda::output::render::{BROKEN_MARK, connector_lines, render_view};
    let dir = run_all(
        "broken_bolt",
        &two_bolts(
            [0.0, 0.0],
            "strength = 1.0e4",
            Some("[time]\nstep = 0.1\nsteps = 2\n[physics]\ngravity = [0.0, 10.0]\nvelocity_carry = 0.0"),
        ),
        2,
    );
    let lines = connector_lines(&dir, 1).expect("connector rows");
    assert_eq!(lines.iter().map(|l| l.broken).collect::<Vec<_>>(), [false, true]);
    let (png, view) = render_view(&dir, Some(1), &dir.join("broken.png"), (800, 600)).expect("render");
    let (w, _, px) = decode(&png);
    let mid = view.px((lines[1].a + lines[1].b) / 2.0);
    let mark = [BROKEN_MARK.0, BROKEN_MARK.1, BROKEN_MARK.2];
    assert_eq!(px[mid.1 as usize * w as usize + mid.0 as usize], mark, "cross at the broken bolt's middle");
    // at step 2 (no row: it broke before) it is still drawn, where it broke
    let later = connector_lines(&dir, 2).expect("connector rows");
    let broken: Vec<_> = later.iter().filter(|l| l.broken).collect();
    assert_eq!((later.len(), broken.len()), (2, 1));
    assert_eq!((broken[0].a, broken[0].b), (lines[1].a, lines[1].b));
    let (png, view) = render_view(&dir, Some(2), &dir.join("broken_2.png"), (800, 600)).expect("render");
    let (w, _, px) = decode(&png);
    let mid = view.px((lines[1].a + lines[1].b) / 2.0);
    assert_eq!(px[mid.1 as usize * w as usize + mid.0 as usize], mark, "cross at step 2");
    let opts = PlotOptions { size: (640, 480), svg: false, ..PlotOptions::default() };
    let plots = plot_results(&dir, &dir.join("plots"), &opts).expect("plots");
    let forces = plots.iter().find(|p| p.ends_with("connector_forces.png")).expect("connector plot");
    assert!(decode(forces).2.contains(&mark), "the break is marked");
    let intact = run_all("intact_bolts", &two_bolts([2.0e4, 5.0e4], "", None), 2);
    let plots = plot_results(&intact, &intact.join("plots"), &opts).expect("plots");
    let forces = plots.iter().find(|p| p.ends_with("connector_forces.png")).expect("connector plot");
    assert!(!decode(forces).2.contains(&mark), "no break, no mark");
}

/// Contacts are marked in the colour of their interface (the joint set): the cap's two corner
/// contacts on the rock take the interface `joint` (contacts.csv), and the picture holds the
/// first joint colour of render/overlays.rs, (230, 120, 0), which nothing else draws.
#[test]
fn joint_sets_are_coloured() {
    let dir = run_all("joint_colour", &two_bolts([2.0e4, 5.0e4], "", None), 2);
    let t = pbdda::output::results::Table::read(&dir.join("contacts.csv")).expect("contacts");
    assert!(t.text("interface").unwrap().iter().all(|i| i == "joint"));
    let png = render_step(&dir, None, &dir.join("joints.png"), (800, 600)).expect("render");
    assert!(decode(&png).2.contains(&[230, 120, 0]), "joint colour drawn");
}

/// The meshed cantilever (examples/mesh_cantilever.toml on cantilever_1.msh) after 2 steps: the
/// pixel at each element's centroid has the colour of its von Mises stress in the colour bar's
/// range 0 to the step's largest (stresses from the step's .vtu; the elements are at least
/// 20 px across at this size, their edges 1 px, so the centroid is inside the fill). The tip
/// element under the load is coloured, not the plain fill of a deformable body.
#[test]
fn mesh_elements_are_drawn_with_a_stress_colour_map() {
    use pbdda::output::render::{Range, elements, render_view};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/mesh_cantilever.toml");
    let text = std::fs::read_to_string(&path).expect("example");
    let dir = run_all("mesh_cantilever", &text, 2);
    let els = elements(&dir, 2).expect("elements");
    assert_eq!(els.len(), 86, "cantilever_1.msh has 86 triangles (meshes/reference.json)");
    let (png, view) = render_view(&dir, Some(2), &dir.join("mesh.png"), (1000, 400)).expect("render");
    let (w, _, px) = decode(&png);
    let range = Range::of(els.iter().map(|e| e.von_mises), Some(0.0));
    assert!(range.hi > 0.0);
    for e in &els {
        let (x, y) = view.px(e.corners.iter().sum::<pbdda::geometry::Vec2>() / 3.0);
        let c = range.colour(e.von_mises);
        assert_eq!(px[y as usize * w as usize + x as usize], [c.0, c.1, c.2], "element at ({x}, {y})");
    }
}
