// Path with reuse: the fused path pass (shaders/path.wgsl), whose indirect channel shares each
// bounce's hit among a small group of neighbouring pixels, the lanes of one subgroup (path
// reuse, Bekaert, Sbert and Halton 2002). Each pixel of a group samples `bounces` bounces from
// its primary hit x1 by its BSDF and finds the light leaving each hit x2, as path.wgsl does;
// then it joins its x1 to every other member's x2 with a visibility ray, and weighs all the
// group's x2 by the balance heuristic over the members' sampling densities:
//
//   indirect_i = 1/b * sum_k f_i(x2_k) G_i(x2_k) L(x2_k) / sum_j p_j(x2_k)
//
// f_i the BSDF at x1_i (its cosine included), G_i = cos_x / d_i^2 and p_j(x) = pdf_j(x1_j -> x)
// cos_x / d_j^2 * V(x1_j, x): member j's BSDF sampling density in area measure (0 when it cannot
// see x), b = bounces per pixel. Every member's own density is in the sum, so the estimate is
// unbiased: each x2_k is drawn by exactly one member, and the weights p_j / sum p_j sum to 1
// wherever some member can draw the point. The visibility rays are the ones the sum needs
// (each member traces its own row); they are shadow rays, between two points of the scene, so
// they skip the hull faces (src/scene/hull.rs). The members' sums are a butterfly of subgroup
// shuffles over the group. A pixel thus gets members * b samples of its indirect light for b
// bounce rays, b next-event estimates and (members - 1) * b visibility rays. The group's
// bounce directions are consecutive points of one stratified sequence (the group's first
// pixel's), as one pixel's split bounces are in path.wgsl.
//
// A scene of Lambertian surfaces only (scene_has_specular false) shares everywhere. In any other
// scene each pixel traces the bounces its group would have pooled (bounces * reuse_pixels) by
// itself, and its estimate is path.wgsl's (the same samples and arithmetic, in index order),
// unless per_pixel_sharing asks to decide per sample, so that the diffuse pixels share however
// glossy or glassy the rest of the scene is. That is off by default: a glossy hit's light is
// its drawer's alone (below), and where glossy hits carry much of the indirect light (a rough
// metal or glass caustic), a pixel that shares gets b of them where tracing alone it gets
// bounces * reuse_pixels; measured 3.5-17x the variance per sample and 1.3-7.7x the variance
// times the time on the scenes tried (docs/benchmark-history.md, 2026-12-04). Per sample:
// - L(x2) toward another member's x1 is the light the member that drew x2 found leaving it (its
//   next-event estimate and, past max_depth 3, the paths that continue from x2: path_light.wgsl),
//   the same toward every x1 in front of x2 only where x2 is Lambertian (no map tilting its
//   normal toward the viewer, no null mask). Any other x2, and a delta sample (a smooth coat,
//   a mask's pass-through), is its drawer's alone, weighed as path.wgsl weighs it: the balance
//   heuristic above covers the BSDFs' non-delta parts, whose weights still sum to 1 where the
//   members' continuous densities are nonzero.
// - A pixel whose every lobe is delta (smooth glass and mirrors) draws nothing the others could
//   use: it traces the bounces its group would have pooled by itself, as above.
// Russian roulette is not applied at the shared first bounce (it would make a member's density
// depend on its throughput): it starts at the next one, which keeps the estimate unbiased.
//
// The group exchanges its points through subgroup shuffles, not workgroup memory: on lavapipe
// a workgroup barrier suspends and resumes every SIMD row of the workgroup, and three of them
// per sample cost more than the bounces the reuse saves (docs/benchmark-history.md). Groups are
// aligned runs of `reuse_pixels` lanes of a subgroup (rounded down to a power of two, at most
// the subgroup); the invocations are laid out so that, on lavapipe's subgroups of 8
// consecutive invocations, a group of 8 is a 4x2 block of pixels and one of 4 a 2x2 block
// (elsewhere the groups are other neighbours, the estimate as unbiased). Nothing depends on
// the subgroup being 8 lanes wide: lavapipe forced to 16 renders the same image bit for bit
// (tests/reuse_subgroup_width.rs).
//
// Same channels and expectation as path.wgsl; the measured speed against error:
// docs/benchmark-history.md.
#include "lib/provided_scene.wgsl"
#include "lib/rng.wgsl"
#include "lib/sampler.wgsl"
#include "lib/camera_ray.wgsl"
#include "lib/sampling.wgsl"
#include "lib/bsdf.wgsl"
#include "lib/mis.wgsl"
#include "lib/bvh.wgsl"
#include "lib/cutout_map.wgsl"
#include "lib/ray_count.wgsl"
#include "lib/tile_order.wgsl"
#include "lib/primary.wgsl"
#include "lib/surface.wgsl"
#include "lib/shading.wgsl"
#include "lib/texture.wgsl"
#include "lib/shading_point.wgsl"
#include "lib/light_sample.wgsl"
#include "lib/light_select.wgsl"
#include "lib/nee.wgsl"
#include "lib/shade_ambient.wgsl"
#include "lib/shade_direct.wgsl"
#include "lib/path_primary.wgsl"
#include "lib/path_pass.wgsl"
#include "lib/path_light.wgsl"

