//! HDF5 + XDMF time series (feature `hdf5`). One `<name>.h5` per method holds a group
//! `step_<k>` per output time with the datasets `points` (n×3), `cauchy_stress` or `piola_stress` (n×9) and
//! `velocity` (n×3) and the attribute `time` (every dataset carries a `units` attribute:
//! `m`, `Pa`, `m/s`; the group's `time_units` is `s`), and one `connectivity` dataset (n×1, the vertex index
//! of each point); `<name>.xdmf` describes them as a temporal collection of poly-vertex
//! grids, each with its own topology item, so the XDMF readers of ParaView (Xdmf3), pyvista
//! and meshio (`meshio.xdmf.TimeSeriesReader`, which wants a `DataItem` under every
//! `Topology`) all read it.
//!
//! The grid ([`TimeSeries::write_grid`]: the Eulerian cells of DGMPM and MPM, the FEM
//! mesh deformed by its displacement) goes into the same groups as `grid_points` (v×3),
//! `grid_<stress>` (c×9, per cell), `grid_velocity` (c×3, per cell), for FEM
//! `grid_nodal_velocity` (v×3), with one `grid_connectivity` (c×k, the cell's vertices in
//! VTK order, which is XDMF's: `Polyline` of 2 in 1D, `Quadrilateral` in 2D,
//! `Hexahedron` in 3D); `<name>_grid.xdmf` describes them as a second temporal collection
//! (a file of its own: meshio's reader takes one collection per file). The points are
//! written at every step because the FEM mesh moves; the connectivity once.
//! The `.h5` is written under a temporary name and renamed by [`TimeSeries::finish`].
use crate::{write_atomic, IoError};
use hdf5::types::VarLenUnicode;
use std::path::{Path, PathBuf};

/// An HDF5 time series being written.
pub struct TimeSeries {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<hdf5::File>,
    steps: Vec<(f64, usize)>,
    stress_name: &'static str,
    /// The grid's shape once [`TimeSeries::write_grid`] has run, and the steps that carry it.
    grid: Option<GridShape>,
    grid_steps: Vec<usize>,
}

/// What the grid collection's XDMF needs to know.
#[derive(Debug, Clone, Copy, PartialEq)]
struct GridShape {
    vertices: usize,
    cells: usize,
    nodes_per_cell: usize,
    nodal_velocity: bool,
}

impl GridShape {
    /// The XDMF topology of a cell with `nodes_per_cell` vertices in VTK order.
    fn topology(&self) -> &'static str {
        match self.nodes_per_cell {
            2 => "Polyline",
            4 => "Quadrilateral",
            _ => "Hexahedron",
        }
    }
}

/// The grid of one output time: points (v×3), connectivity (c×k, VTK order), per-cell
/// stress (c×9) and velocity (c×3), optional nodal velocity (v×3).
pub struct GridFrame<'a> {
    /// Vertex positions, row-major v×3.
    pub points: &'a [f64],
    /// Each cell's vertices in VTK order, row-major c×`nodes_per_cell`.
    pub connectivity: &'a [usize],
    /// Vertices per cell: 2, 4 or 8.
    pub nodes_per_cell: usize,
    /// Cell-averaged stress, row-major c×9.
    pub cell_stress: &'a [f64],
    /// Cell-averaged velocity, row-major c×3.
    pub cell_velocity: &'a [f64],
    /// Nodal velocity (v×3; empty when the method has none on its grid).
    pub nodal_velocity: &'a [f64],
}

fn h5_error(path: &Path) -> impl Fn(hdf5::Error) -> IoError + '_ {
    move |e| IoError::Serialise {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Attach the string attribute `name` (`units`, `time_units`) to a dataset or group.
fn set_units(location: &hdf5::Location, name: &str, units: &str) -> hdf5::Result<()> {
    let value: VarLenUnicode = units
        .parse()
        .map_err(|e| hdf5::Error::from(format!("units {units:?}: {e}")))?;
    location
        .new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&value)
}

impl TimeSeries {
    /// Start a series at `path` (`.h5`) whose stress dataset is named `stress_name`
    /// (`cauchy_stress` or `piola_stress`).
    pub fn create(path: &Path, stress_name: &'static str) -> Result<Self, IoError> {
        let tmp = crate::temporary_path(path);
        let file = hdf5::File::create(&tmp).map_err(h5_error(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            file: Some(file),
            steps: Vec::new(),
            stress_name,
            grid: None,
            grid_steps: Vec::new(),
        })
    }

