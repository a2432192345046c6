//! `impact figures`: the paper's comparison figures and the studies no paper has, in one
//! command, each as PNG and SVG, with `index.html` (every figure, the command that remakes
//! it, its key numbers, the machine) and `index.json` (the same, for scripts).
//!
//! Figures ([`FigureName`]):
//! - `fig3`: the elastic bar (paper Fig. 3): σₓₓ(x) at the scene's three output times,
//!   DGMPM, MPM, FEM and the exact solution.
//! - `fig5`: the partial plate impact (paper Fig. 5): σₓₓ maps of MPM, FEM, DGMPM and the
//!   converged reference at the three output times with one colour bar, above the
//!   bottom-row profiles at the same times.
//! - `fig6`: the Saint-Venant–Kirchhoff bar (paper Fig. 6): the displacement of DGMPM's
//!   points at each output time, and Πₓₓ of every method against the exact solution.
//! - `work-precision`: error against run time on the bar, svk-bar, plate-wave and plate
//!   (reduced ladders; `--full`: the ladders of `impact bench work-precision`).
//! - `stability`: critical Courant numbers (empirical, von Neumann, monotone) of every
//!   configuration (reduced perturbed runs; `--full`: those of `impact stability`).
//! - `mpm-variants`: DGMPM against MPM with every shape function on the bar.
//! - `elastoplastic`: both fronts (precursor and plastic wave) of ep-bar and ep-plate-wave,
//!   with the elastic and the elastoplastic Riemann solvers.
//!
//! The folder is replaced as a whole when complete ([`impact_io::folder::OutputFolder`]);
//! making some figures keeps the others already there (their files and index entries).
//! Every figure is laid out for one printed width, `--width full` (190 mm, the default) or
//! `--width single` (a 90 mm column), at 300 dpi, with 7-9 pt text at that width (the
//! type sizes stay, the panels shrink); each entry of `index.json` records the PNG's pixel
//! size and that width. Every figure is written as PNG, SVG and PDF, both vector (the PDF
//! by [`impact_io::plot::PdfBackend`], its page the printed width).
mod paper;
mod studies;
mod three_d;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One figure of `impact figures`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FigureName {
    /// The elastic bar (paper Fig. 3).
    Fig3,
    /// The partial plate impact (paper Fig. 5).
    Fig5,
    /// The Saint-Venant–Kirchhoff bar (paper Fig. 6).
    Fig6,
    /// Work-precision of every configuration on four scenes.
    WorkPrecision,
    /// The stability map.
    Stability,
    /// DGMPM against every MPM shape function.
    MpmVariants,
    /// The elastoplastic fronts of ep-bar and ep-plate-wave.
    Elastoplastic,
    Block,
    Lamb,
}

impl FigureName {
    /// Every figure, in index order.
    pub const ALL: [FigureName; 9] = [
        FigureName::Fig3,
        FigureName::Fig5,
        FigureName::Fig6,
        FigureName::WorkPrecision,
        FigureName::Stability,
        FigureName::MpmVariants,
        FigureName::Elastoplastic,
        FigureName::Block,
        FigureName::Lamb,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            FigureName::Fig3 => "fig3",
            FigureName::Fig5 => "fig5",
            FigureName::Fig6 => "fig6",
            FigureName::WorkPrecision => "work-precision",
            FigureName::Stability => "stability",
            FigureName::MpmVariants => "mpm-variants",
            FigureName::Elastoplastic => "elastoplastic",
            FigureName::Block => "block",
            FigureName::Lamb => "lamb",
        }
    }
}

/// What `impact figures` was asked for.
#[derive(Debug, Clone)]
pub struct FiguresOptions {
    /// Output folder.
    pub out: PathBuf,
    /// Paper-scale ladders and sweeps instead of the reduced ones.
    pub full: bool,
    /// The figures to make (empty: all).
    pub only: Vec<FigureName>,
    /// Progress bars and status lines on stderr.
    pub progress: bool,
    /// The printed width every figure is laid out for (`--width`).
    pub width: impact_io::plot::PrintWidth,
}

