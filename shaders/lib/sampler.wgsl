// Samples for every pass, stateless: a sample is a function of the pixel, the sample index (the
// frame's place in the accumulation), the user seed and a dimension number, so passes that run
// side by side never share a generator or a texture, and the same frame gives the same numbers
// in whichever pass asks. Two samplers, chosen per pass by the `sampler_kind` param (the graph sets
// it; every pass of a graph should use the same one):
//   SAMPLER_INDEPENDENT (0): the seed's PCG hash, independent uniform numbers.
//   SAMPLER_SOBOL (1): each dimension pair is the 2D Sobol (0,2)-sequence, its index shuffled
//     and its values Owen-scrambled per pixel and pair (padded, as pbrt-v4's
//     PaddedSobolSampler; hash-based scrambling after Burley 2020, with Vegdahl's improved
//     Laine-Karras hash). The shuffle is itself a nested uniform scramble of the index, so the
//     first 2^k samples are an aligned block of 2^k Sobol points, a (0,k,2)-net, and every
//     prefix is a union of such nets: stratified whenever the accumulation stops.
//
// Dimension numbers (one 2D pair each; a 1D sample takes the first coordinate of its own pair)
// are allocated below, so independent passes never share one. Next-event estimation to every
// light draws light i's point from pair `dim + SAMPLER_LIGHT_STRIDE * i`.
const DIM_PIXEL: u32 = 0u;            // intersect: sub-pixel jitter
const DIM_AMBIENT: u32 = 1u;          // ambient: occlusion ray direction
const DIM_DIRECT_SELECT: u32 = 2u;    // direct: which light (light selection)
const DIM_DIRECT_LIGHT: u32 = 3u;     // direct: point on the light
const DIM_BOUNCE: u32 = 4u;           // indirect: bounce direction
const DIM_BOUNCE_SELECT: u32 = 5u;    // indirect: which light at the bounce's hit
const DIM_BOUNCE_LIGHT: u32 = 6u;     // indirect: point on that light
// Pair 7 is free. The direct channel's BSDF sample at the primary hit (its MIS half) takes
// the first bounce's pairs, DIM_BOUNCE and DIM_BOUNCE_LOBE: one path (lib/shade_direct.wgsl).
const SAMPLER_LIGHT_STRIDE: u32 = 8u;
// The thin lens's aperture sample (lib/camera_ray.wgsl): far from every other pair, so pairs
// added above never meet it and no other pass's samples move.
const DIM_LENS: u32 = 0x30000000u;
// 1D choices of a BSDF lobe, and every sample of path vertices past the first bounce's hit,
// take pairs far above the light pairs (dim + 8 i): path_dim below.
const DIM_BOUNCE_LOBE: u32 = 0x40000001u;

// The sampler pair `slot` (PATH_DIM_*) of the vertex that ends a path's `depth`-th segment
// (depth >= 3: vertices past the first bounce's hit). Light i's point takes
// slot PATH_DIM_LIGHT + SAMPLER_LIGHT_STRIDE * i, so pairs stay distinct below 2^17 lights.
fn path_dim(depth: u32, slot: u32) -> u32 {
    return 0x50000000u + (depth << 20u) + slot;
}
const PATH_DIM_SELECT: u32 = 0u;
const PATH_DIM_BSDF: u32 = 1u;
const PATH_DIM_LOBE: u32 = 2u;
const PATH_DIM_LIGHT: u32 = 3u;
// Russian roulette after the k-th BSDF sample: path_dim(k + 1, PATH_DIM_RR).
const PATH_DIM_RR: u32 = 4u;

const SAMPLER_INDEPENDENT: u32 = 0u;
const SAMPLER_SOBOL: u32 = 1u;

// A pass param: which sampler (see above).
override sampler_kind: u32 = 1u;
// A pass param: the sample index is the frame's index in the current accumulation (restarting
// at 0 on a reset, so a seed always gives the same image), or, for graphs that keep history
// across resets (reprojection), the frame's index since the session started, so new samples
// never repeat ones the history already holds.
override sample_index_restarts: bool = true;

// Where a pass takes its samples: a pixel's sample `index` under the user's `seed`.
struct SampleSource {
    pixel: u32,
    index: u32,
    seed: u32,
}

