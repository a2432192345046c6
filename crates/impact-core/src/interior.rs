//! The clean interior: where no boundary can have influenced a run yet (`[metrics] interior`).
//!
//! An exact solution of the unbounded body (the oblique plane wave,
//! [`crate::exact::PlaneWave`]) holds in a box only until the boundaries' influence arrives.
//! A scheme carries information at most a fixed number of cell layers per step, its reach
//! `R` (below), so after `s` steps a boundary has influenced at most the `R s` layers next to
//! it; one more layer covers what acts at `t = 0` (a constrained face node, a ghost state)
//! and samples that sit off their cell (moved points, sub-cell regions). The clean interior
//! after `s` steps is the box
//!
//! `[x_lo + m h_l, x_hi − m h_l]` along each axis `l`, `m = R s + 1` cells,
//!
//! and a sample counts when its whole region lies in it. The reach per step:
//!
//! - DGMPM: 1 with Euler (a cell's update reads its face neighbours for donor-cell, its
//!   `3^D` neighbourhood for CTU), 2 with RK2 (two such stages);
//! - FEM (lumped mass, central differences): 1 (a node's force reads the elements that
//!   share it);
//! - MPM: a point writes to the nodes of its support and reads them back: with hats the
//!   nodes of its own cell, so 1; with GIMP, B-splines and CPDI up to 2 nodes beyond its cell
//!   on either side, and back, so 3.
//!
//! A run takes at most `⌈t/Δt⌉` steps plus one per output time before `t` (each output
//! time shortens a step); the measurement uses the steps actually taken.
use crate::options::{option_enum, Integrator, MethodConfig, MethodOptions, MpmShape};
use crate::{Grid, Vector};
use serde::{Deserialize, Serialize};

option_enum! {
    /// Where the errors against an exact solution are measured (`[metrics] interior`).
    InteriorRule {
        /// Over the whole body (the default, but for a plane wave).
        Whole = "whole",
        /// Over the clean interior (module doc): the samples no boundary can have
        /// influenced by the numerical domain of dependence (the default for a plane wave).
        Dependence = "dependence",
    }
}

/// Cell layers `config`'s method can carry information across in one step (module doc).
pub fn reach_per_step(config: &MethodConfig) -> usize {
    match config.options {
        MethodOptions::Dgmpm(o) => match o.integrator {
            Integrator::Euler => 1,
            Integrator::Rk2 => 2,
        },
        MethodOptions::Mpm(o) => match o.shape {
            MpmShape::Linear => 1,
            _ => 3,
        },
        MethodOptions::Fem(_) => 1,
    }
}

/// The most steps a run of Courant number `courant` (time step `courant h / c`) takes to
/// the last of `output_times`: `⌈t/Δt⌉` plus one per earlier output time.
pub fn steps_bound(output_times: &[f64], courant: f64, spacing: f64, speed: f64) -> usize {
    let t = output_times.last().copied().unwrap_or(0.0);
    let dt = courant * spacing / speed;
    (t / dt).ceil() as usize + output_times.len().saturating_sub(1)
}

/// The cells in from each face that a boundary can have influenced after `steps` steps
/// of `config` (module doc).
pub fn margin_cells(config: &MethodConfig, steps: usize) -> usize {
    reach_per_step(config) * steps + 1
}

/// The clean interior box of a grid after some steps of a method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interior<const D: usize> {
    /// Low corner (m).
    pub lo: Vector<D>,
    /// High corner (m).
    pub hi: Vector<D>,
    /// Cells in from each face.
    pub margin_cells: usize,
}

impl<const D: usize> Interior<D> {
    /// The clean interior of `grid` after `steps` steps of `config`, or `None` where the
    /// margin leaves no whole cell along some axis.
    pub fn after(grid: &Grid<D>, config: &MethodConfig, steps: usize) -> Option<Self> {
        let m = margin_cells(config, steps);
        if (0..D).any(|l| grid.cells[l] <= 2 * m) {
            return None;
        }
        let lo = grid.origin + grid.spacing * m as f64;
        let hi = grid.upper() - grid.spacing * m as f64;
        Some(Self {
            lo,
            hi,
            margin_cells: m,
        })
    }

    /// Whether the region `[x − half, x + half]` lies in the box (to a round-off).
    pub fn holds(&self, x: &Vector<D>, half: &Vector<D>) -> bool {
        (0..D).all(|l| {
            let tol = 1e-9 * (self.hi[l] - self.lo[l]).abs().max(half[l]);
            x[l] - half[l] >= self.lo[l] - tol && x[l] + half[l] <= self.hi[l] + tol
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::MethodKind;

    #[test]
    fn margin_follows_the_reach_and_empties_the_box() {
        let grid = Grid::<2> {
            origin: Vector::<2>::zeros(),
            spacing: Vector::<2>::new(0.1, 0.1),
            cells: [20, 10],
        };
        let dgmpm = MethodConfig::new(MethodKind::Dgmpm, 1.0, 1);
        let inside = Interior::after(&grid, &dgmpm, 3).unwrap();
        assert_eq!(inside.margin_cells, 4);
        assert!((inside.lo[0] - 0.4).abs() < 1e-12 && (inside.hi[1] - 0.6).abs() < 1e-12);
        let h = Vector::<2>::repeat(0.05);
        assert!(inside.holds(&Vector::<2>::new(0.45, 0.55), &h));
        assert!(!inside.holds(&Vector::<2>::new(0.35, 0.55), &h));
        // 10 cells along y: a margin of 5 leaves none
        assert!(Interior::after(&grid, &dgmpm, 4).is_none());
        let mut rk2 = dgmpm;
        rk2.dgmpm_mut().unwrap().integrator = Integrator::Rk2;
        assert_eq!(margin_cells(&rk2, 3), 7);
        let mut spline = MethodConfig::new(MethodKind::Mpm, 0.5, 1);
        assert_eq!(margin_cells(&spline, 2), 3);
        spline.mpm_mut().unwrap().shape = MpmShape::Bspline2;
        assert_eq!(margin_cells(&spline, 2), 7);
        assert_eq!(steps_bound(&[1.0, 2.0], 0.5, 1.0, 1.0), 5);
    }
}
