//! Figures drawn with plotters: PNG (bitmap backend, DejaVu Sans embedded: no system
//! libraries or fonts needed), SVG (plotters' SVG backend) or PDF (vector, [`PdfBackend`],
//! the base-14 Helvetica), chosen by the file's extension, each written atomically.
//!
//! Conventions every figure follows (issue 13): axis labels with symbol and unit; tick
//! labels without exponents on linear axes (the caller scales values to a readable unit,
//! e.g. MPa) and `10ⁿ` at every decade on log axes (plotters' log coordinates over whole
//! decades, [`decade_range`]); the legend in its own column beside the panels; lines 2 px
//! wide (3 px for the exact/reference curve); markers only on sparse series
//! ([`MARKER_LIMIT`]); the Okabe–Ito colour-blind-safe palette ([`colour`]) with marker
//! shapes cycling too, so more than seven series stay apart; maps with a colour bar
//! (`colorous`' ColorBrewer RdBu, centred at zero, range from [`robust_range`]) and grey
//! for cells without data.
//!
//! Layout: `lines` (line panels, linear or log axes), `maps` (colour maps with a colour
//! bar), `bars` (grouped horizontal bars over named categories); [`Stacked`] puts two
//! figures one above the other.
mod bars;
mod lines;
mod maps;
mod pdf;
mod pdf_fonts;

pub use bars::{bar_chart, BarFigure, BarGroup};
pub use lines::{line_panels, Axis, LineFigure, Panel, Series};
pub use maps::{colour_maps, robust_range, MapFigure, MapPanel};
pub use pdf::{PdfBackend, PdfError};

use crate::IoError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        // the embedded font is valid TrueType; a failure would only lose the labels
        let _ = plotters::style::register_font(
            "sans-serif",
            plotters::style::FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// Series with at most this many points get markers; denser ones are lines only.
pub const MARKER_LIMIT: usize = 40;

/// Print resolution every figure is laid out for (PNG pixels per inch; an SVG's user
/// units are the same pixels, so it prints at the same proportions when scaled to its
/// stated width).
pub const DPI: f64 = 300.0;

/// Type sizes at print size (pt): panel titles, axis labels, tick labels and the legend
/// all within the 7-9 pt journals ask for.
pub mod type_size {
    /// Panel titles.
    pub const TITLE: f64 = 9.0;
    /// Axis labels and the legend.
    pub const LABEL: f64 = 8.0;
    /// Tick labels and notes.
    pub const TICK: f64 = 7.0;
}

/// The width a figure is made for: a journal's single column (90 mm) or full text width
/// (190 mm). Its pixel width is that at [`DPI`], so `pt` sizes print at their size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum PrintWidth {
    /// One column, 90 mm.
    Single,
    /// The full text width, 190 mm.
    #[default]
    Full,
}

impl PrintWidth {
    /// The width in millimetres.
    pub fn mm(self) -> f64 {
        match self {
            PrintWidth::Single => 90.0,
            PrintWidth::Full => 190.0,
        }
    }

    /// The width in pixels at [`DPI`].
    pub fn pixels(self) -> u32 {
        (self.mm() / 25.4 * DPI).round() as u32
    }

    /// Its name in `index.json` (`single column, 90 mm`).
    pub fn describe(self) -> &'static str {
        match self {
            PrintWidth::Single => "single column, 90 mm",
            PrintWidth::Full => "full width, 190 mm",
        }
    }
}

/// `points` (typographic, 1/72 in) in pixels at [`DPI`].
pub fn pt(points: f64) -> u32 {
    (points * DPI / 72.0).round() as u32
}

/// The font of `points` pt at print size.
pub fn font(points: f64) -> (&'static str, u32) {
    ("sans-serif", pt(points))
}

/// Okabe & Ito (2008) colour-blind-safe palette: 0 is black (exact/reference), then blue,
/// vermillion, bluish green, reddish purple, orange, sky blue, yellow; cycles beyond.
pub fn colour(index: usize) -> RGBColor {
    const OKABE_ITO: [RGBColor; 8] = [
        RGBColor(0, 0, 0),
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(240, 228, 66),
    ];
    if index == 0 {
        return OKABE_ITO[0];
    }
    OKABE_ITO[1 + (index - 1) % 7]
}

