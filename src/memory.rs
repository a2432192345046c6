//! Will a run fit in this machine's memory? Checked before anything is allocated, so that a
//! grid too large for the machine is refused with a clear message instead of being killed by
//! the kernel half-way (the scene's own limit, [`impact_core::scene::MAX_POINTS`], only
//! bounds what any machine could hold: a 512³ block at one point per cell).
//!
//! The estimate is `points × bytes per point`, with the bytes per point a run peaks at,
//! measured (BENCHMARKS.md: "peak memory" of the 2D plate at 3·10⁶ cells, the 3D block at
//! 128³ and 256²×152, heap counted plus the output's sample buffer) and rounded up:
//! 1D 300 B for every method; 2D 550 B; 3D DGMPM 460 B (fused path 308 B + the samples'
//! 144 B), MPM 500 B, FEM 300 B. Several points per cell cost less per point (the grid's
//! buffers are shared by the cell's points), so the estimate stays an upper bound there.
//! The machine's memory is Linux's `MemTotal` (`/proc/meminfo`); elsewhere nothing is
//! checked.
use impact_core::options::MethodKind;
use impact_core::SceneError;

/// Peak bytes per point of a run of `kind` in dimension `dim` (module doc).
pub fn bytes_per_point(kind: MethodKind, dim: usize) -> f64 {
    match (dim, kind) {
        (1, _) => 300.0,
        (2, _) => 550.0,
        (_, MethodKind::Dgmpm) => 460.0,
        (_, MethodKind::Mpm) => 500.0,
        (_, MethodKind::Fem) => 300.0,
    }
}

/// The machine's physical memory in bytes (`MemTotal`), if known.
pub fn machine_bytes() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// Refuse a run of `kind` over `points` points (cells × points per cell) in dimension
/// `dim` whose estimated peak memory exceeds `machine` bytes; `field` and `value` name what
/// set the size (`domain.cells` or `--cells`).
pub fn check_fits(
    field: &str,
    value: String,
    kind: MethodKind,
    dim: usize,
    points: f64,
    machine: f64,
) -> Result<(), SceneError> {
    let need = points * bytes_per_point(kind, dim);
    if need <= machine {
        return Ok(());
    }
    Err(SceneError::new(
        field,
        value,
        format!(
            "a grid that fits this machine's memory: {kind} needs about {:.1} GB for {points:.3e} \
             points ({:.0} B per point in {dim}D) and the machine has {:.1} GB",
            need / 1e9,
            bytes_per_point(kind, dim),
            machine / 1e9
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_512_cube_at_one_point_per_cell_fits_64_gb_and_not_23() {
        let points = 512f64.powi(3);
        let gb = 1024f64.powi(3);
        for kind in [MethodKind::Dgmpm, MethodKind::Fem] {
            assert!(check_fits(
                "domain.cells",
                "[512, 512, 512]".into(),
                kind,
                3,
                points,
                64.0 * gb
            )
            .is_ok());
        }
        let err = check_fits(
            "domain.cells",
            "[512, 512, 512]".into(),
            MethodKind::Dgmpm,
            3,
            points,
            23.0 * gb,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("domain.cells") && err.contains("[512, 512, 512]") && err.contains("GB"),
            "{err}"
        );
    }
}
