//! `impact figures`: its flags and the list of figures made (stdout).
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub(crate) struct FiguresArgs {
    /// Figures to make (default: all); the others already in the folder are kept.
    #[arg(value_enum)]
    figures: Vec<impact::figures::FigureName>,
    /// Output folder.
    #[arg(long, default_value = "figures")]
    out: PathBuf,
    /// Paper-scale ladders and sweeps (minutes to an hour) instead of the reduced ones.
    #[arg(long)]
    full: bool,
    /// The printed width the figures are laid out for, with 7-9 pt text at that size:
    /// `full` (190 mm, a journal's text width) or `single` (a 90 mm column).
    #[arg(long, value_enum, default_value = "full")]
    width: impact_io::plot::PrintWidth,
    /// No progress bars or status lines on stderr.
    #[arg(long)]
    quiet: bool,
}

pub(crate) fn command(args: &FiguresArgs) -> Result<()> {
    let index = impact::figures::run(&impact::figures::FiguresOptions {
        out: args.out.clone(),
        full: args.full,
        only: args.figures.clone(),
        progress: !args.quiet,
        width: args.width,
    })?;
    for e in &index.entries {
        let stems: Vec<&str> = e.images.iter().map(|i| i.stem.as_str()).collect();
        say!("{:<15} {:>7.2} s  {}", e.name, e.seconds, stems.join(", "));
    }
    say!("wrote {}", args.out.join("index.html").display());
    Ok(())
}
