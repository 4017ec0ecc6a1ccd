//! Material lines, hole, load and measured points and bolts: the blocks they name.

use super::super::ImportError;
use super::{Ctx, crossing, num, pt, pts};
use std::fmt::Write as _;

impl Ctx<'_> {
    /// DC's dc13: a material line gives its material to every block one of whose edges it
    /// crosses, or, crossing none, to the block holding its first point; later lines win; the
    /// rest keep material 1. Each block whose material is not 1 becomes a `[[region]]` of its own
    /// outline (pbdda gives a region's material to the blocks whose centroid lies inside it).
    pub(super) fn regions(&mut self, out: &mut String) -> Result<(), ImportError> {
        let mut material = vec![1i64; self.arr.faces.len()];
        for (k, m) in self.g.material_lines.iter().enumerate() {
            let mut hit = Vec::new();
            for e in &self.arr.edges {
                let (p, q) = (self.arr.vertices[e.v[0]], self.arr.vertices[e.v[1]]);
                if crossing(m.a, m.b, p, q).is_some() {
                    hit.extend(e.faces.iter().flatten().copied());
                }
            }
            if hit.is_empty() {
                match self.arr.locate(m.a) {
                    super::Location::Inside(f) => hit.push(f),
                    _ => {
                        let field = format!("material line {}", k + 1);
                        return Err(ImportError::new(
                            &self.g.file,
                            m.line,
                            field,
                            "crosses no block edge and starts in no block",
                        ));
                    }
                }
            }
            for f in hit {
                material[f] = m.kind;
            }
        }
        for (f, &m) in material.iter().enumerate() {
            if m == 1 || self.removed[f] {
                continue;
            }
            let face = &self.arr.faces[f];
            let outline = self.arr.corners(&face.loop_);
            if !super::arrange::inside(face.centroid, &outline) {
                self.notes.push(format!(
                    "{} (material {m}) is concave with its centroid outside it: its [[region]] may give the material to another block",
                    self.block_name(f)
                ));
            }
            let _ = writeln!(
                out,
                "\n# {}: block material {m} (material lines)\n[[region]]\nvertices = {}\nmaterial = \"mat-{m}\"",
                self.block_name(f),
                pts(&outline)
            );
        }
        Ok(())
    }

    /// The blocks hole points delete, as `[[excavation]]`s of their outlines (removed before t = 0).
    pub(super) fn excavations(&mut self, out: &mut String) {
        let mut k = 0;
        for f in (0..self.arr.faces.len()).filter(|&f| self.removed[f]) {
            k += 1;
            let outline = self.arr.corners(&self.arr.faces[f].loop_);
            let _ = writeln!(
                out,
                "\n# the block a hole point deletes\n[[excavation]]\nname = \"hole-{k}\"\nvertices = {}",
                pts(&outline)
            );
        }
    }

    /// `[[load]]`s from the DDAML load histories: each force component with its own history
    /// (pbdda's history scales one force vector; ntdda's records give fx and fy separately).
    pub(super) fn loads(&mut self, out: &mut String) -> Result<(), ImportError> {
        let histories = self.a.map_or(&[][..], |a| &a.load_histories[..]);
        for (k, l) in self.g.loads.iter().enumerate() {
            let at = format!("{}:{}: load point {} {}", self.g.file, l.line, k + 1, pt(l.p));
            let Some(h) = histories.get(k) else {
                self.ignored
                    .push(format!("{at}: no load history (the text analysis format has none): no [[load]]"));
                continue;
            };
            let f = self
                .holder(l.p)
                .map_err(|m| ImportError::new(&self.g.file, l.line, format!("load point {}", k + 1), m))?;
            let body = self.block_name(f);
            for c in 0..2 {
                let Some(peak) = h.rows.iter().map(|r| r[1 + c]).max_by(|a, b| a.abs().total_cmp(&b.abs()))
                else {
                    continue;
                };
                if peak == 0.0 {
                    continue;
                }
                let force = if c == 0 { [peak, 0.0] } else { [0.0, peak] };
                let history: Vec<[f64; 2]> = h.rows.iter().map(|r| [r[0], r[1 + c] / peak]).collect();
                let _ = writeln!(
                    out,
                    "\n# load point {}, {} component: the block holding {}\n[[load]]\nbody = \"{body}\"\npoint = {}\nforce = {}\nhistory = {}",
                    k + 1,
                    ["x", "y"][c],
                    pt(l.p),
                    pt(l.p),
                    pt(force),
                    pts(&history)
                );
            }
        }
        Ok(())
    }

    /// `[[connector]] kind = "bolt"`: ntdda's bolt type 2 is cut at every block edge
    /// (`produce_boltsegments`): grouted; type 1 is anchored at its ends. ntdda gives every bolt
    /// the first `Boltproperties` (combineddf.c): spring stiffness k, strength, pretension; pbdda's
    /// bolt is E A / L, so E A = k L of the whole bolt.
    pub(super) fn bolts(&mut self, out: &mut String) {
        let material = self.a.and_then(|a| a.bolt_materials.first());
        if let Some(a) = self.a {
            for m in a.bolt_materials.iter().skip(1) {
                self.ignored.push(format!(
                    "{}:{}: <Boltproperties>: ntdda uses only the first bolt material (combineddf.c)",
                    a.file, m.line
                ));
            }
        }
        for (k, b) in self.g.bolts.iter().enumerate() {
            let grouted = b.kind == 2;
            let length = (b.b[0] - b.a[0]).hypot(b.b[1] - b.a[1]);
            let _ = writeln!(
                out,
                "\n[[connector]]\nname = \"bolt-{}\"\nkind = \"bolt\"\npoints = {}\ngrouted = {grouted}",
                k + 1,
                pts(&[b.a, b.b])
            );
            let at = format!("{}:{}: bolt {}", self.g.file, b.line, k + 1);
            let Some(m) = material else {
                self.notes.push(format!("{at}: the analysis has no <Boltproperties>: give young and area"));
                continue;
            };
            let _ = writeln!(
                out,
                "young = {}\narea = 1.0\npretension = {}",
                num(m.stiffness * length),
                num(m.pretension)
            );
            if m.strength > 0.0 {
                let _ = writeln!(out, "strength = {}", num(m.strength));
            } else {
                self.notes.push(format!("{at}: strength {}: unbreakable", num(m.strength)));
            }
            self.notes.push(format!(
                "{at}: stiffness k = {} N/m as young = k L = {}, area = 1{}",
                num(m.stiffness),
                num(m.stiffness * length),
                if grouted { "; ntdda gives each segment k, pbdda E A / (segment length)" } else { "" }
            ));
        }
    }

    /// `[[monitor]]`s at the measured points.
    pub(super) fn monitors(&mut self, out: &mut String) -> Result<(), ImportError> {
        for (k, m) in self.g.measured.iter().enumerate() {
            let field = format!("measured point {}", k + 1);
            let f = self.holder(m.p).map_err(|e| ImportError::new(&self.g.file, m.line, field, e))?;
            let _ = writeln!(
                out,
                "\n# measured point {}: the block holding it\n[[monitor]]\nname = \"measured-{}\"\nbody = \"{}\"\npoint = {}",
                k + 1,
                k + 1,
                self.block_name(f),
                pt(m.p)
            );
        }
        Ok(())
    }
}