/// One image of an entry: file stem and pixel size of its PNG.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Image {
    /// File stem: `<stem>.png`, `<stem>.svg` and `<stem>.pdf`.
    pub stem: String,
    /// PNG width and height in pixels (300 dpi at the printed width).
    pub size: [u32; 2],
    /// The printed width the figure is laid out for, with 7-9 pt text at that width
    /// (`full width, 190 mm` or `single column, 90 mm`).
    #[serde(default)]
    pub print_width: String,
    /// The plotted numbers beside the image (`<stem>.csv`: `panel,series,x,y`), for
    /// figures with curves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data: Option<String>,
}

/// One figure in the index.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Entry {
    /// Command-line name (`fig5`).
    pub name: String,
    /// Title.
    pub title: String,
    /// Its images.
    pub images: Vec<Image>,
    /// The command that remakes it.
    pub command: String,
    /// Key numbers (errors, front widths, run times), one line each.
    pub numbers: Vec<String>,
    /// Seconds it took.
    pub seconds: f64,
}

/// `index.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Index {
    /// `impact` version.
    pub version: String,
    /// The machine it ran on.
    pub machine: String,
    /// Reduced (default) or full settings of the last call.
    pub settings: String,
    /// The figures, in [`FigureName::ALL`] order.
    pub entries: Vec<Entry>,
}

/// The CPU model and thread count of this machine (Linux `/proc/cpuinfo`).
pub fn machine() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!(
        "{model}, {threads} threads available, {}",
        std::env::consts::OS
    )
}

/// Where one figure's images go, and how it is remade.
pub struct Target<'a> {
    dir: &'a Path,
    command: String,
    full: bool,
    progress: bool,
    width: impact_io::plot::PrintWidth,
}

impl Target<'_> {
    /// Save `figure`, laid out for the asked printed width, as `<stem>.png`, `<stem>.svg`
    /// and `<stem>.pdf`; the image record.
    pub fn save(&self, stem: &str, mut figure: impl impact_io::plot::Draw) -> Result<Image> {
        figure.set_print_width(self.width);
        for extension in ["png", "svg", "pdf"] {
            let path = self.dir.join(format!("{stem}.{extension}"));
            impact_io::plot::save(&path, &figure)
                .with_context(|| format!("drawing {}", path.display()))?;
        }
        let data = match figure.data() {
            Some(csv) => {
                let path = self.dir.join(format!("{stem}.csv"));
                std::fs::write(&path, csv)
                    .with_context(|| format!("writing {}", path.display()))?;
                Some(format!("{stem}.csv"))
            }
            None => None,
        };
        let (width, height) = figure.size();
        Ok(Image {
            stem: stem.to_string(),
            size: [width, height],
            print_width: figure.print_width().describe().to_string(),
            data,
        })
    }
}

/// Make the figures of `options` into `options.out`; the index written.
pub fn run(options: &FiguresOptions) -> Result<Index> {
    let clock = crate::provenance::Clock::start();
    let folder = impact_io::folder::OutputFolder::open(&options.out)?;
    let dir = folder.path().to_path_buf();
    let wanted: Vec<FigureName> = if options.only.is_empty() {
        FigureName::ALL.to_vec()
    } else {
        options.only.clone()
    };
    // figures not asked for this time are kept from the folder being replaced
    let previous = read_index(&options.out).unwrap_or_default();
    let mut entries = Vec::new();
    for name in FigureName::ALL {
        if !wanted.contains(&name) {
            if let Some(e) = previous.iter().find(|e| e.name == name.name()) {
                carry_over(&options.out, &dir, e)?;
                entries.push(e.clone());
            }
            continue;
        }
        let full = if options.full { " --full" } else { "" };
        let width = match options.width {
            impact_io::plot::PrintWidth::Full => "",
            impact_io::plot::PrintWidth::Single => " --width single",
        };
        let target = Target {
            dir: &dir,
            command: format!(
                "impact figures {} --out {}{full}{width}",
                name.name(),
                options.out.display()
            ),
            full: options.full,
            progress: options.progress,
            width: options.width,
        };
        if options.progress {
            crate::root_eprintln!("figures: making {}", name.name());
        }
        let start = std::time::Instant::now();
        let mut entry = match name {
            FigureName::Fig3 => paper::fig3(&target)?,
            FigureName::Fig5 => paper::fig5(&target)?,
            FigureName::Fig6 => paper::fig6(&target)?,
            FigureName::WorkPrecision => studies::work_precision(&target)?,
            FigureName::Stability => studies::stability(&target)?,
            FigureName::MpmVariants => studies::mpm_variants(&target)?,
            FigureName::Elastoplastic => studies::elastoplastic(&target)?,
            FigureName::Block => three_d::block(&target)?,
            FigureName::Lamb => three_d::lamb(&target)?,
        };
        entry.seconds = start.elapsed().as_secs_f64();
        entries.push(entry);
        crate::interrupt::check()?;
    }
    let index = Index {
        version: env!("CARGO_PKG_VERSION").to_string(),
        machine: machine(),
        settings: if options.full {
            "full"
        } else {
            "reduced (default)"
        }
        .into(),
        entries,
    };
    impact_io::write_json(&dir.join("index.json"), &index)?;
    let html = index_html(&index);
    impact_io::write_atomic(&dir.join("index.html"), |w| w.write_all(html.as_bytes()))?;
    let mut record = crate::provenance::Provenance::new("figures", &clock);
    record.reference =
        "per figure: the shipped scenes' (index.json names each figure's command)".into();
    record.write(&dir, &clock)?;
    folder.commit(concat!("impact ", env!("CARGO_PKG_VERSION")))?;
    Ok(index)
}

