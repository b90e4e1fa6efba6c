// ---- lights (tyndall::lights::Light) ----

struct Incident {
    direction: vec3<f32>,
    distance: f32,
    irradiance: vec3<f32>,
    valid: bool,
}

const NO_INCIDENT: Incident = Incident(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), false);

// The point of a light a receiver connects to (Light::sample_point): a
// point or spot light's position, or a point of an area light's surface
// with its unit `normal` there and the density per unit area (m⁻²) with
// which it was chosen. A sun has none (`valid` false).
struct LightPoint {
    position: vec3<f32>,
    normal: vec3<f32>,
    area_density: f32,
    valid: bool,
}

fn is_area_light(light: Light) -> bool {
    return light.kind == LIGHT_QUAD || light.kind == LIGHT_SPHERE || light.kind == LIGHT_MESH;
}

// The light's point for u ∈ [0, 1)² (Light::sample_point): an area
// light's uniform by area, over the whole surface — a quad by its edges,
// a sphere by uniform_cone over all directions, a mesh by its triangle
// table (mesh_point).
fn light_point_at(light: Light, u: vec2<f32>) -> LightPoint {
    if light.kind == LIGHT_QUAD {
        let y = light.position.xyz + light.direction.xyz * u.x + light.edge_v.xyz * u.y;
        return LightPoint(y, light.normal.xyz, 1.0 / light.intensity.w, true);
    }
    if light.kind == LIGHT_SPHERE {
        let n = uniform_cone(vec3<f32>(0.0, 0.0, 1.0), -1.0, u);
        return LightPoint(light.position.xyz + light.position.w * n, n, 1.0 / light.intensity.w, true);
    }
    if light.kind == LIGHT_MESH {
        return mesh_point(light, u);
    }
    return LightPoint(light.position.xyz, vec3<f32>(0.0), 0.0, light.kind != LIGHT_DIRECTIONAL);
}

// The light's point for a receiver (the CPU's light_point): two random
// numbers for an area light, none for a delta light.
fn light_point(light: Light) -> LightPoint {
    var u = vec2<f32>(0.0);
    if is_area_light(light) {
        u = vec2<f32>(next_1d(), next_1d());
    }
    return light_point_at(light, u);
}

