//! IES LM-63 photometric files (`.ies`), the format fixture makers publish
//! their luminaires' measured intensity distributions in (LM-63-1986,
//! -1991, -1995, -2002 and -2019 all share this layout).
//!
//! A file is a header line (`IESNA:LM-63-2002`, `IES:LM-63-2019`, …;
//! absent in LM-63-1986), `[KEYWORD]` lines, a `TILT=` line, then numbers
//! separated by blanks, commas or line breaks: the lamp count, lumens per
//! lamp, a candela multiplier, the numbers of vertical and horizontal
//! angles, the photometric type (1: Type C), the units and the luminous
//! opening's size; the ballast factor, a future-use (or ballast-lamp)
//! factor and the input watts; the vertical angles, the horizontal
//! angles, and the candela values, one horizontal angle's vertical sweep
//! after another. The table becomes a [`PhotometricProfile`]; the
//! multipliers scale its peak, [`IesFile::peak_candela`].
//!
//! Only Type C photometry (every architectural and stage luminaire's) is
//! read; Types A and B (automotive, floodlights) are refused by name.
//! `TILT=INCLUDE` data (how output varies as the lamp tilts) is read past
//! and not applied: it describes lamps tilted from their rated position;
//! `TILT=<file>` is refused.

use std::path::Path;
use std::sync::Arc;
use tyndall::lights::photometric::PhotometricProfile;

/// A parsed photometric file.
#[derive(Clone, Debug)]
pub struct IesFile {
    /// The distribution, normalised to 1 at its peak.
    pub profile: Arc<PhotometricProfile>,
    /// The largest candela value times the candela multiplier, ballast
    /// factor and ballast-lamp factor: the luminaire's peak luminous
    /// intensity (cd).
    pub peak_candela: f32,
}

/// Most angles of either kind a file may list (LM-63 files hold at most
/// a few hundred; this bounds the table at 2²⁰ values).
pub const MAX_ANGLES: usize = 1024;

/// Reads and parses the `.ies` file at `path`; errors name the file and
/// the line and column where they are found.
pub fn load(path: &Path) -> Result<IesFile, String> {
    let bytes = crate::files::read_capped(path, crate::files::MAX_IES_FILE_BYTES)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    // Files from Windows tools are often Latin-1 (° in keywords): only the
    // numbers matter, so undecodable bytes are replaced.
    let text = String::from_utf8_lossy(&bytes);
    parse(&text).map_err(|e| format!("{}:{e}", path.display()))
}

/// A number of the file's data block with where it was (1-based line and
/// column).
struct Token<'a> {
    text: &'a str,
    line: usize,
    column: usize,
}