/// A whole-decade range `[10^a, 10^b]` holding `[low, high]` (positive), at least two
/// decades wide, so plotters' log coordinates put a labelled tick at every power of ten.
pub fn decade_range(low: f64, high: f64) -> (f64, f64) {
    let (low, high) = if low > 0.0 && high >= low && high.is_finite() {
        (low, high)
    } else {
        (1.0, 10.0)
    };
    let mut a = low.log10().floor();
    let mut b = high.log10().ceil();
    if b - a < 2.0 {
        let missing = 2.0 - (b - a);
        a -= (missing / 2.0).ceil();
        b += (missing / 2.0).floor();
    }
    // widened by 1e-9 so that round-off in plotters' decade stepping (0.1·10 > 1.0) keeps
    // the end decades
    (10f64.powf(a) * (1.0 - 1e-9), 10f64.powf(b) * (1.0 + 1e-9))
}

/// `10ⁿ` with a superscript exponent for a power of ten; a plain short number otherwise.
pub fn decade_label(value: f64) -> String {
    let exponent = value.log10().round();
    if value > 0.0 && (value / 10f64.powf(exponent) - 1.0).abs() < 1e-9 {
        const SUPERSCRIPT: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
        let mut text = String::from("10");
        if exponent < 0.0 {
            text.push('⁻');
        }
        for digit in format!("{}", exponent.abs() as i64).chars() {
            text.push(SUPERSCRIPT[digit.to_digit(10).unwrap_or(0) as usize]);
        }
        text
    } else {
        format!("{value:.3}")
    }
}

/// A tick label on a linear axis whose ticks are about `step` apart: fixed-point with just
/// enough decimals, never an exponent.
pub fn linear_label(value: f64, step: f64) -> String {
    let decimals = if step > 0.0 && step.is_finite() {
        (-(step.log10().floor())).clamp(0.0, 8.0) as usize
    } else {
        2
    };
    let text = format!("{value:.decimals$}");
    // "-0" and "-0.00" read as zero
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

/// A figure that draws itself on any plotters backend.
pub trait Draw {
    /// The printed width the figure is laid out for (its pixel width is that at [`DPI`]).
    fn print_width(&self) -> PrintWidth {
        PrintWidth::Full
    }
    /// Lay the figure out for `width` instead (its pixel width, the panels and legend
    /// sized to it; the type sizes stay [`type_size`]'s at print size).
    fn set_print_width(&mut self, width: PrintWidth);
    /// Size in pixels (PNG) or user units (SVG).
    fn size(&self) -> (u32, u32);
    /// Draw onto `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
    /// The plotted numbers as CSV text, where the figure has curves (line figures:
    /// `panel,series,x,y`, one row per plotted point, in the axes' units and `f64`'s
    /// shortest round-trip digits), so that a figure can be checked against the run it
    /// draws; `None` for maps and bars.
    fn data(&self) -> Option<String> {
        None
    }
}

/// Two figures, one above the other (e.g. Fig. 5's maps above its profiles).
pub struct Stacked<A, B>(pub A, pub B);

impl<A: Draw, B: Draw> Draw for Stacked<A, B> {
    fn print_width(&self) -> PrintWidth {
        self.0.print_width()
    }

    fn set_print_width(&mut self, width: PrintWidth) {
        self.0.set_print_width(width);
        self.1.set_print_width(width);
    }

    fn size(&self) -> (u32, u32) {
        let (a, b) = (self.0.size(), self.1.size());
        (a.0.max(b.0), a.1 + b.1)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(text)?;
        let (top, bottom) = root.split_vertically(self.0.size().1);
        let top = top.shrink((0, 0), self.0.size());
        let bottom = bottom.shrink((0, 0), self.1.size());
        self.0.draw(&top)?;
        self.1.draw(&bottom)
    }

    /// The data of the part that has curves (the upper one first).
    fn data(&self) -> Option<String> {
        self.0.data().or_else(|| self.1.data())
    }
}

/// Draw `figure` into `path`: SVG when the extension is `svg`, PDF when it is `pdf` (vector,
/// the page at the figure's printed width, [`PdfBackend`]), PNG otherwise; written to a
/// temporary name and renamed.
pub fn save(path: &Path, figure: &impl Draw) -> Result<(), IoError> {
    register_font();
    let err = |message: String| IoError::Plot {
        path: path.to_path_buf(),
        message,
    };
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("png");
    let svg = extension == "svg";
    let tmp = crate::temporary_path(path).with_extension(format!("tmp.{extension}"));
    let result = if extension == "pdf" {
        let mut pdf = Vec::new();
        {
            let root = PdfBackend::new(&mut pdf, figure.size()).into_drawing_area();
            figure
                .draw(&root)
                .and_then(|_| root.present().map_err(|e| e.to_string()))
        }
        .and_then(|_| std::fs::write(&tmp, pdf).map_err(|e| e.to_string()))
    } else if svg {
        let root = SVGBackend::new(&tmp, figure.size()).into_drawing_area();
        figure
            .draw(&root)
            .and_then(|_| root.present().map_err(|e| e.to_string()))
    } else {
        let root = BitMapBackend::new(&tmp, figure.size()).into_drawing_area();
        figure
            .draw(&root)
            .and_then(|_| root.present().map_err(|e| e.to_string()))
    };
    if let Err(message) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(message));
    }
    std::fs::rename(&tmp, path).map_err(|source| IoError::File {
        path: path.to_path_buf(),
        source,
    })
}

