//! ntdda's geometry and analysis mapped onto pbdda's rock-mass keys, written as TOML.
//!
//! The mapping (docs/scene-format.md, "Importing ntdda input"): joint lines -> `[domain]` (the
//! outline of the blocks they close) and `[[joint]]` (the pieces inside it), joint types ->
//! `[[interface]] joint-K`, material lines -> `[[region]]` (the blocks DC gives that material),
//! fixed points and lines -> `[domain] fixed_points`, hole points -> `[[excavation]]` (the block
//! DC deletes), load points -> `[[load]]`, measured points -> `[[monitor]]`, bolts ->
//! `[[connector]] kind = "bolt"`, block materials -> `[[material]] mat-K`, time step and step
//! count -> `[time]`, gravity and analysis type -> `[physics]`.

use super::arrange::{self, Arrangement, Location, Segment};
use super::{Analysis, Geometry, Import, ImportError, Line};
use std::fmt::Write as _;

/// Everything decided, before writing.
struct Ctx<'a> {
    g: &'a Geometry,
    a: Option<&'a Analysis>,
    arr: Arrangement,
    /// Blocks deleted by hole points.
    removed: Vec<bool>,
    /// pbdda's name (`blk-N`) of each kept block, in the cutter's order (centroid y, x, area).
    names: Vec<Option<String>>,
    ignored: Vec<String>,
    notes: Vec<String>,
}

fn num(v: f64) -> String {
    format!("{v:?}")
}
fn pt(p: [f64; 2]) -> String {
    format!("[{}, {}]", num(p[0]), num(p[1]))
}
fn pts(p: &[[f64; 2]]) -> String {
    format!("[{}]", p.iter().map(|&q| pt(q)).collect::<Vec<_>>().join(", "))
}

/// The arrangement tests every pair of joint lines: 20,000 lines are 2e8 pairs, about a second.
const MAX_JOINT_LINES: usize = 20_000;

/// Builds the scene from a geometry and (optionally) its analysis.
pub fn build(g: &Geometry, a: Option<&Analysis>) -> Result<Import, ImportError> {
    let segs: Vec<Segment> =
        g.joints.iter().enumerate().map(|(k, j)| Segment { a: j.a, b: j.b, source: k }).collect();
    let first_line = g.joints.first().map_or(1, |j| j.line);
    if g.joints.len() > MAX_JOINT_LINES {
        let m = format!(
            "{} joint lines; the import takes at most {MAX_JOINT_LINES} (it intersects every pair)",
            g.joints.len()
        );
        return Err(ImportError::new(&g.file, first_line, "joint lines", m));
    }
    let arr = arrange::build(&segs).map_err(|m| ImportError::new(&g.file, first_line, "joint lines", m))?;
    let n = arr.faces.len();
    let mut c = Ctx {
        g,
        a,
        arr,
        removed: vec![false; n],
        names: vec![None; n],
        ignored: Vec::new(),
        notes: Vec::new(),
    };
    c.ignored.extend(g.ignored.iter().cloned());
    c.notes.extend(g.notes.iter().cloned());
    if let Some(a) = a {
        c.ignored.extend(a.ignored.iter().cloned());
        c.notes.extend(a.notes.iter().cloned());
        check_indices(g, a)?;
    }
    c.holes();
    c.name_blocks();
    let mut body = String::new();
    c.analysis_part(&mut body);
    c.domain(&mut body)?;
    c.joints(&mut body);
    c.regions(&mut body)?;
    c.excavations(&mut body);
    c.loads(&mut body)?;
    c.bolts(&mut body);
    c.monitors(&mut body)?;
    let mut head = format!(
        "# Imported by `pbdda import-ntdda` from {}{}.\n",
        one_line(&g.file),
        a.map_or(String::new(), |a| format!(" and {}", one_line(&a.file)))
    );
    head += &format!(
        "# The joint lines close {} blocks ({} deleted by hole points).\n",
        n,
        c.removed.iter().filter(|&&r| r).count()
    );
    for (title, list) in
        [("ignored (no meaning in pbdda)", &c.ignored), ("notes (how fields were mapped)", &c.notes)]
    {
        if !list.is_empty() {
            let _ = writeln!(head, "#\n# {title}:");
            for l in list {
                let _ = writeln!(head, "#   {}", one_line(l));
            }
        }
    }
    Ok(Import { toml: format!("{head}\n{body}"), ignored: c.ignored, notes: c.notes })
}

fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// Joint types and material numbers must name materials of the analysis (ntdda indexes its
/// arrays with them unchecked).
fn check_indices(g: &Geometry, a: &Analysis) -> Result<(), ImportError> {
    for j in &g.joints {
        if j.kind as usize > a.joint_materials.len() {
            let m = format!(
                "joint type {} but {} has {} joint materials",
                j.kind,
                a.file,
                a.joint_materials.len()
            );
            return Err(ImportError::new(&g.file, j.line, "joint line: type", m));
        }
    }
    for m in &g.material_lines {
        if m.kind as usize > a.block_materials.len() {
            let msg =
                format!("material {} but {} has {} block materials", m.kind, a.file, a.block_materials.len());
            return Err(ImportError::new(&g.file, m.line, "material line: material", msg));
        }
    }
    let (loads, histories) = (g.loads.len(), a.load_histories.len());
    if histories > 0 && histories != loads {
        let line = a.load_histories[0].line;
        let m = format!("{histories} load histories but {} has {loads} load points", g.file);
        return Err(ImportError::new(&a.file, line, "Loadpointlist", m));
    }
    Ok(())
}

impl Ctx<'_> {
    fn block_name(&self, f: usize) -> String {
        self.names[f].clone().unwrap_or_default()
    }

    /// The kept block holding `p` (on an edge: the first in pbdda's order), or why none.
    fn holder(&self, p: [f64; 2]) -> Result<usize, &'static str> {
        let lowest =
            |fs: Vec<usize>| fs.into_iter().filter(|&f| !self.removed[f]).min_by_key(|&f| self.order(f));
        match self.arr.locate(p) {
            Location::Inside(f) if !self.removed[f] => Ok(f),
            Location::Inside(_) => Err("lies in a block that a hole point deletes"),
            Location::OnEdge(fs) => lowest(fs).ok_or("lies on the edge of deleted blocks only"),
            Location::Outside => Err("lies in no block"),
        }
    }

    fn order(&self, f: usize) -> usize {
        self.names[f].as_ref().and_then(|n| n[4..].parse().ok()).unwrap_or(usize::MAX)
    }

    /// DC deletes the block holding each hole point (dc11, dc17).
    fn holes(&mut self) {
        for (k, h) in self.g.holes.iter().enumerate() {
            let at = format!("{}:{}: hole point {} {}", self.g.file, h.line, k + 1, pt(h.p));
            match self.arr.locate(h.p) {
                Location::Inside(f) if self.removed[f] => {
                    self.notes.push(format!("{at}: its block is deleted by an earlier hole point already"))
                }
                Location::Inside(f) => self.removed[f] = true,
                Location::OnEdge(_) => self.ignored.push(format!(
                    "{at}: lies on a block edge, so which block DC deletes depends on its search order; \
                     nothing is excavated (move the point inside a block)"
                )),
                Location::Outside => {
                    self.ignored.push(format!("{at}: lies in no block; deletes nothing, as in DC"))
                }
            }
        }
    }

    /// `blk-N`, N from 1, in the order of pbdda's cutter ([`block_order`]).
    fn name_blocks(&mut self) {
        let faces = &self.arr.faces;
        let mut kept: Vec<usize> = (0..faces.len()).filter(|&f| !self.removed[f]).collect();
        kept.sort_by(|&a, &b| block_order(&self.arr, a, b));
        for (k, f) in kept.into_iter().enumerate() {
            self.names[f] = Some(format!("blk-{}", k + 1));
        }
    }

    fn analysis_part(&mut self, out: &mut String) {
        let _ = writeln!(out, "[scene]\nname = \"ntdda import\"\n");
        let Some(a) = self.a else {
            self.notes.push(
                "no analysis file: add [time], [[material]] mat-K and [[interface]] joint-K before running"
                    .into(),
            );
            return;
        };
        let _ = writeln!(out, "[time]\nstep = {}\nsteps = {}", num(a.time_step), a.steps);
        if let Some(auto) = a.auto_step {
            let _ = writeln!(out, "adaptive = {auto}");
            self.notes.push(format!(
                "ntdda's automatic time step {}: [time] adaptive = {auto} (pbdda halves a failed step)",
                if auto { "on" } else { "off" }
            ));
        }
        let carry = if a.dynamic { 1.0 } else { 0.0 };
        let _ = writeln!(
            out,
            "\n[physics]\ngravity = [0.0, {}]\nvelocity_carry = {}",
            num(-a.gravity),
            num(carry)
        );
        if let Some(strain) = a.plane_strain {
            let _ = writeln!(out, "plane = \"{}\"", if strain { "strain" } else { "stress" });
        }
        if let Some(every) = a.save_every {
            let _ = writeln!(out, "\n[output]\nevery = {every}");
        }
        for (k, m) in a.block_materials.iter().enumerate() {
            let name = format!("mat-{}", k + 1);
            let _ = writeln!(
                out,
                "\n[[material]]\nname = \"{name}\"\ndensity = {}\nyoung = {}\npoisson = {}",
                num(m.density),
                num(m.young),
                num(m.poisson)
            );
            let at = format!("{}:{}: block material {}", a.file, m.line, k + 1);
            let weight = m.density * a.gravity;
            if (m.unit_weight - weight).abs() > 1e-9 * m.unit_weight.abs().max(weight.abs()) {
                self.notes.push(format!(
                    "{at}: unit weight {} is not density x gravity = {}; pbdda's weight is density x gravity",
                    num(m.unit_weight),
                    num(weight)
                ));
            }
            for (what, v) in [
                ("initial stress", m.initial_stress),
                ("initial strain", m.initial_strain),
                ("initial velocity (vx, vy, vr)", m.initial_velocity),
            ] {
                self.ignored.push(format!("{at}: {what} {v:?}: cut blocks start unstrained and at rest"));
            }
            if let Some(d) = m.damping {
                self.ignored.push(format!("{at}: damping {}: pbdda has no block damping", num(d)));
            }
        }
        self.interfaces(a, out);
    }

    fn interfaces(&mut self, a: &Analysis, out: &mut String) {
        for (k, j) in a.joint_materials.iter().enumerate() {
            let law = format!(
                "friction_angle = {}\ncohesion = {}\ntensile_strength = {}",
                num(j.friction_angle),
                num(j.cohesion),
                num(j.tensile_strength)
            );
            if k == 0 {
                let _ = writeln!(
                    out,
                    "\n# the default contact law: joint type 1's (DC's default type)\n[[interface]]\n{law}"
                );
                self.notes.push(
                    "contacts not along a joint (blocks that meet after moving) take joint type 1's law (the default [[interface]])".into(),
                );
            }
            let _ = writeln!(out, "\n[[interface]]\nname = \"joint-{}\"\n{law}", k + 1);
        }
    }
}

