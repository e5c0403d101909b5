// The albedo that the denoiser divides the image by before filtering and multiplies by after
// (demodulation keeps texture detail out of the filter). A component too dark to divide by is
// left alone (1): dividing by ~0 would blow up noise, and what such a surface shows, emission,
// is not proportional to kd. Both sides must use this same function so the round trip is exact
// at a pixel the filter leaves alone.
const DEMODULATION_MIN_ALBEDO: f32 = 0.01;

fn demodulation_albedo(kd: vec3<f32>) -> vec3<f32> {
    return select(kd, vec3<f32>(1.0), kd < vec3<f32>(DEMODULATION_MIN_ALBEDO));
}
