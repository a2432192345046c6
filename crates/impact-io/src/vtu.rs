//! VTK XML unstructured grids (`.vtu`) and ParaView collections (`.pvd`), readable by
//! ParaView, pyvista and meshio.
//!
//! Two encodings ([`VtuEncoding`]):
//! - `binary` (the default): every data array is zlib-compressed little-endian binary in
//!   one raw `<AppendedData encoding="raw">` section (`format="appended"` with each array's
//!   byte `offset`, `compressor="vtkZLibDataCompressor"`, `header_type="UInt64"`), the
//!   layout VTK's own writer uses: per array the header `[blocks, block size, last partial
//!   block size (0 if full), compressed size of each block]`, then the compressed blocks
//!   (VTK file-format documentation, "Compressed data" and "AppendedData"). Blocks hold
//!   32 KiB of raw data. Raw rather than base64 saves a quarter of the size; zlib's fastest
//!   level, since level 6 wrote a plate frame 4× slower (slower than ASCII) for files only
//!   6 % smaller (`impact bench output`, BENCHMARKS.md).
//! - `ascii`: decimal text with 13 significant digits, for reading by eye.
//!
//! Every file carries `TimeValue` as field data when a time is given, and every data array
//! a `units` attribute (an XML attribute the VTK readers ignore, read by hand or with any
//! XML parser).
use crate::{write_atomic, IoError};
use std::io::Write;
use std::path::Path;

/// VTK cell types used here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellType {
    /// A single point (material points).
    Vertex = 1,
    /// 2-node line (1D elements and cells).
    Line = 3,
    /// 4-node quadrilateral, counter-clockwise (2D elements and cells).
    Quad = 9,
    /// 8-node hexahedron: the bottom face counter-clockwise, then the top face (3D).
    Hexahedron = 12,
}

/// How the arrays of a `.vtu` are encoded (`--vtu`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum VtuEncoding {
    /// zlib-compressed binary, appended raw (module doc).
    #[default]
    Binary,
    /// Decimal text.
    Ascii,
}

/// A data array: name, number of components, values (`len = n · components`), units.
#[derive(Debug, Clone)]
pub struct DataArray<'a> {
    /// Array name.
    pub name: &'a str,
    /// Components per entry.
    pub components: usize,
    /// Values, entry-major.
    pub values: &'a [f64],
    /// Physical units (`"Pa"`, `"m/s"`, `"m"`, `"1"` for dimensionless).
    pub units: &'a str,
}

/// An unstructured grid: 3D point coordinates, cells as connectivity lists of one type.
#[derive(Debug, Clone)]
pub struct UnstructuredGrid<'a> {
    /// Point coordinates, `3 · n_points` (m).
    pub points: &'a [f64],
    /// Connectivity, `nodes_per_cell · n_cells`.
    pub connectivity: &'a [usize],
    /// Nodes per cell.
    pub nodes_per_cell: usize,
    /// Cell type.
    pub cell_type: CellType,
    /// Point data.
    pub point_data: Vec<DataArray<'a>>,
    /// Cell data.
    pub cell_data: Vec<DataArray<'a>>,
    /// Physical time of this frame (s), written as the field `TimeValue`.
    pub time: Option<f64>,
}

