//! File sequences: one file per frame of an animation, as simulation
//! caches are written (Blender's fluid cache `fluid_data_0001.vdb`,
//! Houdini's `smoke.$F4.vdb`). A scene names the sequence with a run of
//! `#` where the frame number goes, `fluid_data_####.vdb`, and the frame
//! chosen at load time (`tyndall render --frame N`, Python `frame=N`)
//! replaces the run, zero-padded to the run's length (frame 7 in `####`
//! is `0007`; a frame with more digits than the run keeps all of them, as
//! Blender and Houdini write them).

/// The file name `pattern` names for `frame`: `pattern` itself if it
/// holds no `#`. An error says why a pattern cannot be resolved: it names
/// a sequence but no frame was chosen, or it has more than one run of
/// `#` (which would be ambiguous).
pub fn frame_file(pattern: &str, frame: Option<u32>) -> Result<String, String> {
    let Some(start) = pattern.find('#') else {
        return Ok(pattern.to_string());
    };
    let width = pattern[start..].len() - pattern[start..].trim_start_matches('#').len();
    let rest = &pattern[start + width..];
    if rest.contains('#') {
        return Err(format!(
            "`{pattern}` has more than one run of `#`: a frame sequence marks the frame number with one run (`fluid_data_####.vdb`)"
        ));
    }
    let frame = frame.ok_or_else(|| {
        format!(
            "`{pattern}` names a frame sequence: choose the frame with `--frame N` (Python: `frame=N`)"
        )
    })?;
    Ok(format!("{}{frame:0width$}{rest}", &pattern[..start]))
}

/// Whether `pattern` names a frame sequence.
pub fn is_sequence(pattern: &str) -> bool {
    pattern.contains('#')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_replace_the_run_zero_padded() {
        assert_eq!(
            frame_file("cache/data/fluid_data_####.vdb", Some(7)).as_deref(),
            Ok("cache/data/fluid_data_0007.vdb")
        );
        assert_eq!(
            frame_file("smoke.#.vdb", Some(120)).as_deref(),
            Ok("smoke.120.vdb")
        );
        assert_eq!(
            frame_file("a_##.vdb", Some(12345)).as_deref(),
            Ok("a_12345.vdb")
        );
        assert_eq!(frame_file("plain.vdb", Some(3)).as_deref(), Ok("plain.vdb"));
        assert_eq!(frame_file("plain.vdb", None).as_deref(), Ok("plain.vdb"));
        let e = frame_file("f_####.vdb", None).expect_err("no frame");
        assert!(e.contains("--frame N") && e.contains("f_####.vdb"), "{e}");
        let e = frame_file("f_##_##.vdb", Some(1)).expect_err("two runs");
        assert!(e.contains("more than one run"), "{e}");
    }
}