    /// Append one output time: `points` (n×3), `stress` (n×9), `velocity` (n×3), row-major.
    pub fn write_step(
        &mut self,
        t: f64,
        points: &[f64],
        stress: &[f64],
        velocity: &[f64],
    ) -> Result<(), IoError> {
        let n = points.len() / 3;
        let file = self.file.as_ref().expect("internal: series not finished");
        let err = h5_error(&self.path);
        if self.steps.is_empty() {
            let connectivity: Vec<i64> = (0..n as i64).collect();
            file.new_dataset::<i64>()
                .shape([n, 1])
                .create("connectivity")
                .and_then(|ds| ds.write_raw(&connectivity))
                .map_err(&err)?;
        }
        let group = file
            .create_group(&format!("step_{}", self.steps.len()))
            .map_err(&err)?;
        for (name, data, cols, units) in [
            ("points", points, 3, "m"),
            (self.stress_name, stress, 9, "Pa"),
            ("velocity", velocity, 3, "m/s"),
        ] {
            let ds = group
                .new_dataset::<f64>()
                .shape([n, cols])
                .create(name)
                .map_err(&err)?;
            ds.write_raw(data).map_err(&err)?;
            set_units(&ds, "units", units).map_err(&err)?;
        }
        let time = group.new_attr::<f64>().create("time").map_err(&err)?;
        time.write_scalar(&t).map_err(&err)?;
        set_units(&group, "time_units", "s").map_err(&err)?;
        self.steps.push((t, n));
        Ok(())
    }

    /// Add the grid to the last step written by [`TimeSeries::write_step`] (module doc).
    /// The grid's shape must be the same at every step.
    pub fn write_grid(&mut self, frame: &GridFrame) -> Result<(), IoError> {
        let err = h5_error(&self.path);
        let shape = GridShape {
            vertices: frame.points.len() / 3,
            cells: frame.cell_velocity.len() / 3,
            nodes_per_cell: frame.nodes_per_cell,
            nodal_velocity: !frame.nodal_velocity.is_empty(),
        };
        let serialise = |message: String| IoError::Serialise {
            path: self.path.clone(),
            message,
        };
        let Some(k) = self.steps.len().checked_sub(1) else {
            return Err(serialise("a grid frame before any step".into()));
        };
        if self.grid_steps.last() == Some(&k) {
            return Err(serialise(format!("step {k} already has its grid")));
        }
        let file = self.file.as_ref().expect("internal: series not finished");
        match self.grid {
            None => {
                let connectivity: Vec<i64> = frame.connectivity.iter().map(|&v| v as i64).collect();
                file.new_dataset::<i64>()
                    .shape([shape.cells, shape.nodes_per_cell])
                    .create("grid_connectivity")
                    .and_then(|ds| ds.write_raw(&connectivity))
                    .map_err(&err)?;
                self.grid = Some(shape);
            }
            Some(first) if first != shape => {
                return Err(serialise(format!(
                    "grid of step {k} has {} vertices and {} cells, the first had {} and {}",
                    shape.vertices, shape.cells, first.vertices, first.cells
                )))
            }
            Some(_) => {}
        }
        let group = file.group(&format!("step_{k}")).map_err(&err)?;
        let stress = format!("grid_{}", self.stress_name);
        let mut arrays = vec![
            ("grid_points", frame.points, shape.vertices, 3, "m"),
            (stress.as_str(), frame.cell_stress, shape.cells, 9, "Pa"),
            ("grid_velocity", frame.cell_velocity, shape.cells, 3, "m/s"),
        ];
        if shape.nodal_velocity {
            arrays.push((
                "grid_nodal_velocity",
                frame.nodal_velocity,
                shape.vertices,
                3,
                "m/s",
            ));
        }
        for (name, data, rows, cols, units) in arrays {
            let ds = group
                .new_dataset::<f64>()
                .shape([rows, cols])
                .create(name)
                .map_err(&err)?;
            ds.write_raw(data).map_err(&err)?;
            set_units(&ds, "units", units).map_err(&err)?;
        }
        self.grid_steps.push(k);
        Ok(())
    }

