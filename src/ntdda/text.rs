//! ntdda's original text formats (Shi's DC/DF input): whitespace-separated numbers read in a
//! fixed order, as `fscanf` reads them in `geomreader.c` (`geometryReader1`) and
//! `analysisreader.c` (`ddafile_read_original_analysis`). Line breaks carry no meaning there;
//! here each number remembers its line, so that an error names it.

use super::{Analysis, BlockMaterial, Geometry, ImportError, JointMaterial, Line, Point};

/// A larger count is taken as a malformed file rather than a model (it would be read anyway,
/// number by number, so this only makes the message clearer).
const MAX_COUNT: u64 = 10_000_000;

/// The numbers of a text file in order, each with its 1-based line.
struct Tokens<'a> {
    file: &'a str,
    words: Vec<(&'a str, usize)>,
    next: usize,
}

impl<'a> Tokens<'a> {
    fn new(file: &'a str, source: &'a str) -> Self {
        let words = source
            .lines()
            .enumerate()
            .flat_map(|(i, l)| l.split_whitespace().map(move |w| (w, i + 1)))
            .collect();
        Self { file, words, next: 0 }
    }

    fn last_line(&self) -> usize {
        self.words.last().map_or(1, |w| w.1)
    }

    fn word(&mut self, field: &str) -> Result<(&'a str, usize), ImportError> {
        let w = self.words.get(self.next).copied().ok_or_else(|| {
            ImportError::new(self.file, self.last_line(), field, "the file ends before this field")
        })?;
        self.next += 1;
        Ok(w)
    }

    /// A finite real number (`%lf`).
    fn real(&mut self, field: &str) -> Result<(f64, usize), ImportError> {
        let (w, line) = self.word(field)?;
        match w.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok((v, line)),
            _ => Err(ImportError::new(self.file, line, field, format!("expected a number, found `{w}`"))),
        }
    }

    /// A non-negative integer count (`%d`).
    fn count(&mut self, field: &str) -> Result<usize, ImportError> {
        let (w, line) = self.word(field)?;
        match w.parse::<u64>() {
            Ok(v) if v <= MAX_COUNT => Ok(v as usize),
            Ok(v) => Err(ImportError::new(self.file, line, field, format!("{v} is more than {MAX_COUNT}"))),
            Err(_) => Err(ImportError::new(
                self.file,
                line,
                field,
                format!("expected a whole number >= 0, found `{w}`"),
            )),
        }
    }

    /// `n` numbers named `what: NAME` for NAME in `names`; the line of the first.
    fn reals<const N: usize>(
        &mut self,
        what: &str,
        names: [&str; N],
    ) -> Result<([f64; N], usize), ImportError> {
        let mut out = [0.0; N];
        let mut first = 0;
        for (k, name) in names.iter().enumerate() {
            let (v, line) = self.real(&format!("{what}: {name}"))?;
            out[k] = v;
            if k == 0 {
                first = line;
            }
        }
        Ok((out, first))
    }

    /// Whatever follows the fields the reader takes: listed, since ntdda never reads it.
    fn trailing(&self, ignored: &mut Vec<String>) {
        if let Some(&(w, line)) = self.words.get(self.next) {
            let n = self.words.len() - self.next;
            ignored.push(format!(
                "{}:{line}: {n} further value(s) from `{w}` on: ntdda's reader stops before them",
                self.file
            ));
        }
    }
}

/// A geometry file in the text format (`geomreader.c`, `geometryReader1`): e00; the numbers of
/// joint lines and of boundary lines; of material lines, bolts, fixed, load, measured and hole
/// points; then the joint lines `x1 y1 x2 y2 type`, the material lines `x1 y1 x2 y2 material`, the
/// fixed lines `x1 y1 x2 y2` (a point when both ends coincide), the load, measured and hole points
/// `x y`.
pub fn geometry(file: &str, source: &str) -> Result<Geometry, ImportError> {
    let mut t = Tokens::new(file, source);
    let mut g = Geometry { file: file.to_owned(), ..Geometry::default() };
    let (e00, e00_line) = t.real("edge-node distance e00")?;
    if e00 < 0.0 {
        return Err(ImportError::new(file, e00_line, "edge-node distance e00", "must be >= 0"));
    }
    g.e00 = e00;
    let joints = t.count("number of joint lines")?;
    g.boundary_lines = t.count("number of boundary lines")?;
    let matlines = t.count("number of material lines")?;
    let bolts = t.count("number of bolts")?;
    let fixed = t.count("number of fixed points")?;
    let loads = t.count("number of load points")?;
    let measured = t.count("number of measured points")?;
    let holes = t.count("number of hole points")?;
    if g.boundary_lines > joints {
        return Err(ImportError::new(
            file,
            t.words[2].1,
            "number of boundary lines",
            format!(
                "{} boundary lines but only {joints} joint lines (they are the first joint lines)",
                g.boundary_lines
            ),
        ));
    }
    if bolts > 0 {
        // geomreader.c reads the count, warns "Rock bolts are not yet implemented" and reads no
        // bolt line: numbers meant as bolts would be read as the next joint lines.
        return Err(ImportError::new(
            file,
            t.words[4].1,
            "number of bolts",
            format!(
                "{bolts} bolts, but ntdda's text geometry has no bolt lines (geomreader.c reads \
                 none); bolts need the DDAML format"
            ),
        ));
    }
    for k in 1..=joints {
        let what = format!("joint line {k}");
        let ([x1, y1, x2, y2, ty], line) = t.reals(&what, ["x1", "y1", "x2", "y2", "type"])?;
        let kind = whole(file, line, &format!("{what}: type"), ty)?;
        g.joints.push(Line { a: [x1, y1], b: [x2, y2], kind, line });
    }
    for k in 1..=matlines {
        let what = format!("material line {k}");
        let ([x1, y1, x2, y2, m], line) = t.reals(&what, ["x1", "y1", "x2", "y2", "material"])?;
        let kind = whole(file, line, &format!("{what}: material"), m)?;
        g.material_lines.push(Line { a: [x1, y1], b: [x2, y2], kind, line });
    }
    for k in 1..=fixed {
        let ([x1, y1, x2, y2], line) = t.reals(&format!("fixed point {k}"), ["x1", "y1", "x2", "y2"])?;
        g.fixed.push(Line { a: [x1, y1], b: [x2, y2], kind: 0, line });
    }
    for (n, what, list) in [
        (loads, "load point", &mut g.loads),
        (measured, "measured point", &mut g.measured),
        (holes, "hole point", &mut g.holes),
    ] {
        for k in 1..=n {
            let ([x, y], line) = t.reals(&format!("{what} {k}"), ["x", "y"])?;
            list.push(Point { p: [x, y], line });
        }
    }
    t.trailing(&mut g.ignored);
    Ok(g)
}

