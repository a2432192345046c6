//! PNG line plots drawn with plotters (bitmap backend, DejaVu Sans embedded: no system
//! libraries or fonts needed).
use crate::IoError;
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

/// One curve of a panel.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
    /// Colour index (0 exact/black, 1.. methods).
    pub colour: usize,
    /// Draw as a stepwise dashed reference.
    pub reference: bool,
}

/// One panel: a title and its curves.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// Curves.
    pub series: Vec<Series>,
    /// This panel's y-axis label (default: the figure's).
    pub y_label: Option<String>,
}

fn colour(i: usize) -> RGBColor {
    const PALETTE: [RGBColor; 13] = [
        RGBColor(0, 0, 0),
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(255, 127, 14),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
        RGBColor(0, 0, 128),
        RGBColor(128, 0, 0),
    ];
    PALETTE[i % PALETTE.len()]
}

/// Draw `panels` stacked vertically into a PNG at `path` (written atomically).
pub fn line_panels(
    path: &Path,
    panels: &[Panel],
    x_label: &str,
    y_label: &str,
) -> Result<(), IoError> {
    register_font();
    let err = |e: String| IoError::Plot {
        path: path.to_path_buf(),
        message: e,
    };
    let tmp = crate::temporary_path(path).with_extension("tmp.png");
    let height = 330 * panels.len().max(1) as u32;
    {
        let root = BitMapBackend::new(&tmp, (1000, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let areas = root.split_evenly((panels.len().max(1), 1));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            for s in &panel.series {
                for &(x, y) in &s.points {
                    if x.is_finite() && y.is_finite() {
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                        y0 = y0.min(y);
                        y1 = y1.max(y);
                    }
                }
            }
            if x0 > x1 {
                (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
            }
            let pad = 0.08 * (y1 - y0).max(1e-30);
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, ("sans-serif", 20))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(80)
                .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(panel.y_label.as_deref().unwrap_or(y_label))
                .y_label_formatter(&|v| format!("{v:.2e}"))
                .draw()
                .map_err(|e| err(e.to_string()))?;
            for s in &panel.series {
                let c = colour(s.colour);
                let style = if s.reference {
                    c.stroke_width(2)
                } else {
                    c.stroke_width(1)
                };
                chart
                    .draw_series(LineSeries::new(s.points.iter().copied(), style))
                    .map_err(|e| err(e.to_string()))?
                    .label(s.label.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
                if !s.reference {
                    chart
                        .draw_series(
                            s.points
                                .iter()
                                .map(|&(x, y)| Circle::new((x, y), 2, c.filled())),
                        )
                        .map_err(|e| err(e.to_string()))?;
                }
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(SeriesLabelPosition::LowerRight)
                .draw()
                .map_err(|e| err(e.to_string()))?;
        }
        root.present().map_err(|e| err(e.to_string()))?;
    }
    std::fs::rename(&tmp, path).map_err(|source| IoError::File {
        path: path.to_path_buf(),
        source,
    })
}

/// One colour map: values per cell of a regular `nx × ny` grid covering `extent`.
#[derive(Debug, Clone)]
pub struct MapPanel {
    /// Panel title.
    pub title: String,
    /// Cells along x and y.
    pub cells: [usize; 2],
    /// `[x0, x1, y0, y1]`.
    pub extent: [f64; 4],
    /// Values, x fastest (`NaN` = no data).
    pub values: Vec<f64>,
}

/// Blue-white-red diverging colour for `s` in `[-1, 1]`.
fn diverging(s: f64) -> RGBColor {
    let s = s.clamp(-1.0, 1.0);
    let (r, g, b) = if s < 0.0 {
        let a = 1.0 + s;
        (a, a, 1.0)
    } else {
        let a = 1.0 - s;
        (1.0, a, a)
    };
    RGBColor((r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8)
}

/// Draw colour maps side by side with a shared symmetric range `[-range, range]`
/// (blue: compression, red: tension) into a PNG at `path` (written atomically).
pub fn colour_maps(
    path: &Path,
    panels: &[MapPanel],
    range: f64,
    label: &str,
) -> Result<(), IoError> {
    register_font();
    let err = |e: String| IoError::Plot {
        path: path.to_path_buf(),
        message: e,
    };
    let tmp = crate::temporary_path(path).with_extension("tmp.png");
    let width = 420 * panels.len().max(1) as u32;
    {
        let root = BitMapBackend::new(&tmp, (width, 420)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let (top, bottom) = root.split_vertically(380);
        let areas = top.split_evenly((1, panels.len().max(1)));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            let [x0, x1, y0, y1] = panel.extent;
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, ("sans-serif", 18))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(40)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .disable_mesh()
                .draw()
                .map_err(|e| err(e.to_string()))?;
            let [nx, ny] = panel.cells;
            let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
            chart
                .draw_series(
                    (0..ny)
                        .flat_map(|j| (0..nx).map(move |i| (i, j)))
                        .filter_map(|(i, j)| {
                            let v = panel.values[j * nx + i];
                            v.is_finite().then(|| {
                                let (xa, ya) = (x0 + i as f64 * dx, y0 + j as f64 * dy);
                                Rectangle::new(
                                    [(xa, ya), (xa + dx, ya + dy)],
                                    diverging(v / range).filled(),
                                )
                            })
                        }),
                )
                .map_err(|e| err(e.to_string()))?;
        }
        bottom
            .draw(&Text::new(
                format!("{label}: blue -{range:.3e} (compression) .. white 0 .. red +{range:.3e}"),
                (20, 10),
                ("sans-serif", 16),
            ))
            .map_err(|e| err(e.to_string()))?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    std::fs::rename(&tmp, path).map_err(|source| IoError::File {
        path: path.to_path_buf(),
        source,
    })
}
