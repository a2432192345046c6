//! The command line's scene and method flags parsed outside the CLI: the Python package
//! turns its keyword arguments (`cells=200`, `points_per_cell=2`) into the same flags
//! (`--cells 200 --points-per-cell 2`) and parses them with the CLI's own [`Overrides`]
//! definition, so that names, allowed values and messages are the CLI's.
use crate::Overrides;
use impact_core::method::MethodKind;

/// A flag the CLI would refuse, with clap's message up to its first blank line (the
/// error and the allowed values), without `error: `.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct FlagError(pub String);

#[derive(clap::Parser)]
#[command(name = "impact", no_binary_name = true)]
struct OverrideFlags {
    #[command(flatten)]
    overrides: Overrides,
}

/// The overrides of `flags` (`["--cells", "200", "--allow-unstable"]`).
pub fn overrides_from_flags(flags: &[String]) -> Result<Overrides, FlagError> {
    use clap::Parser as _;
    OverrideFlags::try_parse_from(flags)
        .map(|f| f.overrides)
        .map_err(message)
}

/// The flags of `impact check` that set the comparison (the CLI flattens them into its
/// arguments; the Python package's `impact.check` takes them as keyword arguments).
#[derive(Debug, Clone, clap::Args)]
pub struct CheckFlags {
    /// The MPM to compare with: the scene's (default), the scene's with one shape function
    /// (linear, gimp, bspline2, bspline3, cpdi), or `all-mpm` (every shape function, then
    /// every shape with PIC and with APIC, one verdict each; the gate passes only if DGMPM
    /// beats them all).
    #[arg(long)]
    pub against: Option<String>,
    /// DGMPM's Courant number only (`--courant` sets both methods).
    #[arg(long, allow_negative_numbers = true)]
    pub dgmpm_courant: Option<f64>,
    /// MPM's Courant number only.
    #[arg(long, allow_negative_numbers = true)]
    pub mpm_courant: Option<f64>,
    /// DGMPM's points per cell only (`--points-per-cell` sets both methods).
    #[arg(long)]
    pub dgmpm_points_per_cell: Option<usize>,
    /// MPM's points per cell only.
    #[arg(long)]
    pub mpm_points_per_cell: Option<usize>,
    /// MPM's front width over DGMPM's must exceed this at every output time (1: strictly
    /// narrower).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub min_width_ratio: f64,
    /// DGMPM's overshoot passes when at most this many % of the jump, whatever MPM's is
    /// (default: it must be below MPM's).
    #[arg(long, allow_negative_numbers = true)]
    pub max_overshoot: Option<f64>,
}

impl CheckFlags {
    /// The check's options (`progress`: bars and status lines on stderr).
    pub fn options(&self, progress: bool) -> anyhow::Result<crate::check::CheckOptions> {
        use crate::check::{Against, CheckOptions, Thresholds};
        Ok(CheckOptions {
            against: self.against.as_deref().map(Against::parse).transpose()?,
            dgmpm_courant: self.dgmpm_courant,
            mpm_courant: self.mpm_courant,
            dgmpm_points_per_cell: self.dgmpm_points_per_cell,
            mpm_points_per_cell: self.mpm_points_per_cell,
            thresholds: Thresholds {
                min_width_ratio: self.min_width_ratio,
                max_overshoot: self.max_overshoot,
            },
            progress,
        })
    }
}

/// `impact run`'s `--method` (the CLI flattens it into its run flags, and
/// [`run_flags`] parses it the same way).
#[derive(clap::Args, Debug, Clone)]
pub struct MethodFlag {
    /// Methods to run, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "dgmpm,mpm,fem"
    )]
    pub method: Vec<MethodKind>,
}

/// The run's own flags besides the overrides: `--method`, as `impact run` takes it.
#[derive(clap::Parser)]
#[command(name = "impact", no_binary_name = true)]
struct RunFlags {
    #[command(flatten)]
    overrides: Overrides,
    #[command(flatten)]
    methods: MethodFlag,
}

#[derive(clap::Parser)]
#[command(name = "impact", no_binary_name = true)]
struct CheckArgs {
    #[command(flatten)]
    overrides: Overrides,
    #[command(flatten)]
    gate: CheckFlags,
}

/// The overrides and methods of `flags` (`["--cells", "200", "--method", "dgmpm,mpm"]`).
pub fn run_flags(flags: &[String]) -> Result<(Overrides, Vec<MethodKind>), FlagError> {
    use clap::Parser as _;
    RunFlags::try_parse_from(flags)
        .map(|f| (f.overrides, f.methods.method))
        .map_err(message)
}

/// The overrides and comparison flags of `flags` (`["--against", "all-mpm"]`).
pub fn check_flags(flags: &[String]) -> Result<(Overrides, CheckFlags), FlagError> {
    use clap::Parser as _;
    CheckArgs::try_parse_from(flags)
        .map(|f| (f.overrides, f.gate))
        .map_err(message)
}

/// clap's message up to its first blank line (the error and the allowed values), without
/// `error: `: the tips and usage after it are the CLI's.
fn message(e: clap::Error) -> FlagError {
    let text = e.render().to_string();
    let lines: Vec<&str> = text.lines().take_while(|l| !l.trim().is_empty()).collect();
    FlagError(lines.join("\n").trim_start_matches("error: ").to_string())
}
