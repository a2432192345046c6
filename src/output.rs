//! Writing a run's files. Stress arrays and columns are named by the measure the method
//! carries ([`StressMeasure`]): `cauchy_stress` in small strain, `piola_stress` (first
//! Piola–Kirchhoff) under Saint-Venant–Kirchhoff.
//!
//! Per method and output time a CSV profile (the samples along the measuring line with
//! their coordinates, every stress and velocity component, and the reference solution as
//! `reference_*` columns) and two `.vtu` files (the samples as vertices, with their
//! `reference_position` and, at output times, the reference solution under the CSV's
//! `reference_*` names; the grid cells, or the FEM mesh with `nodal_velocity` at its nodes
//! and the cell averages as cell data, with their fields); per method a `.pvd`
//! collection of each; with the `hdf5` feature a `<method>.h5` time series of the samples
//! and of the grid, described by `<method>.xdmf` (samples) and `<method>_grid.xdmf` (the
//! grid's quadrilaterals or hexahedra: `impact_io::h5`); per run `summary.json`, `stress.png` (profiles at up to three times)
//! and, in 2D, `stress_map.png` (σ_xx colour map per method at the last output time).
use crate::run::{Observer, RunRecord};
use impact_core::method::Samples;
use impact_core::reference::{line_samples, Reference, TimeMetrics};
use impact_core::{Grid, Method, StressMeasure};
use impact_io::vtu::{write_pvd, VtuEncoding};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The frame name of the initial state's `.vtu` files.
const INITIAL: &str = "initial";

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Dimension.
    pub dim: usize,
    /// Reference the errors are measured against.
    pub reference: String,
    /// The converged reference's method, options, refinement and fine cells and the
    /// second reference of the spread (absent for an exact reference or none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_setup: Option<crate::reference_setup::ReferenceSetup>,
    /// Where profiles, errors and fronts are measured ([`impact_core::line`]).
    pub metrics_line: String,
    /// One entry per method.
    pub runs: Vec<RunRecord>,
    /// Peak resident memory of the process (MiB, Linux `VmHWM`), if known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_rss_mib: Option<f64>,
    /// On several ranks: each rank's peak resident memory (MiB, `VmHWM`), in rank order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub peak_rss_mib_per_rank: Vec<f64>,
    /// The stability guard's notes: configurations run above their von Neumann limit
    /// under `--allow-unstable`, or not checked ([`crate::guard`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stability: Vec<String>,
}

/// Peak resident set size of this process in MiB (Linux: `VmHWM` of `/proc/self/status`).
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Profiles of one method: `(t, [(x, σ_xx)])` per output time.
pub type Profiles = Vec<(f64, Vec<(f64, f64)>)>;

/// σ_xx per grid cell (`NaN` where no sample lies) at each output time, for colour maps.
pub type CellMaps = Vec<(f64, Vec<f64>)>;

/// Writes files at output times and keeps the profiles for the plots.
pub struct FileWriter<'a, const D: usize> {
    dir: PathBuf,
    method: String,
    grid: Grid<D>,
    reference: Option<&'a Reference>,
    samples: Samples<D>,
    /// Profiles kept for `stress.png`.
    pub profiles: Profiles,
    /// Cell averages of σ_xx at each output over the map's plane
    /// ([`crate::plane::MapPlane`]), for `stress_map.png` (2D and 3D).
    pub maps: CellMaps,
    /// Current x positions of the bottom-row samples at each output, for `svk.png`.
    pub positions: Vec<(f64, Vec<f64>)>,
    pvd: Vec<(f64, String)>,
    pvd_grid: Vec<(f64, String)>,
    progress: Option<indicatif::ProgressBar>,
    t_end: f64,
    /// Write files at output times (`false`: no I/O).
    pub files: bool,
    /// Keep profiles, maps and positions in memory for the figures.
    pub collect: bool,
    /// Linear elasticity in 2D: the material giving the plane-strain `σ_zz` written in the
    /// 3×3 stress tensors (`None`: the zz slot is 0: the 1D bar, and SVK, whose `Π_zz` is
    /// not tracked).
    pub plane_strain: Option<impact_core::LinearElastic>,
    /// Which stress the samples carry: names the arrays and columns.
    pub measure: StressMeasure,
    /// How the `.vtu` arrays are encoded (`--vtu`).
    pub encoding: VtuEncoding,
    /// Where the profile is taken (default: the bottom row along x).
    pub line: impact_core::line::MeasureLine,
    /// The `.h5` time series (feature `hdf5`), opened at the first output.
    #[cfg(feature = "hdf5")]
    h5: Option<impact_io::h5::TimeSeries>,
    /// The fields of every output time, kept in memory when `Some` ([`crate::fields`]).
    pub keep: Option<Vec<crate::fields::Frame>>,
    /// On several ranks: where this rank writes its piece of each samples frame
    /// ([`pieces`]); `None` on one rank (one `.vtu` per frame).
    pub pieces: Option<pieces::Pieces>,
    /// This rank's owned samples (the pieces' content).
    owned: Samples<D>,
    /// Whether `samples` holds the measuring line's samples only (gathered on several
    /// ranks, [`impact_core::comm_line::gather_line`]) rather than the whole body's.
    line_only: bool,
    /// How the ranks split the grid (`--ranks-grid`, [`crate::ranks::rank_grid`]): which
    /// cells this rank's grid piece holds ([`grid_pieces`]).
    pub rank_grid: impact_core::comm::RankGrid,
}

