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
// Mirrors tyndall::integrators::march::in_scattered.
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
