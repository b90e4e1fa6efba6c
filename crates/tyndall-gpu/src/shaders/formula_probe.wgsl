// Kernels that evaluate each function of formulas.wgsl on a list of
// inputs, for tests/formulas.rs ("one formula, two languages"). Each item
// has two input vec4s and one output vec4.

@group(0) @binding(0) var<storage, read> inputs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4<f32>>;

fn item_count() -> u32 {
    return arrayLength(&outputs);
}

// in0 = (g, cos θ) → out.x = p(θ)
@compute @workgroup_size(64)
fn probe_phase(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    outputs[i] = vec4<f32>(phase_hg(a.x, a.y), 0.0, 0.0, 0.0);
}

// in0 = (profile, cos cutoff, cos inner, cos θ) → out.x = falloff
@compute @workgroup_size(64)
fn probe_spot(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    outputs[i] = vec4<f32>(spot_falloff(u32(a.x), a.y, a.z, a.w), 0.0, 0.0, 0.0);
}

// in0 = (before.rgb, model), in1 = (colour.rgb, α) → out.rgb = tint after
@compute @workgroup_size(64)
fn probe_glass(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    outputs[i] = vec4<f32>(glass_tint_after(u32(a.w), a.xyz, b.xyz, b.w), 0.0);
}

// in0 = (σt, d) → out.x = exp(−σt·d)
@compute @workgroup_size(64)
fn probe_transmittance(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    outputs[i] = vec4<f32>(transmittance(a.x, a.y), 0.0, 0.0, 0.0);
}

// in0 = (f.rgb, T), in1 = (n, p_e, p_d) → out.rgb = single_sample
@compute @workgroup_size(64)
fn probe_single_sample(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    outputs[i] = vec4<f32>(single_sample(a.xyz, a.w, b.x, b.y, b.z), 0.0);
}

// in0 = (y.xyz, u), in1 = (a, b, t) on the ray from 0 along +x →
// out = (sample(u), pdf(sample(u)), pdf(t), valid)
@compute @workgroup_size(64)
fn probe_equiangular(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    let s = equiangular_new(vec3<f32>(0.0), vec3<f32>(1.0, 0.0, 0.0), a.xyz, b.x, b.y);
    let t = equiangular_sample(s, a.w);
    outputs[i] = vec4<f32>(t, equiangular_pdf(s, t), equiangular_pdf(s, b.z), select(0.0, 1.0, s.valid));
}

// in0 = (σt, a, b, u), in1 = (t) → out = (sample(u), pdf(sample(u)),
// pdf(t), valid)
@compute @workgroup_size(64)
fn probe_exponential(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    let s = exponential_new(a.x, a.y, a.z);
    let t = exponential_sample(s, a.w);
    outputs[i] = vec4<f32>(t, exponential_pdf(s, t), exponential_pdf(s, b.x), select(0.0, 1.0, s.valid));
}

// in0 = (axis.xyz, cos θmax), in1 = (u.x, u.y) → out = (direction,
// density)
@compute @workgroup_size(64)
fn probe_uniform_cone(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    outputs[i] = vec4<f32>(uniform_cone(a.xyz, a.w, b.xy), uniform_cone_pdf(a.w));
}

// in0 = (o.xyz, u.x), in1 = (u.y, width, height) for the rectangle with
// its corner at the origin and edges along +x and +y → out = (the
// sample, solid angle), or 0 without one
@compute @workgroup_size(64)
fn probe_spherical_rectangle(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    let s = spherical_rectangle_new(vec3<f32>(0.0), vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), b.y, b.z, a.xyz);
    if !s.valid {
        outputs[i] = vec4<f32>(0.0);
        return;
    }
    outputs[i] = vec4<f32>(spherical_rectangle_sample(s, vec2<f32>(a.w, b.x)), s.solid_angle);
}

// in0 = (outgoing.xyz, α), in1 = (incident.xyz, _) → out.x =
// ggx_eval(α, outgoing, +y, incident)
@compute @workgroup_size(64)
fn probe_ggx_eval(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= item_count() { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    outputs[i] = vec4<f32>(ggx_eval(a.w, a.xyz, vec3<f32>(0.0, 1.0, 0.0), b.xyz), 0.0, 0.0, 0.0);
}
