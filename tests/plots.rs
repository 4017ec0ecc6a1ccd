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
fn every_example_plots_and_renders() {
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
