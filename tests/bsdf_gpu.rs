//! The WGSL BSDF library (shaders/lib/bsdf*.wgsl) on the GPU (lavapipe in CI), through
//! tests/data/bsdf/bsdf_probe.wgsl: its answers against the CPU twin (src/bsdf), and its
//! sampled directions by chi-square against the twin's pdf.

mod bsdf_support;
mod common;

use bsdf_support::{Case, Rng, cases, chi2_p_value, rounding_tolerance};
use common::bvh_gpu::{Gpu, dispatch_and_read, gpu, output_buffer};
use common::root;
use glam::{Vec2, Vec3};
use passgraph::gpu::texels::create_texel_view;
use passgraph::graph::shader_source::ShaderSource;
use passgraph::material::materials_texels;
use passgraph::material::{Sample, eval, is_delta, pdf, sample};
use passgraph::scene::{MATERIAL_METALLIC_ROUGHNESS, MATERIAL_PLASTIC, Material};

/// The materials view the probe binds, laid out by scene loading's own code from the cases'
/// materials, and each case's table index in it (NO_TABLE for models without one).
struct Materials {
    texels: Vec<[f32; 4]>,
    table: Vec<u32>,
}

fn materials(cases: &[Case]) -> Materials {
    let ms: Vec<Material> = cases
        .iter()
        .map(|c| Material {
            kind: c.bsdf.kind,
            alpha: c.bsdf.alpha,
            ior: c.bsdf.ior,
            distribution: c.bsdf.distribution as u32,
            ..Material::DEFAULT
        })
        .collect();
    let (ms, texels) = materials_texels(&ms);
    for (m, c) in ms.iter().zip(cases) {
        // Rough plastic's own table, or the metallic-roughness model's shared albedo table.
        assert_eq!(
            m.table != passgraph::scene::NO_TABLE,
            (c.bsdf.table.is_some() && c.bsdf.kind == MATERIAL_PLASTIC)
                || c.bsdf.kind == MATERIAL_METALLIC_ROUGHNESS,
            "{}: scene loading and the twin disagree on the table",
            c.name
        );
    }
    Materials {
        texels,
        table: ms.iter().map(|m| m.table).collect(),
    }
}

/// Matches `Query` in bsdf_probe.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Query {
    kd_kind: [f32; 4],
    ks_ns: [f32; 4],
    tf_ior: [f32; 4],
    n_alpha: [f32; 4],
    wo_outside: [f32; 4],
    wi: [f32; 4],
    u: [f32; 4],
    eta_distribution: [f32; 4],
    k_fresnel: [f32; 4],
}

/// Matches `Answer` in bsdf_probe.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Answer {
    eval_pdf: [f32; 4],
    wi_delta: [f32; 4],
    weight_pdf: [f32; 4],
    at_sample: [f32; 4],
}

impl Answer {
    fn sample(&self) -> Sample {
        Sample {
            wi: Vec3::from_slice(&self.wi_delta[..3]),
            weight: Vec3::from_slice(&self.weight_pdf[..3]),
            pdf: self.weight_pdf[3],
            delta: self.wi_delta[3] != 0.0,
        }
    }
}

fn query(case: &Case, table: u32, wi: Vec3, u: Vec2, u_lobe: f32) -> Query {
    let b = &case.bsdf;
    Query {
        kd_kind: [b.kd.x, b.kd.y, b.kd.z, f32::from_bits(b.kind)],
        ks_ns: [b.ks.x, b.ks.y, b.ks.z, b.ns],
        tf_ior: [b.tf.x, b.tf.y, b.tf.z, b.ior],
        n_alpha: [case.n.x, case.n.y, case.n.z, b.alpha],
        wo_outside: [
            case.wo.x,
            case.wo.y,
            case.wo.z,
            if case.outside { 1.0 } else { 0.0 },
        ],
        wi: [wi.x, wi.y, wi.z, 0.0],
        u: [u.x, u.y, u_lobe, f32::from_bits(table)],
        eta_distribution: [
            b.eta.x,
            b.eta.y,
            b.eta.z,
            f32::from_bits(b.distribution as u32),
        ],
        k_fresnel: [b.k.x, b.k.y, b.k.z, f32::from_bits(b.fresnel)],
    }
}

fn run(gpu: &Gpu, materials: &Materials, queries: &[Query]) -> Vec<Answer> {
    run_with_kinds(gpu, materials, queries, None)
}

