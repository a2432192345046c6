//! VTK XML unstructured grids (`.vtu`, ASCII), readable by ParaView, pyvista and meshio.
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
}

/// A data array: name, number of components, values (`len = n · components`).
#[derive(Debug, Clone)]
pub struct DataArray<'a> {
    /// Array name.
    pub name: &'a str,
    /// Components per entry.
    pub components: usize,
    /// Values, entry-major.
    pub values: &'a [f64],
}

/// An unstructured grid: 3D point coordinates, cells as connectivity lists of one type.
#[derive(Debug, Clone)]
pub struct UnstructuredGrid<'a> {
    /// Point coordinates, `3 · n_points`.
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
}

fn write_array(w: &mut dyn Write, a: &DataArray) -> std::io::Result<()> {
    writeln!(
        w,
        "        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">",
        a.name, a.components
    )?;
    for chunk in a.values.chunks(a.components.max(1) * 4) {
        let line: Vec<String> = chunk.iter().map(|v| format!("{v:.12e}")).collect();
        writeln!(w, "          {}", line.join(" "))?;
    }
    writeln!(w, "        </DataArray>")
}

/// Write `grid` to `path` (atomically).
pub fn write_vtu(path: &Path, grid: &UnstructuredGrid) -> Result<(), IoError> {
    let n_points = grid.points.len() / 3;
    let n_cells = grid.connectivity.len() / grid.nodes_per_cell.max(1);
    write_atomic(path, |w| {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
        )?;
        writeln!(w, "  <UnstructuredGrid>")?;
        writeln!(
            w,
            "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
        )?;
        writeln!(w, "      <Points>")?;
        write_array(
            w,
            &DataArray {
                name: "Points",
                components: 3,
                values: grid.points,
            },
        )?;
        writeln!(w, "      </Points>")?;
        writeln!(w, "      <Cells>")?;
        writeln!(
            w,
            "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
        )?;
        for cell in grid.connectivity.chunks(grid.nodes_per_cell.max(1)) {
            let line: Vec<String> = cell.iter().map(|v| v.to_string()).collect();
            writeln!(w, "          {}", line.join(" "))?;
        }
        writeln!(w, "        </DataArray>")?;
        writeln!(
            w,
            "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
        )?;
        for c in 0..n_cells {
            writeln!(w, "          {}", (c + 1) * grid.nodes_per_cell)?;
        }
        writeln!(w, "        </DataArray>")?;
        writeln!(
            w,
            "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
        )?;
        for _ in 0..n_cells {
            writeln!(w, "          {}", grid.cell_type as u8)?;
        }
        writeln!(w, "        </DataArray>")?;
        writeln!(w, "      </Cells>")?;
        writeln!(w, "      <PointData>")?;
        for a in &grid.point_data {
            write_array(w, a)?;
        }
        writeln!(w, "      </PointData>")?;
        writeln!(w, "      <CellData>")?;
        for a in &grid.cell_data {
            write_array(w, a)?;
        }
        writeln!(w, "      </CellData>")?;
        writeln!(w, "    </Piece>")?;
        writeln!(w, "  </UnstructuredGrid>")?;
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
