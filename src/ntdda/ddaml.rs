//! ntdda's DDAML (XML) formats: `<DDA><Geometry>…</Geometry></DDA>` as `geomddaml.c` reads it
//! and `<DDA><Analysis>…</Analysis></DDA>` as `analysisddaml.c` reads it. Elements are matched
//! by local name (ntdda ignores the `Berkeley:` prefix too). Where ntdda skips an element it does
//! not know, it is listed as ignored here; where ntdda segfaults or exits on a missing attribute
//! or a wrong number of values, this is an error naming the line.

use super::{
    Analysis, BlockMaterial, BoltMaterial, Geometry, ImportError, JointMaterial, Line, LoadHistory, Point,
};
use roxmltree::{Document, Node, ParsingOptions};

/// One element's context for errors.
struct Ctx<'a, 'i> {
    file: &'a str,
    doc: &'a Document<'i>,
}

impl<'a, 'i> Ctx<'a, 'i> {
    fn line(&self, n: Node) -> usize {
        self.doc.text_pos_at(n.range().start).row as usize
    }

    fn err(&self, n: Node, field: impl Into<String>, message: impl Into<String>) -> ImportError {
        ImportError::new(self.file, self.line(n), field, message)
    }

    /// The element's text as `count` numbers.
    fn numbers(&self, n: Node, field: &str, count: usize) -> Result<Vec<f64>, ImportError> {
        let text: String = n.descendants().filter(|d| d.is_text()).filter_map(|d| d.text()).collect();
        let v = parse_numbers(&text)
            .map_err(|w| self.err(n, field, format!("expected a number, found `{w}`")))?;
        if v.len() != count {
            return Err(self.err(
                n,
                field,
                format!("needs {count} numbers, found {} (`{}`)", v.len(), text.trim()),
            ));
        }
        Ok(v)
    }

    /// A required attribute as a number.
    fn attr(&self, n: Node, name: &str) -> Result<f64, ImportError> {
        let field = format!("{}@{name}", n.tag_name().name());
        let s = n.attribute(name).ok_or_else(|| self.err(n, &field, "the attribute is missing"))?;
        match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(n, &field, format!("expected a number, found `{s}`"))),
        }
    }

    fn whole_attr(&self, n: Node, name: &str) -> Result<i64, ImportError> {
        let v = self.attr(n, name)?;
        super::text::whole(self.file, self.line(n), &format!("{}@{name}", n.tag_name().name()), v)
    }

    fn flag(&self, n: Node, name: &str, yes: &str) -> Result<bool, ImportError> {
        let field = format!("{}@{name}", n.tag_name().name());
        let s = n.attribute(name).ok_or_else(|| self.err(n, &field, "the attribute is missing"))?;
        Ok(s.trim() == yes)
    }

    fn ignore(&self, n: Node, why: &str) -> String {
        format!("{}:{}: <{}>: {why}", self.file, self.line(n), n.tag_name().name())
    }
}

fn parse_numbers(text: &str) -> Result<Vec<f64>, String> {
    text.split_whitespace()
        .map(|w| w.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| w.to_owned()))
        .collect()
}

fn parse<'i>(file: &str, source: &'i str) -> Result<Document<'i>, ImportError> {
    let options = ParsingOptions { allow_dtd: true, ..ParsingOptions::default() };
    Document::parse_with_options(source, options)
        .map_err(|e| ImportError::new(file, e.pos().row as usize, "XML", e.to_string()))
}

/// The `section` element (`Geometry` or `Analysis`) under the root `DDA`.
fn section<'a, 'i>(c: &Ctx<'a, 'i>, name: &str) -> Result<Node<'a, 'i>, ImportError> {
    let root = c.doc.root_element();
    if root.tag_name().name() != "DDA" {
        return Err(c.err(
            root,
            "DDA",
            format!("the root element is <{}>, not <DDA>", root.tag_name().name()),
        ));
    }
    root.children()
        .find(|n| n.is_element() && n.tag_name().name() == name)
        .ok_or_else(|| c.err(root, name, format!("<DDA> has no <{name}> element")))
}

fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// A DDAML geometry file (`geomddaml.c`, `gtab_type`).
pub fn geometry(file: &str, source: &str) -> Result<Geometry, ImportError> {
    let doc = parse(file, source)?;
    let c = Ctx { file, doc: &doc };
    let geo = section(&c, "Geometry")?;
    let mut g = Geometry { file: file.to_owned(), ..Geometry::default() };
    let mut have_e00 = false;
    for n in elements(geo) {
        match n.tag_name().name() {
            "Edgenodedist" => {
                g.e00 = c.attr(n, "distance")?;
                have_e00 = true;
            }
            "Jointlist" => lines(&c, n, "Joint", "type", &mut g.joints, &mut g.ignored)?,
            "Matlinelist" => lines(&c, n, "Line", "type", &mut g.material_lines, &mut g.ignored)?,
            "Fixedpointlist" => {
                for e in elements(n) {
                    match e.tag_name().name() {
                        "Line" => {
                            let v = c.numbers(e, "Fixedpointlist/Line", 4)?;
                            g.fixed.push(Line { a: [v[0], v[1]], b: [v[2], v[3]], kind: 0, line: c.line(e) });
                        }
                        "Point" => {
                            let v = c.numbers(e, "Fixedpointlist/Point", 2)?;
                            g.fixed.push(Line { a: [v[0], v[1]], b: [v[0], v[1]], kind: 0, line: c.line(e) });
                        }
                        _ => g.ignored.push(c.ignore(e, "not a <Line> or <Point>: ntdda skips it")),
                    }
                }
            }
            "Loadpointlist" => points(&c, n, &mut g.loads, &mut g.ignored)?,
            "Measuredpointlist" => points(&c, n, &mut g.measured, &mut g.ignored)?,
            "Holepointlist" => points(&c, n, &mut g.holes, &mut g.ignored)?,
            "Boltlist" => bolts(&c, n, &mut g)?,
            "Seismicpointlist" => g
                .ignored
                .push(c.ignore(n, "seismic points (ntdda's earthquake input records): no meaning here")),
            "Boundlist" => g.ignored.push(c.ignore(
                n,
                "boundary lines: ntdda counts them but never passes them to the cutter (geomddaml.c)",
            )),
            _ => g.ignored.push(c.ignore(n, "not a geometry element ntdda reads: skipped as ntdda does")),
        }
    }
    if !have_e00 {
        return Err(c.err(geo, "Edgenodedist", "<Geometry> has no <Edgenodedist distance=\"…\"/>"));
    }
    if g.e00 < 0.0 {
        return Err(c.err(geo, "Edgenodedist@distance", "must be >= 0"));
    }
    Ok(g)
}

/// `<Joint type="K">x1 y1 x2 y2</Joint>` or `<Line type="K">…</Line>` children of a list.
fn lines(
    c: &Ctx,
    list: Node,
    child: &str,
    attr: &str,
    out: &mut Vec<Line>,
    ignored: &mut Vec<String>,
) -> Result<(), ImportError> {
    for e in elements(list) {
        if e.tag_name().name() != child {
            ignored.push(c.ignore(e, &format!("not a <{child}>: ntdda skips it")));
            continue;
        }
        let kind = c.whole_attr(e, attr)?;
        let v = c.numbers(e, &format!("{}/{child}", list.tag_name().name()), 4)?;
        out.push(Line { a: [v[0], v[1]], b: [v[2], v[3]], kind, line: c.line(e) });
    }
    Ok(())
}

/// `<Point>x y</Point>` children of a point list.
fn points(c: &Ctx, list: Node, out: &mut Vec<Point>, ignored: &mut Vec<String>) -> Result<(), ImportError> {
    for e in elements(list) {
        if e.tag_name().name() != "Point" {
            ignored.push(c.ignore(e, "not a <Point>: ntdda skips it"));
            continue;
        }
        let v = c.numbers(e, &format!("{}/Point", list.tag_name().name()), 2)?;
        out.push(Point { p: [v[0], v[1]], line: c.line(e) });
    }
    Ok(())
}