impl<'a, const D: usize> FileWriter<'a, D> {
    /// A writer for `method` into `dir`, with an optional progress bar over `[0, t_end]`.
    pub fn new(
        dir: &Path,
        method: &str,
        grid: &Grid<D>,
        reference: Option<&'a Reference>,
        progress: Option<indicatif::ProgressBar>,
        t_end: f64,
    ) -> Self {
        Self {
            dir: dir.to_path_buf(),
            method: method.to_string(),
            grid: grid.clone(),
            reference,
            samples: Samples::default(),
            profiles: Vec::new(),
            maps: Vec::new(),
            collect: true,
            positions: Vec::new(),
            pvd: Vec::new(),
            pvd_grid: Vec::new(),
            progress,
            t_end,
            files: true,
            plane_strain: None,
            measure: StressMeasure::Cauchy,
            encoding: VtuEncoding::Binary,
            line: impact_core::line::MeasureLine::bottom_row(grid),
            #[cfg(feature = "hdf5")]
            h5: None,
            keep: None,
            pieces: None,
            owned: Samples::default(),
            line_only: false,
            rank_grid: crate::ranks::rank_grid(),
        }
    }

    /// Write the `.pvd` collections of the frames written so far and finish the progress bar.
    pub fn finish(&mut self) -> anyhow::Result<()> {
        if let Some(p) = self.progress.take() {
            p.finish_and_clear();
        }
        #[cfg(feature = "hdf5")]
        if let Some(series) = self.h5.take() {
            series.finish()?;
        }
        if !self.pvd.is_empty() {
            write_pvd(&self.dir.join(format!("{}.pvd", self.method)), &self.pvd)?;
            write_pvd(
                &self.dir.join(format!("{}_grid.pvd", self.method)),
                &self.pvd_grid,
            )?;
        }
        Ok(())
    }
}

mod fields;
mod grid_file;
pub mod grid_pieces;
pub mod pieces;
mod samples;
use fields::{reference_names, stress_components, tensor9, with_zz, AXES};

