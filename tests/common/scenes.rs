//! Scene text builders shared by tests: rectangles, disks, a scene header, and the `settling`
//! scene (36 disks, six blocks and a deformable slab dropped into a box).

use pbdda::model::Model;
use std::fmt::Write;

/// A deterministic pseudo-random sequence in [0, 1) (a 64-bit LCG; the scene must not depend
/// on any crate's generator).
pub struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

pub fn rectangle(s: &mut String, name: &str, x0: f64, y0: f64, x1: f64, y1: f64, extra: &str) {
    writeln!(
        s,
        "[[body]]\nname = \"{name}\"\nshape = \"polygon\"\nvertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]\n{extra}\n"
    )
    .unwrap();
}

pub fn disk(s: &mut String, name: &str, x: f64, y: f64, r: f64, extra: &str) {
    writeln!(
        s,
        "[[body]]\nname = \"{name}\"\nshape = \"disk\"\ncenter = [{x}, {y}]\nradius = {r}\n{extra}\n"
    )
    .unwrap();
}

pub fn header(s: &mut String, dt: f64, tolerance: f64, max_iterations: usize) {
    writeln!(
        s,
        r#"[scene]
name = "determinism"

[time]
step = {dt}
steps = 1

[physics]
gravity = [0.0, -9.81]

[solver]
tolerance = {tolerance}
max_iterations = {max_iterations}

[[material]]
name = "rock"
density = 2500.0
young = 1.0e7
poisson = 0.3

[[interface]]
friction = 0.5
"#
    )
    .unwrap();
}

/// A box 8 m wide; 36 disks (radius 0.25-0.4) on a jittered grid, six blocks and one
/// deformable block above them, all falling.
pub fn settling() -> Model {
    pbdda::scene::parse(&settling_text(), "settling.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The text of [`settling`].
pub fn settling_text() -> String {
    let mut s = String::new();
    header(&mut s, 0.01, 1e-8, 20_000);
    let fixed = "material = \"rock\"\nfixed = true";
    rectangle(&mut s, "floor", -1.0, -1.0, 9.0, 0.0, fixed);
    rectangle(&mut s, "left", -1.0, 0.0, 0.0, 14.0, fixed);
    rectangle(&mut s, "right", 8.0, 0.0, 9.0, 14.0, fixed);
    let mut rng = Lcg(2018);
    let rigid = "material = \"rock\"";
    for i in 0..36 {
        let (col, row) = ((i % 6) as f64, (i / 6) as f64);
        let r = 0.25 + 0.15 * rng.next();
        let x = 1.0 + 1.2 * col + 0.3 * (rng.next() - 0.5);
        let y = 1.0 + 1.0 * row + 0.1 * rng.next();
        disk(&mut s, &format!("d{i}"), x, y, r, rigid);
    }
    for i in 0..6 {
        let x = 0.6 + 1.25 * i as f64 + 0.2 * rng.next();
        let y = 7.5 + 0.3 * rng.next();
        rectangle(&mut s, &format!("b{i}"), x, y, x + 0.6, y + 0.4, rigid);
    }
    let soft = "material = \"rock\"\nmodel = \"deformable\"\nangular_velocity = 0.5";
    rectangle(&mut s, "slab", 2.0, 9.0, 5.0, 9.6, soft);
    s
}

/// The bolt pull-out of `tests/rock/bolt_yield.rs` (its header derives the closed form): a
/// fixed block and a free 1 m² block joined by a bolt of rest length L along x, pulled at the
/// free block's centroid by the load `history`; no gravity, static relaxation.
pub mod pull {
    /// The bolt's Young's modulus [Pa], section [m²], rest length [m] and yield force [N].
    pub const E: f64 = 1.0e8;
    pub const AREA: f64 = 0.01;
    pub const L: f64 = 2.0;
    pub const Y: f64 = 1.0e4;
    pub const RHO: f64 = 10.0; // the free block is 1 m² : m = 10 kg
    /// The step [s].
    pub const DT: f64 = 0.01;

    /// The scene text: `history` the load's [[t, F]] table, `ultimate` the bolt's
    /// `ultimate_strain` (none: it never breaks), `steps` steps.
    pub fn scene(history: &str, ultimate: Option<f64>, steps: usize) -> String {
        let ultimate = ultimate.map_or(String::new(), |u| format!("ultimate_strain = {u}"));
        format!(
            r#"
[scene]
name = "pull"
[time]
step = {DT}
steps = {steps}
adaptive = false
[physics]
gravity = [0.0, 0.0]
velocity_carry = 0.0
[[material]]
name = "m"
density = {RHO}
[[body]]
name = "anchor"
shape = "polygon"
vertices = [[-1.0, 0.0], [0.0, 0.0], [0.0, 1.0], [-1.0, 1.0]]
material = "m"
fixed = true
[[body]]
name = "free"
shape = "polygon"
vertices = [[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]]
material = "m"
[[load]]
body = "free"
point = [1.5, 0.5]
force = [1.0, 0.0]
history = {history}
[[connector]]
kind = "bolt"
points = [[-0.5, 0.5], [1.5, 0.5]]
bodies = ["anchor", "free"]
young = {E}
area = {AREA}
yield_force = {Y}
{ultimate}
"#
        )
    }
}
