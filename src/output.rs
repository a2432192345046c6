//! Writing a run's files: per method and output time a CSV profile (with the exact
//! solution as columns when there is one) and a `.vtu`; per method a `.pvd` collection;
//! per run `summary.json` and the stress plot.
use crate::run::{Observer, RunRecord};
use anyhow::Context;
use impact_core::method::Samples;
use impact_core::reference::{Reference, TimeMetrics};
use impact_core::Method;
use impact_io::plot::{line_panels, Panel, Series};
use impact_io::vtu::{write_pvd, write_vtu, CellType, DataArray, UnstructuredGrid};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Dimension.
    pub dim: usize,
    /// Reference the errors are measured against.
    pub reference: String,
    /// One entry per method.
    pub runs: Vec<RunRecord>,
}

/// Profiles of one method: `(t, [(x, σ_xx)])` per output time.
pub type Profiles = Vec<(f64, Vec<(f64, f64)>)>;

/// Writes files at output times and keeps the profiles for the plot.
pub struct FileWriter<'a, const D: usize> {
    dir: PathBuf,
    method: String,
    reference: Option<&'a Reference>,
    samples: Samples<D>,
    /// `(t, x, σ_xx)` kept for the plot.
    pub profiles: Profiles,
    pvd: Vec<(f64, String)>,
    progress: Option<indicatif::ProgressBar>,
    t_end: f64,
}

impl<'a, const D: usize> FileWriter<'a, D> {
    /// A writer for `method` into `dir`, with an optional progress bar over `[0, t_end]`.
    pub fn new(
        dir: &Path,
        method: &str,
        reference: Option<&'a Reference>,
        progress: Option<indicatif::ProgressBar>,
        t_end: f64,
    ) -> Self {
        Self {
            dir: dir.to_path_buf(),
            method: method.to_string(),
            reference,
            samples: Samples::default(),
            profiles: Vec::new(),
            pvd: Vec::new(),
            progress,
            t_end,
        }
    }

    /// Write the `.pvd` of the frames written so far and finish the progress bar.
    pub fn finish(&mut self) -> anyhow::Result<()> {
        if let Some(p) = self.progress.take() {
            p.finish_and_clear();
        }
        if !self.pvd.is_empty() {
            write_pvd(&self.dir.join(format!("{}.pvd", self.method)), &self.pvd)?;
        }
        Ok(())
    }
}

fn pad3<const D: usize>(v: &impact_core::Vector<D>) -> [f64; 3] {
    let mut out = [0.0; 3];
    for l in 0..D.min(3) {
        out[l] = v[l];
    }
    out
}

