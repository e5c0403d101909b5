// Path with reuse: the fused path pass (shaders/path.wgsl), whose indirect channel shares each
// bounce's hit among a small group of neighbouring pixels, the lanes of one subgroup (path
// reuse, Bekaert, Sbert and Halton 2002). Each pixel of a group traces `bounces` bounces from
// its primary hit x1 and the light leaving each hit x2, as path.wgsl does; then it joins its x1 to every other
// member's x2 with a visibility ray, and weighs all the group's x2 by the balance heuristic
// over the members' sampling densities:
//
//   indirect_i = 1/b * sum_k f_i(x2_k) / sum_j p_j(x2_k)
//
// f_i(x) = brdf(x1_i) cos_i cos_x / d_i^2 * V(x1_i, x) * L(x), p_j(x) = cos_j cos_x / (pi d_j^2)
// * V(x1_j, x) (cosine sampling from x1_j, in area measure), b = bounces per pixel. Every
// member's own density is in the sum, so the estimate is unbiased: each x2_k is drawn by
// exactly one member, and the weights p_j / sum p_j sum to 1 wherever some member can draw the
// point. The visibility rays are the ones the sum needs (V(x1_j, x2_k) for every pair: each
// member traces its own row), and they are shadow rays, between two points of the scene, so
// they skip the hull faces (src/scene/hull.rs). A pixel thus gets members * b samples of
// its indirect light for b bounce rays, b next-event estimates and (members - 1) * b
// visibility rays. The group's bounce directions are consecutive points of one stratified
// sequence (the group's first pixel's), as one pixel's split bounces are in path.wgsl.
//
// L(x) toward another member's x1 is the light the member that drew x found leaving it (its
// next-event estimate and, past max_depth 3, the paths that continue from x: path_light.wgsl):
// the same toward every x1 only for a Lambertian x. A scene with any other lobe
// (scene_has_specular) shares nothing: each pixel traces as many bounces as its group would have pooled
// (bounces * reuse_pixels), and the estimate is path.wgsl's.
//
// The group exchanges its points through subgroup shuffles, not workgroup memory: on lavapipe
// a workgroup barrier suspends and resumes every SIMD row of the workgroup, and three of them
// per sample cost more than the bounces the reuse saves (docs/benchmark-history.md). Groups are
// aligned runs of `reuse_pixels` lanes of a subgroup; the invocations are laid out so that, on
// lavapipe's subgroups of 8 consecutive invocations, a group of 8 is a 4x2 block of pixels and
// one of 4 a 2x2 block (elsewhere the groups are other neighbours, the estimate as unbiased).
//
// Same channels and expectation as path.wgsl; the measured speed against error:
// docs/benchmark-history.md.
#include "lib/scene.wgsl"
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
#include "lib/path_pass.wgsl"
#include "lib/path_light.wgsl"

// A pass param: bounces each pixel traces per sample, 1 to REUSE_MAX_BOUNCES.
override bounces: u32 = 1u;
// A pass param: pixels per group sharing their bounces (1, 2, 4 or 8; at most the subgroup).
override reuse_pixels: u32 = 4u;

// Room in each lane's private arrays; 8 pixels of 4 bounces fill a 32-bit visibility row.
const REUSE_MAX_BOUNCES: u32 = 4u;
const REUSE_MAX_PIXELS: u32 = 8u;

// The tile position of invocation i of the 64 that shade an 8x8 tile (dispatch PerTile(8, 8):
// subgroup builtins need a one-dimensional workgroup): each run of 8 invocations covers a 4x2
// block, its halves 2x2 blocks, its pairs side by side.
fn reuse_local(i: u32) -> vec3<u32> {
    let block = i / 8u;
    let lane = i % 8u;
    return vec3<u32>((block % 2u) * 4u + (lane / 4u) * 2u + lane % 2u, (block / 2u) * 2u + (lane % 4u) / 2u, 0u);
}