// The includer declares `frame` (Frame) and includes scene.wgsl and rng.wgsl. `samples_per_frame`
// and `k` let one frame hold several samples (sample k of the frame). `pixel` is the frame's
// (a tile's, when the image is rendered in tiles); the sequence is the whole image's pixel's.
fn sample_source(pixel: vec2<u32>, samples_per_frame: u32, k: u32) -> SampleSource {
    return image_sample_source(pixel + frame.image_origin, samples_per_frame, k);
}

// As sample_source, for a pixel of the whole image.
fn image_sample_source(pixel: vec2<u32>, samples_per_frame: u32, k: u32) -> SampleSource {
    // A render of the sample range A..B starts its accumulation at 0 and its samples at A.
    let frame_index = select(frame.index, frame.accumulated, sample_index_restarts) + frame.first_sample;
    return SampleSource(image_pixel_index(pixel), frame_index * samples_per_frame + k, frame.seed);
}

// The index of a pixel of the whole image, row-major: what names its sample sequence.
fn image_pixel_index(pixel: vec2<u32>) -> u32 {
    return pixel.y * frame.image_size.x + pixel.x;
}

// Part j of `count` splitting one sample (several bounces, several light samples): sample
// index index * count + j, so one sample's parts are consecutive points of one stratified
// sequence.
fn sample_split(source: SampleSource, count: u32, j: u32) -> SampleSource {
    return SampleSource(source.pixel, source.index * count + j, source.seed);
}

// A 32-bit hash of the pixel, seed and dimension: the pair's scrambling seed.
fn sampler_seed(source: SampleSource, dim: u32) -> u32 {
    return pcg_hash(pcg_hash(pcg_hash(source.pixel ^ pcg_hash(source.seed)) ^ dim) + dim);
}

// Vegdahl's Laine-Karras hash: bit i of the result depends only on bits 0..i of x, so on
// bit-reversed values it is an Owen scramble.
fn sampler_lk_hash(x_in: u32, seed: u32) -> u32 {
    var x = x_in;
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Nested uniform (Owen) scramble of a 32-bit binary fraction.
fn sampler_owen(x: u32, seed: u32) -> u32 {
    return reverseBits(sampler_lk_hash(reverseBits(x), seed));
}

// The second Sobol dimension's generator matrix applied to i, bit-reversed. Its column k is
// v_k with v_0 = 2^31 and v_{k+1} = v_k ^ (v_k >> 1), so bit 31 - m of v_k is
// binomial(k, m) mod 2, which is 1 exactly when m's bits are a subset of k's (Lucas): bit m of
// the result is the XOR of i's bits k over the supersets k of m. Five masked shift-XORs compute
// that for all 32 bits at once (the subset-sum transform over the 5 bits of a bit position)
// instead of a loop over i's 32 bits.
fn sampler_sobol1_reversed(i: u32) -> u32 {
    var x = i;
    x ^= (x >> 1u) & 0x55555555u;
    x ^= (x >> 2u) & 0x33333333u;
    x ^= (x >> 4u) & 0x0f0f0f0fu;
    x ^= (x >> 8u) & 0x00ff00ffu;
    x ^= (x >> 16u) & 0x0000ffffu;
    return x;
}

fn sampler_to_unit(x: u32) -> f32 {
    return f32(x >> 8u) * (1.0 / 16777216.0);
}

// A 2D sample in [0, 1)^2 from pair `dim`.
fn sample_2d(source: SampleSource, dim: u32) -> vec2<f32> {
    let seed = sampler_seed(source, dim);
    if sampler_kind == SAMPLER_INDEPENDENT {
        var state = pcg_hash(seed ^ source.index);
        state = pcg_hash(state + source.index);
        return vec2<f32>(rng_next(&state), rng_next(&state));
    }
    let index = sampler_owen(source.index, seed);
    // Dimension 0 is the van der Corput sequence, reverseBits(index); its scramble folds in.
    let x = reverseBits(sampler_lk_hash(index, pcg_hash(seed + 1u)));
    // sampler_owen(sobol1(index)) with sobol1 = reverseBits(sampler_sobol1_reversed(index)).
    let y = reverseBits(sampler_lk_hash(sampler_sobol1_reversed(index), pcg_hash(seed + 2u)));
    return vec2<f32>(sampler_to_unit(x), sampler_to_unit(y));
}

// A 1D sample in [0, 1) from pair `dim` (its first coordinate).
fn sample_1d(source: SampleSource, dim: u32) -> f32 {
    return sample_2d(source, dim).x;
}