/// A number that must be a whole number (a type or material index read as `%lf`).
pub(super) fn whole(file: &str, line: usize, field: &str, v: f64) -> Result<i64, ImportError> {
    if v.fract() != 0.0 || !(1.0..=1e9).contains(&v) {
        return Err(ImportError::new(file, line, field, format!("expected a whole number >= 1, found {v}")));
    }
    Ok(v as i64)
}

/// An analysis file in the text format (`analysisreader.c`, `ddafile_read_original_analysis`):
/// analysis type (1 dynamic, 0 static); number of time steps; of block materials; of joint
/// materials; the maximum displacement ratio g2; the maximum time step g1; then per block
/// material 13 numbers `ma we e0 u0 s11 s22 s12 t11 t22 t12 vx vy vr` (unit mass, unit weight,
/// Young's modulus, Poisson's ratio, initial stresses, initial strains, initial velocities);
/// per joint material `friction-angle cohesion tension`. The reader reads no load or displacement
/// histories (its `k5` flags are all set to "none") and sets gravity to `we / ma` of material 1.
pub fn analysis(file: &str, source: &str) -> Result<Analysis, ImportError> {
    let mut t = Tokens::new(file, source);
    let mut a = Analysis { file: file.to_owned(), ..Analysis::default() };
    let (kind, kind_line) = t.real("analysis type")?;
    a.dynamic = match kind {
        0.0 => false,
        1.0 => true,
        _ => {
            return Err(ImportError::new(
                file,
                kind_line,
                "analysis type",
                format!("expected 0 (static) or 1 (dynamic), found {kind}"),
            ));
        }
    };
    a.steps = t.count("number of time steps")?;
    let blocks = t.count("number of block materials")?;
    let joints = t.count("number of joint materials")?;
    let (g2, _) = t.real("maximum displacement ratio g2")?;
    let (g1, g1_line) = t.real("maximum time step g1")?;
    if g1 <= 0.0 {
        return Err(ImportError::new(
            file,
            g1_line,
            "maximum time step g1",
            format!("must be > 0 (got {g1})"),
        ));
    }
    a.time_step = g1;
    a.auto_step = Some(true);
    a.ignored.push(format!(
        "maximum displacement ratio g2 = {g2}: ntdda's limit on a step's motion; pbdda limits it by the contact threshold"
    ));
    a.ignored.push(
        "penalty: the text format has none (ntdda sets pfactor 50); pbdda has no penalty springs".into(),
    );
    for k in 1..=blocks {
        let what = format!("block material {k}");
        let names = ["ma", "we", "e0", "u0", "s11", "s22", "s12", "t11", "t22", "t12", "vx", "vy", "vr"];
        let (v, line) = t.reals(&what, names)?;
        a.block_materials.push(BlockMaterial {
            density: v[0],
            unit_weight: v[1],
            young: v[2],
            poisson: v[3],
            initial_stress: [v[4], v[5], v[6]],
            initial_strain: [v[7], v[8], v[9]],
            initial_velocity: [v[10], v[11], v[12]],
            damping: None,
            line,
        });
    }
    for k in 1..=joints {
        let what = format!("joint material {k}");
        let ([f, c, s], line) = t.reals(&what, ["friction angle", "cohesion", "tension"])?;
        a.joint_materials.push(JointMaterial { friction_angle: f, cohesion: c, tensile_strength: s, line });
    }
    // analysisreader.c: adn->gravaccel = adn->materialProps[1][1]/adn->materialProps[1][0];
    let first = a.block_materials.first().ok_or_else(|| {
        ImportError::new(
            file,
            t.last_line(),
            "number of block materials",
            "at least one block material is needed (gravity is we / ma of material 1)",
        )
    })?;
    if first.density <= 0.0 {
        return Err(ImportError::new(
            file,
            first.line,
            "block material 1: ma",
            format!("must be > 0 (got {})", first.density),
        ));
    }
    a.gravity = first.unit_weight / first.density;
    t.trailing(&mut a.ignored);
    Ok(a)
}
