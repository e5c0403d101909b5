// The sub-pixel position a raster graph samples in a frame. A rasteriser samples every pixel at
// the same offset, so the whole frame shares one jitter, drawn as intersect draws pixel (0, 0)'s
// (DIM_PIXEL of the frame's sample, through the pixel filter): distributed as intersect's, so
// each pixel's expectation is intersect's, with its own pixel sequence over frames, but
// neighbours share the offset. With `pixel_jitter` off, the pixel centre (as intersect with
// pixel_jitter off). The includer declares `frame` and includes scene.wgsl, rng.wgsl and
// sampler.wgsl.
#include "pixel_filter.wgsl"

// A pass param: jitter within the pixel (true) or sample its centre (tests).
override pixel_jitter: bool = true;

fn frame_jitter() -> vec2<f32> {
    if !pixel_jitter {
        return vec2<f32>(0.5);
    }
    return pixel_filter_position(sample_2d(image_sample_source(vec2<u32>(0u), 1u, 0u), DIM_PIXEL));
}
