//! HDF5 + XDMF time series (feature `hdf5`). One `<name>.h5` per method holds a group
//! `step_<k>` per output time with the datasets `points` (n×3), `cauchy_stress` or `piola_stress` (n×9) and
//! `velocity` (n×3) and the attribute `time` (every dataset carries a `units` attribute:
//! `m`, `Pa`, `m/s`; the group's `time_units` is `s`), and one `connectivity` dataset (n×1, the vertex index
//! of each point); `<name>.xdmf` describes them as a temporal collection of poly-vertex
//! grids, each with its own topology item, so the XDMF readers of ParaView (Xdmf3), pyvista
//! and meshio (`meshio.xdmf.TimeSeriesReader`, which wants a `DataItem` under every
//! `Topology`) all read it.
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
        })
    }
}
