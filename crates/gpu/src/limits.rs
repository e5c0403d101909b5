//! A plan against the device's limits and features, before anything is created: wgpu would
//! otherwise stop at the first object that does not fit, with its raw validation text. Each
//! error names the resource or pass, the limit and what to change.

use super::error::GpuError;
use passgraph_graph::interface::BindingKind;
use passgraph_graph::plan::{Plan, ResourceKind};

/// Checks every resource the plan allocates and every kept pass against `limits` and
/// `features` (the device's).
pub fn check_limits(
    plan: &Plan,
    limits: &wgpu::Limits,
    features: wgpu::Features,
) -> Result<(), GpuError> {
    let over = |what: String, reason: String| GpuError::OverLimit {
        graph: plan.graph.clone(),
        what,
        reason,
    };
    let [out_w, out_h] = plan.output_size;
    let smaller = format!("use a smaller --size than {out_w}x{out_h}");
    for r in plan.resources.iter().filter(|r| r.physical.is_some()) {
        let what = format!("resource '{}'", r.name);
        match r.kind {
            ResourceKind::Texture {
                width,
                height,
                layers,
                ..
            } => {
                let max = limits.max_texture_dimension_2d;
                if width > max || height > max {
                    return Err(over(
                        what,
                        format!(
                            "{width}x{height} texels is more than this device's max_texture_dimension_2d ({max}); {smaller} (or a smaller `size` in the graph)"
                        ),
                    ));
                }
                let max = limits.max_texture_array_layers;
                if layers > max {
                    return Err(over(
                        what,
                        format!(
                            "{layers} layers is more than this device's max_texture_array_layers ({max}); declare fewer `layers`"
                        ),
                    ));
                }
            }
            ResourceKind::Buffer { size } => {
                let max = limits.max_buffer_size;
                if size > max {
                    return Err(over(
                        what,
                        format!(
                            "{size} bytes is more than this device's max_buffer_size ({max}); {smaller} (or a smaller buffer `size` in the graph)"
                        ),
                    ));
                }
            }
            ResourceKind::Provided(_) => {}
        }
    }
    for pass in &plan.passes {
        let what = format!("pass '{}'", pass.name);
        let [x, y, z] = pass.workgroup_size;
        let max = [
            limits.max_compute_workgroup_size_x,
            limits.max_compute_workgroup_size_y,
            limits.max_compute_workgroup_size_z,
        ];
        let invocations = u64::from(x) * u64::from(y) * u64::from(z);
        let max_invocations = limits.max_compute_invocations_per_workgroup;
        if x > max[0] || y > max[1] || z > max[2] || invocations > u64::from(max_invocations) {
            return Err(over(
                what,
                format!(
                    "@workgroup_size({x}, {y}, {z}) in {} is more than this device allows (at most {}x{}x{} and {max_invocations} invocations, max_compute_invocations_per_workgroup); use a smaller @workgroup_size, e.g. (8, 8, 1)",
                    pass.shader.path.display(),
                    max[0],
                    max[1],
                    max[2]
                ),
            ));
        }
        if let Some(raster) = &pass.raster {
            let max = limits.max_color_attachments;
            if raster.color.len() > max as usize {
                return Err(over(
                    what,
                    format!(
                        "draws into {} colour attachments, more than this device's max_color_attachments ({max}); list fewer in `color` in {}",
                        raster.color.len(),
                        pass.pass_file.display()
                    ),
                ));
            }
        }
        let max = limits.max_compute_workgroups_per_dimension;
        if pass.workgroups.iter().any(|&n| n > max) {
            let [a, b, c] = pass.workgroups;
            return Err(over(
                what,
                format!(
                    "dispatches {a}x{b}x{c} workgroups, more than this device's max_compute_workgroups_per_dimension ({max}); {smaller} (or fewer `Workgroups` in {})",
                    pass.pass_file.display()
                ),
            ));
        }
        for b in &pass.bindings {
            let r = &plan.resources[b.resource];
            let ResourceKind::Buffer { size } = r.kind else {
                continue;
            };
            let (max, limit) = match b.kind {
                BindingKind::Storage { .. } => (
                    limits.max_storage_buffer_binding_size,
                    "max_storage_buffer_binding_size",
                ),
                BindingKind::Uniform { .. } => (
                    limits.max_uniform_buffer_binding_size,
                    "max_uniform_buffer_binding_size",
                ),
                _ => continue,
            };
            if size > max {
                return Err(over(
                    format!(
                        "resource '{}' (pass '{}', binding '{}')",
                        r.name, pass.name, b.name
                    ),
                    format!(
                        "{size} bytes is more than this device's {limit} ({max}); {smaller} (or a smaller buffer `size` in the graph)"
                    ),
                ));
            }
        }
        if pass.needs_subgroups && !features.contains(wgpu::Features::SUBGROUP) {
            return Err(over(
                what,
                format!(
                    "{} uses subgroup operations, which the device passgraph runs on does not offer (wgpu feature SUBGROUP); use a graph without this pass (e.g. graphs/pathtracer-fast.ron instead of graphs/pathtracer-reuse.ron)",
                    pass.shader.path.display()
                ),
            ));
        }
        if enables_f16(&pass.shader.code) && !features.contains(wgpu::Features::SHADER_F16) {
            return Err(over(
                what,
                format!(
                    "{} has `enable f16;`, but the device passgraph runs on has no 16-bit floats in shaders (wgpu feature SHADER_F16); use f32",
                    pass.shader.path.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Whether WGSL code enables the f16 extension (`enable f16;`, possibly among others).
fn enables_f16(code: &str) -> bool {
    code.lines().any(|line| {
        line.trim()
            .strip_prefix("enable")
            .is_some_and(|rest| rest.split([',', ';', ' ']).any(|w| w.trim() == "f16"))
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn f16_is_found_in_enable_directives_only() {
        assert!(super::enables_f16("enable f16;\nfn main() {}"));
        assert!(super::enables_f16("  enable subgroups, f16;"));
        assert!(!super::enables_f16(
            "// f16 is not enabled\nfn f16_like() {}"
        ));
    }
}
