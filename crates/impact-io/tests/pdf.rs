//! The vector PDF of a figure (`plot::save` to `.pdf`, `plot::PdfBackend`): a valid
//! one-page PDF 1.4 whose cross-reference table points at every object, its page the
//! printed width, its labels text (not pixels) in Helvetica and Symbol, its curves paths,
//! and no image anywhere.
use impact_io::plot::{save, Axis, LineFigure, Panel, PrintWidth, Series};
use std::io::Read as _;

fn figure(width: PrintWidth) -> LineFigure {
    let curve = |label: &str, colour: usize, shift: f64| Series {
        label: label.into(),
        points: (0..30)
            .map(|i| (i as f64 * 0.1, (i as f64 * 0.3).sin() + shift))
            .collect(),
        colour,
        reference: colour == 0,
        marker: None,
    };
    let panel = Panel {
        title: "bar (C = 0.5)".into(),
        x: Axis::linear("x (m)"),
        y: Axis::linear("σₓₓ (MPa)"),
        series: vec![curve("exact", 0, 0.0), curve("DGMPM", 1, 0.1)],
    };
    LineFigure::new(vec![panel], 1, width, 0.5)
}

/// The PDF's bytes, its page's MediaBox and its content stream, inflated; panics where the
/// structure is broken (header, trailer, xref offsets, one page).
fn parse(pdf: &[u8]) -> ([f64; 4], String) {
    let text = String::from_utf8_lossy(pdf);
    assert!(text.starts_with("%PDF-1.4\n") && text.ends_with("%%EOF\n"));
    let tail = &text[text.rfind("startxref\n").unwrap() + 10..];
    let xref_at: usize = tail.lines().next().unwrap().parse().unwrap();
    let table = std::str::from_utf8(&pdf[xref_at..]).unwrap();
    let mut lines = table.lines();
    assert_eq!(lines.next(), Some("xref"));
    let count: usize = lines.next().unwrap()[2..].parse().unwrap();
    assert_eq!(lines.next(), Some("0000000000 65535 f "));
    for k in 1..count {
        let line = lines.next().unwrap();
        let offset: usize = line[..10].parse().unwrap();
        assert!(
            pdf[offset..].starts_with(format!("{k} 0 obj\n").as_bytes()),
            "object {k} is not at {offset}"
        );
    }
    assert!(lines.next().unwrap().starts_with("trailer"));
    assert!(text.contains(&format!("/Size {count} /Root 1 0 R")));
    assert_eq!(text.matches("/Type /Page ").count(), 1);
    assert!(text.contains("/Type /Pages /Kids [3 0 R] /Count 1"));
    let media = &text[text.find("/MediaBox [").unwrap() + 11..];
    let media: Vec<f64> = media[..media.find(']').unwrap()]
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    // the content stream: /Length bytes after "stream\n", Flate (byte offsets: the
    // header's binary comment is not UTF-8)
    let find = |needle: &[u8]| pdf.windows(needle.len()).position(|w| w == needle).unwrap();
    let at = find(b"/FlateDecode >>\nstream\n");
    let length_at = find(b"<< /Length ") + 11;
    let length: usize = std::str::from_utf8(&pdf[length_at..at])
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let start = at + "/FlateDecode >>\nstream\n".len();
    let stream = &pdf[start..start + length];
    assert!(pdf[start + length..].starts_with(b"\nendstream"));
    let mut content = String::new();
    flate2::read::ZlibDecoder::new(stream)
        .read_to_string(&mut content)
        .unwrap();
    (media.try_into().unwrap(), content)
}

#[test]
fn a_figure_pdf_is_vector_at_its_printed_width() {
    let dir = std::env::temp_dir().join(format!("impact-pdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (width, mm) in [(PrintWidth::Single, 90.0), (PrintWidth::Full, 190.0)] {
        let path = dir.join("figure.pdf");
        save(&path, &figure(width)).unwrap();
        let pdf = std::fs::read(&path).unwrap();
        let (media, content) = parse(&pdf);
        let text = String::from_utf8_lossy(&pdf);
        // the page is the printed width (pt), to the pixel (72/300 pt)
        assert_eq!(media[..2], [0.0, 0.0]);
        assert!((media[2] - mm / 25.4 * 72.0).abs() < 0.25, "{media:?}");
        // no raster anywhere: no image XObject, no inline image
        assert!(!text.contains("/Image") && !text.contains("/XObject"));
        assert!(!content.contains(" Do") && !content.contains("BI "));
        // the labels are text: Helvetica, Symbol σ and lowered xx, escaped parentheses
        assert!(text.contains("/BaseFont /Helvetica /Encoding /WinAnsiEncoding"));
        assert!(text.contains("/BaseFont /Symbol"));
        assert!(content.contains("(x \\(m\\)) Tj"), "{content}");
        assert!(content.contains("(bar \\(C = 0.5\\)) Tj"));
        assert!(content.contains("(DGMPM) Tj") && content.contains("(exact) Tj"));
        let sigma = content.find("(s) Tj").expect("σ in Symbol");
        let after = &content[sigma..];
        let sub = after.find("(xx) Tj").unwrap();
        // "(s) Tj /F1 <0.7 size> Tf -<rise> Ts (xx) Tj": lowered, then back on the baseline
        assert!(
            after[..sub].ends_with(" Ts ") && after[..sub].contains(" Tf -"),
            "{after}"
        );
        assert!(after[sub..].contains(" Tf 0 Ts ( \\(MPa\\)) Tj"), "{after}");
        // the curves are paths: 30 points each, stroked
        let longest = content
            .split(" S\n")
            .map(|path| path.matches(" l\n").count())
            .max()
            .unwrap();
        assert!(longest >= 29, "{longest}");
        // the fonts are 7-9 pt at print size (70 % for scripts): every Tf size, in pixels
        // at 300 dpi, × 72/300
        let sizes: Vec<f64> = content
            .lines()
            .filter_map(|l| l.split(" Tf").next().filter(|_| l.contains(" Tf")))
            .map(|s| s.rsplit(' ').next().unwrap().parse::<f64>().unwrap() * 72.0 / 300.0)
            .collect();
        for &points in &sizes {
            let script = (0.7 * 6.9..=0.7 * 9.2).contains(&points);
            assert!((6.9..=9.2).contains(&points) || script, "{points} pt");
        }
        assert!(sizes.iter().any(|&s| (6.9..=9.2).contains(&s)));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
