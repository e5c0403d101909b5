// The segment a wavefront path's record holds, traced (lib/wavefront.wgsl). Included after
// bvh.wgsl and wavefront.wgsl.

// The closest hit of the path's ray, into its record.
fn wavefront_trace(path: ptr<function, WavefrontPath>) {
    let hit = closest_hit((*path).origin, (*path).dir, 0.0, 3.0e38);
    (*path).triangle = hit.triangle;
    (*path).hit_t = hit.t;
    (*path).hit_u = hit.u;
    (*path).hit_v = hit.v;
}
