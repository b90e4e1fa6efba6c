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
                    let pdf_e = equiangular_pdf(equiangular, t);
                    let camera = transmittance(sigma_t(), t - a);
                    sum += single_sample(f, camera, n, pdf_e, exponential_pdf(distance, t));
                }
            }
        }
        let f = scattered_radiance(i, light, y, x_d, ray.direction);
        if any(f != vec3<f32>(0.0)) {
            let pdf_e = equiangular_pdf(equiangular, t_d);
            sum += single_sample(f, transmittance(sigma_t(), t_d - a), n, pdf_e, pdf_d);
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