/// As [`run`], with the `scene_material_kinds` override set to `kinds` (a scene's bits).
fn run_with_kinds(
    gpu: &Gpu,
    materials: &Materials,
    queries: &[Query],
    kinds: Option<u32>,
) -> Vec<Answer> {
    use wgpu::util::DeviceExt;
    let path = root().join("tests/data/bsdf/bsdf_probe.wgsl");
    let source = ShaderSource::load(&path, &root().join("shaders")).expect("includes resolve");
    // With `kinds`, the module the renderer would build: specialised by
    // crates/gpu/src/specialise.rs to that value (dead models removed), not wgpu's substitution.
    let constants: Vec<(&str, f64)> = kinds
        .map(|k| vec![("scene_material_kinds", f64::from(k))])
        .unwrap_or_default();
    let shader = match kinds {
        Some(_) => wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(
            passgraph::gpu::specialise::specialise(
                &source.code,
                Some((naga::ShaderStage::Compute, "main")),
                &constants,
            )
            .expect("the probe specialises"),
        )),
        None => wgpu::ShaderSource::Wgsl(source.code.into()),
    };
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("bsdf_probe"),
            source: shader,
        });
    // An explicit layout, as the renderer's: specialising removes globals nothing reads (with
    // Lambert only, the material table), which a layout derived from the module would lack.
    let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bsdf_probe"),
            entries: &[
                storage(0, true),
                storage(1, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::ReadOnly,
                        format: wgpu::TextureFormat::Rgba32Uint,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
            ],
        });
    let pipeline_layout = gpu
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("bsdf_probe"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("bsdf_probe"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
    let input = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("queries"),
            contents: bytemuck::cast_slice(queries),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let answers = output_buffer(gpu, (queries.len() * size_of::<Answer>()) as u64);
    let view = create_texel_view(
        &gpu.device,
        &gpu.queue,
        "materials",
        bytemuck::cast_slice(&materials.texels),
    )
    .expect("the tables fit a texture")
    .create_view(&Default::default());
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: answers.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&view),
            },
        ],
    });
    dispatch_and_read(gpu, &pipeline, &bind_group, queries.len(), &answers)
}

/// Relative difference with an absolute floor for values near zero.
fn rel(a: f32, b: f32, floor: f32) -> f32 {
    (a - b).abs() / (a.abs().max(b.abs()).max(floor))
}

/// Fails when the WGSL and the CPU twin drift apart (a formula edited on one side only, a
/// select with its arms swapped, a missing scene_has_kind branch). Both compute in f32 from the
/// same inputs, lavapipe with its own FMA contraction and normalize: eval and pdf agree within
/// `rounding_tolerance` (tests/bsdf_support: a few epsilon of input difference through each
/// model's condition number). Samples go through sin and cos of 2 pi u, whose lavapipe results
/// differ from the CPU's by some ulps: wi within 1e-4, and weight and pdf within
/// `rounding_tolerance` scaled by the measured difference of wi in units of 4 epsilon. Lobe
/// choices (u_lobe against F, or a sample at the horizon) may differ when u_lobe is within
/// rounding of F: at most 0.1% of the samples.
#[test]
fn gpu_eval_pdf_and_sample_match_the_cpu_twin() {
    let gpu = gpu();
    let mut rng = Rng::new(42);
    let mut queries = Vec::new();
    let mut owners = Vec::new();
    let all = cases(false);
    let materials = materials(&all);
    for (c, case) in all.iter().enumerate() {
        for _ in 0..100 {
            let mut wi = rng.sphere();
            // Half near the mirror direction, where near-smooth lobes are not zero.
            if rng.unit() < 0.5 {
                let mirror = 2.0 * case.wo.dot(case.n) * case.n - case.wo;
                wi = (mirror + 0.05 * rng.sphere()).normalize();
            }
            let u = rng.vec2();
            queries.push(query(case, materials.table[c], wi, u, rng.unit()));
            owners.push(c);
        }
    }
    let answers = run(&gpu, &materials, &queries);
    let (mut worst_eval, mut worst_sample, mut worst_wi) = (0.0f32, 0.0f32, 0.0f32);
    let mut branch_differences = 0;
    let mut worst_case = String::new();
    let mut differences = Vec::new();
    for ((q, a), &c) in queries.iter().zip(&answers).zip(&owners) {
        let case = &all[c];
        let wi = Vec3::from_slice(&q.wi[..3]);
        let e = eval(&case.bsdf, case.n, case.outside, case.wo, wi);
        let p = pdf(&case.bsdf, case.n, case.outside, case.wo, wi);
        let tol = rounding_tolerance(case, wi);
        for k in 0..3 {
            let d = rel(a.eval_pdf[k], e[k], 1e-6);
            if d > worst_eval {
                worst_case = format!("{} at wi {wi} (tolerance {tol:e})", case.name);
            }
            worst_eval = worst_eval.max(d);
            differences.push(d);
            assert!(
                d <= tol,
                "{}: GPU eval {:?} CPU {e} at {wi} (tolerance {tol})",
                case.name,
                a.eval_pdf
            );
        }
        let d = rel(a.eval_pdf[3], p, 1e-6);
        worst_eval = worst_eval.max(d);
        differences.push(d);
        assert!(
            d <= tol,
            "{}: GPU pdf {} CPU {p} at {wi} (tolerance {tol})",
            case.name,
            a.eval_pdf[3]
        );

        let u = Vec2::new(q.u[0], q.u[1]);
        let cpu = sample(&case.bsdf, case.n, case.outside, case.wo, u, q.u[2]);
        let g = a.sample();
        let same_branch = g.delta == cpu.delta
            && (g.pdf > 0.0) == (cpu.pdf > 0.0)
            && (g.wi - cpu.wi).length() <= 1e-4;
        if !same_branch {
            branch_differences += 1;
            continue;
        }
        let mut d = rel(g.pdf, cpu.pdf, 1e-6);
        for k in 0..3 {
            d = d.max(rel(g.weight[k], cpu.weight[k], 1e-6));
        }
        worst_sample = worst_sample.max(d);
        worst_wi = worst_wi.max((g.wi - cpu.wi).length());
        let scale = ((g.wi - cpu.wi).length() / (4.0 * f32::EPSILON)).max(1.0);
        assert!(
            d <= rounding_tolerance(case, cpu.wi) * scale,
            "{}: GPU sample {g:?} CPU {cpu:?} (u {u}, u_lobe {})",
            case.name,
            q.u[2]
        );
    }
    println!(
        "{} queries: eval/pdf largest relative difference {worst_eval:e}, samples: wi \
         {worst_wi:e}, weight and pdf {worst_sample:e}, {branch_differences} lobe choices differ",
        queries.len()
    );
    differences.sort_by(f32::total_cmp);
    println!(
        "eval/pdf relative differences: median {:e}, 99th percentile {:e}; largest {worst_case}",
        differences[differences.len() / 2],
        differences[differences.len() * 99 / 100]
    );
    assert!(
        branch_differences * 1000 <= queries.len(),
        "{branch_differences} samples took another branch on the GPU"
    );
}

