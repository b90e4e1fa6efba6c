// Kernels that evaluate the scene-dependent functions of the march module
// — lights.wgsl's, the fog's, the shapes' and the BVH's, the march's and
// the camera's — on a list of inputs, for tests/lights.rs,
// tests/scattering.rs and tests/march_functions.rs ("one formula, two
// languages", issue 26). Appended to the whole march module, so they run
// the very functions the march runs, on the buffers scene_buffers.rs
// uploads. Each item has three input vec4s and two output vec4s.

@group(0) @binding(20) var<storage, read> probe_inputs: array<vec4<f32>>;
@group(0) @binding(21) var<storage, read_write> probe_outputs: array<vec4<f32>>;

fn probe_count() -> u32 {
    return arrayLength(&probe_outputs) / 2u;
}

// in0 = (origin.xyz, t0), in1 = (direction.xyz, t1), in2 = (light index)
// → out0 = spot_reach (lo, hi, 1) or 0
@compute @workgroup_size(64)
fn probe_spot_reach(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    let light = lights[u32(c.x)];
    probe_outputs[2u * i] = vec4<f32>(spot_reach(light, Ray(a.xyz, b.xyz), a.w, b.w), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (x.xyz, _), in2 = (light index, u.x, u.y) → the light's point
// y = light_point_at(u) and incident(light, x, y): out0 = (direction,
// distance), out1 = (irradiance, valid)
@compute @workgroup_size(64)
fn probe_incident(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let c = probe_inputs[3u * i + 2u];
    let light = lights[u32(c.x)];
    let inc = incident(light, a.xyz, light_point_at(light, c.yz));
    probe_outputs[2u * i] = vec4<f32>(inc.direction, inc.distance);
    probe_outputs[2u * i + 1u] = vec4<f32>(inc.irradiance, select(0.0, 1.0, inc.valid));
}

// in0 = (x.xyz, _), in1 = (k.x, k.y) integers below 2²⁴, in2 = (light
// index) → sample_incident(light, x) drawing u = k/2²⁴ (next_1d's first
// two numbers, set through the R₃ slots it reads first): out0 =
// (direction, distance), out1 = (irradiance, valid)
@compute @workgroup_size(64)
fn probe_sample_incident(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    leading = vec3<u32>(u32(b.x) << 8u, u32(b.y) << 8u, 0u);
    leading_used = 0u;
    let inc = sample_incident(lights[u32(c.x)], a.xyz);
    probe_outputs[2u * i] = vec4<f32>(inc.direction, inc.distance);
    probe_outputs[2u * i + 1u] = vec4<f32>(inc.irradiance, select(0.0, 1.0, inc.valid));
}

// Bound with the march's own bindings (formula_probe::evaluate_in_scene).
// in0 = (x.xyz, _), in1 = (view.xyz, _), in2 = (light index, u.x, u.y)
// → out0 = scattered_radiance(i, light, light_point_at(light, u), x, view)
@compute @workgroup_size(64)
fn probe_scattered_radiance(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    let index = u32(c.x);
    let light = lights[index];
    let radiance = scattered_radiance(index, light, light_point_at(light, c.yz), a.xyz, b.xyz);
    probe_outputs[2u * i] = vec4<f32>(radiance, 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (x.xyz, on_surface 0 or 1), in1 = (normal.xyz, _), in2 = (light
// index, u.x, u.y) → inc = incident(light, x, light_point_at(light, u));
// out0 = (light_arriving(i, light, x, on_surface, normal, inc), 1) where
// inc is valid, else 0
@compute @workgroup_size(64)
fn probe_light_arriving(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    let index = u32(c.x);
    let light = lights[index];
    let inc = incident(light, a.xyz, light_point_at(light, c.yz));
    var out0 = vec4<f32>(0.0);
    if inc.valid {
        out0 = vec4<f32>(light_arriving(index, light, a.xyz, a.w != 0.0, b.xyz, inc), 1.0);
    }
    probe_outputs[2u * i] = out0;
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (film.xy, lens.xy) → out0 = (origin, _), out1 = (direction, _)
// of camera_ray(film, lens)
@compute @workgroup_size(64)
fn probe_camera_ray(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let ray = camera_ray(probe_inputs[3u * i].xy, probe_inputs[3u * i].zw);
    probe_outputs[2u * i] = vec4<f32>(ray.origin, 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(ray.direction, 0.0);
}

// in0 = (origin.xyz, t0), in1 = (direction.xyz, t1) → out0 =
// (fog_interval(ray, t0, t1), _)
@compute @workgroup_size(64)
fn probe_fog_interval(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    probe_outputs[2u * i] = vec4<f32>(fog_interval(Ray(a.xyz, b.xyz), a.w, b.w), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (origin.xyz, _), in1 = (direction.xyz, _) → hit = nearest_hit(ray):
// out0 = (t, found 1 or 0, the primitive's material, _), out1 =
// (geometric_normal at the hit, _), both 0 where nothing is hit
@compute @workgroup_size(64)
fn probe_nearest_hit(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let ray = Ray(probe_inputs[3u * i].xyz, probe_inputs[3u * i + 1u].xyz);
    let hit = nearest_hit(ray);
    var out0 = vec4<f32>(0.0);
    var out1 = vec4<f32>(0.0);
    if hit.found {
        out0 = vec4<f32>(hit.t, 1.0, f32(primitives[hit.primitive].material), 0.0);
        out1 = vec4<f32>(geometric_normal(hit.primitive, ray_at(ray, hit.t)), 0.0);
    }
    probe_outputs[2u * i] = out0;
    probe_outputs[2u * i + 1u] = out1;
}

// in0 = (incoming.xyz, roughness), in1 = (normal.xyz, _), in2 = (k.x,
// k.y) integers below 2²⁴ → out0 = (reflect_layer(roughness, incoming,
// normal), _) drawing u = k/2²⁴ through the R₃ slots next_1d reads first
@compute @workgroup_size(64)
fn probe_reflect(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    leading = vec3<u32>(u32(c.x) << 8u, u32(c.y) << 8u, 0u);
    leading_used = 0u;
    probe_outputs[2u * i] = vec4<f32>(reflect_layer(a.w, a.xyz, b.xyz), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (origin.xyz, t_hit), in1 = (direction.xyz, _), in2 = (k, _, _, _)
// an integer below 2²⁴ → out0 = (in_scattered(ray, t_hit, 0, 1), _): the
// march's whole lattice (one stratum) with jitter k/2²⁴; delta lights
// only (an area light's points would draw further numbers)
@compute @workgroup_size(64)
fn probe_in_scattered(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    leading = vec3<u32>(u32(c.x) << 8u, 0u, 0u);
    leading_used = 0u;
    probe_outputs[2u * i] = vec4<f32>(in_scattered(Ray(a.xyz, b.xyz), a.w, 0u, 1u), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (x.xyz, roughness), in1 = (normal.xyz, n + specular), in2 =
// (diffuse.rgb, albedo) → out0 = (direct_lighting(diffuse, specular
// (grey), roughness, albedo, incoming, x, normal), _), seen along
// incoming = normalize((0.2 + 0.5·n)·t − normal), n an integer, t the
// first of orthonormal_pair(normal); delta lights only (an area light's
// points would draw random numbers)
@compute @workgroup_size(64)
fn probe_direct_lighting(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    let tilt = 0.2 + 0.5 * floor(b.w);
    let specular = b.w - floor(b.w);
    let incoming = normalize(tilt * orthonormal_pair(b.xyz)[0] - b.xyz);
    probe_outputs[2u * i] = vec4<f32>(direct_lighting(c.xyz, vec3<f32>(specular), a.w, c.w, incoming, a.xyz, b.xyz), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (origin.xyz, t_hit), in1 = (direction.xyz, _), in2 = (seed, _, _,
// _) an integer below 2²⁴ → out0 = (single_in_scattered(ray, t_hit, 0, 1),
// _): one sample of single scattering's estimator (one stratum), every
// random number from the PCG stream seeded by `seed` (none from the R₃
// slots), so that items of different seeds are independent samples
@compute @workgroup_size(64)
fn probe_single_in_scattered(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    rng_state = pcg(u32(c.x) ^ 0x9e3779b9u);
    leading_used = 3u;
    probe_outputs[2u * i] = vec4<f32>(single_in_scattered(Ray(a.xyz, b.xyz), a.w, 0u, 1u), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}

// in0 = (origin.xyz, _), in1 = (direction.xyz, _), in2 = (seed, _, _, _)
// an integer below 2²⁴ → out0 = (radiance(ray, 0, 1), _): one sample of
// the camera path (one stratum), its random numbers from the PCG stream
// seeded by `seed`, so that items of different seeds are independent
@compute @workgroup_size(64)
fn probe_radiance(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= probe_count() { return; }
    let a = probe_inputs[3u * i];
    let b = probe_inputs[3u * i + 1u];
    let c = probe_inputs[3u * i + 2u];
    rng_state = pcg(u32(c.x) ^ 0x85ebca6bu);
    leading_used = 3u;
    probe_outputs[2u * i] = vec4<f32>(radiance(Ray(a.xyz, b.xyz), 0u, 1u), 0.0);
    probe_outputs[2u * i + 1u] = vec4<f32>(0.0);
}
