//! `impact stability`: its flags and the sweep's lines (stdout).
use anyhow::Result;
use clap::Args;
use impact::Overrides;
use std::path::PathBuf;

#[derive(Args)]
pub(crate) struct StabilityArgs {
    /// Sweep on this scene (a shipped name or a scene file): its material, model, point
    /// layout and cell size, on its grid cut to at most 150 cells (1D), or cut or widened to
    /// 16×12 (2D) or 12×12×12 (3D), with every edge unloaded. Default: the paper's bar (1D)
    /// and the plane wave cut to 16×12 cells (2D).
    #[arg(long, conflicts_with = "dim")]
    scene: Option<String>,
    /// Scene and method flags of `impact run` that the sweep does not vary (--riemann,
    /// --edges, --stress-update, --frame, --shape, --yield-stress, --hardening).
    #[command(flatten)]
    overrides: Overrides,
    /// Dimensions to sweep (default 1,2; with --scene, the scene's).
    #[arg(long, value_delimiter = ',')]
    dim: Option<Vec<usize>>,
    /// Steps of each perturbed run in 1D.
    #[arg(long, default_value_t = 20000)]
    steps_1d: usize,
    /// Steps of each perturbed run in 2D.
    #[arg(long, default_value_t = 3000)]
    steps_2d: usize,
    /// Output folder.
    #[arg(long, default_value = "out/stability")]
    out: PathBuf,
    /// Where the points sit in a cell (DGMPM and MPM): centred sub-cells, shifted by
    /// `--shift`, or at the 1D local `--positions`.
    #[arg(long, value_enum)]
    layout: Option<impact_core::method::LayoutKind>,
    /// Shift of every point in sub-cell widths, |shift| < 0.5 (`--layout shifted`).
    #[arg(long)]
    shift: Option<f64>,
    /// Local positions in (0, 1) of the points of a cell, comma-separated (`--layout
    /// given`, 1D; only that number of points per cell is swept).
    #[arg(long, value_delimiter = ',')]
    positions: Option<Vec<f64>>,
}

pub(crate) fn command(args: &StabilityArgs) -> Result<()> {
    let options = impact::stability_run::StabilityOptions {
        scene: args.scene.clone(),
        dim: args.dim.clone(),
        overrides: args.overrides.clone(),
        steps_1d: args.steps_1d,
        steps_2d: args.steps_2d,
        out: args.out.clone(),
        layout: args.layout,
        shift: args.shift,
        positions: args.positions.clone(),
    };
    impact::stability_run::run(&options, |line| say!("{line}"))?;
    say!("wrote {}", args.out.display());
    Ok(())
}