// A pass param: bounces each pixel traces per sample, 1 to REUSE_MAX_BOUNCES.
override bounces: u32 = 1u;
// A pass param: pixels per group sharing their bounces (1, 2, 4 or 8; at most the subgroup).
override reuse_pixels: u32 = 4u;
// A pass param: in a scene with other lobes than Lambert's, share per sample (see above)
// instead of letting every pixel trace alone.
override per_pixel_sharing: bool = false;

// Room in each lane's private arrays: bounces per pixel, pixels per group, and one density per
// group hit.
const REUSE_MAX_BOUNCES: u32 = 4u;
const REUSE_MAX_PIXELS: u32 = 8u;
const REUSE_MAX_HITS: u32 = REUSE_MAX_BOUNCES * REUSE_MAX_PIXELS;

// The tile position of invocation i of the 64 that shade an 8x8 tile (dispatch PerTile(8, 8):
// subgroup builtins need a one-dimensional workgroup): each run of 8 invocations covers a 4x2
// block, its halves 2x2 blocks, its pairs side by side.
fn reuse_local(i: u32) -> vec3<u32> {
    let block = i / 8u;
    let lane = i % 8u;
    return vec3<u32>((block % 2u) * 4u + (lane / 4u) * 2u + lane % 2u, (block / 2u) * 2u + (lane % 4u) / 2u, 0u);
}

// Whether the light leaving the bounce hit x is the same toward every point in front of it:
// a Lambertian surface whose shading normal no map tilts toward the viewer and no null mask
// mixes with a pass-through. (Toward a point behind its shading normal a Lambertian x reflects
// nothing: the receiver checks that.)
fn reuse_shareable(x: ShadingPoint) -> bool {
    return scene_has_kind(MATERIAL_LAMBERT) && x.b.kind == MATERIAL_LAMBERT
        && all(x.ns == x.n_smooth) && x.opacity == 1.0;
}

