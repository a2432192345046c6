//! The grid file of an output frame ([`super::FileWriter`]): on one rank the whole grid as
//! one `.vtu`, each cell with the average of its samples (DGMPM, MPM: the Eulerian grid) or
//! the FEM mesh deformed by the nodal displacement with the nodal velocity; on several
//! ranks one piece per rank, every method's ([`super::grid_pieces`]: nothing gathered but
//! the figures' map plane, to rank 0).
//! Both write their arrays through [`FileWriter::write_grid_arrays`] (`.vtu`, and the
//! `.h5` series with the `hdf5` feature).
use super::fields::{pad3, tensor9, vtk_order, with_zz};
use super::{FileWriter, INITIAL};
use anyhow::Context;
use impact_core::{Grid, Method, Tensor, Vector};
use impact_io::vtu::{write_vtu, DataArray, UnstructuredGrid};
use std::path::Path;

impl<const D: usize> FileWriter<'_, D> {
    /// The grid cells with the averages of their samples (DGMPM, MPM: the Eulerian grid),
    /// or the FEM mesh with nodal velocity and element stress (deformed by `u`): σ_xx kept
    /// for the maps at output times, the `.vtu` written when files are.
    fn grid(&mut self, method: &dyn Method<D>, frame: &str, t: f64) -> anyhow::Result<()> {
        let g = &self.grid;
        let s = &self.samples;
        let cells = g.cell_count();
        let mut stress = vec![impact_core::Tensor::<D>::zeros(); cells];
        let mut velocity = vec![Vector::<D>::zeros(); cells];
        let mut count = vec![0usize; cells];
        for i in 0..s.len() {
            if let Some((c, _)) = g.locate(&s.reference[i]) {
                stress[c] += s.stress[i];
                velocity[c] += s.velocity[i];
                count[c] += 1;
            }
        }
        let plane = crate::plane::MapPlane::of(g, &self.line);
        let mut map = vec![f64::NAN; plane.map_or(0, |p| p.grid(g).cell_count())];
        for c in 0..cells {
            if count[c] > 0 {
                stress[c] /= count[c] as f64;
                velocity[c] /= count[c] as f64;
                if let Some(k) = plane.and_then(|p| p.cell_in_plane(g, c)) {
                    map[k] = stress[c][(0, 0)];
                }
            }
        }
        // maps are drawn in 2D and 3D (the plane through the measuring line)
        // the kept frame of this output time (none yet at the initial frame)
        if let Some(last) = self.keep.as_mut().and_then(|k| k.last_mut()) {
            last.map.clone_from(&map);
        }
        if self.collect && D > 1 && frame != INITIAL {
            self.maps.push((t, map));
        }
        if !self.files {
            return Ok(());
        }
        // (one rank: the piece is the whole mesh)
        let nodal = method.piece_nodal_fields();
        let mut points: Vec<f64> = Vec::with_capacity(3 * g.vertex_count());
        for v in 0..g.vertex_count() {
            let mut x = g.vertex_position(v);
            if let Some((_, u)) = &nodal {
                x += u[v];
            }
            points.extend_from_slice(&pad3(&x));
        }
        let (order, _) = vtk_order(D);
        let connectivity: Vec<usize> = (0..cells)
            .flat_map(|c| order.iter().map(move |&a| (c, a)))
            .map(|(c, a)| g.vertex_of(c, a))
            .collect();
        let (cell_stress, cell_velocity) = self.cell_arrays(&stress, &velocity);
        let nodal_velocity: Vec<f64> = nodal
            .as_ref()
            .map(|(v, _)| v.iter().flat_map(pad3).collect())
            .unwrap_or_default();
        let file = format!("{}_grid_{frame}.vtu", self.method);
        let arrays = GridArrays {
            points: &points,
            connectivity: &connectivity,
            cell_stress: &cell_stress,
            cell_velocity: &cell_velocity,
            nodal_velocity: &nodal_velocity,
        };
        self.write_grid_arrays(&self.dir.join(&file), (frame, t), &arrays)?;
        self.pvd_grid.push((t, file));
        Ok(())
    }
    /// Whether the grid is written in pieces (several ranks, [`super::grid_pieces`]).
    pub(super) fn grid_in_pieces(method: &dyn Method<D>) -> bool {
        method.comm().size() > 1
    }

    /// `arrays` as the grid `.vtu` `path` (cell stress and velocity, the nodal velocity
    /// where there is one) and into the `.h5` series (output times only; on several ranks
    /// the rank's own series, of its piece).
    #[cfg_attr(not(feature = "hdf5"), allow(unused_variables))]
    pub(super) fn write_grid_arrays(
        &mut self,
        path: &Path,
        (frame, t): (&str, f64),
        arrays: &GridArrays,
    ) -> anyhow::Result<()> {
        let mut point_data = Vec::new();
        if !arrays.nodal_velocity.is_empty() {
            point_data.push(DataArray {
                name: "nodal_velocity",
                components: 3,
                values: arrays.nodal_velocity,
                units: "m/s",
            });
        }
        let cell_data = vec![
            DataArray {
                name: self.measure.array_name(),
                components: 9,
                values: arrays.cell_stress,
                units: "Pa",
            },
            DataArray {
                name: "velocity",
                components: 3,
                values: arrays.cell_velocity,
                units: "m/s",
            },
        ];
        let (_, cell_type) = vtk_order(D);
        let grid = UnstructuredGrid {
            points: arrays.points,
            connectivity: arrays.connectivity,
            nodes_per_cell: Grid::<D>::NODES_PER_CELL,
            cell_type,
            point_data,
            cell_data,
            time: Some(t),
        };
        let file = path
            .file_name()
            .map_or(String::new(), |f| f.display().to_string());
        write_vtu(path, &grid, self.encoding).with_context(|| format!("writing {file}"))?;
        #[cfg(feature = "hdf5")]
        if let (Some(series), true) = (self.h5.as_mut(), frame != INITIAL) {
            series.write_grid(&impact_io::h5::GridFrame {
                points: arrays.points,
                connectivity: arrays.connectivity,
                nodes_per_cell: Grid::<D>::NODES_PER_CELL,
                cell_stress: arrays.cell_stress,
                cell_velocity: arrays.cell_velocity,
                nodal_velocity: arrays.nodal_velocity,
            })?;
        }
        Ok(())
    }

    /// The cells' stress (3×3 each, σ_zz filled in plane strain) and velocity (3 each), as
    /// the grid `.vtu` stores them.
    pub(super) fn cell_arrays(
        &self,
        stress: &[Tensor<D>],
        velocity: &[Vector<D>],
    ) -> (Vec<f64>, Vec<f64>) {
        let zz = self.plane_strain;
        let cell_stress = stress
            .iter()
            .flat_map(|t| with_zz(tensor9(t), t, zz))
            .collect();
        (cell_stress, velocity.iter().flat_map(pad3).collect())
    }

    /// The grid frame: one `.vtu`, or this rank's piece ([`super::grid_pieces`]).
    pub(super) fn grid_frame(
        &mut self,
        method: &dyn Method<D>,
        frame: &str,
        t: f64,
    ) -> anyhow::Result<()> {
        if Self::grid_in_pieces(method) {
            self.grid_piece(method, frame, t)
        } else {
            self.grid(method, frame, t)
        }
    }
}

/// A grid frame's arrays ([`FileWriter::write_grid_arrays`]): points (3 per vertex), cells'
/// vertices, per-cell 3×3 stress and velocity, per-vertex nodal velocity (empty but FEM).
pub(super) struct GridArrays<'a> {
    pub(super) points: &'a [f64],
    pub(super) connectivity: &'a [usize],
    pub(super) cell_stress: &'a [f64],
    pub(super) cell_velocity: &'a [f64],
    pub(super) nodal_velocity: &'a [f64],
}