/// Fails when the GPU's sampler does not follow the density (a WGSL-only sampling bug the twin
/// does not share), and when a GPU sample's weight is not its eval / pdf. 50 000 GPU samples
/// per case, chi-square against the twin's pdf at the threshold of bsdf_sampling.rs; weights
/// within `rounding_tolerance` as there (the same f32 quantity by two expressions).
#[test]
fn gpu_samples_follow_pdf_by_chi_square_and_weigh_eval_over_pdf() {
    let gpu = gpu();
    let mut report = String::new();
    let all = cases(false);
    let materials = materials(&all);
    for (i, case) in all.iter().enumerate() {
        if is_delta(&case.bsdf) {
            continue;
        }
        let mut rng = Rng::new(7000 + i as u64);
        let queries: Vec<Query> = (0..50_000)
            .map(|_| {
                let u = rng.vec2();
                query(case, materials.table[i], case.n, u, rng.unit())
            })
            .collect();
        let answers = run(&gpu, &materials, &queries);
        let samples: Vec<Sample> = answers.iter().map(Answer::sample).collect();
        let p = chi2_p_value(case, &samples);
        report += &format!("{}: p {p:.3e}\n", case.name);
        assert!(
            p > bsdf_support::P_THRESHOLD,
            "{}: GPU chi-square p-value {p}",
            case.name
        );
        for (a, s) in answers.iter().zip(&samples) {
            if s.delta || s.pdf <= 0.0 {
                continue;
            }
            let e = Vec3::from_slice(&a.at_sample[..3]);
            let expected = e / a.at_sample[3];
            let tol = rounding_tolerance(case, s.wi);
            for k in 0..3 {
                assert!(
                    rel(s.weight[k], expected[k], 1e-6) <= tol,
                    "{}: GPU weight {} but eval / pdf {expected}",
                    case.name,
                    s.weight
                );
            }
        }
    }
    println!("{report}");
}

/// Fails when a model's code escapes its `scene_has_kind` guard, or the guards break the
/// library when specialised: with `scene_material_kinds` = Lambert only (a Lambert-only scene),
/// Lambert answers exactly as with every kind, and every other kind answers nothing (its code
/// is gone).
#[test]
fn a_lambert_only_scene_keeps_lambert_and_specialises_the_rest_away() {
    let gpu = gpu();
    let mut rng = Rng::new(99);
    let all = cases(false);
    let materials = materials(&all);
    let queries: Vec<Query> = all
        .iter()
        .enumerate()
        .flat_map(|(c, case)| {
            (0..20)
                .map(|_| {
                    let wi = rng.sphere();
                    let u = rng.vec2();
                    query(case, materials.table[c], wi, u, rng.unit())
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let lambert_only = 1u32 << passgraph::scene::MATERIAL_LAMBERT;
    let every = run(&gpu, &materials, &queries);
    let specialised = run_with_kinds(&gpu, &materials, &queries, Some(lambert_only));
    for (i, (a, b)) in every.iter().zip(&specialised).enumerate() {
        let case = &all[i / 20];
        if case.bsdf.kind == passgraph::scene::MATERIAL_LAMBERT {
            assert_eq!(
                bytemuck::bytes_of(a),
                bytemuck::bytes_of(b),
                "{}: Lambert changed under specialisation",
                case.name
            );
        } else {
            assert_eq!(
                b.eval_pdf, [0.0; 4],
                "{}: eval/pdf without its code",
                case.name
            );
            assert_eq!(
                b.weight_pdf, [0.0; 4],
                "{}: a sample without its code",
                case.name
            );
        }
    }
}
