//! gmsh `.msh` reader: MSH 4.1 (ASCII and binary) and MSH 2.2 (ASCII).
//!
//! Reads nodes, first-order elements (3-node triangles, 2-node lines, points) and physical groups
//! (`$PhysicalNames`, and `$Entities` in 4.1), then builds a [`Mesh`]. Every problem is a
//! [`MeshError`] naming the file and the line (binary files: the byte offset); no input panics.
//! Unknown sections are skipped. z coordinates are ignored (the mesh lies in the xy plane).

use std::collections::HashMap;

use super::{Location, Mesh, MeshError, MeshErrorKind as K};
use crate::geometry::Vec2;

mod build;

/// Parses the bytes of a gmsh file; `file` names it in errors.
pub fn parse(file: &str, bytes: &[u8]) -> Result<Mesh, MeshError> {
    let mut r = Reader { file, b: bytes, pos: 0, bin: None, section: "$MeshFormat" };
    let raw = r.read_all()?;
    build::build(&r, raw)
}

/// Binary layout from the header.
#[derive(Clone, Copy)]
struct Bin {
    size_t: usize,
    big_endian: bool,
}

/// One node of the file.
pub(super) struct RawNode {
    pub tag: u64,
    pub p: Vec2,
}

/// One element of the file (first-order triangle, line or point).
pub(super) struct RawElement {
    pub tag: u64,
    /// 0 point, 1 line, 2 triangle.
    pub dim: usize,
    /// Offset of `nodes` in [`Raw::element_nodes`]; `dim + 1` nodes.
    pub first: usize,
    /// Physical tags of the element.
    pub physical: Vec<i64>,
    /// Byte offset of the element in the file (for messages).
    pub pos: usize,
}

/// Everything read from the file before checks.
#[derive(Default)]
pub(super) struct Raw {
    pub names: Vec<(usize, i64, String)>,
    pub nodes: Vec<RawNode>,
    pub node_pos: Vec<usize>,
    pub elements: Vec<RawElement>,
    pub element_nodes: Vec<u64>,
    /// Byte offset of the `$Elements` header.
    pub elements_pos: usize,
    /// (dim, entity tag) -> physical tags (MSH 4.1 `$Entities`).
    entities: HashMap<(i64, i64), Vec<i64>>,
}