// Whether x1 (point p, normal n) and the bounce hit q (normal nq, facing the side it was drawn
// from) face each other: the cosines of a connection from x1 to q are both positive.
fn reuse_facing(p: vec3<f32>, n: vec3<f32>, q: vec3<f32>, nq: vec3<f32>) -> bool {
    let w = q - p;
    return dot(n, w) > 0.0 && dot(nq, w) < 0.0;
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
    // Only Lambertian bounce hits reflect the same light toward every member.
    let share = !scene_has_specular;
    let members = select(1u, min(min(reuse_pixels, REUSE_MAX_PIXELS), lanes), share);
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
        var s = Surface(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), false, 0u);
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
                s = p.s;
                wo = -ray.dir;
            }
        }

        if !share {
            // Nothing to share: each pixel traces the bounces its group would have pooled, and
            // the estimate is path.wgsl's (the same samples and arithmetic, in index order).
            if has_first {
                let n = b * clamp(reuse_pixels, 1u, REUSE_MAX_PIXELS);
                var own = vec3<f32>(0.0);
                for (var j = 0u; j < n; j++) {
                    let bounce = sample_split(source, n, j);
                    own += bounce_path(p, wo, bounce, sample_2d(bounce, DIM_BOUNCE));
                }
                sum_indirect += own / f32(n);
            }
            continue;
        }

        // This pixel's bounces: sample (index * members + member) * b + j of the group's
        // sequence. Hit point (w = 1 when there is one), normal toward this x1, reflected light.
        var second: array<vec4<f32>, REUSE_MAX_BOUNCES>;
        var normal: array<vec3<f32>, REUSE_MAX_BOUNCES>;
        var light: array<vec3<f32>, REUSE_MAX_BOUNCES>;
        for (var j = 0u; j < b; j++) {
            second[j] = vec4<f32>(0.0);
            normal[j] = vec3<f32>(0.0);
            light[j] = vec3<f32>(0.0);
            if has_first {
                let bounce = SampleSource(first_pixel, (source.index * members + member) * b + j, source.seed);
                let u = sample_2d(bounce, DIM_BOUNCE);
                let d = sample_cosine(s.n, u.x, u.y);
                let hit = closest_hit(offset_ray(s.p, s.n), d, 0.0, 3.0e38);
                if hit.triangle != NO_HIT {
                    let x2 = shading_point(hit.triangle, hit.u, hit.v, d);
                    second[j] = vec4<f32>(x2.s.p, 1.0);
                    normal[j] = x2.s.n;
                    light[j] = path_light(x2, d, sample_split(source, b, j), vec3<f32>(1.0));
                }
            }
        }

        // Which of the group's bounce hits this x1 could have drawn: its own when facing, the
        // others' when facing and visible. Bit m * b + j: member m's bounce j.
        var visible = 0u;
        let origin = offset_ray(s.p, s.n);
        for (var m = 0u; m < members; m++) {
            for (var j = 0u; j < b; j++) {
                let q = subgroupShuffle(second[j], base + m);
                let nq = subgroupShuffle(normal[j], base + m);
                if has_first && q.w != 0.0 && reuse_facing(s.p, s.n, q.xyz, nq) {
                    var open = m == member;
                    if !open {
                        let end = offset_ray(q.xyz, nq);
                        open = !shadow_hit(origin, end - origin, 0.0, 1.0 - 1e-4);
                    }
                    if open {
                        visible |= 1u << (m * b + j);
                    }
                }
            }
        }

        // The members' primary hits and visibility rows.
        var first_p: array<vec3<f32>, REUSE_MAX_PIXELS>;
        var first_n: array<vec3<f32>, REUSE_MAX_PIXELS>;
        var rows: array<u32, REUSE_MAX_PIXELS>;
        for (var n = 0u; n < members; n++) {
            first_p[n] = subgroupShuffle(s.p, base + n);
            first_n[n] = subgroupShuffle(s.n, base + n);
            rows[n] = subgroupShuffle(visible, base + n);
        }

        // Lambertian (share is false otherwise): f = kd / pi toward every q.
        let f1 = p.b.kd * (1.0 / PI);
        var estimate = vec3<f32>(0.0);
        for (var m = 0u; m < members; m++) {
            for (var j = 0u; j < b; j++) {
                let q = subgroupShuffle(second[j], base + m).xyz;
                let nq = subgroupShuffle(normal[j], base + m);
                let lq = subgroupShuffle(light[j], base + m);
                let bit = 1u << (m * b + j);
                if (visible & bit) == 0u {
                    continue;
                }
                let w = q - s.p;
                let d2 = dot(w, w);
                let dir = w * inverseSqrt(d2);
                let cos_i = dot(s.n, dir);
                let cos_q = -dot(nq, dir);
                // sum_n p_n(q) * pi * d_i^2: this pixel's own term is cos_i cos_q, so the
                // ratio stays finite however near q lies.
                var density = 0.0;
                for (var n = 0u; n < members; n++) {
                    if (rows[n] & bit) == 0u {
                        continue;
                    }
                    let wn = q - first_p[n];
                    let dn2 = dot(wn, wn);
                    density += dot(first_n[n], wn) * -dot(nq, wn) * d2 / (dn2 * dn2);
                }
                estimate += f1 * cos_i * cos_q * lq * (PI / density);
            }
        }
        sum_indirect += estimate / f32(b);
    }
    if inside {
        store_channel_means(id.xy, sum_l0, sum_direct, sum_indirect, sum_ambient);
    }
    count_rays(local_index);
}
