//! A grid's index-to-world transform (OpenVDB math/Transform.cc
//! `Transform::read`, math/Maps.h `*Map::read`).
//!
//! The transform is a map type name followed by that map's fields, all
//! `f64` (a `Vec3d` is three, a `Mat4d` sixteen, row by row):
//!
//! | map | fields |
//! |---|---|
//! | `UniformScaleMap`, `ScaleMap` | scale, voxel size, inverse scale, inverse scale², inverse twice scale (5 × `Vec3d`) |
//! | `UniformScaleTranslateMap`, `ScaleTranslateMap` | translation, then the five of `ScaleMap` |
//! | `TranslationMap` | translation |
//! | `AffineMap`, `UnitaryMap` | the 4×4 matrix |
//!
//! OpenVDB multiplies row vectors on the left (`world = index · M`, the
//! translation in the last row), so the sixteen doubles read row by row
//! are the columns of the column-vector matrix glam uses. Only the scale
//! and translation of the scale maps are used; the rest are derived
//! values. `NonlinearFrustumMap` (a perspective frustum) is refused by
//! name, as is any other map.

use super::stream::Stream;
use glam::{DMat4, DVec3, Mat4};

fn vec3(s: &mut Stream) -> Result<DVec3, String> {
    Ok(DVec3::new(s.f64()?, s.f64()?, s.f64()?))
}

/// Reads a transform into an affine index-to-world matrix; a transform
/// that is not finite or is singular is an error.
pub fn read_transform(s: &mut Stream) -> Result<Mat4, String> {
    let map = s.string()?;
    let scale_map = |s: &mut Stream| -> Result<DVec3, String> {
        let scale = vec3(s)?;
        for _ in 0..4 {
            vec3(s)?; // voxel size and derived inverses
        }
        Ok(scale)
    };
    let m = match map.as_str() {
        "UniformScaleMap" | "ScaleMap" => DMat4::from_scale(scale_map(s)?),
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let t = vec3(s)?;
            let scale = scale_map(s)?;
            DMat4::from_translation(t) * DMat4::from_scale(scale)
        }
        "TranslationMap" => DMat4::from_translation(vec3(s)?),
        "AffineMap" | "UnitaryMap" => {
            let mut a = [0.0; 16];
            for v in &mut a {
                *v = s.f64()?;
            }
            DMat4::from_cols_array(&a)
        }
        "NonlinearFrustumMap" => {
            return Err(
                "the grid's transform is a NonlinearFrustumMap (a perspective frustum), which this reader does not support; resample the grid to a linear transform".into(),
            );
        }
        other => {
            return Err(format!(
                "the grid's transform is an unknown map \"{other}\""
            ));
        }
    };
    check(&map, m)
}

/// The transform as f32, refused unless finite, affine and invertible.
fn check(map: &str, m: DMat4) -> Result<Mat4, String> {
    let f = m.as_mat4();
    if !m.is_finite() || !f.is_finite() {
        return Err(format!("the grid's transform ({map}) is not finite: {m}"));
    }
    let row3 = m.row(3);
    if row3 != glam::DVec4::new(0.0, 0.0, 0.0, 1.0) {
        return Err(format!(
            "the grid's transform ({map}) is not affine: last column {row3}"
        ));
    }
    // Singular or so nearly singular that f32 cannot invert it.
    let det = f.determinant();
    let scale = f.x_axis.length() * f.y_axis.length() * f.z_axis.length();
    if det == 0.0 || !det.is_finite() || (det.abs() as f64) < 1e-6 * scale as f64 || scale == 0.0 {
        return Err(format!(
            "the grid's transform ({map}) is singular (determinant {det}): a voxel has zero size"
        ));
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(name: &str, values: &[f64]) -> Vec<u8> {
        let mut b = (name.len() as u32).to_le_bytes().to_vec();
        b.extend_from_slice(name.as_bytes());
        for v in values {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b
    }

    /// TranslationMap (one `Vec3d`) and UnitaryMap (a `Mat4d`, as
    /// AffineMap): OpenVDB 10 simplifies both away before writing (a
    /// Transform turns them into UniformScaleTranslateMap and AffineMap),
    /// so no test file holds them and this checks the layout read from
    /// math/Maps.h. The matrix is OpenVDB's, row-vector convention: a
    /// rotation by 90° about z maps index x to world y, and the last row
    /// translates.
    #[test]
    fn translation_and_unitary_maps() {
        let m = read_transform(&mut Stream::new(&bytes(
            "TranslationMap",
            &[1.0, -2.0, 0.5],
        )))
        .unwrap();
        assert_eq!(
            m.transform_point3(glam::Vec3::ONE),
            glam::Vec3::new(2.0, -1.0, 1.5)
        );
        #[rustfmt::skip]
        let rows = [
            0.0, 1.0, 0.0, 0.0,
            -1.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 1.0, 0.0,
            5.0, 6.0, 7.0, 1.0,
        ];
        let m = read_transform(&mut Stream::new(&bytes("UnitaryMap", &rows))).unwrap();
        assert_eq!(
            m.transform_point3(glam::Vec3::X),
            glam::Vec3::new(5.0, 7.0, 7.0)
        );
        let mut projective = rows;
        projective[3] = 0.5;
        let e = read_transform(&mut Stream::new(&bytes("AffineMap", &projective))).unwrap_err();
        assert!(e.contains("not affine"), "{e}");
    }

    /// ScaleTranslateMap: world = index·scale + translation; a zero scale
    /// is an error, as is a frustum.
    #[test]
    fn scale_translate_and_degenerate_maps() {
        let mut v = vec![1.0, 2.0, 3.0, 0.5, 0.25, 2.0];
        v.extend([0.0; 12]);
        let m = read_transform(&mut Stream::new(&bytes("ScaleTranslateMap", &v))).unwrap();
        let p = m.transform_point3(glam::Vec3::new(2.0, 4.0, 1.0));
        assert_eq!(p, glam::Vec3::new(2.0, 3.0, 5.0));
        v[4] = 0.0;
        let e = read_transform(&mut Stream::new(&bytes("ScaleTranslateMap", &v))).unwrap_err();
        assert!(e.contains("singular"), "{e}");
        let e = read_transform(&mut Stream::new(&bytes("NonlinearFrustumMap", &[]))).unwrap_err();
        assert!(e.contains("NonlinearFrustumMap"), "{e}");
        let mut nan = vec![f64::NAN; 3];
        nan.extend([1.0; 12]);
        let e = read_transform(&mut Stream::new(&bytes("ScaleMap", &nan))).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
    }
}
