//! The `.vtu` file itself: VTK XML UnstructuredGrid with its arrays appended as base64.

use super::{CellValues, Grid};
use std::io::Write;

/// One data array of a `.vtu` file: its XML attributes and its values, appended raw.
struct Array<'a> {
    name: &'a str,
    components: usize,
    values: Values<'a>,
}

enum Values<'a> {
    F64(std::borrow::Cow<'a, [f64]>),
    I32(Vec<i32>),
    /// Point ids and offsets: Int32 while every value fits (half the bytes), else Int64.
    Ids(&'a [u64], bool),
    U8(Vec<u8>),
}

impl Values<'_> {
    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I32(_) => "Int32",
            Values::Ids(_, true) => "Int64",
            Values::Ids(_, false) => "Int32",
            Values::U8(_) => "UInt8",
        }
    }

    /// Size of the data in bytes.
    fn bytes(&self) -> usize {
        match self {
            Values::F64(v) => 8 * v.len(),
            Values::I32(v) => 4 * v.len(),
            Values::Ids(v, wide) => (if *wide { 8 } else { 4 }) * v.len(),
            Values::U8(v) => v.len(),
        }
    }

    /// The block of the appended data: its size (UInt64), then its values, little-endian,
    /// base64-encoded together as one stream (padded at the block's end).
    fn write(&self, w: &mut impl Write, buf: &mut Vec<u8>) -> std::io::Result<()> {
        let mut w = base64::write::EncoderWriter::new(w, &base64::engine::general_purpose::STANDARD);
        self.write_raw(&mut w, buf)?;
        w.finish().map(|_| ())
    }

    fn write_raw(&self, w: &mut impl Write, buf: &mut Vec<u8>) -> std::io::Result<()> {
        w.write_all(&(self.bytes() as u64).to_le_bytes())?;
        match self {
            Values::F64(v) => write_le(w, buf, v, |x| x.to_le_bytes()),
            Values::I32(v) => write_le(w, buf, v, |x| x.to_le_bytes()),
            Values::Ids(v, true) => write_le(w, buf, v, |x| (x as i64).to_le_bytes()),
            Values::Ids(v, false) => write_le(w, buf, v, |x| (x as i32).to_le_bytes()),
            Values::U8(v) => w.write_all(v),
        }
    }
}

/// Writes `values` as little-endian bytes, a few thousand at a time through `buf`.
fn write_le<T: Copy, const N: usize>(
    w: &mut impl Write,
    buf: &mut Vec<u8>,
    values: &[T],
    bytes: impl Fn(T) -> [u8; N],
) -> std::io::Result<()> {
    for chunk in values.chunks(4096) {
        buf.clear();
        chunk.iter().for_each(|&x| buf.extend_from_slice(&bytes(x)));
        w.write_all(buf)?;
    }
    Ok(())
}

impl Grid {
    /// Writes the grid as a VTK XML UnstructuredGrid (`.vtu`) with its data appended raw: the
    /// cell data of the module notes, the points' `displacement` once a mesh is added.
    pub fn write_vtu(&self, w: &mut impl Write) -> std::io::Result<()> {
        let c = &self.cells;
        let ints = |f: fn(&CellValues) -> i32| Values::I32(c.iter().map(f).collect());
        let reals = |f: fn(&CellValues) -> f64| Values::F64(c.iter().map(f).collect());
        let triple = |f: fn(&CellValues) -> [f64; 3]| Values::F64(c.iter().flat_map(f).collect());
        let array = |name, components, values| Array { name, components, values };
        let cell = [
            array("body", 1, ints(|v| v.body)),
            array("body_b", 1, ints(|v| v.body_b)),
            array("kind", 1, ints(|v| v.kind)),
            array("state", 1, ints(|v| v.state)),
            array("velocity", 3, triple(|v| [v.velocity[0], v.velocity[1], 0.0])),
            array("angular_velocity", 1, reals(|v| v.angular_velocity)),
            array("rotation", 1, reals(|v| v.rotation)),
            array("stress", 3, triple(|v| v.stress)),
            array("strain", 3, triple(|v| v.strain)),
            array("normal_force", 1, reals(|v| v.normal_force)),
            array("shear_force", 1, reals(|v| v.shear_force)),
            array("axial_force", 1, reals(|v| v.axial_force)),
            array("plastic_strain", 1, reals(|v| v.plastic_strain)),
        ];
        let point: Vec<Array> =
            self.displacement.iter().map(|d| array("displacement", 3, Values::F64(d.into()))).collect();
        let points = [array("Points", 3, Values::F64((&self.points[..]).into()))];
        // every id is below the point count, every offset at most the connectivity's length
        let wide = self.num_points().max(self.connectivity.len()) > i32::MAX as usize;
        let cells = [
            array("connectivity", 1, Values::Ids(&self.connectivity, wide)),
            array("offsets", 1, Values::Ids(&self.offsets, wide)),
            array("types", 1, Values::U8(self.types.iter().map(|&t| t as u8).collect())),
        ];
        let (np, nc) = (self.num_points(), self.num_cells());
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
        )?;
        writeln!(w, "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">")?;
        let mut offset = 0;
        let sections: [(&str, &str, &[Array]); 4] = [
            ("PointData", if point.is_empty() { "" } else { " Vectors=\"displacement\"" }, &point),
            ("CellData", " Scalars=\"body\" Vectors=\"velocity\"", &cell),
            ("Points", "", &points),
            ("Cells", "", &cells),
        ];
        for (tag, active, arrays) in sections {
            writeln!(w, "      <{tag}{active}>")?;
            for a in arrays {
                let (ty, name, n) = (a.values.vtk_type(), a.name, a.components);
                writeln!(
                    w,
                    "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{n}\" format=\"appended\" offset=\"{offset}\"/>"
                )?;
                offset += (8 + a.values.bytes()).div_ceil(3) * 4;
            }
            writeln!(w, "      </{tag}>")?;
        }
        writeln!(w, "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"base64\">")?;
        w.write_all(b"_")?;
        let mut buf = Vec::with_capacity(8 * 4096);
        for (_, _, arrays) in sections {
            for a in arrays {
                a.values.write(w, &mut buf)?;
            }
        }
        writeln!(w, "\n  </AppendedData>\n</VTKFile>")
    }
}