/// `<Bolt type="T">x1 y1 x2 y2</Bolt>`: type 1 is Shi's end-anchored bolt, type 2 the segmented
/// bolt that `produce_boltsegments` cuts at every block edge (grouted). ntdda takes a missing or
/// unknown type as 1, with a warning.
fn bolts(c: &Ctx, list: Node, g: &mut Geometry) -> Result<(), ImportError> {
    for e in elements(list) {
        if e.tag_name().name() != "Bolt" {
            g.ignored.push(c.ignore(e, "not a <Bolt>: ntdda skips it"));
            continue;
        }
        let kind = match e.attribute("type").map(|s| s.trim().parse::<i64>()) {
            Some(Ok(k @ (1 | 2))) => k,
            other => {
                let why = if other.is_none() { "no type" } else { "a type other than 1 or 2" };
                g.notes.push(format!(
                    "{}:{}: <Bolt> has {why}: taken as type 1 (end-anchored), as ntdda does",
                    c.file,
                    c.line(e)
                ));
                1
            }
        };
        let v = c.numbers(e, "Boltlist/Bolt", 4)?;
        g.bolts.push(Line { a: [v[0], v[1]], b: [v[2], v[3]], kind, line: c.line(e) });
    }
    Ok(())
}

/// A DDAML analysis file (`analysisddaml.c`, `atab_type`).
pub fn analysis(file: &str, source: &str) -> Result<Analysis, ImportError> {
    let doc = parse(file, source)?;
    let c = Ctx { file, doc: &doc };
    let ana = section(&c, "Analysis")?;
    let mut a = Analysis { file: file.to_owned(), gravity: 9.81, ..Analysis::default() };
    let (mut have_steps, mut have_dt) = (false, false);
    for n in elements(ana) {
        let ign = |why: &str| c.ignore(n, why);
        match n.tag_name().name() {
            "Analysistype" => a.dynamic = c.flag(n, "type", "dynamic")?,
            "Numtimesteps" => {
                let v = c.attr(n, "timesteps")?;
                if v.fract() != 0.0 || !(0.0..=1e9).contains(&v) {
                    return Err(c.err(
                        n,
                        "Numtimesteps@timesteps",
                        format!("expected a whole number >= 0, found {v}"),
                    ));
                }
                a.steps = v as usize;
                have_steps = true;
            }
            "Maxtimestep" => {
                a.time_step = c.attr(n, "maxtimestep")?;
                if a.time_step <= 0.0 {
                    return Err(c.err(
                        n,
                        "Maxtimestep@maxtimestep",
                        format!("must be > 0 (got {})", a.time_step),
                    ));
                }
                have_dt = true;
            }
            "Gravaccel" => a.gravity = n.attribute("value").map_or(Ok(9.81), |_| c.attr(n, "value"))?,
            "Autotimestep" => a.auto_step = Some(c.flag(n, "flag", "yes")?),
            "Planestrain" => a.plane_strain = Some(c.flag(n, "flag", "yes")?),
            "Saveinterval" => {
                let v = n.attribute("step").and_then(|s| s.trim().parse::<usize>().ok()).unwrap_or(10);
                a.save_every = Some(if v == 0 { 10 } else { v });
            }
            "Jointproperties" => a.joint_materials.push(joint_material(&c, n)?),
            "Blockmaterial" => a.block_materials.push(block_material(&c, n)?),
            "Boltproperties" => {
                let v = c.numbers(n, "Boltproperties", 3)?;
                a.bolt_materials.push(BoltMaterial {
                    stiffness: v[0],
                    strength: v[1],
                    pretension: v[2],
                    line: c.line(n),
                });
            }
            "Loadpointlist" => load_histories(&c, n, &mut a)?,
            tag => a.ignored.push(ign(ignored_why(tag))),
        }
    }
    if !have_steps {
        return Err(c.err(ana, "Numtimesteps", "<Analysis> has no <Numtimesteps timesteps=\"…\"/>"));
    }
    if !have_dt {
        return Err(c.err(ana, "Maxtimestep", "<Analysis> has no <Maxtimestep maxtimestep=\"…\"/>"));
    }
    Ok(a)
}

