//! `cargo run -p passgraph-gpu --example postprocess [-- WxH [OUT.ppm]]`: a raster pass and a
//! compute post-process chain, a renderer that is not a path tracer, built on the framework
//! crates alone. Prints the plan and the image's mean; writes a PPM if asked.

mod renderer;

use passgraph_gpu::GpuContext;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size = match args.first() {
        Some(s) => {
            let (w, h) = s.split_once('x').ok_or(format!("'{s}' is not WxH"))?;
            let n = |t: &str| t.parse::<u32>().map_err(|_| format!("'{s}' is not WxH"));
            [n(w)?, n(h)?]
        }
        None => [64, 48],
    };
    print!("{}", renderer::compile(size)?);
    let ctx = GpuContext::new(None).map_err(|e| e.to_string())?;
    let texels = renderer::render(&ctx, size, 2, [1.0, 0.9, 0.8])?;
    let n = texels.len() as f32;
    let mean = texels.iter().fold([0.0f32; 3], |m, t| {
        [m[0] + t[0] / n, m[1] + t[1] / n, m[2] + t[2] / n]
    });
    println!(
        "{}x{}: mean rgb {:.4} {:.4} {:.4}",
        size[0], size[1], mean[0], mean[1], mean[2]
    );
    if let Some(out) = args.get(1) {
        let mut ppm = format!("P6\n{} {}\n255\n", size[0], size[1]).into_bytes();
        ppm.extend(texels.iter().flat_map(|t| {
            [t[0], t[1], t[2]].map(|v| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8)
        }));
        std::fs::write(out, ppm).map_err(|e| format!("{out}: cannot write: {e}"))?;
        println!("wrote {out}");
    }
    Ok(())
}
