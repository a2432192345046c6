//! The text of the PDF backend ([`super::pdf`]): characters mapped to the base-14 fonts
//! every PDF reader has (Helvetica in WinAnsiEncoding for Latin text, Symbol for Greek
//! letters and mathematical signs), superscript and subscript characters to raised or
//! lowered plain ones, and the fonts' standard advance widths (Adobe's AFM metrics) for
//! text extents.

/// Normal, raised or lowered text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Script {
    /// On the baseline, full size.
    Normal,
    /// Raised, 70 %.
    Super,
    /// Lowered, 70 %.
    Sub,
}

/// A stretch of text in one font and script: the font's bytes and their widths (em).
#[derive(Debug, PartialEq)]
pub(super) struct Run {
    /// In the Symbol font (else Helvetica).
    pub symbol: bool,
    /// Raised, lowered or not.
    pub script: Script,
    /// The font's bytes.
    pub bytes: Vec<u8>,
    /// The sum of their widths (em of the run's own size).
    pub widths: f64,
}

impl Run {
    /// Its advance in em of the base size.
    pub fn width(&self) -> f64 {
        self.widths
            * match self.script {
                Script::Normal => 1.0,
                _ => 0.7,
            }
    }
}

/// `text` as runs of (font, script, bytes), each character mapped by [`glyph`].
pub(super) fn runs(text: &str) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for ch in text.chars() {
        let Some((symbol, script, byte, width)) = glyph(ch) else {
            continue;
        };
        match runs.last_mut() {
            Some(run) if run.symbol == symbol && run.script == script => {
                run.bytes.push(byte);
                run.widths += width;
            }
            _ => runs.push(Run {
                symbol,
                script,
                bytes: vec![byte],
                widths: width,
            }),
        }
    }
    runs
}

/// Helvetica's advance widths (1/1000 em) of the ASCII characters 32-126 (Adobe AFM).
const HELVETICA: [u16; 95] = [
    278, 278, 355, 556, 556, 889, 667, 191, 333, 333, 389, 584, 278, 333, 278, 278, // ' '-/
    556, 556, 556, 556, 556, 556, 556, 556, 556, 556, 278, 278, 584, 584, 584, 556, // 0-?
    1015, 667, 667, 722, 722, 667, 611, 778, 722, 278, 500, 667, 556, 833, 722, 778, // @-O
    667, 778, 722, 667, 611, 722, 667, 944, 667, 667, 611, 278, 278, 278, 469, 556, // P-_
    333, 556, 556, 500, 556, 556, 278, 556, 556, 222, 222, 500, 222, 833, 556, 556, // `-o
    556, 556, 333, 500, 278, 556, 500, 722, 500, 500, 500, 334, 260, 334, 584, // p-~
];

/// Helvetica (WinAnsiEncoding) characters beyond ASCII: (char, byte, width).
const HELVETICA_MORE: [(char, u8, u16); 9] = [
    ('×', 0xD7, 584),
    ('·', 0xB7, 278),
    ('½', 0xBD, 834),
    ('±', 0xB1, 584),
    ('µ', 0xB5, 556),
    ('°', 0xB0, 400),
    ('–', 0x96, 556),
    ('—', 0x97, 1000),
    ('é', 0xE9, 556),
];

/// Symbol's Greek letters and signs: (char, byte, width).
const SYMBOL: [(char, u8, u16); 34] = [
    ('α', b'a', 631),
    ('β', b'b', 549),
    ('γ', b'g', 411),
    ('δ', b'd', 494),
    ('ε', b'e', 439),
    ('θ', b'q', 521),
    ('κ', b'k', 549),
    ('λ', b'l', 549),
    ('μ', b'm', 576),
    ('ν', b'n', 521),
    ('ξ', b'x', 493),
    ('π', b'p', 549),
    ('ρ', b'r', 549),
    ('σ', b's', 603),
    ('τ', b't', 439),
    ('φ', b'f', 521),
    ('ψ', b'y', 686),
    ('ω', b'w', 686),
    ('Γ', b'G', 603),
    ('Δ', b'D', 612),
    ('Θ', b'Q', 741),
    ('Λ', b'L', 686),
    ('Π', b'P', 768),
    ('Σ', b'S', 592),
    ('Φ', b'F', 763),
    ('Ω', b'W', 768),
    ('−', 0x2D, 549),
    ('≤', 0xA3, 549),
    ('≥', 0xB3, 549),
    ('→', 0xAE, 987),
    ('≈', 0xBB, 549),
    ('∞', 0xA5, 713),
    ('∂', 0xB6, 494),
    ('√', 0xD6, 549),
];

/// Superscript and subscript characters and the plain ones they raise or lower.
const SCRIPTS: [(char, char, Script); 30] = [
    ('⁰', '0', Script::Super),
    ('¹', '1', Script::Super),
    ('²', '2', Script::Super),
    ('³', '3', Script::Super),
    ('⁴', '4', Script::Super),
    ('⁵', '5', Script::Super),
    ('⁶', '6', Script::Super),
    ('⁷', '7', Script::Super),
    ('⁸', '8', Script::Super),
    ('⁹', '9', Script::Super),
    ('⁻', '−', Script::Super),
    ('⁺', '+', Script::Super),
    ('ⁿ', 'n', Script::Super),
    ('₀', '0', Script::Sub),
    ('₁', '1', Script::Sub),
    ('₂', '2', Script::Sub),
    ('₃', '3', Script::Sub),
    ('ₓ', 'x', Script::Sub),
    ('ᵧ', 'y', Script::Sub),
    ('ₐ', 'a', Script::Sub),
    ('ₑ', 'e', Script::Sub),
    ('ₕ', 'h', Script::Sub),
    ('ᵢ', 'i', Script::Sub),
    ('ₖ', 'k', Script::Sub),
    ('ₘ', 'm', Script::Sub),
    ('ₙ', 'n', Script::Sub),
    ('ₚ', 'p', Script::Sub),
    ('ₛ', 's', Script::Sub),
    ('ₜ', 't', Script::Sub),
    ('ᵣ', 'r', Script::Sub),
];

/// The font (Symbol or not), script, byte and width (em) of `ch`; `None` for a combining
/// mark (skipped), `?` for a character neither font has.
fn glyph(ch: char) -> Option<(bool, Script, u8, f64)> {
    if ('\u{300}'..='\u{36f}').contains(&ch) {
        return None;
    }
    // the Latin-1 superscripts are Helvetica glyphs: set them raised like the others
    let (plain, script) = SCRIPTS
        .iter()
        .find(|s| s.0 == ch)
        .map_or((ch, Script::Normal), |s| (s.1, s.2));
    let code = plain as u32;
    let found = if (32..=126).contains(&code) {
        Some((false, code as u8, HELVETICA[code as usize - 32]))
    } else if let Some(&(_, byte, width)) = HELVETICA_MORE.iter().find(|g| g.0 == plain) {
        Some((false, byte, width))
    } else {
        SYMBOL
            .iter()
            .find(|g| g.0 == plain)
            .map(|&(_, byte, width)| (true, byte, width))
    };
    let (symbol, byte, width) = found.unwrap_or((false, b'?', 556));
    Some((symbol, script, byte, width as f64 / 1000.0))
}