/// Draw `title` centred in a strip at the top of `area` (`points` pt) and return the area
/// under it, so tick labels at the top of a chart never run into its title.
pub fn titled<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    points: f64,
) -> Result<DrawingArea<DB, Shift>, String> {
    let height = (1.9 * pt(points) as f64) as u32;
    let (strip, rest) = area.split_vertically(height);
    let style =
        TextStyle::from(font(points).into_font()).pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
    let (w, h) = strip.dim_in_pixel();
    strip
        .draw(&Text::new(
            title.to_string(),
            (w as i32 / 2, h as i32 / 2),
            style,
        ))
        .map_err(text)?;
    Ok(rest)
}

/// A plotters error as text.
fn text<E: std::fmt::Debug>(e: E) -> String {
    format!("{e:?}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::coord::ranged1d::Ranged;
    use plotters::prelude::LogCoord;

    #[test]
    fn log_axes_tick_at_every_power_of_ten() {
        for (low, high) in [(3.2e-5, 0.7), (0.011, 0.09), (2.0, 2.5), (1e-3, 1e3)] {
            let (a, b) = decade_range(low, high);
            assert!(
                a <= low && b >= high && b / a >= 99.9,
                "{low}..{high}: {a}..{b}"
            );
            // whole decades
            assert!((a.log10() - a.log10().round()).abs() < 1e-8, "{a}");
            let coord: LogCoord<f64> = (a..b).log_scale().into();
            let ticks = coord.key_points(10);
            let decades = (b / a).log10().round() as usize;
            assert_eq!(ticks.len(), decades + 1, "{ticks:?}");
            for t in &ticks {
                let exponent = t.log10().round();
                assert!(
                    (t / 10f64.powf(exponent) - 1.0).abs() < 1e-12,
                    "{t} in {ticks:?}"
                );
            }
        }
        assert_eq!(decade_label(1e-3), "10⁻³");
        assert_eq!(decade_label(100.0), "10²");
        assert_eq!(decade_label(1.0), "10⁰");
    }

    #[test]
    fn type_sizes_in_pixels_at_print_width() {
        // 7-9 pt at print size: 29-38 px at 300 dpi
        assert_eq!((pt(7.0), pt(9.0)), (29, 38));
        assert_eq!(PrintWidth::Full.pixels(), 2244);
        assert_eq!(PrintWidth::Single.pixels(), 1063);
    }

    #[test]
    fn linear_labels_have_no_exponent() {
        assert_eq!(linear_label(-250.0, 50.0), "-250");
        assert_eq!(linear_label(0.35, 0.05), "0.35");
        assert_eq!(linear_label(-0.0, 0.5), "0.0");
        assert!(!linear_label(1234.5, 100.0).contains('e'));
    }
}
