//! The grid's `.vtu` on several ranks (issue 27), without gathering the body: every rank
//! writes the cells of its own box (`RankBox::owned` of the run's rank grid) as
//! `<method>_grid_<frame>_r<rank>.vtu` into the shared staging folder, each cell with the
//! average of the samples whose reference position lies in it, and rank 0 lists the pieces
//! in `<method>_grid_<frame>.pvtu` (listed by `<method>_grid.pvd`). On one rank the grid is
//! one `.vtu` as before.
//!
//! **Which samples a rank averages.** A cell's samples are added in the global sample
//! order, as on one rank, so a piece's cells are the serial file's bit for bit. On the
//! total Lagrangian point methods a sample's reference cell lies in its owner's box (a rank
//! seeds its own cells' points); the migrating MPM's points belong to the rank of their
//! *current* cell, so a point that crossed a rank face averages into a cell of another
//! rank: every rank sends the few samples whose reference cell is not its own (one
//! all-gather of those only: `(global index, cell, σ, v)`), and every rank sorts what lands
//! in its box by global index before adding. The figures' map plane
//! ([`crate::plane::MapPlane`]) is gathered from the boxes' cells in the plane only, and to
//! rank 0 only (`Comm::gather_to_root_into`): rank 0 alone draws the figures, so the other
//! ranks keep no map (in 2D the plane is the whole grid: 16 B per cell of it).
//!
//! **FEM.** The grid file is the mesh deformed by the nodal displacement, with the nodal
//! velocity and the element stress and velocity (the element-centre samples, one per
//! cell). A rank's piece is its owned elements and their nodes: per axis the node layers
//! `[a, b]` of its element layers `[a, b)`, so the node layer `b` of a cut is in the pieces
//! of both ranks beside it (as the `.pvtu` readers expect of pieces that share a face). The
//! rank holds that layer as halo, whose state is its owner's bit for bit (received after
//! every step, `impact_fem::slab`), so its piece's points and nodal velocity are the serial
//! file's at those nodes, from the rank's own memory ([`Method::piece_nodal_fields`]): no
//! mesh is gathered. The point methods' pieces have the same vertex box, undeformed and
//! without nodal data.
use super::fields::{pad3, vtk_order};
use super::FileWriter;
use impact_core::comm::RankBox;
use impact_core::{Method, Tensor, Vector};
use impact_io::vtu::write_pvtu_with_cells;

/// Rank `rank`'s grid piece of `method`'s `frame`.
pub fn file(method: &str, frame: &str, rank: usize) -> String {
    format!("{method}_grid_{frame}_r{rank}.vtu")
}

/// The cells of one rank's box: global multi-indices to local (lexicographic, x fastest).
struct BoxCells<const D: usize> {
    owned: [std::ops::Range<usize>; D],
}

impl<const D: usize> BoxCells<D> {
    /// The local index of the global cell `idx`, if the box holds it.
    fn local(&self, idx: &[usize; D]) -> Option<usize> {
        let (mut local, mut stride) = (0, 1);
        for (range, &i) in self.owned.iter().zip(idx) {
            if !range.contains(&i) {
                return None;
            }
            local += (i - range.start) * stride;
            stride *= range.len();
        }
        Some(local)
    }

    fn count(&self) -> usize {
        self.owned.iter().map(ExactSizeIterator::len).product()
    }

    /// The global multi-index of local cell `local`.
    fn global(&self, mut local: usize) -> [usize; D] {
        std::array::from_fn(|k| {
            let n = self.owned[k].len();
            let i = self.owned[k].start + local % n;
            local /= n;
            i
        })
    }
}

