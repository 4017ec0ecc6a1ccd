//! Loads and monitors, the error value itself, and scenes that parse but cannot run.

use super::*;

// ------------------------------------------------------------------ loads and monitors

#[test]
fn load_body_must_exist() {
    assert!(parse(&load_on("d1", ""), "scene.toml").is_ok());
    fails(&load_on("d9", ""), "16 load[0].body: unknown body \"d9\"");
}

#[test]
fn load_history_times_increase_strictly() {
    let equal = load_on("d1", "history = [[0, 1], [0, 2]]\n");
    fails(&equal, "19 load[0].history: history[1] has time 0 after 0");
    let decreasing = load_on("d1", "history = [[1, 1], [0.5, 2]]\n");
    fails(&decreasing, "19 load[0].history: increase strictly");
}

#[test]
fn load_history_is_pairs_at_least_one() {
    fails(&load_on("d1", "history = []\n"), "19 load[0].history: at least one");
    let triple = load_on("d1", "history = [[0, 1, 2]]\n");
    fails(&triple, "19 load[0].history: history[0] must have 2");
}

#[test]
fn monitor_body_must_exist() {
    let source = append(&monitor("O", "nobody"));
    fails(&source, "17 monitor[0].body: unknown body \"nobody\"");
}

#[test]
fn duplicate_monitor_name_names_the_second() {
    let source = append(&(monitor("O", "d1") + &monitor("O", "d1")));
    fails(&source, "20 monitor[1].name: duplicate monitor name \"O\"");
}

// ------------------------------------------------------------------ the error itself

#[test]
fn display_reads_file_line_column_key_message() {
    let e = rejected(&edit(13, "radius = -1"));
    assert_eq!(e.to_string(), "scene.toml:13:1: body[0].radius: radius must be positive (got -1)");
    assert_eq!((e.file.as_str(), e.column), ("scene.toml", 1));
    let e = rejected(&edit(13, "  radius = -1"));
    assert_eq!((e.line, e.column), (13, 3));
}

#[test]
fn diagnostic_points_at_the_offending_line() {
    use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme};
    let e = rejected(&edit(13, "radius = -1"));
    let labels: Vec<_> = e.labels().into_iter().flatten().collect();
    assert_eq!(labels.len(), 1);
    let offset: usize = MINIMAL.lines().take(12).map(|l| l.len() + 1).sum();
    assert_eq!((labels[0].offset(), labels[0].len()), (offset, "radius = -1".len()));
    let mut out = String::new();
    let handler = GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor());
    handler.render_report(&mut out, &e).expect("render to a String");
    assert!(out.contains("radius = -1") && out.contains("scene.toml:13:1"), "{out}");
}