// A point of a mesh light (MeshLight::sample_point): u.x picks triangle
// k by binary search of the cumulative table c (the first entry above
// u.x), and, rescaled within k's share c_k − c_{k−1}, places the point
// on it with u.y. The density per unit area is that share over k's area
// A_k, taken from the f32 table itself, so the estimate is exact for the
// table as uploaded (the CPU's f64 table gives 1/A).
fn mesh_point(light: Light, u: vec2<f32>) -> LightPoint {
    var lo = 0u;
    var hi = light.triangle_count;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if light_triangles[light.first_triangle + mid].v0.w <= u.x {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let k = min(lo, light.triangle_count - 1u);
    let t = light_triangles[light.first_triangle + k];
    var low = 0.0;
    if k > 0u {
        low = light_triangles[light.first_triangle + k - 1u].v0.w;
    }
    let share = t.v0.w - low;
    var within = 0.5;
    if share > 0.0 {
        within = clamp((u.x - low) / share, 0.0, 0.99999994);
    }
    let y = triangle_point(t.v0.xyz, t.e1.xyz, t.e2.xyz, vec2<f32>(within, u.y));
    return LightPoint(y, t.normal.xyz, share / t.e1.w, true);
}

// cos θ_y of the light leaving area light `light` against the unit
// `direction` from the receiver, at a point of unit normal `normal`:
// ≤ 0 where a one-sided emitter shows its back.
fn emitting_cosine(light: Light, direction: vec3<f32>, normal: vec3<f32>) -> f32 {
    let cos_y = -dot(direction, normal);
    if light.two_sided != 0u {
        return abs(cos_y);
    }
    return cos_y;
}

// Light from `light` arriving at `x` from its point `y`, before
// occlusion, glass and fog (Light::incident): I(dir)/d² for point and
// spot lights (none outside the cone), E for a sun, and for an area
// light L·cos θ_y/(d²·p_A(y)) — its radiance over the point's density in
// solid angle — none behind a one-sided emitter.
fn incident(light: Light, x: vec3<f32>, y: LightPoint) -> Incident {
    if light.kind == LIGHT_DIRECTIONAL {
        return Incident(-light.direction.xyz, INFINITE, light.intensity.xyz, true);
    }
    if !y.valid {
        return NO_INCIDENT;
    }
    let to_light = y.position - x;
    let d2 = dot(to_light, to_light);
    if !(d2 > 0.0) {
        return NO_INCIDENT;
    }
    let direction = to_light / sqrt(d2);
    if is_area_light(light) {
        let cos_y = emitting_cosine(light, direction, y.normal);
        if !(cos_y > 0.0) {
            return NO_INCIDENT;
        }
        return Incident(direction, sqrt(d2), light.intensity.xyz * (cos_y / (d2 * y.area_density)), true);
    }
    var falloff = 1.0;
    if light.kind == LIGHT_SPOT {
        falloff = spot_falloff(light.profile, light.cos_cutoff, light.cos_inner,
            -dot(direction, light.direction.xyz));
        if !(falloff > 0.0) {
            return NO_INCIDENT;
        }
    }
    return Incident(direction, sqrt(d2), light.intensity.xyz * (falloff / d2), true);
}

// Light from a point of `light` chosen for the surface point `x`, over
// the point's density (Light::sample_li, as the CPU march's direct
// lighting draws it): a rectangle's point uniform in its solid angle
// seen from x within SOLID_ANGLE_REACH diagonals of its centre
// (QuadLight::sample_incident), a sphere's uniform in the cone it
// subtends from outside (SphereLight::sample_incident); else the point
// of light_point_at, uniform by area.
fn sample_incident(light: Light, x: vec3<f32>) -> Incident {
    if !is_area_light(light) {
        return incident(light, x, light_point_at(light, vec2<f32>(0.0)));
    }
    let u = vec2<f32>(next_1d(), next_1d());
    let diagonal = light.direction.xyz + light.edge_v.xyz;
    let from_centre = x - (light.position.xyz + 0.5 * diagonal);
    let reach2 = SOLID_ANGLE_REACH * SOLID_ANGLE_REACH * dot(diagonal, diagonal);
    if light.kind == LIGHT_QUAD && light.rectangle != 0u && dot(from_centre, from_centre) < reach2 {
        let width = length(light.direction.xyz);
        let height = length(light.edge_v.xyz);
        let rect = spherical_rectangle_new(light.position.xyz, light.direction.xyz / width,
            light.edge_v.xyz / height, width, height, x);
        if rect.valid {
            let to_light = spherical_rectangle_sample(rect, u) - x;
            let d2 = dot(to_light, to_light);
            if !(d2 > 0.0) {
                return NO_INCIDENT;
            }
            let direction = to_light / sqrt(d2);
            if !(emitting_cosine(light, direction, light.normal.xyz) > 0.0) {
                return NO_INCIDENT;
            }
            return Incident(direction, sqrt(d2), light.intensity.xyz * rect.solid_angle, true);
        }
    }
    if light.kind == LIGHT_SPHERE {
        let to_center = light.position.xyz - x;
        let d2 = dot(to_center, to_center);
        let r = light.position.w;
        if d2 > r * r * (1.0 + 1e-4) {
            let cos_max = sqrt(max(1.0 - r * r / d2, 0.0));
            let d = sqrt(d2);
            let axis = to_center / d;
            let direction = uniform_cone(axis, cos_max, u);
            // The nearer intersection, from the triangle x, centre,
            // point (as the CPU: a ray test misses at the silhouette).
            let c = min(dot(direction, axis), 1.0);
            let sin2 = max(1.0 - c * c, 0.0);
            let distance = d * c - sqrt(max(r * r - d2 * sin2, 0.0));
            return Incident(direction, distance, light.intensity.xyz / uniform_cone_pdf(cos_max), true);
        }
    }
    return incident(light, x, light_point_at(light, u));
}

// E·V·Tr_glass·T_fog: light `i` (`light`) arriving at `x` as `inc`, from
// a point in fog (`on_surface` false) or on a surface with unit normal
// `normal` (the shadow ray then starts just off it). Visibility comes
// from the light's shadow map when maps are on, except for area lights,
// which have none (maps.rs) and keep shadow rays, as on the CPU.
// Mirrors tyndall::integrators::lighting::light_arriving.
fn light_arriving(i: u32, light: Light, x: vec3<f32>, on_surface: bool, normal: vec3<f32>, inc: Incident) -> vec3<f32> {
    var origin = x;
    if on_surface {
        origin = offset_origin(x, normal, inc.direction);
    }
    var distance = inc.distance;
    if distance < INFINITE {
        distance = inc.distance - dot(origin - x, inc.direction);
    }
    var glass: vec3<f32>;
    if params.use_maps != 0u && !is_area_light(light) {
        glass = map_transmittance(i, origin, on_surface, normal, inc.direction);
    } else {
        glass = shadow_transmittance(origin, inc.direction, distance);
    }
    if all(glass == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    return inc.irradiance * glass * fog_transmittance_along(x, inc.direction, inc.distance);
}

// Radiance scattered at fog point `x` towards the camera (against unit
// `view`) from light `i` (`light`) via its point `y`, per unit length: the paper's
// eq. 1, σs·p(θ)·E·V·Tr_glass·T_fog
// (tyndall::integrators::lighting::scattered_radiance); 0 outside a spot's cone
// or behind a one-sided emitter, without a visibility query.
fn scattered_radiance(i: u32, light: Light, y: LightPoint, x: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    let inc = incident(light, x, y);
    if !inc.valid {
        return vec3<f32>(0.0);
    }
    let sigma_s = params.fog_albedo_sigma_t.xyz * sigma_t();
    let phase = phase_hg(params.background_g.w, dot(inc.direction, view));
    return sigma_s * phase * light_arriving(i, light, x, false, vec3<f32>(0.0), inc);
}

// Orders *a ≤ *b.
fn order_pair(a: ptr<function, f32>, b: ptr<function, f32>) {
    let lo = min(*a, *b);
    *b = max(*a, *b);
    *a = lo;
}

// Adds the piece [lo, hi] of `ray` to the cone's reach `acc` (lo, hi, 1
// if any) if its midpoint lies inside spot `light`'s cone.
fn add_piece_in_cone(light: Light, ray: Ray, lo: f32, hi: f32, acc: vec3<f32>) -> vec3<f32> {
    if hi <= lo {
        return acc;
    }
    var mid = 0.5 * (lo + hi);
    if hi >= INFINITE {
        mid = lo + 1.0 + abs(lo);
    }
    let p = ray_at(ray, mid) - light.position.xyz;
    if !(dot(p, light.direction.xyz) > length(p) * light.cos_cutoff) {
        return acc;
    }
    if acc.z == 0.0 {
        return vec3<f32>(lo, hi, 1.0);
    }
    return vec3<f32>(acc.x, hi, 1.0);
}

// The part of [t0, t1] along `ray` inside the cone of spot `light`
// (tyndall::lights::SpotLight::clip_ray): the cone's quadric and apex
// plane cut the segment; the pieces whose midpoint lies inside are
// joined. Returns (lo, hi, 1), or (0, 0, 0) if the ray misses the cone.
// The cuts live in five scalars (a cut that does not exist or falls
// outside [t0, t1] becomes t0, an empty piece), sorted by a 9-comparator
// network: no array indexed at run time, which a GPU would keep in slow
// per-thread memory.
//
// Solved about t_c, where the ray passes nearest the apex, as the CPU's
// is: about the ray's origin, the discriminant of a thin beam crossed
// near its apex far from the origin cancels below f32's rounding.
fn spot_reach(light: Light, ray: Ray, t0: f32, t1: f32) -> vec3<f32> {
    let axis = light.direction.xyz;
    let t_c = -dot(ray.origin - light.position.xyz, ray.direction);
    let v = ray.origin + t_c * ray.direction - light.position.xyz;
    let vd = dot(v, axis);
    let wd = dot(ray.direction, axis);
    let cos2 = light.cos_cutoff * light.cos_cutoff;
    let a = wd * wd - cos2;
    let b = 2.0 * (vd * wd - cos2 * dot(v, ray.direction));
    let c = vd * vd - cos2 * dot(v, v);
    var root0 = t0;
    var root1 = t0;
    if abs(a) > 1e-12 {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let q = -0.5 * (b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc));
            root0 = t_c + q / a;
            if q != 0.0 {
                root1 = t_c + c / q;
            }
        }
    } else if b != 0.0 {
        root0 = t_c - c / b;
    }
    var plane = t0;
    if wd != 0.0 {
        plane = t_c - vd / wd;
    }
    var c0 = t0;
    var c1 = t1;
    var c2 = select(t0, root0, root0 >= t0 && root0 <= t1);
    var c3 = select(t0, root1, root1 >= t0 && root1 <= t1);
    var c4 = select(t0, plane, plane >= t0 && plane <= t1);
    order_pair(&c0, &c3);
    order_pair(&c1, &c4);
    order_pair(&c0, &c2);
    order_pair(&c1, &c3);
    order_pair(&c0, &c1);
    order_pair(&c2, &c4);
    order_pair(&c1, &c2);
    order_pair(&c3, &c4);
    order_pair(&c2, &c3);
    var result = vec3<f32>(0.0);
    result = add_piece_in_cone(light, ray, c0, c1, result);
    result = add_piece_in_cone(light, ray, c1, c2, result);
    result = add_piece_in_cone(light, ray, c2, c3, result);
    result = add_piece_in_cone(light, ray, c3, c4, result);
    return result;
}

// The part of [t0, t1] along `ray` that light i can reach: its cone for a
// spot, everything for other lights (tyndall::lights::Light::reach).
fn reach(i: u32, ray: Ray, t0: f32, t1: f32) -> vec3<f32> {
    let light = lights[i];
    if light.kind == LIGHT_SPOT {
        return spot_reach(light, ray, t0, t1);
    }
    return vec3<f32>(t0, t1, select(0.0, 1.0, t0 < t1));
}
