// Random numbers: PCG (O'Neill 2014; the RXS-M-XS output of Jarzynski & Olano 2020).
// Each pixel's seed lives in the persistent seed texture; intersect advances it once per
// frame and every other pass derives its own stream from it, so passes stay independent.

fn pcg_hash(x: u32) -> u32 {
    let s = x * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

// A generator for one pass: the pixel's seed this frame, decorrelated by a per-pass stream id.
fn rng_stream(seed: u32, stream: u32) -> u32 {
    return pcg_hash(seed ^ pcg_hash(stream));
}

// Uniform in [0, 1): 24 random bits, so 1.0 is never returned.
fn rng_next(state: ptr<function, u32>) -> f32 {
    *state = *state * 747796405u + 2891336453u;
    let s = *state;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return f32(((w >> 22u) ^ w) >> 8u) * (1.0 / 16777216.0);
}