// The indirect light of a pixel that shares nothing: the mean of n bounces it traces itself,
// path.wgsl's estimate.
fn traced_alone(p: ShadingPoint, wo: vec3<f32>, source: SampleSource, n: u32) -> vec3<f32> {
    var own = vec3<f32>(0.0);
    for (var j = 0u; j < n; j++) {
        let bounce = sample_split(source, n, j);
        own += bounce_path(p, wo, bounce, sample_2d(bounce, DIM_BOUNCE));
    }
    return own / f32(n);
}

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
    @builtin(subgroup_invocation_id) lane: u32,
    @builtin(subgroup_size) lanes: u32,
) {
    let id = scattered_pixel(group, groups, reuse_local(local_index), frame);
    let inside = id.x < frame.width && id.y < frame.height;
    let b = clamp(bounces, 1u, REUSE_MAX_BOUNCES);
    // A power of two, so that groups are aligned and the butterfly below stays inside one.
    let members = 1u << firstLeadingBit(min(clamp(reuse_pixels, 1u, REUSE_MAX_PIXELS), lanes));
    let member = lane % members;
    let base = lane - member;
    // The group's first lane's pixel, whose sequence the group's bounce directions share.
    let first_pixel = subgroupShuffle(image_pixel_index(id.xy + frame.image_origin), base);

    var sum_l0 = vec3<f32>(0.0);
    var sum_direct = vec3<f32>(0.0);
    var sum_indirect = vec3<f32>(0.0);
    var sum_ambient = vec3<f32>(0.0);
    for (var k = 0u; k < samples_per_frame; k++) {
        let source = sample_source(id.xy, samples_per_frame, k);
        var has_first = false;
        var p: ShadingPoint;
        var wo = vec3<f32>(0.0);
        if inside {
            let ray = path_primary(id.xy, source);
            let lit = shade_direct(ray, source);
            sum_l0 += lit.l0;
            sum_direct += lit.direct;
            sum_ambient += shade_ambient(ray, source, params.ambient_color, params.radius);
            // Without lights there is nothing to find at a second hit: no bounce at all.
            if ray.triangle != NO_HIT && scene_light_count > 0u {
                has_first = true;
                p = shading_point(ray.triangle, ray.u, ray.v, ray.dir);
                wo = -ray.dir;
            }
        }
        let pooled = b * clamp(reuse_pixels, 1u, REUSE_MAX_PIXELS);
        if scene_has_specular && !per_pixel_sharing {
            if has_first {
                sum_indirect += traced_alone(p, wo, source, pooled);
            }
            continue;
        }
        // Every lane takes part in the shuffles below; only a pixel with a non-delta lobe at
        // its primary hit draws and receives shared hits.
        let alone = has_first && bsdf_is_delta(p.b);
        let shares = has_first && !alone;

        // This pixel's bounces: sample (index * members + member) * b + j of the group's
        // sequence. A hit others may use (w = 1), its geometric normal toward this x1, its
        // shading normal, the light it reflects; the light of the rest is this pixel's own.
        var second: array<vec4<f32>, REUSE_MAX_BOUNCES>;
        var normal: array<vec3<f32>, REUSE_MAX_BOUNCES>;
        var shading_n: array<vec3<f32>, REUSE_MAX_BOUNCES>;
        var light: array<vec3<f32>, REUSE_MAX_BOUNCES>;
        var estimate = vec3<f32>(0.0);
        for (var j = 0u; j < b; j++) {
            second[j] = vec4<f32>(0.0);
            normal[j] = vec3<f32>(0.0);
            shading_n[j] = vec3<f32>(0.0);
            light[j] = vec3<f32>(0.0);
            if !shares {
                continue;
            }
            let bounce = SampleSource(first_pixel, (source.index * members + member) * b + j, source.seed);
            let bs = point_sample(p, wo, sample_2d(bounce, DIM_BOUNCE), sample_1d(bounce, DIM_BOUNCE_LOBE));
            if all(bs.weight == vec3<f32>(0.0)) {
                continue;
            }
            let hit = closest_hit(leaving(p.s, bs.wi), bs.wi, 0.0, 3.0e38);
            if hit.triangle == NO_HIT {
                continue;
            }
            let x2 = shading_point(hit.triangle, hit.u, hit.v, bs.wi);
            let l = path_light(x2, bs.wi, sample_split(source, b, j), roulette_odds(bs.weight, bs));
            if !bs.delta && reuse_shareable(x2) {
                second[j] = vec4<f32>(x2.s.p, 1.0);
                normal[j] = x2.s.n;
                shading_n[j] = x2.ns;
                light[j] = l;
            } else {
                estimate += bs.weight * l;
            }
        }

        // This pixel's density of drawing each of the group's shared hits (index m * b + j:
        // member m's bounce j), 0 where it cannot: the hit faces away or lies outside the
        // BSDF's non-delta lobes, or something blocks the way.
        var density: array<f32, REUSE_MAX_HITS>;
        for (var m = 0u; m < members; m++) {
            for (var j = 0u; j < b; j++) {
                let q = subgroupShuffle(second[j], base + m);
                let nq = subgroupShuffle(normal[j], base + m);
                var area = 0.0;
                let w = q.xyz - p.s.p;
                let d2 = dot(w, w);
                if shares && q.w != 0.0 && d2 > 0.0 {
                    let dir = w * inverseSqrt(d2);
                    let cos_q = -dot(nq, dir);
                    let pdf = point_pdf(p, wo, dir);
                    if cos_q > 0.0 && pdf > 0.0 {
                        var open = m == member;
                        if !open {
                            let origin = leaving(p.s, dir);
                            let end = offset_ray(q.xyz, nq);
                            open = !shadow_hit(origin, end - origin, 0.0, 1.0 - 1e-4);
                        }
                        if open {
                            area = pdf * cos_q / d2;
                        }
                    }
                }
                density[m * b + j] = area;
            }
        }

        // The group's densities, summed by a butterfly over its lanes (every lane gets the
        // same sums: the additions pair the same terms), and this pixel's share of each hit.
        for (var m = 0u; m < members; m++) {
            for (var j = 0u; j < b; j++) {
                let h = m * b + j;
                var total = density[h];
                for (var step = 1u; step < members; step <<= 1u) {
                    total += subgroupShuffleXor(total, step);
                }
                let q = subgroupShuffle(second[j], base + m).xyz;
                let nq = subgroupShuffle(normal[j], base + m);
                let nsq = subgroupShuffle(shading_n[j], base + m);
                let lq = subgroupShuffle(light[j], base + m);
                if density[h] == 0.0 {
                    continue;
                }
                let w = q - p.s.p;
                let d2 = dot(w, w);
                let dir = w * inverseSqrt(d2);
                // The path's value is 0 toward an x1 behind x2's shading normal.
                if dot(nsq, dir) < 0.0 {
                    estimate += point_eval(p, wo, dir) * (-dot(nq, dir) / d2) * lq / total;
                }
            }
        }

        if shares {
            sum_indirect += estimate / f32(b);
        }
        if alone {
            sum_indirect += traced_alone(p, wo, source, pooled);
        }
    }
    if inside {
        store_channel_means(id.xy, sum_l0, sum_direct, sum_indirect, sum_ambient);
    }
    count_rays(local_index);
}