    /// Close the file, rename it into place and write the `.xdmf` beside it.
    pub fn finish(mut self) -> Result<(), IoError> {
        if let Some(f) = self.file.take() {
            f.close().map_err(h5_error(&self.path))?;
        }
        std::fs::rename(&self.tmp, &self.path).map_err(|source| IoError::File {
            path: self.path.clone(),
            source,
        })?;
        let h5_name = self
            .path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let xdmf = self.path.with_extension("xdmf");
        write_atomic(&xdmf, |w| {
            writeln!(w, "<?xml version=\"1.0\"?>")?;
            writeln!(w, "<Xdmf Version=\"3.0\">\n  <Domain>")?;
            writeln!(
                w,
                "    <Grid Name=\"series\" GridType=\"Collection\" CollectionType=\"Temporal\">"
            )?;
            for (k, (t, n)) in self.steps.iter().enumerate() {
                let item = |name: &str, cols: usize| {
                    format!(
                        "<DataItem Dimensions=\"{n} {cols}\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{h5_name}:/step_{k}/{name}</DataItem>"
                    )
                };
                writeln!(w, "      <Grid Name=\"step_{k}\" GridType=\"Uniform\">")?;
                writeln!(w, "        <Time Value=\"{t:.17e}\"/>")?;
                writeln!(w, "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{n}\" NodesPerElement=\"1\">")?;
                writeln!(w, "          <DataItem Dimensions=\"{n} 1\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">{h5_name}:/connectivity</DataItem>")?;
                writeln!(w, "        </Topology>")?;
                writeln!(
                    w,
                    "        <Geometry GeometryType=\"XYZ\">{}</Geometry>",
                    item("points", 3)
                )?;
                let stress = self.stress_name;
                writeln!(w, "        <Attribute Name=\"{stress}\" AttributeType=\"Tensor\" Center=\"Node\">{}</Attribute>", item(stress, 9))?;
                writeln!(w, "        <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">{}</Attribute>", item("velocity", 3))?;
                writeln!(w, "      </Grid>")?;
            }
            writeln!(w, "    </Grid>\n  </Domain>\n</Xdmf>")
        })?;
        match self.grid {
            Some(shape) => self.write_grid_xdmf(&h5_name, shape),
            None => Ok(()),
        }
    }

    /// `<name>_grid.xdmf`: the grid of every step that has one (module doc).
    fn write_grid_xdmf(&self, h5_name: &str, shape: GridShape) -> Result<(), IoError> {
        let stem = self.path.file_stem().unwrap_or_default().to_string_lossy();
        let xdmf = self.path.with_file_name(format!("{stem}_grid.xdmf"));
        let GridShape {
            vertices,
            cells,
            nodes_per_cell,
            nodal_velocity,
        } = shape;
        write_atomic(&xdmf, |w| {
            writeln!(w, "<?xml version=\"1.0\"?>")?;
            writeln!(w, "<Xdmf Version=\"3.0\">\n  <Domain>")?;
            writeln!(
                w,
                "    <Grid Name=\"grid\" GridType=\"Collection\" CollectionType=\"Temporal\">"
            )?;
            for &k in &self.grid_steps {
                let t = self.steps[k].0;
                let item = |name: &str, rows: usize, cols: usize| {
                    format!(
                        "<DataItem Dimensions=\"{rows} {cols}\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{h5_name}:/step_{k}/{name}</DataItem>"
                    )
                };
                writeln!(w, "      <Grid Name=\"grid_{k}\" GridType=\"Uniform\">")?;
                writeln!(w, "        <Time Value=\"{t:.17e}\"/>")?;
                writeln!(
                    w,
                    "        <Topology TopologyType=\"{}\" NumberOfElements=\"{cells}\" NodesPerElement=\"{nodes_per_cell}\">",
                    shape.topology()
                )?;
                writeln!(w, "          <DataItem Dimensions=\"{cells} {nodes_per_cell}\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">{h5_name}:/grid_connectivity</DataItem>")?;
                writeln!(w, "        </Topology>")?;
                writeln!(
                    w,
                    "        <Geometry GeometryType=\"XYZ\">{}</Geometry>",
                    item("grid_points", vertices, 3)
                )?;
                let stress = format!("grid_{}", self.stress_name);
                writeln!(w, "        <Attribute Name=\"{}\" AttributeType=\"Tensor\" Center=\"Cell\">{}</Attribute>", self.stress_name, item(&stress, cells, 9))?;
                writeln!(w, "        <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Cell\">{}</Attribute>", item("grid_velocity", cells, 3))?;
                if nodal_velocity {
                    writeln!(w, "        <Attribute Name=\"nodal_velocity\" AttributeType=\"Vector\" Center=\"Node\">{}</Attribute>", item("grid_nodal_velocity", vertices, 3))?;
                }
                writeln!(w, "      </Grid>")?;
            }
            writeln!(w, "    </Grid>\n  </Domain>\n</Xdmf>")
        })
    }
}