impl Ctx<'_> {
    fn domain(&mut self, out: &mut String) -> Result<(), ImportError> {
        let outline = self.arr.corners(&self.arr.outline);
        let _ = writeln!(out, "\n# the outline of the blocks that the joint lines close\n[domain]");
        let _ = writeln!(out, "vertices = {}\nmaterial = \"mat-1\"\nmodel = \"deformable\"", pts(&outline));
        self.notes.push("DDA blocks are simply deformable: [domain] model = \"deformable\"".into());
        if self.g.boundary_lines > 0 {
            self.notes.push(format!(
                "the first {} joint lines are DC's boundary lines; the outline is the outer loop of all joint lines (DC's boundary lines differ only in how DC merges their vertices)",
                self.g.boundary_lines
            ));
        }
        self.ignored.push(format!(
            "edge-node distance e00 = {}: DC's vertex merge radius (1.25 e00 w0); pbdda merges by [domain] min_edge",
            num(self.g.e00)
        ));
        let mut fixed = Vec::new();
        for (k, l) in self.g.fixed.iter().enumerate() {
            fixed.extend(self.fixed_line(k, l)?);
        }
        if !fixed.is_empty() {
            let _ = writeln!(out, "fixed_points = {}", pts(&fixed));
        }
        Ok(())
    }

    /// The points that fix the blocks a fixed line (or point) lies in, as DC's dc10 makes fixed
    /// points along a fixed line: one point strictly inside each block it passes.
    fn fixed_line(&mut self, k: usize, l: &Line) -> Result<Vec<[f64; 2]>, ImportError> {
        let at = format!("{}:{}: fixed point {}", self.g.file, l.line, k + 1);
        let err =
            |m: &str| ImportError::new(&self.g.file, l.line, format!("fixed point {}", k + 1), m.to_owned());
        if l.a == l.b {
            return match self.arr.locate(l.a) {
                Location::Inside(f) if !self.removed[f] => Ok(vec![l.a]),
                _ => {
                    let f = self.holder(l.a).map_err(&err)?;
                    let p = self.arr.interior_point(f);
                    self.notes.push(format!(
                        "{at} {} lies on an edge of {}: fixed by its interior point {}",
                        pt(l.a),
                        self.block_name(f),
                        pt(p)
                    ));
                    Ok(vec![p])
                }
            };
        }
        let mut ts = vec![0.0, 1.0];
        for e in &self.arr.edges {
            let (p, q) = (self.arr.vertices[e.v[0]], self.arr.vertices[e.v[1]]);
            if let Some(t) = crossing(l.a, l.b, p, q) {
                ts.push(t);
            }
        }
        ts.sort_by(f64::total_cmp);
        let mut blocks: Vec<usize> = Vec::new();
        let mut points = Vec::new();
        for w in ts.windows(2).filter(|w| w[1] > w[0]) {
            let t = 0.5 * (w[0] + w[1]);
            let m = [l.a[0] + t * (l.b[0] - l.a[0]), l.a[1] + t * (l.b[1] - l.a[1])];
            let (f, p) = match self.arr.locate(m) {
                Location::Inside(f) if !self.removed[f] => (f, m),
                Location::OnEdge(_) => match self.holder(m) {
                    Ok(f) => (f, self.arr.interior_point(f)),
                    Err(_) => continue,
                },
                _ => continue,
            };
            if !blocks.contains(&f) {
                blocks.push(f);
                points.push(p);
            }
        }
        if points.is_empty() {
            return Err(err("the fixed line passes no block"));
        }
        let names: Vec<String> = blocks.iter().map(|&f| self.block_name(f)).collect();
        self.notes.push(format!("{at} (a line): fixes {} by a point inside each", names.join(", ")));
        Ok(points)
    }

    /// `[[joint]]`: the pieces of each joint line that separate two kept blocks (pieces on the
    /// outline, on a deleted block or closing no block are not joints here).
    fn joints(&mut self, out: &mut String) {
        let interior = |e: &arrange::Edge| match e.faces {
            [Some(a), Some(b)] => !self.removed[a] && !self.removed[b],
            _ => false,
        };
        for (k, j) in self.g.joints.iter().enumerate() {
            let d = [j.b[0] - j.a[0], j.b[1] - j.a[1]];
            let t = |v: usize| {
                let p = self.arr.vertices[v];
                (p[0] - j.a[0]) * d[0] + (p[1] - j.a[1]) * d[1]
            };
            let mut pieces: Vec<(f64, f64, usize, usize)> = Vec::new();
            let mut any = false;
            for e in self.arr.edges.iter().filter(|e| e.sources.contains(&k)) {
                any = true;
                if e.sources[0] != k || !interior(e) {
                    continue;
                }
                let (v0, v1) = if t(e.v[0]) <= t(e.v[1]) { (e.v[0], e.v[1]) } else { (e.v[1], e.v[0]) };
                pieces.push((t(v0), t(v1), v0, v1));
            }
            pieces.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut runs: Vec<(usize, usize)> = Vec::new();
            for p in pieces {
                match runs.last_mut() {
                    Some(r) if r.1 == p.2 => r.1 = p.3,
                    _ => runs.push((p.2, p.3)),
                }
            }
            let at = format!("{}:{}: joint line {} (type {})", self.g.file, j.line, k + 1, j.kind);
            if !any {
                self.ignored.push(format!("{at}: closes no block; DC deletes it (dangling)"));
            } else if runs.is_empty() {
                self.notes.push(format!("{at}: lies on the outline or on deleted blocks only: no [[joint]]"));
            }
            for (a, b) in runs {
                let p = [self.arr.vertices[a], self.arr.vertices[b]];
                let _ = writeln!(
                    out,
                    "\n# joint line {}\n[[joint]]\npoints = {}\ninterface = \"joint-{}\"",
                    k + 1,
                    pts(&p),
                    j.kind
                );
            }
        }
    }
}

