//! Smooth dielectric interfaces: Fresnel reflectance and the choice
//! between reflection and refraction (Snell's law).

use glam::Vec3;

/// Fresnel reflectance of a smooth dielectric interface for unpolarised
/// light arriving at `cos_i` (> 0) to the normal, with `eta` = n_incident
/// / n_transmitted; 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parallel = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perpendicular = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// The Fresnel reflectance met by a ray travelling along `incoming` at a
/// dielectric of index `ior` with geometric normal `normal` (either side).
pub fn dielectric_reflectance(incoming: Vec3, normal: Vec3, ior: f32) -> f32 {
    let (n, eta) = dielectric_sides(incoming, normal, ior);
    fresnel_dielectric(-incoming.dot(n), eta)
}

/// The normal facing `incoming` at a dielectric of index `ior` with
/// geometric normal `normal`, and the ratio n_incident / n_transmitted.
fn dielectric_sides(incoming: Vec3, normal: Vec3, ior: f32) -> (Vec3, f32) {
    if incoming.dot(normal) < 0.0 {
        (normal, 1.0 / ior)
    } else {
        (-normal, ior)
    }
}

/// The next direction of a ray travelling along `incoming` that meets a
/// dielectric of index `ior` with geometric normal `normal` (either side):
/// the reflected or the refracted direction, chosen with probability the
/// Fresnel reflectance by `u`, so the path's weight is unchanged (the
/// interface neither absorbs nor emits).
pub fn dielectric_scatter(incoming: Vec3, normal: Vec3, ior: f32, u: f32) -> Vec3 {
    let (n, eta) = dielectric_sides(incoming, normal, ior);
    let cos_i = -incoming.dot(n);
    let reflectance = fresnel_dielectric(cos_i, eta);
    if u < reflectance {
        return incoming + 2.0 * cos_i * n;
    }
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    (incoming * eta + n * (eta * cos_i - cos_t)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Normal incidence: R = ((n − 1)/(n + 1))² = 0.04 for n = 1.5; total
    /// internal reflection beyond the critical angle asin(1/1.5) = 41.8°.
    #[test]
    fn fresnel_values() {
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!(fresnel_dielectric(40f32.to_radians().cos(), 1.5) < 1.0);
        assert_eq!(fresnel_dielectric(43f32.to_radians().cos(), 1.5), 1.0);
        assert!((fresnel_dielectric(1e-4, 1.0 / 1.5) - 1.0).abs() < 1e-2);
    }

    /// Refraction obeys Snell's law: n₁ sin θ₁ = n₂ sin θ₂.
    #[test]
    fn refraction_obeys_snell() {
        let incoming = Vec3::new(0.5, -1.0, 0.0).normalize();
        // u = 1 never reflects (R < 1 here).
        let out = dielectric_scatter(incoming, Vec3::Y, 1.5, 1.0);
        let sin_in = incoming.x.abs();
        let sin_out = out.x.abs();
        assert!(out.y < 0.0 && (sin_in - 1.5 * sin_out).abs() < 1e-5);
        // Light paths are reversible: sent back, it leaves along −incoming.
        let back = dielectric_scatter(-out, Vec3::Y, 1.5, 1.0);
        assert!(
            (back + incoming).length() < 1e-5,
            "reversible: {back} vs {}",
            -incoming
        );
    }
}