/// Raw little-endian bytes of a typed array.
trait Bytes: Copy {
    const VTK_TYPE: &'static str;
    fn extend_bytes(self, out: &mut Vec<u8>);
    fn text(self) -> String;
}
impl Bytes for f64 {
    const VTK_TYPE: &'static str = "Float64";
    fn extend_bytes(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
    fn text(self) -> String {
        format!("{self:.12e}")
    }
}
impl Bytes for i64 {
    const VTK_TYPE: &'static str = "Int64";
    fn extend_bytes(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
    fn text(self) -> String {
        self.to_string()
    }
}
impl Bytes for u8 {
    const VTK_TYPE: &'static str = "UInt8";
    fn extend_bytes(self, out: &mut Vec<u8>) {
        out.push(self);
    }
    fn text(self) -> String {
        self.to_string()
    }
}

/// Bytes of raw data per compressed block (VTK's default).
const BLOCK: usize = 1 << 15;

/// The `binary` payload of one array (module doc): the UInt64 header, then the compressed
/// blocks.
fn compressed_payload(raw: &[u8]) -> std::io::Result<Vec<u8>> {
    use flate2::{write::ZlibEncoder, Compression};
    let blocks: Vec<&[u8]> = raw.chunks(BLOCK).collect();
    let mut header: Vec<u64> = vec![
        blocks.len() as u64,
        BLOCK as u64,
        (raw.len() % BLOCK) as u64,
    ];
    let mut body = Vec::with_capacity(raw.len() / 4);
    for block in &blocks {
        let mut encoder =
            ZlibEncoder::new(Vec::with_capacity(block.len() / 4), Compression::fast());
        encoder.write_all(block)?;
        let compressed = encoder.finish()?;
        header.push(compressed.len() as u64);
        body.extend_from_slice(&compressed);
    }
    let mut payload: Vec<u8> = header.iter().flat_map(|h| h.to_le_bytes()).collect();
    payload.extend_from_slice(&body);
    Ok(payload)
}

/// Writes `<DataArray>` elements: inline text (`ascii`), or a reference into the appended
/// section that it fills (`binary`).
struct Arrays {
    encoding: VtuEncoding,
    appended: Vec<u8>,
}

impl Arrays {
    /// Write one `<DataArray>` of `values` (as `T`) with `components` per entry.
    fn write<T: Bytes>(
        &mut self,
        w: &mut dyn Write,
        name: &str,
        components: usize,
        units: Option<&str>,
        values: impl ExactSizeIterator<Item = T>,
    ) -> std::io::Result<()> {
        let units = units.map_or(String::new(), |u| format!(" units=\"{u}\""));
        let head = format!(
            "        <DataArray type=\"{}\" Name=\"{name}\" NumberOfComponents=\"{components}\"",
            T::VTK_TYPE
        );
        match self.encoding {
            VtuEncoding::Binary => {
                let mut raw = Vec::with_capacity(values.len() * std::mem::size_of::<T>());
                values.for_each(|v| v.extend_bytes(&mut raw));
                let offset = self.appended.len();
                self.appended.extend_from_slice(&compressed_payload(&raw)?);
                writeln!(w, "{head} format=\"appended\" offset=\"{offset}\"{units}/>")
            }
            VtuEncoding::Ascii => {
                writeln!(w, "{head} format=\"ascii\"{units}>")?;
                let per_line = components.max(1) * 4;
                let mut line = Vec::with_capacity(per_line);
                for v in values {
                    line.push(v.text());
                    if line.len() == per_line {
                        writeln!(w, "          {}", line.join(" "))?;
                        line.clear();
                    }
                }
                if !line.is_empty() {
                    writeln!(w, "          {}", line.join(" "))?;
                }
                writeln!(w, "        </DataArray>")
            }
        }
    }
}

/// Write `grid` to `path` (atomically) in `encoding`.
pub fn write_vtu(
    path: &Path,
    grid: &UnstructuredGrid,
    encoding: VtuEncoding,
) -> Result<(), IoError> {
    let n_points = grid.points.len() / 3;
    let per_cell = grid.nodes_per_cell.max(1);
    let n_cells = grid.connectivity.len() / per_cell;
    let compressor = match encoding {
        VtuEncoding::Binary => " header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        VtuEncoding::Ascii => "",
    };
    write_atomic(path, |w| {
        let mut arrays = Arrays {
            encoding,
            appended: Vec::new(),
        };
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\"{compressor}>"
        )?;
        writeln!(w, "  <UnstructuredGrid>")?;
        if let Some(t) = grid.time {
            writeln!(w, "    <FieldData>")?;
            writeln!(
                w,
                "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
                 format=\"ascii\" units=\"s\">{t:.17e}</DataArray>"
            )?;
            writeln!(w, "    </FieldData>")?;
        }
        writeln!(
            w,
            "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
        )?;
        writeln!(w, "      <Points>")?;
        arrays.write(w, "Points", 3, Some("m"), grid.points.iter().copied())?;
        writeln!(w, "      </Points>")?;
        writeln!(w, "      <Cells>")?;
        let connectivity = grid.connectivity.iter().map(|&v| v as i64);
        arrays.write(w, "connectivity", 1, None, connectivity)?;
        let offsets = (0..n_cells).map(|c| ((c + 1) * per_cell) as i64);
        arrays.write(w, "offsets", 1, None, offsets)?;
        let types = std::iter::repeat_n(grid.cell_type as u8, n_cells);
        arrays.write(w, "types", 1, None, types)?;
        writeln!(w, "      </Cells>")?;
        for (tag, data) in [
            ("PointData", &grid.point_data),
            ("CellData", &grid.cell_data),
        ] {
            writeln!(w, "      <{tag}>")?;
            for a in data {
                let values = a.values.iter().copied();
                arrays.write(w, a.name, a.components, Some(a.units), values)?;
            }
            writeln!(w, "      </{tag}>")?;
        }
        writeln!(w, "    </Piece>")?;
        writeln!(w, "  </UnstructuredGrid>")?;
        if encoding == VtuEncoding::Binary {
            write!(w, "  <AppendedData encoding=\"raw\">\n   _")?;
            w.write_all(&arrays.appended)?;
            writeln!(w, "\n  </AppendedData>")?;
        }
        writeln!(w, "</VTKFile>")
    })
}

/// Write a ParaView collection (`.pvd`) listing `(time, file)` pairs.
pub fn write_pvd(path: &Path, entries: &[(f64, String)]) -> Result<(), IoError> {
    write_atomic(path, |w| {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(w, "<VTKFile type=\"Collection\" version=\"0.1\">")?;
        writeln!(w, "  <Collection>")?;
        for (t, file) in entries {
            writeln!(w, "    <DataSet timestep=\"{t:.12e}\" file=\"{file}\"/>")?;
        }
        writeln!(w, "  </Collection>")?;
        writeln!(w, "</VTKFile>")
    })
}

/// A parallel unstructured grid (`.pvtu`): the pieces `pieces` (file names relative to the
/// `.pvtu`) that together form one frame, each a `.vtu` of [`write_vtu`] with the point
/// arrays `point_arrays` (name, components; every array `Float64`) and no cell data. The
/// pieces are listed in order, so a reader's concatenation of their points and arrays is
/// in that order (pyvista's `read`, meshio's `read` of each piece, ParaView).
pub fn write_pvtu(
    path: &Path,
    point_arrays: &[(&str, usize)],
    pieces: &[String],
    encoding: VtuEncoding,
) -> Result<(), IoError> {
    write_pvtu_with_cells(path, point_arrays, &[], pieces, encoding)
}

/// [`write_pvtu`] with the cell arrays `cell_arrays` (name, components; `Float64`) too: the
/// pieces of a grid split over ranks (no `PCellData` where `cell_arrays` is empty, so
/// [`write_pvtu`]'s files are unchanged).
pub fn write_pvtu_with_cells(
    path: &Path,
    point_arrays: &[(&str, usize)],
    cell_arrays: &[(&str, usize)],
    pieces: &[String],
    encoding: VtuEncoding,
) -> Result<(), IoError> {
    let compressor = match encoding {
        VtuEncoding::Binary => " header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
        VtuEncoding::Ascii => "",
    };
    write_atomic(path, |w| {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\"{compressor}>"
        )?;
        writeln!(w, "  <PUnstructuredGrid GhostLevel=\"0\">")?;
        // (no `PCellData` without cell arrays: the samples' `.pvtu` as before)
        for (tag, arrays) in [("PPointData", point_arrays), ("PCellData", cell_arrays)] {
            if tag == "PCellData" && arrays.is_empty() {
                continue;
            }
            writeln!(w, "    <{tag}>")?;
            for (name, components) in arrays {
                writeln!(
                    w,
                    "      <PDataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{components}\"/>"
                )?;
            }
            writeln!(w, "    </{tag}>")?;
        }
        writeln!(w, "    <PPoints>")?;
        writeln!(
            w,
            "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>"
        )?;
        writeln!(w, "    </PPoints>")?;
        for piece in pieces {
            writeln!(w, "    <Piece Source=\"{piece}\"/>")?;
        }
        writeln!(w, "  </PUnstructuredGrid>")?;
        writeln!(w, "</VTKFile>")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// Decode one `binary` payload back to its raw bytes (the inverse of
    /// [`compressed_payload`], as VTK's reader does it).
    fn decode(payload: &[u8]) -> Vec<u8> {
        let word = |k: usize| u64::from_le_bytes(payload[8 * k..8 * k + 8].try_into().unwrap());
        let blocks = word(0) as usize;
        let mut at = (3 + blocks) * 8;
        let mut out = Vec::new();
        for k in 0..blocks {
            let size = word(3 + k) as usize;
            let mut decoder = flate2::read::ZlibDecoder::new(&payload[at..at + size]);
            decoder.read_to_end(&mut out).unwrap();
            at += size;
        }
        assert_eq!(at, payload.len());
        out
    }

    #[test]
    fn compressed_arrays_decode_to_the_same_bits() {
        // several blocks, a partial last one, values that do not compress to nothing
        let values: Vec<f64> = (0..10_000).map(|i| (i as f64 * 0.37).sin() * 1e8).collect();
        let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let payload = compressed_payload(&raw).unwrap();
        let back: Vec<f64> = decode(&payload)
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(back.len(), values.len());
        assert!(back
            .iter()
            .zip(&values)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(decode(&compressed_payload(&[]).unwrap()), Vec::<u8>::new());
    }
}