/// Why an analysis element that pbdda does not import is skipped (listed in the import's report).
fn ignored_why(tag: &str) -> &'static str {
    match tag {
        "Gravity" => "ntdda's gravity turn-on phase and its tolerances: pbdda applies gravity from t = 0",
        "Autopenalty" => "penalty number and factor: pbdda has no penalty springs",
        "AConstants" => {
            "ntdda's contact constants (open-close, penalty, angle overlap): pbdda's contacts are exact"
        }
        "Rotation" => "ntdda's rotation linearisation: pbdda's is its own (math note)",
        "Mintimestep" => "ntdda's smallest automatic step: pbdda's is [time] step / 2^max_halvings",
        "Maxdisplacement" => {
            "ntdda's limit on a step's motion (g2): pbdda limits it by the contact threshold"
        }
        "OCLimit" | "Opencloselimit" => "ntdda's open-close iteration limit: pbdda's contacts need none",
        "Writevertices" => "ntdda's output choice: pbdda writes every body",
        "Timehistory" => "earthquake ground motion: not imported",
        "ContactDamping" => "contact damping: pbdda has none",
        _ => "not an analysis element ntdda reads: skipped as ntdda does",
    }
}

fn child_text<'a, 'i>(n: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    elements(n).find(|e| e.tag_name().name() == name)
}

fn joint_material(c: &Ctx, n: Node) -> Result<JointMaterial, ImportError> {
    // analysisddaml.c parseJointproperties: atof of each child's text; a missing child stays 0.
    let get = |name: &str| -> Result<f64, ImportError> {
        child_text(n, name).map_or(Ok(0.0), |e| Ok(c.numbers(e, &format!("Jointproperties/{name}"), 1)?[0]))
    };
    Ok(JointMaterial {
        friction_angle: get("Friction")?,
        cohesion: get("Cohesion")?,
        tensile_strength: get("Tensile")?,
        line: c.line(n),
    })
}

fn block_material(c: &Ctx, n: Node) -> Result<BlockMaterial, ImportError> {
    let field = |name: &str| format!("Blockmaterial/{name}");
    let one = |name: &str| -> Result<f64, ImportError> {
        let e = child_text(n, name).ok_or_else(|| c.err(n, field(name), "missing"))?;
        Ok(c.numbers(e, &field(name), 1)?[0])
    };
    let three = |name: &str| -> Result<[f64; 3], ImportError> {
        child_text(n, name).map_or(Ok([0.0; 3]), |e| {
            let v = c.numbers(e, &field(name), 3)?;
            Ok([v[0], v[1], v[2]])
        })
    };
    Ok(BlockMaterial {
        density: one("Unitmass")?,
        unit_weight: one("Unitweight")?,
        young: one("Youngsmod")?,
        poisson: one("Poissonratio")?,
        // ntdda exits with "Damping tag not found in BlockMaterials"
        damping: Some(one("Damping")?),
        initial_stress: three("Istress")?,
        initial_strain: three("Istrain")?,
        initial_velocity: three("Ivelocity")?,
        line: c.line(n),
    })
}

/// `<Loadpoint numpoints="N">t fx fy; t fx fy; …</Loadpoint>`, one per load point in order.
fn load_histories(c: &Ctx, list: Node, a: &mut Analysis) -> Result<(), ImportError> {
    for e in elements(list) {
        if e.tag_name().name() != "Loadpoint" {
            a.ignored.push(c.ignore(e, "not a <Loadpoint>: ntdda skips it"));
            continue;
        }
        let n = c.attr(e, "numpoints")?;
        if n.fract() != 0.0 || n < 2.0 {
            return Err(c.err(e, "Loadpoint@numpoints", format!("2 or more records are required (got {n})")));
        }
        let text: String = e.descendants().filter(|d| d.is_text()).filter_map(|d| d.text()).collect();
        let mut rows = Vec::new();
        for record in text.split(';').map(str::trim).filter(|r| !r.is_empty()) {
            let v = parse_numbers(record)
                .map_err(|w| c.err(e, "Loadpoint", format!("expected a number, found `{w}`")))?;
            if v.len() != 3 {
                return Err(c.err(e, "Loadpoint", format!("each record is `t fx fy;`, found `{record}`")));
            }
            rows.push([v[0], v[1], v[2]]);
        }
        if rows.len() != n as usize {
            return Err(c.err(
                e,
                "Loadpoint@numpoints",
                format!("says {n} records, the element has {}", rows.len()),
            ));
        }
        if rows.windows(2).any(|w| w[1][0] < w[0][0]) {
            return Err(c.err(e, "Loadpoint", "the record times must not decrease"));
        }
        a.load_histories.push(LoadHistory { rows, line: c.line(e) });
    }
    Ok(())
}
