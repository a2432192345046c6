//! A vector PDF backend for plotters: every figure's `.pdf` is drawn with PDF 1.4 path and
//! text operators, with no system library (plotters' own PDF route, plotters-cairo, needs
//! the system's cairo).
//!
//! The page is the figure's printed width ([`PrintWidth`](super::PrintWidth)), so one
//! pixel of the figure's layout (laid out at [`DPI`]) is `72 / DPI` pt. The content stream
//! starts with `s 0 0 -s 0 H cm` (s = page width / pixel width, H = page height): the
//! drawing then uses plotters' pixel coordinates, y down, unchanged. Lines, polylines,
//! polygons and rectangles are paths (`m`/`l`/`re`, stroked with `S` or filled with `f`);
//! circles are four cubic Bézier arcs (control points at κ = 0.5523 of the radius,
//! radial error 0.03 %); single pixels are 1 × 1 squares. Strokes are drawn through pixel
//! centres (+0.5), as the bitmap backend covers the pixel right and below a coordinate;
//! filled rectangles cover their end pixels (plotters' corners are inclusive). Round caps
//! and joins. Transparency is not used by the figures: a colour with alpha 0 draws
//! nothing, any other is opaque.
//!
//! Text uses the base-14 fonts every PDF reader has, not embedded: Helvetica
//! (WinAnsiEncoding) for Latin text and Symbol for Greek letters and mathematical signs;
//! superscript and subscript characters (`10⁻³`, `σₓₓ`) are set at 70 % size with a text
//! rise of +0.33 em / −0.15 em. A character neither font has is drawn as `?`. Text
//! extents, for plotters' layout and for anchoring, are the fonts' standard advance widths
//! (Adobe's AFM metrics, `pdf_fonts.rs`). The em is the style's size in pixels, so an 8 pt
//! label (`pt(8.0)` px at [`DPI`]) is set at 8 pt; plotters' bitmap and SVG backends set
//! it at 0.86 and 0.81 of that (`size / 1.24` in SVG). Text is anchored as the SVG backend
//! anchors it: the baseline 0.76 em under the top (`VPos::Top`), 0.36 em under the centre
//! (about half Helvetica's cap height, 0.718 em) and 0.21 em over the bottom (its
//! descender); rotations of 90°, 180° and 270° set the text matrix.
//!
//! The file: catalog, pages, one page, its Flate-compressed content stream, the two
//! fonts; a cross-reference table with every object's byte offset.
use super::pdf_fonts::{runs, Run, Script};
use super::DPI;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
    FontTransform,
};
use std::fmt::Write as _;

/// The error of a PDF drawing (compression only; drawing itself cannot fail).
#[derive(Debug, thiserror::Error)]
#[error("PDF: {0}")]
pub struct PdfError(String);

/// A plotters backend that writes a one-page vector PDF into `out` on [`present`](
/// DrawingBackend::present).
pub struct PdfBackend<'a> {
    out: &'a mut Vec<u8>,
    size: (u32, u32),
    content: String,
}

impl<'a> PdfBackend<'a> {
    /// A page of `size` pixels (at [`DPI`]), written into `out`.
    pub fn new(out: &'a mut Vec<u8>, size: (u32, u32)) -> Self {
        let (w, h) = (size.0.max(1), size.1.max(1));
        let scale = 72.0 / DPI;
        let content = format!(
            "1 J 1 j\n{} 0 0 {} 0 {} cm\n",
            num(scale),
            num(-scale),
            num(h as f64 * scale)
        );
        Self {
            out,
            size: (w, h),
            content,
        }
    }

    /// `r g b` (0-1) of `color` followed by `op` (`RG` stroke, `rg` fill); `None` for a
    /// transparent colour.
    fn colour(&mut self, color: BackendColor, op: &str) -> Option<()> {
        if color.alpha == 0.0 {
            return None;
        }
        let (r, g, b) = color.rgb;
        let c = |v: u8| num(v as f64 / 255.0);
        let _ = writeln!(self.content, "{} {} {} {op}", c(r), c(g), c(b));
        Some(())
    }

    /// Stroke colour and width of `style`.
    fn stroke<S: BackendStyle>(&mut self, style: &S) -> Option<()> {
        self.colour(style.color(), "RG")?;
        let _ = writeln!(self.content, "{} w", style.stroke_width().max(1));
        Some(())
    }