#[test]
fn load_reads_files_and_names_unreadable_ones() {
    let dir = std::env::temp_dir().join(format!("pbdda-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("scene.toml");
    std::fs::write(&path, MINIMAL).expect("write scene");
    assert_eq!(load(&path).map(|m| m.name).ok().as_deref(), Some("t"));
    std::fs::write(&path, edit(13, "radius = -1")).expect("write scene");
    let e = load(&path).expect_err("rejected");
    assert_eq!((e.file, e.line), (path.display().to_string(), 13));
    let missing = dir.join("missing.toml");
    let e = load(&missing).expect_err("unreadable");
    assert!(e.to_string().starts_with(&format!("{}: cannot read", missing.display())), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

proptest! {
    /// Any prefix of a valid scene, and any insertion into it, parses or fails with a
    /// positioned error; never a panic.
    #[test]
    fn malformed_files_never_panic(cut in 0usize..2000, insert in "[\\[\\]{}=,.\"a-z0-9 \n-]{0,8}") {
        let cut = cut.min(FULL.len());
        let cut = (0..=cut).rev().find(|&i| FULL.is_char_boundary(i)).unwrap_or(0);
        for source in [FULL[..cut].to_owned(), format!("{}{insert}{}", &FULL[..cut], &FULL[cut..])] {
            if let Err(e) = parse(&source, "scene.toml") {
                prop_assert!(e.line >= 1 && e.line <= source.lines().count() + 1, "{}", e);
            }
        }
    }
}

/// Names go unquoted into the CSV outputs (docs/scene-format.md): no commas or quotes.
#[test]
fn names_must_be_csv_safe() {
    fails(&edit(10, "name = \"d,1\""), "10 body[0].name: without commas");
}

// ---------------------------------------------------------------- scenes that cannot run
// (issue 11, point 3): the rule, its line and its key; the numbers are the scene's own.

/// 1e300 s in steps of 1 ms is 1e303 steps, not a saturated 1.8e19; 1e9 steps is the bound,
/// and half a step is not one step.
#[test]
fn step_counts_are_bounded() {
    fails(&edit(5, "end = 1e300"), "5 time.end: is 1e303 steps, more than 1e9");
    fails(&edit(5, "steps = 1000000001"), "5 time.steps: more than 1e9");
    assert_eq!(ok(&edit(5, "steps = 1000000000")).time.steps, 1_000_000_000);
    fails(&edit(5, "end = 0.0005"), "5 time.end: less than one step");
}

/// Radius 1e308 makes the area πr² infinite; 1e-320 makes it zero; a density of 1e-320 makes
/// the mass subnormal; dt = 1e-160 makes 2m/dt² infinite; |g| = 1e307 makes m·g infinite
/// (m = 2500π).
#[test]
fn first_step_magnitudes_must_be_finite_and_normal() {
    fails(&edit(13, "radius = 1e308"), "13 body[0].radius: area");
    fails(&edit(13, "radius = 1e-320"), "13 body[0].radius: underflows");
    fails(&edit(8, "density = 1e-320"), "14 body[0].material: mass");
    fails(&edit(4, "step = 1e-160"), "4 time.step: 2m/dt²");
    fails(&edit(5, "steps = 10\n[physics]\ngravity = [0.0, -1e307]"), "7 physics.gravity: m·g");
}

/// A load on a fixed body would be dropped; a monitor 10 m from a unit disk is a typo.
#[test]
fn loads_and_monitors_must_fit_their_body() {
    let fixed = edit(
        14,
        "material = \"rock\"\nfixed = true\n[[load]]\nbody = \"d1\"\npoint = [0.0, 0.0]\nforce = [1.0, 0.0]",
    );
    fails(&fixed, "17 load[0].body: fixed body \"d1\"");
    let far = append("[[monitor]]\nname = \"m\"\nbody = \"d1\"\npoint = [10.0, 0.0]\n");
    fails(&far, "18 monitor[0].point: outside body \"d1\"");
    // 1 m beyond the rim of a disk of diameter 2 is near enough
    assert_eq!(
        ok(&append("[[monitor]]\nname = \"m\"\nbody = \"d1\"\npoint = [2.0, 0.0]\n")).monitors.len(),
        1
    );
}

/// A small disk inside the unit disk, and a second unit disk at the same place.
#[test]
fn body_inside_another_is_rejected() {
    let inner = second_body("disk", "center = [0.1, 0.0]\nradius = 0.5\n");
    fails(&inner, "19 body[1].center: body \"b2\" lies inside body \"d1\"");
    let twin = second_body("disk", "center = [0.0, 0.0]\nradius = 1.0\n");
    fails(&twin, "19 body[1].center: lies inside body");
    // touching disks are a contact, not an overlap
    assert_eq!(ok(&second_body("disk", "center = [2.0, 0.0]\nradius = 1.0\n")).bodies.len(), 2);
}

/// A byte that is not UTF-8 (Latin-1 'é') on line 2 is reported on line 2.
#[test]
fn utf8_errors_name_the_line() {
    let mut bytes = MINIMAL.replacen("\n", " # caf\u{e9}\n", 2).into_bytes();
    let at = bytes.windows(2).rposition(|w| w == [0xc3, 0xa9]).unwrap();
    bytes.splice(at..at + 2, [0xe9]);
    let e = pbdda::scene::parse_bytes(&bytes, "scene.toml").expect_err("not UTF-8");
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("not valid UTF-8 (byte 0xe9"), "{e}");
}
