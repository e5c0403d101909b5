// Counting the rays a pass traces, cheaply: each invocation's count (bvh.wgsl's
// `bvh_rays_traced`) is summed in workgroup memory, then one atomic per workgroup adds it to the
// pass's `ray_count` buffer, a 64-bit total as two u32 (low, high). The including shader declares
// `@group(0) @binding(N) var<storage, read_write> ray_count: array<atomic<u32>, 2>;` and ends
// its entry point, in uniform control flow, with `count_rays(local_index)`.

var<workgroup> workgroup_rays: atomic<u32>;

fn count_rays(local_index: u32) {
    atomicAdd(&workgroup_rays, bvh_rays_traced);
    workgroupBarrier();
    if local_index == 0u {
        let n = atomicLoad(&workgroup_rays);
        let old = atomicAdd(&ray_count[0], n);
        // Carry into the high word when the low word wraps.
        if old + n < old {
            atomicAdd(&ray_count[1], 1u);
        }
    }
}
