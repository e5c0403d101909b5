//! `passgraph view` in a real window: under Xvfb (a virtual X server), a script switches the
//! channel, flies forward and takes screenshots of what the window shows; the screenshots must
//! show the Cornell box. Needs Xvfb and lavapipe (scripts/setup installs both).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// The virtual X server, killed when the test ends, passed or failed.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start(log: &Path) -> Xvfb {
        let on_path = std::env::var_os("PATH")
            .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join("Xvfb").is_file()));
        assert!(
            on_path,
            "Xvfb is not installed; the viewer test needs a virtual X server: run scripts/setup"
        );
        // -displayfd makes Xvfb choose a free display itself and print its number on stdout
        // once it accepts connections: no guessed numbers, no race with its start.
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(log).unwrap())
            .spawn()
            .expect("cannot start Xvfb");
        let mut line = String::new();
        let read = BufReader::new(child.stdout.take().unwrap()).read_line(&mut line);
        let number = line.trim().to_string();
        let server = Xvfb {
            child,
            display: format!(":{number}"),
        };
        assert!(
            read.is_ok() && !number.is_empty() && number.chars().all(|c| c.is_ascii_digit()),
            "Xvfb did not start: {}",
            std::fs::read_to_string(log).unwrap_or_default()
        );
        server
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn screenshot(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// Mean RGB over the rectangle [x0, x1) x [y0, y1), in fractions of the image.
fn mean(img: &image::RgbImage, x: [f32; 2], y: [f32; 2]) -> [f32; 3] {
    let (w, h) = (img.width() as f32, img.height() as f32);
    let mut sum = [0.0f32; 3];
    let mut n = 0.0;
    for py in (y[0] * h) as u32..(y[1] * h) as u32 {
        for px in (x[0] * w) as u32..(x[1] * w) as u32 {
            let p = img.get_pixel(px, py).0;
            for k in 0..3 {
                sum[k] += f32::from(p[k]);
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

/// The widest run of white pixels on one row of the top third: the ceiling light's width
/// (noise gives isolated white pixels, never a long run).
fn light_width(img: &image::RgbImage) -> u32 {
    let mut widest = 0;
    for y in 0..img.height() / 3 {
        let mut run = 0;
        for x in 0..img.width() {
            let white = img.get_pixel(x, y).0.iter().all(|&c| c > 230);
            run = if white { run + 1 } else { 0 };
            widest = widest.max(run);
        }
    }
    widest
}

#[test]
fn viewer_under_xvfb_shows_the_cornell_box_and_follows_scripted_input() {
    let dir = tempfile::tempdir().unwrap();
    let xvfb = Xvfb::start(&dir.path().join("xvfb.log"));
    let shot = |name: &str| -> PathBuf { dir.path().join(name) };
    let script = dir.path().join("script.txt");
    std::fs::write(
        &script,
        format!(
            "# the sum after some frames, then L0 alone, then the sum after flying forward\n\
             wait 8\n\
             screenshot {}\n\
             key 2\n\
             screenshot {}\n\
             key 1\n\
             hold w 15\n\
             wait 20\n\
             screenshot {}\n\
             quit\n",
            shot("sum.png").display(),
            shot("l0.png").display(),
            shot("forward.png").display()
        ),
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_passgraph"))
        .args(["view", "--size", "128x128", "--frames", "400", "--script"])
        .arg(&script)
        .env("DISPLAY", &xvfb.display)
        // Only the virtual server: never a developer's real session.
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "passgraph view failed:\n{stderr}");
    assert!(
        stderr.contains("view: 32 frames"),
        "the script quits in frame 32 (--frames 400 is only a backstop):\n{stderr}"
    );
    // The adapter with its driver and version, as render and bench print it.
    let info = passgraph::gpu::GpuContext::new(None).unwrap();
    let adapter = passgraph::gpu::context::describe(info.adapter_info());
    assert!(
        stderr.contains(&format!("adapter: {adapter}; surface")),
        "{adapter}\n{stderr}"
    );

    let sum = screenshot(&shot("sum.png"));
    // The window starts at twice the image size; the screenshot is what it shows.
    assert_eq!(sum.dimensions(), (256, 256));
    let left = mean(&sum, [0.03, 0.15], [0.3, 0.7]);
    let right = mean(&sum, [0.85, 0.97], [0.3, 0.7]);
    let light = mean(&sum, [0.44, 0.56], [0.13, 0.15]);
    let back = mean(&sum, [0.4, 0.6], [0.25, 0.4]);
    assert!(
        left[0] > 2.0 * left[1].max(left[2]),
        "left wall red: {left:?}"
    );
    assert!(
        right[1] > 1.3 * right[0].max(right[2]),
        "right wall green: {right:?}"
    );
    assert!(
        light.iter().all(|&c| c > 200.0),
        "the light is white: {light:?}"
    );
    assert!(
        back.iter().all(|&c| c > 40.0),
        "the back wall is lit: {back:?}"
    );

    // Key 2 shows L0, emission alone: the light, and walls far darker than in the sum.
    let l0 = screenshot(&shot("l0.png"));
    let l0_light = mean(&l0, [0.44, 0.56], [0.13, 0.15]);
    let l0_back = mean(&l0, [0.4, 0.6], [0.25, 0.4]);
    assert!(
        l0_light.iter().all(|&c| c > 200.0),
        "L0 light: {l0_light:?}"
    );
    assert!(
        l0_back.iter().all(|&c| c < 10.0),
        "L0 back wall: {l0_back:?}"
    );

    // Flying forward (a quarter of the way to the box), the light looks wider.
    let forward = screenshot(&shot("forward.png"));
    let (before, after) = (light_width(&sum), light_width(&forward));
    assert!(before > 20, "the light is {before} pixels wide");
    assert!(
        after as f32 > 1.15 * before as f32,
        "the light looks wider after flying forward: {before} -> {after} pixels"
    );
}