/// The parameter along a-b where it crosses p-q, if it does (touching counts).
fn crossing(a: [f64; 2], b: [f64; 2], p: [f64; 2], q: [f64; 2]) -> Option<f64> {
    let (r, s) = ([b[0] - a[0], b[1] - a[1]], [q[0] - p[0], q[1] - p[1]]);
    let d = r[0] * s[1] - r[1] * s[0];
    if d.abs() <= 1e-12 * (r[0].hypot(r[1]) * s[0].hypot(s[1])) {
        return None;
    }
    let w = [p[0] - a[0], p[1] - a[1]];
    let t = (w[0] * s[1] - w[1] * s[0]) / d;
    let u = (w[0] * r[1] - w[1] * r[0]) / d;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(t)
}

mod points;

/// The order of pbdda's cutter (math note §12.4): centroid y, then x, then area, then the
/// vertex lists from their lowest, then leftmost, vertex. Total: which of two blocks of equal
/// centroid and area comes first does not depend on the order the faces were found in.
fn block_order(arr: &Arrangement, a: usize, b: usize) -> std::cmp::Ordering {
    let (fa, fb) = (&arr.faces[a], &arr.faces[b]);
    fa.centroid[1]
        .total_cmp(&fb.centroid[1])
        .then(fa.centroid[0].total_cmp(&fb.centroid[0]))
        .then(fa.area.total_cmp(&fb.area))
        .then_with(|| crate::rockmass::shape_order(&arr.points(&fa.loop_), &arr.points(&fb.loop_)))
}