impl<const D: usize> FileWriter<'_, D> {
    /// The averages of σ and v over each cell of this rank's box (module doc; collective).
    fn box_averages(
        &self,
        method: &dyn Method<D>,
        cells: &BoxCells<D>,
    ) -> (Vec<Tensor<D>>, Vec<Vector<D>>, Vec<usize>) {
        let (g, s, comm) = (&self.grid, &self.owned, method.comm());
        let order = method.owned_sample_order();
        let offset = if order.is_empty() {
            let counts = comm.all_gather(&[s.len() as f64]);
            counts[..comm.rank()].iter().sum::<f64>() as usize
        } else {
            0
        };
        let width = 2 + D * D + D;
        let (mut mine, mut foreign) = (Vec::new(), Vec::new());
        for i in 0..s.len() {
            let Some((c, _)) = g.locate(&s.reference[i]) else {
                continue;
            };
            let global = order.get(i).copied().unwrap_or(offset + i);
            let into = match cells.local(&g.cell_multi_index(c)) {
                Some(_) => &mut mine,
                None => &mut foreign,
            };
            // (indices below 2^53 travel exactly as f64)
            into.extend([global as f64, c as f64]);
            into.extend_from_slice(s.stress[i].as_slice());
            into.extend_from_slice(s.velocity[i].as_slice());
        }
        for entry in comm.all_gather(&foreign).chunks_exact(width) {
            if cells
                .local(&g.cell_multi_index(entry[1] as usize))
                .is_some()
            {
                mine.extend_from_slice(entry);
            }
        }
        let mut entries: Vec<&[f64]> = mine.chunks_exact(width).collect();
        entries.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let n = cells.count();
        let mut stress = vec![Tensor::<D>::zeros(); n];
        let mut velocity = vec![Vector::<D>::zeros(); n];
        let mut count = vec![0usize; n];
        for e in entries {
            let Some(l) = cells.local(&g.cell_multi_index(e[1] as usize)) else {
                continue;
            };
            stress[l] += Tensor::<D>::from_column_slice(&e[2..2 + D * D]);
            velocity[l] += Vector::<D>::from_column_slice(&e[2 + D * D..]);
            count[l] += 1;
        }
        for l in 0..n {
            if count[l] > 0 {
                stress[l] /= count[l] as f64;
                velocity[l] /= count[l] as f64;
            }
        }
        (stress, velocity, count)
    }

    /// This rank's piece of the grid frame `frame` (and rank 0's `.pvtu`), the map plane
    /// gathered from the pieces' cells in it (module doc; collective).
    pub(super) fn grid_piece(
        &mut self,
        method: &dyn Method<D>,
        frame: &str,
        t: f64,
    ) -> anyhow::Result<()> {
        let comm = method.comm();
        let g = self.grid.clone();
        let owner = RankBox::new(&g.cells, &self.rank_grid, comm.size(), comm.rank(), 0)?;
        let cells = BoxCells::<D> {
            owned: std::array::from_fn(|k| owner.owned[k].clone()),
        };
        // (`owned` holds this rank's owned samples: `FileWriter::gather`)
        let (stress, velocity, count) = self.box_averages(method, &cells);
        let global_cell = |l: usize| g.cell_index(cells.global(l));
        // the map plane: (plane cell, σ_xx) of the box's sampled cells in it, gathered to
        // rank 0 (the other ranks keep no map), at the output times the figures draw
        if D > 1 && self.collect && frame != super::INITIAL {
            let plane = crate::plane::MapPlane::of(&g, &self.line);
            let mut mine = Vec::new();
            for l in (0..cells.count()).filter(|&l| count[l] > 0) {
                if let Some(k) = plane.and_then(|p| p.cell_in_plane(&g, global_cell(l))) {
                    mine.extend([k as f64, stress[l][(0, 0)]]);
                }
            }
            let (mut gathered, mut counts) = (Vec::new(), Vec::new());
            comm.gather_to_root_into(&mine, &mut gathered, &mut counts);
            if comm.is_root() {
                let mut map = vec![f64::NAN; plane.map_or(0, |p| p.grid(&g).cell_count())];
                for entry in gathered.chunks_exact(2) {
                    map[entry[0] as usize] = entry[1];
                }
                self.maps.push((t, map));
            }
        }
        let Some(pieces) = self.pieces.clone().filter(|_| self.files) else {
            return Ok(());
        };
        // the box's vertices (x fastest), at the whole grid's vertex positions, FEM's
        // moved by their displacement (the nodes of its owned elements, in this order)
        let vertices = BoxCells::<D> {
            owned: std::array::from_fn(|k| owner.owned[k].start..owner.owned[k].end + 1),
        };
        let nodal = method.piece_nodal_fields();
        if let Some((v, _)) = &nodal {
            anyhow::ensure!(
                v.len() == vertices.count(),
                "internal: {} nodes in the piece's nodal fields, {} in its box",
                v.len(),
                vertices.count()
            );
        }
        let vertex_counts = g.vertex_counts();
        let mut points = Vec::with_capacity(3 * vertices.count());
        for v in 0..vertices.count() {
            let idx = vertices.global(v);
            let (mut global, mut stride) = (0, 1);
            for (&i, &n) in idx.iter().zip(&vertex_counts) {
                global += i * stride;
                stride *= n;
            }
            let mut x = g.vertex_position(global);
            if let Some((_, u)) = &nodal {
                x += u[v];
            }
            points.extend_from_slice(&pad3(&x));
        }
        let (order, _) = vtk_order(D);
        let mut connectivity = Vec::with_capacity(order.len() * cells.count());
        for l in 0..cells.count() {
            let idx = cells.global(l);
            for &a in order {
                let corner: [usize; D] = std::array::from_fn(|k| idx[k] + ((a >> k) & 1));
                connectivity.push(vertices.local(&corner).unwrap_or_default());
            }
        }
        let (cell_stress, cell_velocity) = self.cell_arrays(&stress, &velocity);
        let nodal_velocity: Vec<f64> = nodal
            .as_ref()
            .map(|(v, _)| v.iter().flat_map(pad3).collect())
            .unwrap_or_default();
        let name = file(&self.method, frame, pieces.rank);
        let arrays = super::grid_file::GridArrays {
            points: &points,
            connectivity: &connectivity,
            cell_stress: &cell_stress,
            cell_velocity: &cell_velocity,
            nodal_velocity: &nodal_velocity,
        };
        self.write_grid_arrays(&pieces.dir.join(&name), (frame, t), &arrays)?;
        let names: Vec<String> = (0..pieces.ranks)
            .map(|r| file(&self.method, frame, r))
            .collect();
        let pvtu = format!("{}_grid_{frame}.pvtu", self.method);
        let listed = [(self.measure.array_name(), 9), ("velocity", 3)];
        let point_listed: &[(&str, usize)] = match nodal {
            Some(_) => &[("nodal_velocity", 3)],
            None => &[],
        };
        write_pvtu_with_cells(
            &self.dir.join(&pvtu),
            point_listed,
            &listed,
            &names,
            self.encoding,
        )?;
        self.pvd_grid.push((t, pvtu));
        Ok(())
    }
}
