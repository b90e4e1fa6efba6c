// Direct light on a surface of Lambertian reflectance `diffuse` and a
// specular layer of reflectance `specular` and roughness `roughness`
// (its GGX lobe's single-scattering albedo towards the viewer `albedo`),
// seen along `incoming`: Σ (ρ/π·cos θ + f_layer)·E·V·Tr_glass·T_fog, one
// sample_incident per light, f_layer = compensated(specular,
// albedo)·ggx_eval for delta lights alone (the CPU's
// surface_direct_lighting).
fn direct_lighting(diffuse: vec3<f32>, specular: vec3<f32>, roughness: f32, albedo: f32, incoming: vec3<f32>, x: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let glossy = roughness > 0.0 && any(specular > vec3<f32>(0.0));
    if all(diffuse == vec3<f32>(0.0)) && !glossy {
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
        var f = diffuse / PI * cos_theta;
        if glossy && !is_area_light(light) {
            f += compensated(specular, albedo) * ggx_eval(roughness, -incoming, normal, inc.direction);
        }
        sum += light_arriving(i, light, x, true, normal, inc) * f;
    }
    return sum;
}

// The reflective layer's direction (tyndall::materials::Surface::reflect):
// the mirror direction, or a GGX lobe's sample (ggx_sample); zero vector
// when the drawn direction is below the surface.
fn reflect_layer(roughness: f32, incoming: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let u = vec2<f32>(next_1d(), next_1d());
    if roughness <= 0.0 {
        return incoming - 2.0 * dot(incoming, normal) * normal;
    }
    return ggx_sample(roughness, -incoming, normal, u);
}

// The single-scattering albedo of material `m`'s GGX lobe at cosine
// `cos` from its row at cosines (k + 1)/16, linear, held beyond the first
// and last node (tyndall::materials::albedo_in_row).
fn material_albedo(m: u32, cos: f32) -> f32 {
    let x = clamp(cos * 16.0 - 1.0, 0.0, 15.0);
    let k = min(u32(x), 14u);
    let fk = x - f32(k);
    let a = materials[m].albedo[k / 4u][k % 4u];
    let b = materials[m].albedo[(k + 1u) / 4u][(k + 1u) % 4u];
    return a * (1.0 - fk) + b * fk;
}

// The camera path of tyndall::integrators::camera_path::CameraPath::radiance for the
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
        let material_index = primitives[hit.primitive].material;
        let material = materials[material_index];
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
        let albedo = material_albedo(material_index, dot(-ray.direction, normal));
        result += throughput * direct_lighting(diffuse, specular, material.roughness, albedo, ray.direction, x, normal);
        if all(specular == vec3<f32>(0.0)) || bounces >= params.max_bounces {
            return result;
        }
        let direction = reflect_layer(material.roughness, ray.direction, normal);
        if all(direction == vec3<f32>(0.0)) {
            return result;
        }
        bounces++;
        if material.roughness > 0.0 {
            throughput *= compensated(specular, albedo) * ggx_weight(material.roughness, -ray.direction, normal, direction);
        } else {
            throughput *= specular;
        }
        ray = Ray(offset_origin(x, gn, direction), direction);
    }
    return result;
}

// A point uniformly distributed on the unit disk from u in [0, 1)²:
// Shirley and Chiu's concentric map. Mirrors
// tyndall::sampling::concentric_disk.
fn concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let o = 2.0 * u - vec2<f32>(1.0);
    if o.x == 0.0 && o.y == 0.0 {
        return vec2<f32>(0.0);
    }
    let quarter = 0.25 * PI;
    var r: f32;
    var phi: f32;
    if abs(o.x) > abs(o.y) {
        r = o.x;
        phi = quarter * (o.y / o.x);
    } else {
        r = o.y;
        phi = 2.0 * quarter - quarter * (o.x / o.y);
    }
    return r * vec2<f32>(cos(phi), sin(phi));
}

// Whether the camera is a thin lens (camera_position.w its radius,
// camera_forward.w its focus distance; a pinhole has radius 0).
fn has_lens() -> bool {
    return params.camera_position.w > 0.0;
}

// The camera ray through film position `film` (in pixels, y down) and
// the lens point `lens` in [0, 1)² picks (ignored by a pinhole): from the
// lens point to where the pinhole ray meets the plane of focus. Mirrors
// tyndall::camera::Camera::ray.
fn camera_ray(film: vec2<f32>, lens: vec2<f32>) -> Ray {
    let ndc = 2.0 * film / params.half_extent_resolution.zw - vec2<f32>(1.0);
    let pinhole = params.camera_forward.xyz
        + params.camera_right.xyz * (ndc.x * params.half_extent_resolution.x)
        - params.camera_up.xyz * (ndc.y * params.half_extent_resolution.y);
    if !has_lens() {
        return Ray(params.camera_position.xyz, normalize(pinhole));
    }
    let p = params.camera_position.w * concentric_disk(lens);
    let origin = params.camera_position.xyz + params.camera_right.xyz * p.x
        + params.camera_up.xyz * p.y;
    let focus = params.camera_position.xyz + pinhole * params.camera_forward.w;
    return Ray(origin, normalize(focus - origin));
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
    // The film position, uniform over the pixel (a box filter).
    let film = vec2<f32>(f32(id.x) + next_1d(), f32(id.y) + next_1d());
    // A lens point only for a lens: pinhole frames keep their numbers.
    var lens = vec2<f32>(0.5);
    if has_lens() {
        lens = vec2<f32>(next_1d(), next_1d());
    }
    let n = max(params.interleave, 1u);
    let stratum = interleaved_stratum(id.xy, n);
    let l = radiance(camera_ray(film, lens), stratum, n * n);
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