    /// A path through `points` (pixel centres), closed or not, then `op`.
    fn path(&mut self, points: impl IntoIterator<Item = BackendCoord>, close: bool, op: &str) {
        for (k, (x, y)) in points.into_iter().enumerate() {
            let verb = if k == 0 { "m" } else { "l" };
            let _ = writeln!(self.content, "{} {} {verb}", x as f64 + 0.5, y as f64 + 0.5);
        }
        self.content.push_str(if close { "h " } else { "" });
        self.content.push_str(op);
        self.content.push('\n');
    }
}

type Result<T> = std::result::Result<T, DrawingErrorKind<PdfError>>;

impl DrawingBackend for PdfBackend<'_> {
    type ErrorType = PdfError;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }

    fn ensure_prepared(&mut self) -> Result<()> {
        Ok(())
    }

    fn present(&mut self) -> Result<()> {
        let pdf = document(&self.content, self.size)
            .map_err(|e| DrawingErrorKind::DrawingError(PdfError(e)))?;
        *self.out = pdf;
        Ok(())
    }

    fn draw_pixel(&mut self, (x, y): BackendCoord, color: BackendColor) -> Result<()> {
        if self.colour(color, "rg").is_some() {
            let _ = writeln!(self.content, "{x} {y} 1 1 re f");
        }
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<()> {
        if self.stroke(style).is_some() {
            self.path([from, to], false, "S");
        }
        Ok(())
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        (x0, y0): BackendCoord,
        (x1, y1): BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<()> {
        let (left, top) = (x0.min(x1), y0.min(y1));
        let (w, h) = ((x1 - x0).abs(), (y1 - y0).abs());
        if fill {
            if self.colour(style.color(), "rg").is_some() {
                let _ = writeln!(self.content, "{left} {top} {} {} re f", w + 1, h + 1);
            }
        } else if self.stroke(style).is_some() {
            let (x, y) = (left as f64 + 0.5, top as f64 + 0.5);
            let _ = writeln!(self.content, "{x} {y} {w} {h} re S");
        }
        Ok(())
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<()> {
        if self.stroke(style).is_some() {
            self.path(path, false, "S");
        }
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        (cx, cy): BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<()> {
        let drawn = match fill {
            true => self.colour(style.color(), "rg"),
            false => self.stroke(style),
        };
        if drawn.is_none() {
            return Ok(());
        }
        const KAPPA: f64 = 0.552_284_75;
        let (x, y, r) = (cx as f64 + 0.5, cy as f64 + 0.5, radius as f64);
        let k = KAPPA * r;
        let c = &mut self.content;
        let _ = writeln!(c, "{} {} m", num(x + r), num(y));
        // four quarter arcs from the axis direction `a` to `b`: right, down, left, up
        let axes = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (1.0, 0.0)];
        for pair in axes.windows(2) {
            let ((ax, ay), (bx, by)) = (pair[0], pair[1]);
            let _ = writeln!(
                c,
                "{} {} {} {} {} {} c",
                num(x + r * ax + k * bx),
                num(y + r * ay + k * by),
                num(x + r * bx + k * ax),
                num(y + r * by + k * ay),
                num(x + r * bx),
                num(y + r * by)
            );
        }
        c.push_str(if fill { "h f\n" } else { "h S\n" });
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<()> {
        if self.colour(style.color(), "rg").is_some() {
            self.path(vert, true, "f");
        }
        Ok(())
    }

    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        (x, y): BackendCoord,
    ) -> Result<()> {
        let em = style.size();
        let runs = runs(text);
        let width = em * runs.iter().map(Run::width).sum::<f64>();
        if self.colour(style.color(), "rg").is_none() || runs.is_empty() {
            return Ok(());
        }
        let along = match style.anchor().h_pos {
            HPos::Left => 0.0,
            HPos::Center => -width / 2.0,
            HPos::Right => -width,
        };
        let down = em
            * match style.anchor().v_pos {
                VPos::Top => 0.76,
                VPos::Center => 0.36,
                VPos::Bottom => -0.21,
            };
        // the text direction on the page (y down), turned clockwise
        let (cos, sin) = match style.transform() {
            FontTransform::None => (1.0, 0.0),
            FontTransform::Rotate90 => (0.0, 1.0),
            FontTransform::Rotate180 => (-1.0, 0.0),
            FontTransform::Rotate270 => (0.0, -1.0),
        };
        let ox = x as f64 + along * cos - down * sin;
        let oy = y as f64 + along * sin + down * cos;
        let c = &mut self.content;
        let _ = writeln!(
            c,
            "BT {cos} {sin} {sin} {} {} {} Tm",
            -cos,
            num(ox),
            num(oy)
        );
        for run in &runs {
            let (scale, rise) = match run.script {
                Script::Normal => (1.0, 0.0),
                Script::Super => (0.7, 0.33),
                Script::Sub => (0.7, -0.15),
            };
            let font = if run.symbol { "F2" } else { "F1" };
            let _ = write!(c, "/{font} {} Tf {} Ts (", num(em * scale), num(em * rise));
            for &byte in &run.bytes {
                match byte {
                    b'(' | b')' | b'\\' => {
                        c.push('\\');
                        c.push(byte as char);
                    }
                    32..=126 => c.push(byte as char),
                    _ => {
                        let _ = write!(c, "\\{byte:03o}");
                    }
                }
            }
            c.push_str(") Tj\n");
        }
        c.push_str("ET\n");
        Ok(())
    }

    fn estimate_text_size<T: BackendTextStyle>(&self, text: &str, style: &T) -> Result<(u32, u32)> {
        let em = style.size();
        let width = em * runs(text).iter().map(Run::width).sum::<f64>();
        Ok((width.ceil() as u32, em.ceil() as u32))
    }
}

/// A number with at most three decimals, without trailing zeros.
fn num(v: f64) -> String {
    let text = format!("{v:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" | "" => "0".into(),
        t => t.into(),
    }
}

/// The PDF file of one page of `size` pixels drawn by `content`.
fn document(content: &str, size: (u32, u32)) -> std::result::Result<Vec<u8>, String> {
    use std::io::Write as _;
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(content.as_bytes()).map_err(|e| e.to_string())?;
    let stream = z.finish().map_err(|e| e.to_string())?;
    let page_w = size.0 as f64 * 72.0 / DPI;
    let page_h = size.1 as f64 * 72.0 / DPI;
    let mut out: Vec<u8> = b"%PDF-1.4\n%\xe2\xe3\xcf\xd3\n".to_vec();
    let mut offsets = Vec::new();
    let mut object = |out: &mut Vec<u8>, body: &[u8]| {
        offsets.push(out.len());
        out.extend_from_slice(format!("{} 0 obj\n", offsets.len()).as_bytes());
        out.extend_from_slice(body);
        out.extend_from_slice(b"\nendobj\n");
    };
    object(&mut out, b"<< /Type /Catalog /Pages 2 0 R >>");
    object(&mut out, b"<< /Type /Pages /Kids [3 0 R] /Count 1 >>");
    let page = format!(
        "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {} {}] \
         /Resources << /Font << /F1 5 0 R /F2 6 0 R >> >> /Contents 4 0 R >>",
        num(page_w),
        num(page_h)
    );
    object(&mut out, page.as_bytes());
    let mut body = format!(
        "<< /Length {} /Filter /FlateDecode >>\nstream\n",
        stream.len()
    )
    .into_bytes();
    body.extend_from_slice(&stream);
    body.extend_from_slice(b"\nendstream");
    object(&mut out, &body);
    object(
        &mut out,
        b"<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>",
    );
    object(
        &mut out,
        b"<< /Type /Font /Subtype /Type1 /BaseFont /Symbol >>",
    );
    let xref = out.len();
    let count = offsets.len() + 1;
    out.extend_from_slice(format!("xref\n0 {count}\n0000000000 65535 f \n").as_bytes());
    for o in &offsets {
        out.extend_from_slice(format!("{o:010} 00000 n \n").as_bytes());
    }
    out.extend_from_slice(
        format!("trailer\n<< /Size {count} /Root 1 0 R >>\nstartxref\n{xref}\n%%EOF\n").as_bytes(),
    );
    Ok(out)
}