impl<const D: usize> Observer<D> for FileWriter<'_, D> {
    fn progress(&mut self, t: f64) {
        if let Some(p) = &self.progress {
            p.set_position((1000.0 * t / self.t_end) as u64);
        }
    }

    fn output(
        &mut self,
        method: &dyn Method<D>,
        index: usize,
        t: f64,
        _metrics: &TimeMetrics,
    ) -> anyhow::Result<()> {
        method.sample_into(&mut self.samples);
        let s = &self.samples;
        let n = s.len();
        // CSV profile sorted by x (bottom row in 2D: the samples with the smallest y)
        let mut order: Vec<usize> = (0..n).collect();
        if D > 1 {
            let y_min = s.reference.iter().map(|x| x[1]).fold(f64::MAX, f64::min);
            order.retain(|&i| s.reference[i][1] - s.half_size[i][1] <= y_min + 1e-12);
        }
        order.sort_by(|&a, &b| s.reference[a][0].total_cmp(&s.reference[b][0]));
        let col = |f: &dyn Fn(usize) -> f64| order.iter().map(|&i| f(i)).collect::<Vec<f64>>();
        let x = col(&|i| s.reference[i][0]);
        let xc = col(&|i| s.position[i][0]);
        let sxx = col(&|i| s.stress[i][(0, 0)]);
        let vx = col(&|i| s.velocity[i][0]);
        let path = self.dir.join(format!("{}_t{}.csv", self.method, index));
        match self.reference {
            Some(r) => {
                let exact: Vec<(f64, f64)> = order
                    .iter()
                    .map(|&i| {
                        let (xi, h) = (s.reference[i][0], s.half_size[i][0]);
                        r.averages(xi - h, xi + h, t)
                    })
                    .collect();
                let es: Vec<f64> = exact.iter().map(|e| e.0).collect();
                let ev: Vec<f64> = exact.iter().map(|e| e.1).collect();
                impact_io::write_csv(
                    &path,
                    &[
                        "x",
                        "x_current",
                        "stress_xx",
                        "velocity_x",
                        "exact_stress_xx",
                        "exact_velocity_x",
                    ],
                    &[&x, &xc, &sxx, &vx, &es, &ev],
                )?;
            }
            None => impact_io::write_csv(
                &path,
                &["x", "x_current", "stress_xx", "velocity_x"],
                &[&x, &xc, &sxx, &vx],
            )?,
        }
        self.profiles
            .push((t, x.iter().copied().zip(sxx.iter().copied()).collect()));
        // VTU: the samples as vertices with their fields
        let mut points = Vec::with_capacity(3 * n);
        let mut stress = Vec::with_capacity(9 * n);
        let mut velocity = Vec::with_capacity(3 * n);
        for i in 0..n {
            points.extend_from_slice(&pad3(&s.position[i]));
            velocity.extend_from_slice(&pad3(&s.velocity[i]));
            let mut full = [0.0; 9];
            for r in 0..D {
                for c in 0..D {
                    full[3 * r + c] = s.stress[i][(r, c)];
                }
            }
            stress.extend_from_slice(&full);
        }
        let reference: Vec<f64> = s.reference.iter().flat_map(pad3).collect();
        let connectivity: Vec<usize> = (0..n).collect();
        let file = format!("{}_t{}.vtu", self.method, index);
        write_vtu(
            &self.dir.join(&file),
            &UnstructuredGrid {
                points: &points,
                connectivity: &connectivity,
                nodes_per_cell: 1,
                cell_type: CellType::Vertex,
                point_data: vec![
                    DataArray {
                        name: "stress",
                        components: 9,
                        values: &stress,
                    },
                    DataArray {
                        name: "velocity",
                        components: 3,
                        values: &velocity,
                    },
                    DataArray {
                        name: "reference",
                        components: 3,
                        values: &reference,
                    },
                ],
                cell_data: vec![],
            },
        )
        .with_context(|| format!("writing {file}"))?;
        self.pvd.push((t, file));
        Ok(())
    }
}

/// The stress plot: one panel per output time, the exact solution and every method.
pub fn stress_plot(
    path: &Path,
    scene: &str,
    writers: &[(String, Profiles)],
    reference: Option<&Reference>,
    length: f64,
) -> anyhow::Result<()> {
    let times: Vec<f64> = writers
        .iter()
        .map(|w| w.1.iter().map(|p| p.0).collect::<Vec<_>>())
        .max_by_key(|t| t.len())
        .unwrap_or_default();
    // at most three panels, like the paper's Fig. 3
    let picks: Vec<usize> = match times.len() {
        0..=3 => (0..times.len()).collect(),
        n => vec![0, n / 2, n - 1],
    };
    let mut panels = Vec::new();
    for &k in &picks {
        let t = times[k];
        let mut series = Vec::new();
        if let Some(r) = reference {
            let n = 2000;
            let dx = length / n as f64;
            let pts = (0..n)
                .map(|i| {
                    let x = (i as f64 + 0.5) * dx;
                    (x, r.averages(x - 0.5 * dx, x + 0.5 * dx, t).0)
                })
                .collect();
            series.push(Series {
                label: "exact".into(),
                points: pts,
                colour: 0,
                reference: true,
            });
        }
        for (m, (name, profiles)) in writers.iter().enumerate() {
            if let Some((_, pts)) = profiles
                .iter()
                .find(|p| (p.0 - t).abs() <= 1e-12 * t.max(1e-30))
            {
                series.push(Series {
                    label: name.clone(),
                    points: pts.clone(),
                    colour: m + 1,
                    reference: false,
                });
            }
        }
        panels.push(Panel {
            title: format!("{scene}: t = {:.4} ms", t * 1e3),
            series,
        });
    }
    line_panels(path, &panels, "x (m)", "stress_xx (Pa)")?;
    Ok(())
}
