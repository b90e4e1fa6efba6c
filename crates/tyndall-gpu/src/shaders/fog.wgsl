// ---- fog (tyndall::media::Fog) ----

fn has_fog() -> bool {
    return params.fog_min.w != 0.0;
}

fn sigma_t() -> f32 {
    return params.fog_albedo_sigma_t.w;
}

// The part of [t0, t1] along `ray` inside the fog as (a, b, 1), or
// (0, 0, 0) if none (the slab test of tyndall::shapes::Bounds::clip_ray).
fn fog_interval(ray: Ray, t0: f32, t1: f32) -> vec3<f32> {
    if params.fog_max.w == 0.0 {
        if t0 < t1 {
            return vec3<f32>(t0, t1, 1.0);
        }
        return vec3<f32>(0.0);
    }
    let inv = 1.0 / ray.direction;
    let a = (params.fog_min.xyz - ray.origin) * inv;
    let b = (params.fog_max.xyz - ray.origin) * inv;
    // NaN (0·∞ on a slab) is dropped by min/max as in Rust's f32::min.
    let lo = min(a, b);
    let hi = max(a, b);
    let near = max(max(max(lo.x, lo.y), lo.z), t0);
    let far = min(min(min(hi.x, hi.y), hi.z), t1);
    if near < far {
        return vec3<f32>(near, far, 1.0);
    }
    return vec3<f32>(0.0);
}

// Fog transmittance over `distance` from `x` along unit `direction`.
// Mirrors tyndall::media::Fog::transmittance_along.
fn fog_transmittance_along(x: vec3<f32>, direction: vec3<f32>, distance: f32) -> f32 {
    if !has_fog() {
        return 1.0;
    }
    let span = fog_interval(Ray(x, direction), 0.0, distance);
    if span.z == 0.0 {
        return 1.0;
    }
    return transmittance(sigma_t(), span.y - span.x);
}
