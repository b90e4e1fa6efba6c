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
