// The primary ray of a sample traced where it is shaded (the fused passes, the wavefront's
// camera pass), rather than read from the ray texture. Included after scene, sampler,
// camera_ray, bvh and primary.

// The primary ray of `pixel` for `source` (filtered, through the lens) and its closest hit (as intersect traces it).
fn path_primary(pixel: vec2<u32>, source: SampleSource) -> Primary {
    let ray = camera_sample_ray(pixel, source, true);
    let hit = closest_hit(ray.origin, ray.dir, 0.0, 3.0e38);
    return Primary(ray.origin, ray.dir, hit.t, hit.u, hit.v, hit.triangle);
}
