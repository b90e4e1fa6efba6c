// The paper's ray march (tyndall::integrators::march) on the GPU: one
// invocation per pixel and frame follows the camera path through thin
// glass and reflective layers, adds on its fog segment the in-scattered
// light by a jittered fixed-step Riemann sum with interleaved sampling
// (Keller & Heidrich 2001), shades the surface it ends on with direct
// light, and adds the sample to the pixel's running sum.
//
// Visibility towards lights (tyndall::visibility) is either exact — a
// shadow ray tested against every primitive, tinted by the glass it
// crosses under the scene's glass model — or read from the deep coloured
// shadow maps of maps.wgsl (appended to this file). Structs mirror
// scene_buffers.rs and march.rs.

struct Primitive {
    kind: u32,
    material: u32,
    one_sided: u32,
    pad: u32,
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    d: vec4<f32>,
    e: vec4<f32>,
}

struct Material {
    kind: u32,
    two_sided: u32,
    roughness: f32,
    alpha: f32,
    color: vec4<f32>,
    specular: vec4<f32>,
}

// scene_buffers.rs's GpuLight, whose comment says which fields each
// kind of light uses.
struct Light {
    kind: u32,
    profile: u32,
    cos_cutoff: f32,
    cos_inner: f32,
    position: vec4<f32>,
    direction: vec4<f32>,
    intensity: vec4<f32>,
    edge_v: vec4<f32>,
    normal: vec4<f32>,
    two_sided: u32,
    rectangle: u32,
    first_triangle: u32,
    triangle_count: u32,
}

// A triangle of an emissive mesh (scene_buffers.rs's GpuLightTriangle):
// v0.w the mesh's cumulative selection table here, e1.w the area.
struct LightTriangle {
    v0: vec4<f32>,
    e1: vec4<f32>,
    e2: vec4<f32>,
    normal: vec4<f32>,
}

