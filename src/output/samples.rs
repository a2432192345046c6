//! The samples frames: the samples as VTK vertices (one `.vtu`, or this rank's piece,
//! [`super::pieces`]) and the `.h5` series of the `hdf5` feature.
use super::fields::{pad3, reference_names};
use super::FileWriter;
#[cfg(feature = "hdf5")]
use super::INITIAL;
use anyhow::Context;
use impact_io::vtu::{write_vtu, CellType, DataArray, UnstructuredGrid};
use std::path::Path;

impl<const D: usize> FileWriter<'_, D> {
    /// The samples as VTK vertices, in `<method>_<frame>.vtu` (and the `.h5` series at
    /// output times).
    pub(super) fn write_samples(&mut self, frame: &str, t: f64) -> anyhow::Result<()> {
        let file = format!("{}_{frame}.vtu", self.method);
        let reference_solution = self.reference_at_samples(frame, t);
        self.write_sample_vtu(&self.dir.join(&file), frame, t, reference_solution, true)?;
        self.pvd.push((t, file));
        Ok(())
    }

    /// `self.samples` as VTK vertices into `path`, with the reference solution at the
    /// samples where given, and into the `.h5` series when `h5`; the point arrays written
    /// (name, components), for a `.pvtu`.
    pub(super) fn write_sample_vtu(
        &mut self,
        path: &Path,
        frame: &str,
        t: f64,
        reference_solution: Option<(Vec<f64>, Vec<f64>)>,
        h5: bool,
    ) -> anyhow::Result<Vec<(String, usize)>> {
        let s = &self.samples;
        let n = s.len();
        let points: Vec<f64> = s.position.iter().flat_map(pad3).collect();
        let reference_position: Vec<f64> = s.reference.iter().flat_map(pad3).collect();
        let (reference_stress_name, reference_velocity_name) =
            reference_names(self.measure.array_name(), self.line.axis);
        let stress: Vec<f64> = (0..n).flat_map(|i| self.full_stress(i)).collect();
        let velocity: Vec<f64> = s.velocity.iter().flat_map(pad3).collect();
        let connectivity: Vec<usize> = (0..n).collect();
        let file = path
            .file_name()
            .map_or(String::new(), |f| f.display().to_string());
        let grid = UnstructuredGrid {
            points: &points,
            connectivity: &connectivity,
            nodes_per_cell: 1,
            cell_type: CellType::Vertex,
            point_data: vec![
                DataArray {
                    name: self.measure.array_name(),
                    components: 9,
                    values: &stress,
                    units: "Pa",
                },
                DataArray {
                    name: "velocity",
                    components: 3,
                    values: &velocity,
                    units: "m/s",
                },
                DataArray {
                    name: "reference_position",
                    components: 3,
                    values: &reference_position,
                    units: "m",
                },
            ]
            .into_iter()
            .chain(reference_solution.iter().flat_map(|(stress, velocity)| {
                [
                    DataArray {
                        name: &reference_stress_name,
                        components: 1,
                        values: stress,
                        units: "Pa",
                    },
                    DataArray {
                        name: &reference_velocity_name,
                        components: 1,
                        values: velocity,
                        units: "m/s",
                    },
                ]
            }))
            .chain((!s.plastic_strain.is_empty()).then_some(DataArray {
                name: "equivalent_plastic_strain",
                components: 1,
                values: &s.plastic_strain,
                units: "1",
            }))
            .collect(),
            cell_data: vec![],
            time: Some(t),
        };
        let arrays = grid
            .point_data
            .iter()
            .map(|a| (a.name.to_string(), a.components))
            .collect();
        write_vtu(path, &grid, self.encoding).with_context(|| format!("writing {file}"))?;
        if h5 {
            self.write_h5(frame, t, &points, &stress, &velocity)?;
        }
        Ok(arrays)
    }

    /// One output time of the `.h5` series (feature `hdf5`; nothing at the initial frame).
    #[cfg_attr(not(feature = "hdf5"), allow(clippy::unused_self, unused_variables))]
    pub(super) fn write_h5(
        &mut self,
        frame: &str,
        t: f64,
        points: &[f64],
        stress: &[f64],
        velocity: &[f64],
    ) -> anyhow::Result<()> {
        #[cfg(feature = "hdf5")]
        if frame != INITIAL {
            if self.h5.is_none() {
                // on several ranks one series per rank, of its own samples ([`super::pieces`])
                let path = match &self.pieces {
                    Some(p) => p.dir.join(format!("{}_r{}.h5", self.method, p.rank)),
                    None => self.dir.join(format!("{}.h5", self.method)),
                };
                let name = self.measure.array_name();
                self.h5 = Some(impact_io::h5::TimeSeries::create(&path, name)?);
            }
            if let Some(series) = self.h5.as_mut() {
                series.write_step(t, points, stress, velocity)?;
            }
        }
        Ok(())
    }
}