/// Parses the text of an `.ies` file; errors start with `line:column: `.
pub fn parse(text: &str) -> Result<IesFile, String> {
    let lines: Vec<&str> = text.lines().collect();
    let tilt = lines
        .iter()
        .position(|l| l.trim_start().starts_with("TILT"))
        .ok_or_else(|| "1:1: no `TILT=` line: not an IES LM-63 photometric file".to_string())?;
    let tilt_value = lines[tilt].trim().trim_start_matches("TILT").trim_start();
    let tilt_value = tilt_value.strip_prefix('=').map(str::trim).ok_or_else(|| {
        format!(
            "{}:1: expected `TILT=NONE`, `TILT=INCLUDE` or `TILT=<file>`",
            tilt + 1
        )
    })?;
    let mut tokens = lines
        .iter()
        .enumerate()
        .skip(tilt + 1)
        .flat_map(|(i, line)| {
            let mut out = Vec::new();
            let mut start = None;
            for (c, ch) in line.char_indices().chain([(line.len(), ' ')]) {
                let separator = ch.is_whitespace() || ch == ',';
                match (start, separator) {
                    (None, false) => start = Some(c),
                    (Some(s), true) => {
                        out.push(Token {
                            text: &line[s..c],
                            line: i + 1,
                            column: s + 1,
                        });
                        start = None;
                    }
                    _ => {}
                }
            }
            out
        });
    let end = lines.len();
    let mut next = |what: &str| -> Result<(f32, usize, usize), String> {
        let t = tokens
            .next()
            .ok_or_else(|| format!("{end}:1: the file ends before {what}"))?;
        let value: f32 = t.text.parse().map_err(|_| {
            format!(
                "{}:{}: expected {what}, found `{}`",
                t.line, t.column, t.text
            )
        })?;
        if !value.is_finite() {
            return Err(format!(
                "{}:{}: {what} is `{}`, not a finite number",
                t.line, t.column, t.text
            ));
        }
        Ok((value, t.line, t.column))
    };
    match tilt_value {
        "NONE" => {}
        "INCLUDE" => {
            // Lamp-to-luminaire geometry, the number of pairs, then the
            // angles and their multiplying factors.
            next("the tilt data's lamp geometry")?;
            let (pairs, line, column) = next("the number of tilt angles")?;
            let pairs = count(pairs, line, column, "tilt angles")?;
            for _ in 0..2 * pairs {
                next("a tilt angle or factor")?;
            }
        }
        file => {
            return Err(format!(
                "{}:1: tilt data in another file (`TILT={file}`) is not supported: \
                 include it in the file (`TILT=INCLUDE`) or remove it (`TILT=NONE`)",
                tilt + 1
            ));
        }
    }
    let _lamps = next("the number of lamps")?;
    let _lumens = next("the lumens per lamp")?;
    let (multiplier, line, column) = next("the candela multiplier")?;
    if multiplier <= 0.0 {
        return Err(format!(
            "{line}:{column}: the candela multiplier must be > 0, not {multiplier}"
        ));
    }
    let (nv, line, column) = next("the number of vertical angles")?;
    let nv = count(nv, line, column, "vertical angles")?;
    let (nh, line, column) = next("the number of horizontal angles")?;
    let nh = count(nh, line, column, "horizontal angles")?;
    let (kind, line, column) = next("the photometric type")?;
    if kind == 2.0 || kind == 3.0 {
        return Err(format!(
            "{line}:{column}: Type {} photometry is not supported (only Type C, photometric type 1: \
             the vertical axis through the luminaire, as for architectural and stage luminaires)",
            if kind == 2.0 { "B" } else { "A" }
        ));
    } else if kind != 1.0 {
        return Err(format!(
            "{line}:{column}: the photometric type must be 1, 2 or 3, not {kind}"
        ));
    }
    let _units = next("the units type")?;
    for what in ["the luminous opening's width", "its length", "its height"] {
        next(what)?;
    }
    let (ballast, line, column) = next("the ballast factor")?;
    let (ballast_lamp, _, _) = next("the ballast-lamp photometric factor")?;
    if ballast <= 0.0 || ballast_lamp <= 0.0 {
        return Err(format!(
            "{line}:{column}: the ballast factors must be > 0, not {ballast} and {ballast_lamp}"
        ));
    }
    let _watts = next("the input watts")?;
    let (vertical, v_line) = angles(&mut next, nv, "vertical")?;
    let (horizontal, h_line) = angles(&mut next, nh, "horizontal")?;
    let mut candela = Vec::with_capacity(nh);
    for phi in &horizontal {
        let mut row = Vec::with_capacity(nv);
        for theta in &vertical {
            let what = format!("the candela value at horizontal {phi}°, vertical {theta}°");
            let (c, line, column) = next(&what)?;
            if c < 0.0 {
                return Err(format!(
                    "{line}:{column}: {what} is {c}: candela values must be ≥ 0"
                ));
            }
            row.push(c);
        }
        candela.push(row);
    }
    let profile = PhotometricProfile::new(vertical, horizontal, &candela).map_err(|e| {
        // Angle errors belong to their lists; the rest to the table.
        let line = if e.starts_with("vertical") {
            v_line
        } else if e.starts_with("horizontal") {
            h_line
        } else {
            h_line + 1
        };
        format!("{line}:1: {e}")
    })?;
    let peak = candela.iter().flatten().copied().fold(0.0f32, f32::max);
    Ok(IesFile {
        profile: Arc::new(profile),
        peak_candela: peak * multiplier * ballast * ballast_lamp,
    })
}

/// A count read as a number: a whole number in [1, MAX_ANGLES].
fn count(value: f32, line: usize, column: usize, what: &str) -> Result<usize, String> {
    if value != value.trunc() || !(1.0..=MAX_ANGLES as f32).contains(&value) {
        return Err(format!(
            "{line}:{column}: the number of {what} must be a whole number from 1 to {MAX_ANGLES}, not {value}"
        ));
    }
    Ok(value as usize)
}

/// `n` angles of the named kind, and the line the list starts on.
fn angles(
    next: &mut impl FnMut(&str) -> Result<(f32, usize, usize), String>,
    n: usize,
    kind: &str,
) -> Result<(Vec<f32>, usize), String> {
    let mut out = Vec::with_capacity(n);
    let mut first_line = 0;
    for i in 0..n {
        let (a, line, _) = next(&format!("{kind} angle {} of {n}", i + 1))?;
        if i == 0 {
            first_line = line;
        }
        out.push(a);
    }
    Ok((out, first_line))
}