// A node of the threaded BVH (bvh.rs): its box, the node after its
// subtree, and for a leaf `count` > 0 primitives from `first`.
struct BvhNode {
    min: vec3<f32>,
    skip: u32,
    max: vec3<f32>,
    first: u32,
    count: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

struct Params {
    camera_position: vec4<f32>,
    camera_forward: vec4<f32>,
    camera_right: vec4<f32>,
    camera_up: vec4<f32>,
    // (tan(fov_x/2), tan(fov_y/2), width, height)
    half_extent_resolution: vec4<f32>,
    // (albedo.rgb, σt)
    fog_albedo_sigma_t: vec4<f32>,
    // (min.xyz, 1 if there is fog)
    fog_min: vec4<f32>,
    // (max.xyz, 1 if the fog is bounded by the box)
    fog_max: vec4<f32>,
    // (background.rgb, g)
    background_g: vec4<f32>,
    step: f32,
    interleave: u32,
    seed: u32,
    frame: u32,
    // nodes in bvh_nodes (0 without primitives)
    node_count: u32,
    light_count: u32,
    glass_model: u32,
    opaque_to_camera: u32,
    max_bounces: u32,
    step_budget: u32,
    // 1: visibility from the maps of maps.wgsl; 0: shadow rays
    use_maps: u32,
    map_resolution: u32,
    // ESTIMATOR_MARCH or ESTIMATOR_SINGLE: how the fog segment's
    // in-scattering is estimated
    estimator: u32,
    // equiangular samples per light and segment (ESTIMATOR_SINGLE)
    volume_samples: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> primitives: array<Primitive>;
@group(0) @binding(2) var<storage, read> materials: array<Material>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(4) var<storage, read_write> accumulation: array<vec4<f32>>;
// Per pixel, the part of `accumulation` that is in-scattered light and
// the sum of the first hit's distances: what `interleave_resolve` filters.
@group(0) @binding(10) var<storage, read_write> fog_accumulation: array<vec4<f32>>;
// The resolved image (mean radiance, 1) that `interleave_resolve` writes.
@group(0) @binding(11) var<storage, read_write> display: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read> bvh_nodes: array<BvhNode>;
@group(0) @binding(14) var<storage, read> light_triangles: array<LightTriangle>;

const SHAPE_SPHERE: u32 = 0u;
const SHAPE_QUAD: u32 = 1u;
const MATERIAL_OPAQUE: u32 = 0u;
const MATERIAL_EMISSIVE: u32 = 1u;
const MATERIAL_LAMP_FACE: u32 = 2u;
const MATERIAL_GLASS: u32 = 3u;
const LIGHT_POINT: u32 = 0u;
const LIGHT_SPOT: u32 = 1u;
const LIGHT_DIRECTIONAL: u32 = 2u;
const LIGHT_QUAD: u32 = 3u;
const LIGHT_SPHERE: u32 = 4u;
const LIGHT_MESH: u32 = 5u;
const ESTIMATOR_MARCH: u32 = 0u;
const ESTIMATOR_SINGLE: u32 = 1u;
// A distance standing for ∞ (a sun's): exp(−σt·INFINITE) is 0 for σt > 0.
const INFINITE: f32 = 3.0e38;
// tyndall::integrators::march::MAX_OPTICAL_DEPTH.
const MAX_OPTICAL_DEPTH: f32 = 9.21;
// tyndall::integrators::MAX_GLASS_CROSSINGS.
const MAX_GLASS_CROSSINGS: u32 = 64u;
// Panes a blend-model shadow ray orders; more are an error the host
// cannot see, so the host refuses scenes with more glass primitives.
const MAX_BLEND_PANES: u32 = 16u;

struct Ray {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn ray_at(ray: Ray, t: f32) -> vec3<f32> {
    return ray.origin + ray.direction * t;
}

// ---- random numbers ----
//
// A pixel's first three dimensions in a frame (the film position and the
// first in-scattering number: the march's jitter, or single's distance
// sample) are
// frame f's point of the R₃ sequence (Roberts 2018, "The unreasonable
// effectiveness of quasirandom sequences"), fract(r + f·α) with
// α = (1/g, 1/g², 1/g³), g the real root > 1 of x⁴ = x + 1, under a
// random rotation r per pixel (Cranley–Patterson): every frame's point
// is uniform on [0, 1)³, so each pixel's mean is unbiased, and a pixel's
// frames fill the cube evenly, as a CPU pixel's Sobol samples do. Later
// dimensions come from the PCG hash (Jarzynski & Olano 2020).

var<private> rng_state: u32;
var<private> leading: vec3<u32>;
// How many of `leading` next_1d has handed out: 3 (none left) until a
// kernel sets them.
var<private> leading_used: u32 = 3u;

fn pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// 24 bits of `bits`: uniform on [0, 1) in f32.
fn unit_f32(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

// Frame `frame`'s R₃ point rotated by `rotation`, in 32-bit fixed point
// where adding wraps modulo 1 exactly: ⌊2³²·g⁻ᵏ⌋ for k = 1, 2, 3.
fn r3_point(rotation: vec3<u32>, frame: u32) -> vec3<u32> {
    return rotation + frame * vec3<u32>(3518319154u, 2882110344u, 2360945575u);
}

fn next_1d() -> f32 {
    if leading_used < 3u {
        let u = leading[leading_used];
        leading_used += 1u;
        return unit_f32(u);
    }
    rng_state = pcg(rng_state);
    return unit_f32(rng_state);
}

// ---- shapes (tyndall::shapes) ----

fn intersect_sphere(p: Primitive, ray: Ray, t_max: f32) -> f32 {
    let center = p.a.xyz;
    let radius = p.a.w;
    let oc = ray.origin - center;
    let b = dot(oc, ray.direction);
    let c = dot(oc, oc) - radius * radius;
    let perp = oc - b * ray.direction;
    let disc = radius * radius - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let sq = sqrt(disc);
    var q = -b + sq;
    if b > 0.0 {
        q = -b - sq;
    }
    let t0 = min(q, c / q);
    let t1 = max(q, c / q);
    if t0 > 0.0 && t0 < t_max {
        return t0;
    }
    if t1 > 0.0 && t1 < t_max {
        return t1;
    }
    return -1.0;
}

fn intersect_quad(p: Primitive, ray: Ray, t_max: f32) -> f32 {
    let normal = p.d.xyz;
    let denom = dot(normal, ray.direction);
    if denom == 0.0 || (p.one_sided != 0u && denom > 0.0) {
        return -1.0;
    }
    let t = dot(normal, p.a.xyz - ray.origin) / denom;
    if !(t > 0.0 && t < t_max) {
        return -1.0;
    }
    let q = ray_at(ray, t) - p.a.xyz;
    let u = dot(p.e.xyz, cross(q, p.c.xyz));
    let v = dot(p.e.xyz, cross(p.b.xyz, q));
    if u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0 {
        return t;
    }
    return -1.0;
}

fn intersect_triangle(p: Primitive, ray: Ray, t_max: f32) -> f32 {
    let e1 = p.b.xyz;
    let e2 = p.c.xyz;
    let pv = cross(ray.direction, e2);
    let det = dot(e1, pv);
    if det == 0.0 || (p.one_sided != 0u && det < 0.0) {
        return -1.0;
    }
    let inv = 1.0 / det;
    let s = ray.origin - p.a.xyz;
    let u = dot(s, pv) * inv;
    if u < 0.0 || u > 1.0 {
        return -1.0;
    }
    let q = cross(s, e1);
    let v = dot(ray.direction, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return -1.0;
    }
    let t = dot(e2, q) * inv;
    if t > 0.0 && t < t_max {
        return t;
    }
    return -1.0;
}

// Distance to primitive `i` along `ray` in (0, t_max), or −1.
fn intersect(i: u32, ray: Ray, t_max: f32) -> f32 {
    let p = primitives[i];
    if p.kind == SHAPE_SPHERE {
        return intersect_sphere(p, ray, t_max);
    }
    if p.kind == SHAPE_QUAD {
        return intersect_quad(p, ray, t_max);
    }
    return intersect_triangle(p, ray, t_max);
}

fn geometric_normal(i: u32, x: vec3<f32>) -> vec3<f32> {
    let p = primitives[i];
    if p.kind == SHAPE_SPHERE {
        return normalize(x - p.a.xyz);
    }
    return p.d.xyz;
}

struct Hit {
    t: f32,
    primitive: u32,
    found: bool,
}

// ---- the BVH (bvh.rs) ----

// A walk of the threaded BVH along one ray: the next node to visit and
// the rest of the current leaf's primitives.
struct BvhWalk {
    origin: vec3<f32>,
    // 1/direction, with zero components replaced by a tiny value of
    // their sign, so that no slab test meets 0·∞.
    inverse: vec3<f32>,
    node: u32,
    primitive: u32,
    primitive_end: u32,
}

// Marks the end of a walk.
const NO_PRIMITIVE: u32 = 0xffffffffu;

fn bvh_walk(ray: Ray) -> BvhWalk {
    let tiny = select(vec3<f32>(1e-20), vec3<f32>(-1e-20), ray.direction < vec3<f32>(0.0));
    let d = select(ray.direction, tiny, abs(ray.direction) < vec3<f32>(1e-20));
    return BvhWalk(ray.origin, 1.0 / d, 0u, 0u, 0u);
}

// The next primitive whose leaf box the ray meets in [0, t_max], or
// NO_PRIMITIVE: a subtree whose box the ray misses is skipped whole.
// Callers test each primitive themselves and may lower t_max between
// calls (the nearest hit so far).
fn bvh_next(walk: ptr<function, BvhWalk>, t_max: f32) -> u32 {
    loop {
        if (*walk).primitive < (*walk).primitive_end {
            let p = (*walk).primitive;
            (*walk).primitive = p + 1u;
            return p;
        }
        if (*walk).node >= params.node_count {
            return NO_PRIMITIVE;
        }
        let node = bvh_nodes[(*walk).node];
        let a = (node.min - (*walk).origin) * (*walk).inverse;
        let b = (node.max - (*walk).origin) * (*walk).inverse;
        let lo = min(a, b);
        let hi = max(a, b);
        let near = max(max(lo.x, lo.y), max(lo.z, 0.0));
        let far = min(min(hi.x, hi.y), min(hi.z, t_max));
        if near <= far {
            if node.count > 0u {
                (*walk).primitive = node.first;
                (*walk).primitive_end = node.first + node.count;
            }
            (*walk).node += 1u;
        } else {
            (*walk).node = node.skip;
        }
    }
    return NO_PRIMITIVE;
}

// Primary visibility: the nearest hit, through the BVH.
fn nearest_hit(ray: Ray) -> Hit {
    var hit = Hit(INFINITE, 0u, false);
    var walk = bvh_walk(ray);
    loop {
        let i = bvh_next(&walk, hit.t);
        if i == NO_PRIMITIVE {
            break;
        }
        let t = intersect(i, ray, hit.t);
        if t > 0.0 {
            hit = Hit(t, i, true);
        }
    }
    return hit;
}

// ---- ray offsets (tyndall::ray) ----

fn offset_distance(x: vec3<f32>) -> f32 {
    let a = abs(x);
    return 1e-4 * (1.0 + max(a.x, max(a.y, a.z)));
}

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
// seen from x (QuadLight::sample_incident), a sphere's uniform in the
// cone it subtends from outside (SphereLight::sample_incident); else the
// point of light_point_at, uniform by area.
fn sample_incident(light: Light, x: vec3<f32>) -> Incident {
    if !is_area_light(light) {
        return incident(light, x, light_point_at(light, vec2<f32>(0.0)));
    }
    let u = vec2<f32>(next_1d(), next_1d());
    if light.kind == LIGHT_QUAD && light.rectangle != 0u {
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
// (tyndall::integrators::scattered_radiance); 0 outside a spot's cone
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
fn spot_reach(light: Light, ray: Ray, t0: f32, t1: f32) -> vec3<f32> {
    let axis = light.direction.xyz;
    let v = ray.origin - light.position.xyz;
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
            root0 = q / a;
            if q != 0.0 {
                root1 = c / q;
            }
        }
    } else if b != 0.0 {
        root0 = -c / b;
    }
    var plane = t0;
    if wd != 0.0 {
        plane = -vd / wd;
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

// ---- the march (tyndall::integrators::march::in_scattered) ----

// The jitter stratum k of this pixel in an n×n interleaving tile, as
// tyndall::integrators::march::interleaved_stratum (Bayer order for n a
// power of two, row order otherwise).
fn interleaved_stratum(px: vec2<u32>, n_in: u32) -> u32 {
    let n = max(n_in, 1u);
    let x = px.x % n;
    let y = px.y % n;
    if (n & (n - 1u)) == 0u {
        var k = 0u;
        let bits = countTrailingZeros(n);
        for (var b = 0u; b < bits; b++) {
            let xb = (x >> b) & 1u;
            let yb = (y >> b) & 1u;
            k = k * 4u + 2u * (xb ^ yb) + yb;
        }
        return k;
    }
    return y * n + x;
}

// The lattice cells k ≡ r (mod m) a pixel of stratum s evaluates in this
// frame, m = n² the tile's strata: r = (s + f + ρ) mod m, with ρ a random
// rotation per seed. Inside one frame the tile's pixels take each residue
// once (Keller & Heidrich 2001: the tile shares out the lattice); over m
// consecutive frames each pixel takes each residue once, and in any one
// frame its r is uniform over the m residues (because ρ is).
fn lattice_residue(stratum: u32, strata: u32) -> u32 {
    return (stratum + params.frame + pcg(params.seed ^ 0x2c1b3c6du) % strata) % strata;
}

// In-scattered radiance along `ray` over (0, t_hit) by the jittered
// lattice t_k = a + (ξ + k)·h, ξ in stratum s of m = n²: the CPU march's
// Σ_k T(a, t_k)·Σ_lights σs·p(θ)·E·V·Tr_glass·T_fog·h (the paper's eq. 1
// per step), of which this pixel evaluates only the cells k ≡ r (mod m)
// of lattice_residue, each weighted m·h. As r is uniform over the
// residues, the expectation over r is the full sum's: each pixel
// converges to the CPU march of the same step and interleave, while a
// frame costs 1/m of the lattice per pixel.
fn in_scattered(ray: Ray, t_hit: f32, stratum: u32, strata: u32) -> vec3<f32> {
    let jitter = (f32(stratum) + next_1d()) / f32(strata);
    let residue = lattice_residue(stratum, strata);
    let span = fog_interval(ray, 0.0, t_hit);
    let sigma_s = params.fog_albedo_sigma_t.xyz * sigma_t();
    if span.z == 0.0 || all(sigma_s == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let a = span.x;
    let b = min(span.y, a + MAX_OPTICAL_DEPTH / sigma_t());
    // Only the lattice points inside some light's reach are visited.
    var lo = INFINITE;
    var hi = -INFINITE;
    for (var i = 0u; i < params.light_count; i++) {
        let r = reach(i, ray, a, b);
        if r.z != 0.0 {
            lo = min(lo, r.x);
            hi = max(hi, r.y);
        }
    }
    if !(lo < hi) {
        return vec3<f32>(0.0);
    }
    let h = params.step;
    // The first lattice index k ≥ 0 with t_k ≥ lo
    // (tyndall::integrators::march::lattice_range, in f32 here).
    let first = u32(max(ceil((lo - a) / h - jitter), 0.0));
    // The first cell at or after `first` in this pixel's residue class.
    let own = first + (residue + strata - first % strata) % strata;
    // Lights outside, steps inside (the CPU nests them the other way;
    // the sum is the same): each light is read once per ray, and its
    // steps' map lookups stay in one map. On lavapipe this made the
    // demo's 64-step full march 1.4× faster (docs/benchmarks.md).
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < params.light_count; i++) {
        let light = lights[i];
        for (var k = own; k - first < params.step_budget; k += strata) {
            let t = a + (jitter + f32(k)) * h;
            if t >= hi {
                break;
            }
            let x = ray_at(ray, t);
            let camera_t = transmittance(sigma_t(), t - a);
            sum += camera_t * scattered_radiance(i, light, light_point(light), x, ray.direction);
        }
    }
    return sum * (h * f32(strata));
}

// ---- unbiased single scattering (tyndall::integrators::single) ----

// The interleaving pattern's offset for light `i` in this frame, the same
// in every pixel (a Cranley–Patterson rotation): the golden-ratio
// sequence r_f = r₀ + f·φ (mod 1) from a random r₀ per seed and light.
// Each r_f is uniform on [0, 1) because r₀ is, and successive frames'
// offsets spread evenly over [0, 1), so a pixel's offsets over frames are
// stratified as a CPU pixel's samples are.
fn frame_offset(i: u32) -> f32 {
    let r0 = pcg(pcg(params.seed ^ 0x5bd1e995u) ^ i);
    // In 32-bit fixed point, where adding wraps modulo 1 exactly:
    // 0x9e3779b9 = ⌊2³²·(φ − 1)⌋, φ − 1 = 0.6180339887….
    return f32((r0 + params.frame * 0x9e3779b9u) >> 8u) * (1.0 / 16777216.0);
}

// The equiangular sample offset u ∈ [0, 1) of light `i` in this pixel:
// stratum k of the interleaving tile's n² (Keller & Heidrich 2001), so
// that the tile's pixels share out [0, 1) as a march's pixels share out
// the step, jittered inside it, and shifted by the frame's offset modulo
// 1. The shift makes u uniform on [0, 1) in every pixel, so each
// pixel's estimate is unbiased on its own (not only the tile's mean),
// while inside each frame neighbouring pixels stay stratified.
fn interleaved_offset(stratum: u32, strata: u32, i: u32) -> f32 {
    let u = (f32(stratum) + next_1d()) / f32(strata) + frame_offset(i);
    // fract may round up to 1 just below an integer; keep u < 1.
    return min(fract(u), 0.99999994);
}

// In-scattered radiance along `ray` over (0, t_hit), relative to the
// radiance at its origin, as tyndall::integrators::single::in_scattered:
// per light, one emitting point y (light_point: an area light's drawn
// anew on each segment), n equiangular samples about y at offsets
// (k + u)/n of the light's reach (the spot's cone; none for a sun,
// which has no emitting point) and the
// ray's one distance sample t_d, shared by the lights, combined by the
// multi-sample balance heuristic (Veach 1997):
// Σ_k f(t_k)/(n·p_e(t_k) + p_d(t_k)) + f(t_d)/(n·p_e(t_d) + p_d(t_d)),
// f(t) = T(a, t)·eq. 1. Unbiased for any u distribution that is uniform
// on [0, 1) per pixel, as interleaved_offset's is.
fn single_in_scattered(ray: Ray, t_hit: f32, stratum: u32, strata: u32) -> vec3<f32> {
    let u_distance = next_1d();
    let span = fog_interval(ray, 0.0, t_hit);
    let sigma_s = params.fog_albedo_sigma_t.xyz * sigma_t();
    if span.z == 0.0 || all(sigma_s == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let a = span.x;
    let b = span.y;
    let distance = exponential_new(sigma_t(), a, b);
    if !distance.valid {
        return vec3<f32>(0.0);
    }
    let t_d = exponential_sample(distance, u_distance);
    let pdf_d = exponential_pdf(distance, t_d);
    let x_d = ray_at(ray, t_d);
    let n = f32(params.volume_samples);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < params.light_count; i++) {
        let light = lights[i];
        let y = light_point(light);
        let u_equiangular = interleaved_offset(stratum, strata, i);
        var equiangular = Equiangular(0.0, 1.0, 0.0, 0.0, a, b, false);
        if y.valid {
            let r = reach(i, ray, a, b);
            if r.z != 0.0 {
                equiangular = equiangular_new(ray.origin, ray.direction, y.position, r.x, r.y);
            }
        }
        if equiangular.valid {
            for (var k = 0u; k < params.volume_samples; k++) {
                let t = equiangular_sample(equiangular, (f32(k) + u_equiangular) / n);
                let f = scattered_radiance(i, light, y, ray_at(ray, t), ray.direction);
                if any(f != vec3<f32>(0.0)) {
                    let weight = n * equiangular_pdf(equiangular, t) + exponential_pdf(distance, t);
                    sum += f * (transmittance(sigma_t(), t - a) / weight);
                }
            }
        }
        let f = scattered_radiance(i, light, y, x_d, ray.direction);
        if any(f != vec3<f32>(0.0)) {
            let weight = pdf_d + n * equiangular_pdf(equiangular, t_d);
            sum += f * (transmittance(sigma_t(), t_d - a) / weight);
        }
    }
    return sum;
}

// The fog segment's in-scattering by the estimator the host chose.
fn fog_in_scattered(ray: Ray, t_hit: f32, stratum: u32, strata: u32) -> vec3<f32> {
    if params.estimator == ESTIMATOR_SINGLE {
        return single_in_scattered(ray, t_hit, stratum, strata);
    }
    return in_scattered(ray, t_hit, stratum, strata);
}

// Direct light on a Lambertian surface: Σ ρ/π·E·cos θ·V·Tr_glass·T_fog,
// one sample_incident per light (the CPU march's lambert_direct_lighting).
fn direct_lighting(diffuse: vec3<f32>, x: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    if all(diffuse == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < params.light_count; i++) {
        let light = lights[i];
        let inc = sample_incident(light, x);
        if !inc.valid {
            continue;
        }
        let cos_theta = dot(normal, inc.direction);
        if cos_theta <= 0.0 {
            continue;
        }
        sum += light_arriving(i, light, x, true, normal, inc) * cos_theta;
    }
    return sum * diffuse / PI;
}

// The reflective layer's direction (tyndall::materials::Surface::reflect):
// the mirror direction, or a normalised Phong lobe cosⁿ around it with
// n = 2/r² − 2; zero vector when the drawn direction is below the surface.
fn reflect_layer(roughness: f32, incoming: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let mirror = incoming - 2.0 * dot(incoming, normal) * normal;
    let u = vec2<f32>(next_1d(), next_1d());
    if roughness <= 0.0 {
        return mirror;
    }
    let r2 = max(roughness * roughness, 1e-6);
    let exponent = max(2.0 / r2 - 2.0, 0.0);
    let cos_t = pow(u.x, 1.0 / (exponent + 1.0));
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let phi = 2.0 * PI * u.y;
    let frame = orthonormal_pair(mirror);
    let dir = normalize(frame[0] * (sin_t * cos(phi)) + frame[1] * (sin_t * sin(phi)) + mirror * cos_t);
    if dot(dir, normal) > 0.0 {
        return dir;
    }
    return vec3<f32>(0.0);
}

// The camera path of tyndall::integrators::CameraPath::radiance for the
// materials the GPU renders (no dielectrics: the host refuses them).
//
// Also leaves the in-scattered part of the result in `fog_radiance` and
// the first segment's length (FAR_DEPTH if the camera ray escapes) in
// `first_depth`, for interleave_resolve.
var<private> fog_radiance: vec3<f32>;
var<private> first_depth: f32;

// The depth recorded for a camera ray that meets nothing: finite, so that
// sums of it over frames stay finite.
const FAR_DEPTH: f32 = 1.0e30;

fn radiance(first: Ray, stratum: u32, strata: u32) -> vec3<f32> {
    var ray = first;
    fog_radiance = vec3<f32>(0.0);
    first_depth = -1.0;
    var result = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    var bounces = 0u;
    var crossings = 0u;
    loop {
        let hit = nearest_hit(ray);
        if first_depth < 0.0 {
            first_depth = select(FAR_DEPTH, hit.t, hit.found);
        }
        if has_fog() {
            let in_scattered = throughput * fog_in_scattered(ray, hit.t, stratum, strata);
            result += in_scattered;
            fog_radiance += in_scattered;
            var fog_t = 1.0;
            let span = fog_interval(ray, 0.0, hit.t);
            if span.z != 0.0 {
                fog_t = transmittance(sigma_t(), span.y - span.x);
            }
            throughput *= fog_t;
        }
        if !hit.found {
            return result + throughput * params.background_g.xyz;
        }
        if all(throughput == vec3<f32>(0.0)) {
            return result;
        }
        let x = ray_at(ray, hit.t);
        let gn = geometric_normal(hit.primitive, x);
        let front = dot(gn, ray.direction) < 0.0;
        let normal = select(-gn, gn, front);
        let material = materials[primitives[hit.primitive].material];
        var diffuse = material.color.xyz;
        var specular = vec3<f32>(0.0);
        if material.kind == MATERIAL_EMISSIVE || material.kind == MATERIAL_LAMP_FACE {
            if front || (material.kind == MATERIAL_EMISSIVE && material.two_sided != 0u) {
                result += throughput * material.color.xyz;
            }
            return result;
        }
        if material.kind == MATERIAL_GLASS && params.opaque_to_camera == 0u {
            crossings++;
            if crossings > MAX_GLASS_CROSSINGS {
                return result;
            }
            throughput *= glass_filter_transmittance(material.color.xyz, material.alpha);
            ray.origin = offset_origin(x, gn, ray.direction);
            continue;
        }
        if material.kind == MATERIAL_OPAQUE {
            specular = material.specular.xyz;
        }
        result += throughput * direct_lighting(diffuse, x, normal);
        if all(specular == vec3<f32>(0.0)) || bounces >= params.max_bounces {
            return result;
        }
        let direction = reflect_layer(material.roughness, ray.direction, normal);
        if all(direction == vec3<f32>(0.0)) {
            return result;
        }
        bounces++;
        throughput *= specular;
        ray = Ray(offset_origin(x, gn, direction), direction);
    }
    return result;
}

// Marks an invocation outside the image.
const NO_PIXEL: u32 = 0xffffffffu;

// The index of pixel id.xy in the image's arrays, or NO_PIXEL.
fn pixel_index(id: vec3<u32>) -> u32 {
    let width = u32(params.half_extent_resolution.z);
    if id.x >= width || id.y >= u32(params.half_extent_resolution.w) {
        return NO_PIXEL;
    }
    return id.y * width + id.x;
}

@compute @workgroup_size(8, 8)
fn march_frame(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = pixel_index(id);
    if index == NO_PIXEL {
        return;
    }
    rng_state = pcg(index ^ pcg(params.seed ^ pcg(params.frame)));
    let rotation = pcg(index ^ pcg(params.seed ^ 0x68e31da4u));
    leading = r3_point(vec3<u32>(rotation, pcg(rotation), pcg(pcg(rotation))), params.frame);
    leading_used = 0u;
    // The film position, uniform over the pixel (a box filter), then the
    // ray of tyndall::camera::Camera::ray.
    let film = vec2<f32>(f32(id.x) + next_1d(), f32(id.y) + next_1d());
    let ndc = 2.0 * film / params.half_extent_resolution.zw - vec2<f32>(1.0);
    let direction = normalize(params.camera_forward.xyz
        + params.camera_right.xyz * (ndc.x * params.half_extent_resolution.x)
        - params.camera_up.xyz * (ndc.y * params.half_extent_resolution.y));
    let n = max(params.interleave, 1u);
    let stratum = interleaved_stratum(id.xy, n);
    let l = radiance(Ray(params.camera_position.xyz, direction), stratum, n * n);
    accumulation[index] += vec4<f32>(l, 1.0);
    fog_accumulation[index] += vec4<f32>(fog_radiance, first_depth);
}

// Two mean first-hit depths belong to one surface (the discontinuity
// buffer's test, Keller & Heidrich 2001): within DEPTH_TOLERANCE of
// each other, relatively. Depth alone suffices for the first segment's
// in-scattered light, most of it, which depends on the camera ray and
// how far it runs, not on the surface's normal: it is continuous across
// a crease at equal depth. (What a glossy surface reflects of the fog
// does depend on the normal; across a crease it is blurred.)
const DEPTH_TOLERANCE: f32 = 0.05;

// The image of the frames so far with the in-scattered light of each
// pixel averaged over the n×n window around it (which holds each stratum
// of the interleaving tile once), over the window's pixels whose mean
// first-hit depth matches this pixel's: Keller & Heidrich's discontinuity
// buffer, which turns the tile's shared-out lattice cells back into one
// full lattice per pixel. Surface light is not filtered. Dispatched by
// the host only while the image is young (see GpuMarch::display_image).
@compute @workgroup_size(8, 8)
fn interleave_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = pixel_index(id);
    if index == NO_PIXEL {
        return;
    }
    let width = u32(params.half_extent_resolution.z);
    let height = u32(params.half_extent_resolution.w);
    let total = accumulation[index];
    let own = fog_accumulation[index];
    if !(total.w > 0.0) {
        display[index] = vec4<f32>(0.0, 0.0, 0.0, 1.0);
        return;
    }
    let n = i32(max(params.interleave, 1u));
    let depth = own.w;
    var fog = vec3<f32>(0.0);
    var weight = 0.0;
    for (var dy = 0; dy < n; dy++) {
        for (var dx = 0; dx < n; dx++) {
            let x = i32(id.x) + dx - n / 2;
            let y = i32(id.y) + dy - n / 2;
            if x < 0 || y < 0 || x >= i32(width) || y >= i32(height) {
                continue;
            }
            let other = fog_accumulation[u32(y) * width + u32(x)];
            if abs(other.w - depth) <= DEPTH_TOLERANCE * min(other.w, depth) {
                fog += other.xyz;
                weight += 1.0;
            }
        }
    }
    // The pixel itself always passes, so weight ≥ 1.
    display[index] = vec4<f32>((total.xyz - own.xyz + fog / weight) / total.w, 1.0);
}