#[cfg(test)]
mod tests {
    use super::arrange::{Arrangement, Face};
    use super::block_order;
    use std::cmp::Ordering;

    /// Two blocks whose centroids and areas tie exactly (the unit squares [0,1]² and [2,3]×[0,1],
    /// given the same centroid (1.5, 0.5) and area 1, as a tie of the shoelace sums would): the
    /// vertex lists decide, from each block's lowest-leftmost vertex, (0, 0) before (2, 0), in
    /// whichever order the faces were found.
    #[test]
    fn equal_centroids_are_ordered_by_the_vertex_lists() {
        let vertices = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [3.0, 1.0],
            [2.0, 1.0],
        ];
        let face = |loop_: Vec<usize>| Face { loop_, area: 1.0, centroid: [1.5, 0.5] };
        let (left, right) = (face(vec![2, 3, 0, 1]), face(vec![6, 7, 4, 5]));
        for (faces, l, r) in [(vec![left.clone(), right.clone()], 0, 1), (vec![right, left], 1, 0)] {
            let arr = Arrangement {
                vertices: vertices.clone(),
                edges: Vec::new(),
                faces,
                outline: Vec::new(),
                eps: 1e-9,
            };
            assert_eq!(block_order(&arr, l, r), Ordering::Less);
            assert_eq!(block_order(&arr, r, l), Ordering::Greater);
            assert_eq!(block_order(&arr, l, l), Ordering::Equal);
        }
    }
}