/// The entries of an existing `index.json` in `dir`.
fn read_index(dir: &Path) -> Option<Vec<Entry>> {
    let text = std::fs::read_to_string(dir.join("index.json")).ok()?;
    serde_json::from_str::<Index>(&text).ok().map(|i| i.entries)
}

/// Copy an entry's images from the folder being replaced into the staging folder.
fn carry_over(from: &Path, to: &Path, entry: &Entry) -> Result<()> {
    for image in &entry.images {
        for extension in ["png", "svg", "pdf"] {
            let name = format!("{}.{extension}", image.stem);
            // an index of an earlier version has no PDF
            if extension == "pdf" && !from.join(&name).exists() {
                continue;
            }
            std::fs::copy(from.join(&name), to.join(&name))
                .with_context(|| format!("keeping {}", from.join(&name).display()))?;
        }
        if let Some(name) = &image.data {
            std::fs::copy(from.join(name), to.join(name))
                .with_context(|| format!("keeping {}", from.join(name).display()))?;
        }
    }
    Ok(())
}

/// `<`, `>`, `&` escaped for HTML text.
fn html_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The index page: every figure with its command, numbers and timing.
pub fn index_html(index: &Index) -> String {
    let mut html = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>impact figures</title>\n<style>body{font-family:sans-serif;max-width:1400px;\
         margin:auto;padding:1em}img{max-width:100%;border:1px solid #ddd}\
         pre{background:#f4f4f4;padding:.5em}</style></head><body>\n",
    );
    html.push_str(&format!(
        "<h1>impact {}: figures</h1>\n<p>Machine: {}. Settings: {}.</p>\n<ul>\n",
        html_escape(&index.version),
        html_escape(&index.machine),
        html_escape(&index.settings)
    ));
    for e in &index.entries {
        html.push_str(&format!(
            "<li><a href=\"#{}\">{}</a></li>\n",
            e.name,
            html_escape(&e.title)
        ));
    }
    html.push_str("</ul>\n");
    for e in &index.entries {
        html.push_str(&format!(
            "<h2 id=\"{}\">{}</h2>\n<pre>{}</pre>\n",
            e.name,
            html_escape(&e.title),
            html_escape(&e.command)
        ));
        for image in &e.images {
            html.push_str(&format!(
                "<p><img src=\"{0}.png\" width=\"{3}\" alt=\"{0}\"><br>\
                 <a href=\"{0}.svg\">{0}.svg</a> · <a href=\"{0}.pdf\">{0}.pdf</a> · \
                 <a href=\"{0}.png\">{0}.png</a> ({1}×{2} px; {4})</p>\n",
                image.stem,
                image.size[0],
                image.size[1],
                image.size[0] / 2,
                image.print_width
            ));
        }
        html.push_str("<ul>\n");
        for line in &e.numbers {
            html.push_str(&format!("<li>{}</li>\n", html_escape(line)));
        }
        html.push_str(&format!("<li>made in {:.2} s</li>\n</ul>\n", e.seconds));
    }
    html.push_str("</body></html>\n");
    html
}
