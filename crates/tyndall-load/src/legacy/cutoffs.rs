//! Phase 2 of reading a legacy file: what each spotlight cutoff `c`
//! means, and so the cutoff every face gets.
//!
//! A `c` outside a block applies to the emissive faces that follow (until
//! the next `c`). A `c` that ends a block's fields ([`super::statements::TrailingCutoff`])
//! could be either that material's field or such a statement: newlines do
//! not separate statements, so only the material tells the two readings
//! apart. The cutoff of an emissive material is that material's (it makes
//! its faces spots); a non-emissive material has no use for a cutoff, so
//! there it is the statement for the emissive faces that follow. Either
//! reading is warned about, with the token's place, when the other would
//! have given any emissive face a different cutoff.

use super::statements::{Cutoff, Face, LegacyMaterial, Statements};
use crate::source::SourceText;

/// How the cutoffs of a file are read.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct CutoffReading {
    /// The spotlight cutoff (degrees) of each face, `None` for none.
    pub face_cutoff: Vec<Option<f32>>,
    /// One warning (`file:line:column: …`) per trailing `c` whose other
    /// reading would change an emissive face's cutoff.
    pub warnings: Vec<String>,
}

/// Phase 2: reads every `c` of `statements` (see the module's comment).
pub(super) fn disambiguate(statements: &Statements, source: &SourceText) -> CutoffReading {
    let Statements {
        faces,
        materials,
        cutoffs,
        ..
    } = statements;
    let emissive = |m: usize| materials[m].emits();
    let as_statement: Vec<bool> = cutoffs
        .iter()
        .map(|c| c.trailing.as_ref().is_none_or(|t| !emissive(t.material)))
        .collect();
    let face_cutoff = face_cutoffs(faces, materials, cutoffs, &as_statement);
    let emissive_faces: Vec<usize> = (0..faces.len())
        .filter(|&i| emissive(faces[i].material))
        .collect();
    let mut warnings = Vec::new();
    for (i, c) in cutoffs.iter().enumerate() {
        let Some(t) = &c.trailing else { continue };
        let mut other = as_statement.clone();
        other[i] = !other[i];
        let other_cutoff = face_cutoffs(faces, materials, cutoffs, &other);
        let differ = emissive_faces
            .iter()
            .filter(|&&f| face_cutoff[f] != other_cutoff[f])
            .count();
        if differ == 0 {
            continue;
        }
        let (line, column) = source.line_col(t.offset);
        let reading = if as_statement[i] {
            format!(
                "material {} does not emit, so it is read as a statement for the emissive faces that follow",
                t.material
            )
        } else {
            format!(
                "material {} emits, so it is read as that material's cutoff",
                t.material
            )
        };
        warnings.push(format!(
            "{}:{line}:{column}: `c {}` ends the fields of material {}'s block; newlines do not separate statements, so it may be that material's cutoff or a statement: {reading}. The other reading would change {differ} emissive face(s). Write it after `m i` for a statement, or before the block's `emitted` for the material's",
            source.path.display(),
            c.value,
            t.material,
        ));
    }

    CutoffReading {
        face_cutoff,
        warnings,
    }
}

/// The cutoff each face gets when `as_statement[i]` says how cutoff `i`
/// is read: a material's own cutoff (its field, or a trailing `c` read
/// as its field) wins over the last statement before the face, as in the
/// paper's loader.
fn face_cutoffs(
    faces: &[Face],
    materials: &[LegacyMaterial],
    cutoffs: &[Cutoff],
    as_statement: &[bool],
) -> Vec<Option<f32>> {
    let mut own: Vec<Option<f32>> = materials.iter().map(|m| m.cutoff_deg).collect();
    for (c, statement) in cutoffs.iter().zip(as_statement) {
        if let (Some(t), false) = (&c.trailing, statement) {
            own[t.material] = Some(c.value);
        }
    }
    faces
        .iter()
        .map(|f| {
            own[f.material].or_else(|| {
                (0..f.statements)
                    .rev()
                    .find(|&i| as_statement[i])
                    .map(|i| cutoffs[i].value)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::statements::TrailingCutoff;
    use super::*;
    use tyndall::color::Rgb;

    fn material(emitted: f32) -> LegacyMaterial {
        LegacyMaterial {
            emitted: Rgb::splat(emitted),
            alpha: 1.0,
            ..Default::default()
        }
    }

    fn face(material: usize, statements: usize) -> Face {
        Face {
            vertices: [0, 1, 2, 3],
            material,
            statements,
            offset: 0,
        }
    }

    fn trailing(value: f32, material: usize, offset: usize) -> Cutoff {
        Cutoff {
            value,
            trailing: Some(TrailingCutoff { material, offset }),
        }
    }

    fn source() -> SourceText {
        SourceText::new("t.obj", "0123456789\nabcdefghij\n")
    }

    #[test]
    fn a_trailing_cutoff_of_an_emissive_material_is_its_own() {
        // Material 0 emits and ends with `c 20`; a statement `c 45`
        // follows; faces of material 0 keep 20.
        let statements = Statements {
            materials: vec![material(1.0)],
            cutoffs: vec![
                trailing(20.0, 0, 12),
                Cutoff {
                    value: 45.0,
                    trailing: None,
                },
            ],
            faces: vec![face(0, 2)],
            ..Default::default()
        };
        let reading = disambiguate(&statements, &source());
        assert_eq!(reading.face_cutoff, vec![Some(20.0)]);
        // Read as a statement, `c 45` after it would win: the face
        // would change, so the reading is warned about at the token.
        assert_eq!(reading.warnings.len(), 1);
        let w = &reading.warnings[0];
        assert!(w.starts_with("t.obj:2:2: `c 20`"), "{w}");
        assert!(
            w.contains("material 0 emits, so it is read as that material's cutoff"),
            "{w}"
        );
    }

    #[test]
    fn a_trailing_cutoff_of_a_dark_material_is_a_statement_and_warned_about() {
        // Material 0 does not emit and ends with `c 30`; the emissive
        // face of material 1 after it gets 30.
        let statements = Statements {
            materials: vec![material(0.0), material(1.0)],
            cutoffs: vec![trailing(30.0, 0, 13)],
            faces: vec![face(1, 1), face(0, 1)],
            ..Default::default()
        };
        let reading = disambiguate(&statements, &source());
        assert_eq!(reading.face_cutoff, vec![Some(30.0), Some(30.0)]);
        assert_eq!(reading.warnings.len(), 1);
        let w = &reading.warnings[0];
        assert!(
            w.starts_with("t.obj:2:3: `c 30` ends the fields of material 0's block"),
            "{w}"
        );
        assert!(
            w.contains("does not emit") && w.contains("change 1 emissive face(s)"),
            "{w}"
        );
    }

    #[test]
    fn faces_before_a_statement_do_not_get_it() {
        let statements = Statements {
            materials: vec![material(1.0)],
            cutoffs: vec![Cutoff {
                value: 10.0,
                trailing: None,
            }],
            faces: vec![face(0, 0), face(0, 1)],
            ..Default::default()
        };
        let reading = disambiguate(&statements, &source());
        assert_eq!(reading.face_cutoff, vec![None, Some(10.0)]);
        assert!(reading.warnings.is_empty());
    }
}
