// The per-frame uniforms the path tracer provides (src/render/provided.rs), declared once for
// every pass: group 1, each bound by its variable's name, so no graph lists them. A pass's own
// resources are in group 0. Reflection keeps only what an entry point uses: declaring all of
// them here binds none a pass does not read.
#include "scene.wgsl"

@group(1) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(1) var<uniform> camera: Camera;
// The previous frame's camera (reprojection); all zeros after a reset.
@group(1) @binding(2) var<uniform> camera_previous: Camera;