/// What an element type is, for gmsh's type numbers.
enum ElementKind {
    /// Accepted: dimension 0, 1 or 2 with 1, 2 or 3 nodes.
    First(usize),
    SecondOrder(&'static str),
    Quad(&'static str),
    Solid(&'static str),
}

fn element_kind(t: i64) -> Option<ElementKind> {
    use ElementKind::*;
    Some(match t {
        15 => First(0),
        1 => First(1),
        2 => First(2),
        8 => SecondOrder("3-node (second-order) line"),
        26 => SecondOrder("4-node (third-order) line"),
        27 => SecondOrder("5-node line"),
        28 => SecondOrder("6-node line"),
        9 => SecondOrder("6-node (second-order) triangle"),
        20 => SecondOrder("9-node (third-order) triangle"),
        21 => SecondOrder("10-node (third-order) triangle"),
        22 => SecondOrder("12-node triangle"),
        23 => SecondOrder("15-node triangle"),
        24 => SecondOrder("15-node (incomplete) triangle"),
        25 => SecondOrder("21-node triangle"),
        3 => Quad("4-node quadrilateral"),
        10 => Quad("9-node quadrilateral"),
        16 => Quad("8-node quadrilateral"),
        36 => Quad("16-node quadrilateral"),
        37 => Quad("25-node quadrilateral"),
        4 => Solid("4-node tetrahedron"),
        5 => Solid("8-node hexahedron"),
        6 => Solid("6-node prism"),
        7 => Solid("5-node pyramid"),
        11 => Solid("10-node tetrahedron"),
        12 => Solid("27-node hexahedron"),
        13 => Solid("18-node prism"),
        14 => Solid("14-node pyramid"),
        17 => Solid("20-node hexahedron"),
        18 => Solid("15-node prism"),
        19 => Solid("13-node pyramid"),
        29 => Solid("20-node tetrahedron"),
        30 => Solid("35-node tetrahedron"),
        31 => Solid("56-node tetrahedron"),
        _ => return None,
    })
}

pub(super) struct Reader<'a> {
    file: &'a str,
    b: &'a [u8],
    pos: usize,
    bin: Option<Bin>,
    section: &'static str,
}

impl<'a> Reader<'a> {
    pub(super) fn err(&self, pos: usize, kind: K) -> MeshError {
        let location = if self.bin.is_some() {
            Location::Byte(pos)
        } else {
            let end = pos.min(self.b.len());
            Location::Line(1 + self.b[..end].iter().filter(|&&c| c == b'\n').count())
        };
        MeshError { file: self.file.to_owned(), location, kind }
    }

    /// The file ended early: points at its end (ASCII: its last non-blank line).
    fn truncated(&self) -> MeshError {
        self.err(self.end_pos(), K::Truncated(self.section.to_owned()))
    }

    fn end_pos(&self) -> usize {
        if self.bin.is_some() {
            return self.b.len();
        }
        self.b.iter().rposition(|c| !c.is_ascii_whitespace()).unwrap_or(0)
    }

    fn malformed(&self, pos: usize, msg: String) -> MeshError {
        self.err(pos, K::Malformed(msg))
    }

    fn skip_ws(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// Next whitespace-delimited ASCII token and its offset.
    fn token(&mut self) -> Result<(usize, &'a [u8]), MeshError> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.b.len() && !self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos { Err(self.truncated()) } else { Ok((start, &self.b[start..self.pos])) }
    }

    fn ascii<T: std::str::FromStr>(&mut self, what: &str) -> Result<(usize, T), MeshError> {
        let (p, t) = self.token()?;
        match std::str::from_utf8(t).ok().and_then(|s| s.parse::<T>().ok()) {
            Some(v) => Ok((p, v)),
            None => Err(self.malformed(
                p,
                format!("expected {what} in {}, found `{}`", self.section, String::from_utf8_lossy(t)),
            )),
        }
    }

    fn bytes(&mut self, n: usize) -> Result<(usize, &'a [u8]), MeshError> {
        let p = self.pos;
        match p.checked_add(n).filter(|&e| e <= self.b.len()) {
            Some(e) => {
                self.pos = e;
                Ok((p, &self.b[p..e]))
            }
            None => Err(self.truncated()),
        }
    }

    fn uint(&self, b: &[u8], big: bool) -> u64 {
        let mut v = 0u64;
        let mut push = |byte: &u8| v = (v << 8) | u64::from(*byte);
        if big {
            b.iter().for_each(&mut push)
        } else {
            b.iter().rev().for_each(&mut push)
        }
        v
    }

    /// A C `int` (binary: 4 bytes).
    fn int(&mut self, what: &str) -> Result<(usize, i64), MeshError> {
        match self.bin {
            None => self.ascii::<i64>(what),
            Some(bin) => {
                let (p, b) = self.bytes(4)?;
                Ok((p, i64::from(self.uint(b, bin.big_endian) as u32 as i32)))
            }
        }
    }

    /// A `size_t` (binary: the header's data size).
    fn size(&mut self, what: &str) -> Result<(usize, u64), MeshError> {
        match self.bin {
            None => self.ascii::<u64>(what),
            Some(bin) => {
                let (p, b) = self.bytes(bin.size_t)?;
                Ok((p, self.uint(b, bin.big_endian)))
            }
        }
    }

    fn double(&mut self, what: &str) -> Result<(usize, f64), MeshError> {
        let (p, v) = match self.bin {
            None => self.ascii::<f64>(what)?,
            Some(bin) => {
                let (p, b) = self.bytes(8)?;
                (p, f64::from_bits(self.uint(b, bin.big_endian)))
            }
        };
        if v.is_finite() { Ok((p, v)) } else { Err(self.malformed(p, format!("{what} is not finite"))) }
    }

    /// After a section header: binary data starts right after its newline.
    fn start_data(&mut self) -> Result<(), MeshError> {
        if self.bin.is_some() {
            let (p, b) = self.bytes(1)?;
            if b != b"\n" {
                return Err(self.malformed(p, format!("expected a newline after {}", self.section)));
            }
        }
        Ok(())
    }

    fn end(&mut self, name: &str) -> Result<(), MeshError> {
        let (p, t) = self.token()?;
        if t == name.as_bytes() {
            Ok(())
        } else {
            Err(self.malformed(
                p,
                format!(
                    "expected {name}, found `{}` (wrong count in {}?)",
                    String::from_utf8_lossy(t),
                    self.section
                ),
            ))
        }
    }

    fn read_all(&mut self) -> Result<Raw, MeshError> {
        let (p, t) = self.token().map_err(|_| self.err(0, K::MissingSection("$MeshFormat")))?;
        if t != b"$MeshFormat" {
            return Err(self.err(p, K::MissingSection("$MeshFormat")));
        }
        let v2 = self.header()?;
        let mut raw = Raw::default();
        let (mut nodes, mut elements) = (false, false);
        loop {
            self.skip_ws();
            if self.pos >= self.b.len() {
                break;
            }
            let (p, t) = self.token()?;
            match t {
                b"$PhysicalNames" => self.physical_names(&mut raw)?,
                b"$Entities" if !v2 => self.entities(&mut raw)?,
                b"$Nodes" if !nodes => {
                    nodes = true;
                    if v2 { self.nodes_v2(&mut raw)? } else { self.nodes_v4(&mut raw)? }
                }
                b"$Elements" if !elements => {
                    elements = true;
                    raw.elements_pos = p;
                    if v2 { self.elements_v2(&mut raw)? } else { self.elements_v4(&mut raw)? }
                }
                _ if t.first() == Some(&b'$') && !t.starts_with(b"$End") => self.skip_section(t)?,
                _ => {
                    let msg = format!("expected a section header, found `{}`", String::from_utf8_lossy(t));
                    return Err(self.malformed(p, msg));
                }
            }
        }
        if !nodes {
            return Err(self.err(self.end_pos(), K::MissingSection("$Nodes")));
        }
        if !elements {
            return Err(self.err(self.end_pos(), K::MissingSection("$Elements")));
        }
        Ok(raw)
    }

    /// `$MeshFormat`: version, file type, data size (and the binary endianness word). Returns
    /// whether the file is MSH 2.2.
    fn header(&mut self) -> Result<bool, MeshError> {
        let (p, version) = self.token()?;
        let version = String::from_utf8_lossy(version).into_owned();
        let (tp, file_type) = self.ascii::<i64>("the file type (0 ASCII, 1 binary)")?;
        let (sp, size_t) = self.ascii::<usize>("the data size")?;
        let v2 = match (version.as_str(), file_type) {
            ("4.1", 0 | 1) => false,
            ("2.2", 0) => true,
            ("2.2", 1) => return Err(self.err(p, K::UnsupportedVersion("2.2 binary".into()))),
            (_, 0 | 1) => return Err(self.err(p, K::UnsupportedVersion(version))),
            _ => return Err(self.malformed(tp, format!("file type must be 0 or 1, found {file_type}"))),
        };
        if size_t != 4 && size_t != 8 {
            return Err(self.malformed(sp, format!("data size must be 4 or 8, found {size_t}")));
        }
        if file_type == 1 {
            self.bin = Some(Bin { size_t, big_endian: false });
            self.start_data()?;
            let (op, one) = self.bytes(4)?;
            let big_endian = match (self.uint(one, false), self.uint(one, true)) {
                (1, _) => false,
                (_, 1) => true,
                _ => return Err(self.malformed(op, "binary endianness word is not 1".into())),
            };
            self.bin = Some(Bin { size_t, big_endian });
        }
        self.end("$EndMeshFormat")?;
        Ok(v2)
    }

    fn skip_section(&mut self, header: &[u8]) -> Result<(), MeshError> {
        let mut end = b"$End".to_vec();
        end.extend_from_slice(&header[1..]);
        let rest = &self.b[self.pos..];
        match rest.windows(end.len()).position(|w| w == end.as_slice()) {
            Some(i) => {
                self.pos += i + end.len();
                Ok(())
            }
            None => Err(self.err(
                self.end_pos(),
                K::Truncated(format!(
                    "{} (no {})",
                    String::from_utf8_lossy(header),
                    String::from_utf8_lossy(&end)
                )),
            )),
        }
    }

    /// `$PhysicalNames` (ASCII in every format): `dim tag "name"` per line.
    fn physical_names(&mut self, raw: &mut Raw) -> Result<(), MeshError> {
        self.section = "$PhysicalNames";
        let (_, n) = self.ascii::<u64>("the number of physical names")?;
        for _ in 0..n {
            let (dp, dim) = self.ascii::<usize>("a physical dimension")?;
            if dim > 3 {
                return Err(self.malformed(dp, format!("physical dimension must be 0 to 3, found {dim}")));
            }
            let (_, tag) = self.ascii::<i64>("a physical tag")?;
            self.skip_ws();
            let (qp, q) = self.bytes(1)?;
            if q != b"\"" {
                return Err(self.malformed(qp, "expected a quoted physical name".into()));
            }
            let start = self.pos;
            let len = self.b[start..].iter().position(|&c| c == b'"' || c == b'\n');
            match len.map(|l| (l, self.b[start + l])) {
                Some((l, b'"')) => {
                    raw.names.push((
                        dim,
                        tag,
                        String::from_utf8_lossy(&self.b[start..start + l]).into_owned(),
                    ));
                    self.pos = start + l + 1;
                }
                Some(_) => return Err(self.malformed(qp, "unterminated physical name".into())),
                None => return Err(self.truncated()),
            }
        }
        self.end("$EndPhysicalNames")
    }

    /// `$Entities` (4.1): the physical tags of each point, curve, surface and volume.
    fn entities(&mut self, raw: &mut Raw) -> Result<(), MeshError> {
        self.section = "$Entities";
        self.start_data()?;
        let mut counts = [0u64; 4];
        for c in &mut counts {
            *c = self.size("an entity count")?.1;
        }
        for (dim, &count) in counts.iter().enumerate() {
            for _ in 0..count {
                let (_, tag) = self.int("an entity tag")?;
                let coords = if dim == 0 { 3 } else { 6 };
                for _ in 0..coords {
                    self.double("an entity bound")?;
                }
                let (_, np) = self.size("a number of physical tags")?;
                let mut phys = Vec::new();
                for _ in 0..np {
                    phys.push(self.int("a physical tag")?.1);
                }
                if dim > 0 {
                    let (_, nb) = self.size("a number of bounding entities")?;
                    for _ in 0..nb {
                        self.int("a bounding entity tag")?;
                    }
                }
                raw.entities.insert((dim as i64, tag), phys);
            }
        }
        self.end("$EndEntities")
    }

    fn push_node(&mut self, raw: &mut Raw, pos: usize, tag: u64, x: f64, y: f64) {
        raw.nodes.push(RawNode { tag, p: Vec2::new(x, y) });
        raw.node_pos.push(pos);
    }

    fn nodes_v2(&mut self, raw: &mut Raw) -> Result<(), MeshError> {
        self.section = "$Nodes";
        let (_, n) = self.ascii::<u64>("the number of nodes")?;
        for _ in 0..n {
            let (p, tag) = self.ascii::<u64>("a node tag")?;
            let (_, x) = self.double("x")?;
            let (_, y) = self.double("y")?;
            self.double("z")?;
            self.push_node(raw, p, tag, x, y);
        }
        self.end("$EndNodes")
    }

    fn nodes_v4(&mut self, raw: &mut Raw) -> Result<(), MeshError> {
        self.section = "$Nodes";
        self.start_data()?;
        let (_, blocks) = self.size("the number of node blocks")?;
        for _ in 0..3 {
            self.size("a node count or tag bound")?;
        }
        for _ in 0..blocks {
            self.int("an entity dimension")?;
            self.int("an entity tag")?;
            let (pp, parametric) = self.int("the parametric flag")?;
            if parametric != 0 {
                return Err(
                    self.malformed(pp, "parametric nodes are not supported (Mesh.SaveParametric = 0)".into())
                );
            }
            let (_, n) = self.size("the number of nodes in the block")?;
            let mut tags = Vec::new();
            for _ in 0..n {
                let (p, tag) = self.size("a node tag")?;
                tags.push((p, tag));
            }
            for &(p, tag) in &tags {
                let (_, x) = self.double("x")?;
                let (_, y) = self.double("y")?;
                self.double("z")?;
                self.push_node(raw, p, tag, x, y);
            }
        }
        self.end("$EndNodes")
    }

    /// Checks an element type; returns its dimension and number of nodes, or the error for it.
    fn kind(&self, pos: usize, tag: u64, t: i64) -> Result<(usize, usize), MeshError> {
        match element_kind(t) {
            Some(ElementKind::First(d)) => Ok((d, d + 1)),
            Some(ElementKind::SecondOrder(what)) => Err(self.err(pos, K::SecondOrder { element: tag, what })),
            Some(ElementKind::Quad(what)) => Err(self.err(pos, K::Quadrilateral { element: tag, what })),
            Some(ElementKind::Solid(what)) => Err(self.err(pos, K::Solid { element: tag, what })),
            None => Err(self.err(pos, K::UnknownElementType(t))),
        }
    }

    fn elements_v2(&mut self, raw: &mut Raw) -> Result<(), MeshError> {
        self.section = "$Elements";
        let (_, n) = self.ascii::<u64>("the number of elements")?;
        for _ in 0..n {
            let (p, tag) = self.ascii::<u64>("an element tag")?;
            let (_, t) = self.ascii::<i64>("an element type")?;
            let (dim, nn) = self.kind(p, tag, t)?;
            let (_, ntags) = self.ascii::<u64>("the number of element tags")?;
            let mut physical = Vec::new();
            for i in 0..ntags {
                let (_, v) = self.ascii::<i64>("an element tag value")?;
                if i == 0 && v != 0 {
                    physical.push(v);
                }
            }
            let first = raw.element_nodes.len();
            for _ in 0..nn {
                raw.element_nodes.push(self.ascii::<u64>("a node tag")?.1);
            }
            raw.elements.push(RawElement { tag, dim, first, physical, pos: p });
        }
        self.end("$EndElements")
    }

    fn elements_v4(&mut self, raw: &mut Raw) -> Result<(), MeshError> {
        self.section = "$Elements";
        self.start_data()?;
        let (_, blocks) = self.size("the number of element blocks")?;
        for _ in 0..3 {
            self.size("an element count or tag bound")?;
        }
        for _ in 0..blocks {
            let (_, edim) = self.int("an entity dimension")?;
            let (_, etag) = self.int("an entity tag")?;
            let (_, t) = self.int("an element type")?;
            let (_, n) = self.size("the number of elements in the block")?;
            let physical = raw.entities.get(&(edim, etag)).cloned().unwrap_or_default();
            for _ in 0..n {
                let (p, tag) = self.size("an element tag")?;
                let (dim, nn) = self.kind(p, tag, t)?;
                let first = raw.element_nodes.len();
                for _ in 0..nn {
                    raw.element_nodes.push(self.size("a node tag")?.1);
                }
                raw.elements.push(RawElement { tag, dim, first, physical: physical.clone(), pos: p });
            }
        }
        self.end("$EndElements")
    }
}