impl<const D: usize> FileWriter<'_, D> {
    /// The profile along the measuring line ([`impact_core::line`]): kept for the figures
    /// and written as CSV: every sample the line crosses, sorted along it, with its
    /// reference and current coordinates (`x`, `y`, `z`; `x_current`, ...), every stress
    /// component (`<measure>_xx`, `_yy`, `_zz`, `_yz`, `_xz`, `_xy` as the dimension has
    /// them), every velocity component (`velocity_x`, ...), the plastic strain under J2, and
    /// the reference solution along the line's axis `a` (`reference_<measure>_aa`,
    /// `reference_velocity_a`) when there is one. In 1D the columns are those of earlier
    /// versions.
    fn profile(&mut self, index: usize, t: f64) -> anyhow::Result<()> {
        let s = &self.samples;
        let a = self.line.axis;
        let mut order = if self.line_only {
            (0..s.len()).collect()
        } else {
            line_samples(s, &self.line)
        };
        order.sort_by(|&i, &j| s.reference[i][a].total_cmp(&s.reference[j][a]));
        let col = |f: &dyn Fn(usize) -> f64| order.iter().map(|&i| f(i)).collect::<Vec<f64>>();
        let x = col(&|i| s.reference[i][a]);
        let xc = col(&|i| s.position[i][a]);
        let sxx = col(&|i| s.stress[i][(a, a)]);
        let path = self.dir.join(format!("{}_t{}.csv", self.method, index));
        let measure = self.measure.array_name();
        let mut header: Vec<String> = Vec::new();
        let mut columns: Vec<Vec<f64>> = Vec::new();
        for (l, name) in AXES.iter().enumerate().take(D) {
            header.push(name.to_string());
            columns.push(col(&|i| s.reference[i][l]));
        }
        for (l, name) in AXES.iter().enumerate().take(D) {
            header.push(format!("{name}_current"));
            columns.push(col(&|i| s.position[i][l]));
        }
        let full: Vec<[f64; 9]> = order.iter().map(|&i| self.full_stress(i)).collect();
        for &(k, name) in stress_components(D) {
            header.push(format!("{measure}_{name}"));
            columns.push(full.iter().map(|f| f[k]).collect());
        }
        for (l, name) in AXES.iter().enumerate().take(D) {
            header.push(format!("velocity_{name}"));
            columns.push(col(&|i| s.velocity[i][l]));
        }
        if !s.plastic_strain.is_empty() {
            header.push("equivalent_plastic_strain".into());
            columns.push(col(&|i| s.plastic_strain[i]));
        }
        if let Some(r) = self.reference {
            let exact: Vec<(f64, f64)> = order
                .iter()
                .map(|&i| {
                    let (c, h) = (s.reference[i], s.half_size[i]);
                    r.averages(&(c - h), &(c + h), t)
                })
                .collect();
            let (stress_name, velocity_name) = reference_names(measure, a);
            header.extend([stress_name, velocity_name]);
            columns.push(exact.iter().map(|e| e.0).collect());
            columns.push(exact.iter().map(|e| e.1).collect());
        }
        if self.files {
            let names: Vec<&str> = header.iter().map(String::as_str).collect();
            let refs: Vec<&[f64]> = columns.iter().map(|c| c.as_slice()).collect();
            impact_io::write_csv(&path, &names, &refs)?;
        }
        if let Some(kept) = self.keep.as_mut() {
            let profile = (header.as_slice(), columns.as_slice());
            kept.push(crate::fields::Frame::of(
                s,
                (index, t),
                profile,
                self.reference,
            ));
        }
        if self.collect {
            self.positions.push((t, xc));
            self.profiles.push((t, x.into_iter().zip(sxx).collect()));
        }
        Ok(())
    }

    /// Sample `i`'s stress as a 3×3 row-major tensor, with the out-of-plane σ_zz of plane
    /// strain (or the method's own, where it carries one).
    fn full_stress(&self, i: usize) -> [f64; 9] {
        let t = &self.samples.stress[i];
        let mut full = with_zz(tensor9(t), t, self.plane_strain);
        if let Some(szz) = self.samples.stress_zz.get(i) {
            full[8] = *szz;
        }
        full
    }

    /// The reference solution at every sample (`σ_aa`, `v_a` along the line's axis `a`,
    /// averaged over the sample's region), at output times only and where every value is
    /// finite; `None` otherwise.
    fn reference_at_samples(&self, frame: &str, t: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        let (stress, velocity) = self.reference_values(frame, t)?;
        let finite = stress.iter().chain(&velocity).all(|v| v.is_finite());
        finite.then_some((stress, velocity))
    }

    /// [`Self::reference_at_samples`] before the test that every value is finite.
    fn reference_values(&self, frame: &str, t: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        let r = self.reference.filter(|_| frame != INITIAL)?;
        let s = &self.samples;
        let (stress, velocity): (Vec<f64>, Vec<f64>) = (0..s.len())
            .map(|i| {
                let (c, h) = (s.reference[i], s.half_size[i]);
                r.averages(&(c - h), &(c + h), t)
            })
            .unzip();
        Some((stress, velocity))
    }

    /// The samples of this output: every sample on one rank; on several, the measuring
    /// line's only, gathered (the rest of the body stays on its ranks: the pieces), and
    /// this rank's owned samples in `owned`, formed once for the pieces of the frame and of
    /// the grid.
    fn gather(&mut self, method: &dyn Method<D>) {
        self.line_only = Self::grid_in_pieces(method);
        if self.line_only {
            impact_core::comm_line::gather_line(
                method,
                &self.line,
                &mut self.owned,
                &mut self.samples,
            );
        } else {
            method.sample_into(&mut self.samples);
            if self.pieces.is_some() {
                method.owned_samples_into(&mut self.owned);
            }
        }
    }
}

impl<const D: usize> Observer<D> for FileWriter<'_, D> {
    fn progress(&mut self, t: f64) {
        if let Some(p) = &self.progress {
            p.set_position(crate::run::progress_position(t, self.t_end));
        }
    }

    fn output(
        &mut self,
        method: &dyn Method<D>,
        index: usize,
        t: f64,
        _metrics: &TimeMetrics,
    ) -> anyhow::Result<()> {
        if !self.files && !self.collect {
            return Ok(());
        }
        // the collective steps first (gathered samples, this rank's piece), then the
        // writes, whose failure on one rank the caller makes every rank's (`pieces::agree`)
        self.gather(method);
        let frame = format!("t{index}");
        let piece = self.owned_piece(method.comm(), &frame, t);
        self.profile(index, t)?;
        if self.files {
            self.write_frame(&frame, t, piece)?;
        }
        if self.files || (self.collect && D > 1) {
            self.grid_frame(method, &frame, t)?;
        }
        Ok(())
    }

    /// The initial state as the `.pvd` collections' first frame (`<method>_initial.vtu`,
    /// `<method>_grid_initial.vtu` at t = 0).
    fn start(&mut self, method: &dyn Method<D>) -> anyhow::Result<()> {
        if !self.files {
            return Ok(());
        }
        self.gather(method);
        let piece = self.owned_piece(method.comm(), INITIAL, 0.0);
        self.write_frame(INITIAL, 0.0, piece)?;
        self.grid_frame(method, INITIAL, 0.0)?;
        Ok(())
    }
}
