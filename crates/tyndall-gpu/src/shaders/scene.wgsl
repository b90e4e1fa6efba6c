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
// shadow maps of maps.wgsl. Structs mirror scene_buffers.rs; `Params`
// and the constants shared with the Rust renderer (MAX_OPTICAL_DEPTH,
// MAX_GLASS_CROSSINGS, ESTIMATOR_*) come first, generated in Rust
// (march/params.rs).
//
// The kernel is assembled from modules in this order (shaders.rs):
// scene (buffers and kinds), rng, shapes, bvh, visibility, fog, lights,
// march, single, camera (the camera path and the entry points).

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
    // The GGX lobe's single-scattering albedo at cosines (k + 1)/16.
    albedo: array<vec4<f32>, 4>,
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
// A distance standing for ∞ (a sun's): exp(−σt·INFINITE) is 0 for σt > 0.
const INFINITE: f32 = 3.0e38;
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
