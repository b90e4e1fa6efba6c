// ---- ray offsets (tyndall::ray) ----

// Mirrors tyndall::ray::offset_distance.
fn offset_distance(x: vec3<f32>) -> f32 {
    let a = abs(x);
    return 1e-4 * (1.0 + max(a.x, max(a.y, a.z)));
}

// Mirrors tyndall::ray::offset_origin.
fn offset_origin(x: vec3<f32>, normal: vec3<f32>, direction: vec3<f32>) -> vec3<f32> {
    var side = -1.0;
    if dot(normal, direction) >= 0.0 {
        side = 1.0;
    }
    return x + normal * (side * offset_distance(x));
}

fn shadow_ray_end(origin: vec3<f32>, direction: vec3<f32>, distance: f32) -> f32 {
    return distance * (1.0 - 1e-4) - offset_distance(origin + direction * distance);
}

// ---- visibility (tyndall::visibility, shadow rays) ----

// The fraction of a light's light reaching `origin` from `direction` over
// `distance` past geometry: 0 behind an opaque surface, else the tint of
// the panes crossed under the scene's glass model, applied in the order
// light meets them (farthest from `origin` first).
fn shadow_transmittance(origin: vec3<f32>, direction: vec3<f32>, distance: f32) -> vec3<f32> {
    let ray = Ray(origin, direction);
    var t_max = INFINITE;
    if distance < INFINITE {
        t_max = shadow_ray_end(origin, direction, distance);
    }
    var filtered = vec3<f32>(1.0);
    var pane_t: array<f32, MAX_BLEND_PANES>;
    var pane_m: array<u32, MAX_BLEND_PANES>;
    var count = 0u;
    var walk = bvh_walk(ray);
    loop {
        let i = bvh_next(&walk, t_max);
        if i == NO_PRIMITIVE {
            break;
        }
        let t = intersect(i, ray, t_max);
        if t <= 0.0 {
            continue;
        }
        let m = primitives[i].material;
        let material = materials[m];
        if material.kind != MATERIAL_GLASS {
            return vec3<f32>(0.0);
        }
        if params.glass_model == GLASS_FILTER {
            filtered *= glass_filter_transmittance(material.color.xyz, material.alpha);
        } else if count < MAX_BLEND_PANES {
            // Insertion in decreasing distance: light meets the
            // farthest pane first.
            var j = count;
            while j > 0u && pane_t[j - 1u] < t {
                pane_t[j] = pane_t[j - 1u];
                pane_m[j] = pane_m[j - 1u];
                j--;
            }
            pane_t[j] = t;
            pane_m[j] = m;
            count++;
        }
    }
    if params.glass_model == GLASS_FILTER {
        return filtered;
    }
    var tint = vec3<f32>(1.0);
    for (var j = 0u; j < count; j++) {
        let g = materials[pane_m[j]];
        tint = glass_tint_after(GLASS_BLEND, tint, g.color.xyz, g.alpha);
    }
    return tint;
}
