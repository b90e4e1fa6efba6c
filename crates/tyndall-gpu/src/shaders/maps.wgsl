// Deep coloured shadow maps on the GPU (tyndall::shadow_maps, the paper's
// §4.3 and §5.1): per light one perspective face (a spot of cutoff ≤ 60°),
// six cube faces (point lights, wider spots) or one orthographic face (a
// sun). A texel stores the distance to the first opaque surface, negated
// when glass lies before it, and that glass as layers (depth, the light's
// tint after crossing it); a lookup is percentage-closer filtered over
// the four nearest texels. Built by two kernels: `map_count` (depths, and
// each texel's span of the layer array, taken from a counter shared by
// all texels) and `map_layers` (the layers, for texels that have some).
// Where a texel's span lies depends on the order texels took theirs;
// what a lookup reads from it does not.
// Appended to march.wgsl, whose bindings and shape tests it uses.

struct Face {
    origin: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    // (forward.xyz, 0 for a perspective face, 1 for an orthographic one)
    forward_kind: vec4<f32>,
    // tan(half angle) of a perspective face, half extent of an orthographic one
    scale: f32,
    texel_base: u32,
    pad0: u32,
    pad1: u32,
}

struct LightMap {
    face_base: u32,
    face_count: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(5) var<storage, read> faces: array<Face>;
@group(0) @binding(6) var<storage, read> light_maps: array<LightMap>;
@group(0) @binding(7) var<storage, read_write> map_depths: array<f32>;
// Per texel (first layer, layer count).
@group(0) @binding(8) var<storage, read_write> layer_spans: array<vec2<u32>>;
// (tint.rgb, depth)
@group(0) @binding(9) var<storage, read_write> layers: array<vec4<f32>>;
// Layers handed out so far (the host zeroes it before a full build).
@group(0) @binding(13) var<storage, read_write> layers_taken: atomic<u32>;

// tyndall::shadow_maps::LIGHT_CLEARANCE, BIAS_TEXELS, MAX_BIAS_SLOPE.
const LIGHT_CLEARANCE: f32 = 1e-4;
const BIAS_TEXELS: f32 = 1.5;
const MAX_BIAS_SLOPE: f32 = 8.0;
// Glass crossings a texel ray keeps (the host refuses scenes that could
// have more).
const MAX_MAP_LAYERS: u32 = 16u;

// The ray of a face through face coordinates s ∈ [−1, 1]².
fn face_ray(face: Face, s: vec2<f32>) -> Ray {
    let lateral = face.right.xyz * s.x + face.up.xyz * s.y;
    if face.forward_kind.w == 0.0 {
        return Ray(face.origin.xyz, normalize(face.forward_kind.xyz + lateral * face.scale));
    }
    return Ray(face.origin.xyz + lateral * face.scale, face.forward_kind.xyz);
}

// A shape as a ray from the light meets it: one-sided shapes seen from
// their other side (tyndall::shapes::Shape::intersect_from_light).
fn intersect_from_light(i: u32, ray: Ray, t_max: f32) -> f32 {
    var p = primitives[i];
    if p.one_sided != 0u && p.kind == SHAPE_QUAD {
        p.d = -p.d;
        return intersect_quad(p, ray, t_max);
    }
    if p.one_sided != 0u && p.kind != SHAPE_SPHERE {
        let e1 = p.b;
        p.b = p.c;
        p.c = e1;
        p.d = -p.d;
        return intersect_triangle(p, ray, t_max);
    }
    return intersect(i, ray, t_max);
}

var<private> texel_glass_t: array<f32, MAX_MAP_LAYERS>;
var<private> texel_glass_m: array<u32, MAX_MAP_LAYERS>;
var<private> texel_glass_count: u32;

// Traces texel (x, y) of face `f`: returns the first opaque distance and
// leaves the glass before it, nearest first, in the texel_glass arrays.
fn trace_texel(f: u32, x: u32, y: u32) -> f32 {
    let face = faces[f];
    let r = f32(params.map_resolution);
    let s = vec2<f32>((f32(x) + 0.5) / r * 2.0 - 1.0, (f32(y) + 0.5) / r * 2.0 - 1.0);
    let ray = face_ray(face, s);
    let o = abs(ray.origin);
    let clearance = LIGHT_CLEARANCE * (1.0 + max(o.x, max(o.y, o.z)));
    var opaque = INFINITE;
    texel_glass_count = 0u;
    var walk = bvh_walk(ray);
    loop {
        // Glass beyond the nearest opaque surface so far is dropped below,
        // so the walk may stop there.
        let i = bvh_next(&walk, opaque);
        if i == NO_PRIMITIVE {
            break;
        }
        let t = intersect_from_light(i, ray, INFINITE);
        if t <= clearance {
            continue;
        }
        let m = primitives[i].material;
        if materials[m].kind != MATERIAL_GLASS {
            opaque = min(opaque, t);
        } else if texel_glass_count < MAX_MAP_LAYERS {
            var j = texel_glass_count;
            while j > 0u && texel_glass_t[j - 1u] > t {
                texel_glass_t[j] = texel_glass_t[j - 1u];
                texel_glass_m[j] = texel_glass_m[j - 1u];
                j--;
            }
            texel_glass_t[j] = t;
            texel_glass_m[j] = m;
            texel_glass_count++;
        }
    }
    var kept = 0u;
    while kept < texel_glass_count && texel_glass_t[kept] < opaque {
        kept++;
    }
    texel_glass_count = kept;
    return opaque;
}

fn texel_index(id: vec3<u32>) -> u32 {
    let r = params.map_resolution;
    return faces[id.z].texel_base + id.y * r + id.x;
}

// Pass 1: each texel's opaque depth (negated with glass) and its span of
// the layer array.
@compute @workgroup_size(8, 8)
fn map_count(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.map_resolution || id.y >= params.map_resolution {
        return;
    }
    let opaque = trace_texel(id.z, id.x, id.y);
    let i = texel_index(id);
    map_depths[i] = select(opaque, -opaque, texel_glass_count > 0u);
    var first = 0u;
    if texel_glass_count > 0u {
        first = atomicAdd(&layers_taken, texel_glass_count);
    }
    layer_spans[i] = vec2<u32>(first, texel_glass_count);
}

// Pass 2: the layers, in the spans of pass 1 (the host has made the
// layer array hold them all).
@compute @workgroup_size(8, 8)
fn map_layers(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.map_resolution || id.y >= params.map_resolution {
        return;
    }
    let span = layer_spans[texel_index(id)];
    // Most texels see no glass: nothing to write, no need to trace again.
    if span.y == 0u {
        return;
    }
    let offset = span.x;
    trace_texel(id.z, id.x, id.y);
    var tint = vec3<f32>(1.0);
    for (var j = 0u; j < min(texel_glass_count, span.y); j++) {
        let g = materials[texel_glass_m[j]];
        tint = glass_tint_after(params.glass_model, tint, g.color.xyz, g.alpha);
        layers[offset + j] = vec4<f32>(tint, texel_glass_t[j]);
    }
}

// Texel t's answer for a point at `depth` (tyndall::shadow_maps::Face::lookup).
fn texel_answer(t: u32, depth: f32, bias: f32) -> vec3<f32> {
    let stored = map_depths[t];
    if depth > abs(stored) + bias {
        return vec3<f32>(0.0);
    }
    if stored >= 0.0 {
        return vec3<f32>(1.0);
    }
    // The last pane in front of the point sets the tint.
    let span = layer_spans[t];
    let first = span.x;
    var j = span.x + span.y;
    while j > first {
        j--;
        let layer = layers[j];
        if layer.w + bias < depth {
            return layer.xyz;
        }
    }
    return vec3<f32>(1.0);
}

// Light from light i reaching `x` past geometry, from its map
// (tyndall::shadow_maps::ShadowMaps::transmittance): `on_surface` with
// the surface's `normal` for the slope-scaled bias, unit `to_light`.
fn map_transmittance(i: u32, x: vec3<f32>, on_surface: bool, normal: vec3<f32>, to_light: vec3<f32>) -> vec3<f32> {
    let light_map = light_maps[i];
    var f = light_map.face_base;
    if light_map.face_count == 6u {
        let d = -to_light;
        let a = abs(d);
        if a.x >= a.y && a.x >= a.z {
            f += select(1u, 0u, d.x > 0.0);
        } else if a.y >= a.z {
            f += select(3u, 2u, d.y > 0.0);
        } else {
            f += select(5u, 4u, d.z > 0.0);
        }
    }
    let face = faces[f];
    let dv = x - face.origin.xyz;
    let lateral = vec2<f32>(dot(dv, face.right.xyz), dot(dv, face.up.xyz));
    let z = dot(dv, face.forward_kind.xyz);
    let perspective = face.forward_kind.w == 0.0;
    var s: vec2<f32>;
    var depth: f32;
    if perspective {
        if !(z > 0.0) {
            return vec3<f32>(1.0);
        }
        s = lateral / (z * face.scale);
        depth = length(dv);
    } else {
        s = lateral / face.scale;
        depth = z;
    }
    if abs(s.x) > 1.0 || abs(s.y) > 1.0 {
        return vec3<f32>(1.0);
    }
    let r = f32(params.map_resolution);
    var bias = 0.0;
    if on_surface {
        let c = max(abs(dot(normal, to_light)), 1e-3);
        let slope = min(sqrt(1.0 - c * c) / c, MAX_BIAS_SLOPE);
        var footprint = 2.0 * face.scale / r;
        if perspective {
            footprint = depth * 2.0 * face.scale / r;
        }
        bias = footprint * (BIAS_TEXELS + slope);
    }
    // Texel centres sit at integer coordinates p = (s + 1)/2·R − ½.
    let p = (s + vec2<f32>(1.0)) * 0.5 * r - vec2<f32>(0.5);
    let x0 = i32(p.x + 1.0) - 1;
    let y0 = i32(p.y + 1.0) - 1;
    let fr = p - vec2<f32>(f32(x0), f32(y0));
    let top = i32(params.map_resolution) - 1;
    let c0 = u32(clamp(x0, 0, top));
    let c1 = u32(clamp(x0 + 1, 0, top));
    let r0 = u32(clamp(y0, 0, top)) * params.map_resolution;
    let r1 = u32(clamp(y0 + 1, 0, top)) * params.map_resolution;
    let base = face.texel_base;
    return texel_answer(base + r0 + c0, depth, bias) * ((1.0 - fr.x) * (1.0 - fr.y))
        + texel_answer(base + r0 + c1, depth, bias) * (fr.x * (1.0 - fr.y))
        + texel_answer(base + r1 + c0, depth, bias) * ((1.0 - fr.x) * fr.y)
        + texel_answer(base + r1 + c1, depth, bias) * (fr.x * fr.y);
}
