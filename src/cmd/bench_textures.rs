//! `dermis bench textures`: the scene's textures — the character's, the props', the scanned
//! head's maps — loaded from the assets and uploaded, three ways: their block encodings as
//! stored (where the device samples them: BC on a desktop GPU and on lavapipe), their ETC2
//! encodings (the APK's; decoded to RGBA8 on the CPU where the device lacks ETC2, as
//! lavapipe does), and their PNG/JPEG sources decoded (mips built on the CPU). Per way: the
//! bytes read, the CPU time to load and to upload, and the bytes the textures take on the GPU.

use std::time::Instant;

use dermis_engine::asset::head;
use dermis_engine::asset::{dir_reader, load_gltf_slice, Model, Texels};
use dermis_engine::render::{upload_texture, uploaded_bytes, Gpu};
use dermis_engine::scene::PropKind;
use serde_json::json;

use crate::cmd::args::parse_rounds;
use crate::cmd::stats::median;

#[derive(clap::Args, Debug)]
pub struct TexturesArgs {
    /// Loads and uploads of each way (at least 2).
    #[arg(long, default_value_t = 5, value_parser = parse_rounds, allow_hyphen_values = true)]
    pub rounds: usize,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// A way of loading the textures: which files the loader may see.
struct Way {
    name: &'static str,
    /// A path the loader may not read (it then falls back as on a build without it).
    hidden: fn(&str) -> bool,
}

const WAYS: [Way; 3] = [
    Way {
        name: "block encodings (as the device samples them)",
        hidden: |_| false,
    },
    Way {
        name: "ETC2 encodings only (the APK's)",
        hidden: |p| p.ends_with(".ktx2") && !p.ends_with(".etc2.ktx2"),
    },
    Way {
        name: "PNG/JPEG sources decoded",
        hidden: |p| p.ends_with(".ktx2"),
    },
];

/// The character, every prop and the textured head, read through `read`.
fn load(read: &dyn Fn(&str) -> Result<Vec<u8>, String>) -> Result<Vec<Model>, String> {
    let model = |path: &str| -> Result<Model, String> {
        let bytes = read(path)?;
        let dir = path.rsplit_once('/').map_or("", |(d, _)| d);
        let resolve = |uri: &str| match dir {
            "" => read(uri),
            _ => read(&format!("{dir}/{uri}")),
        };
        load_gltf_slice(&bytes, path, &resolve).map_err(|e| e.to_string())
    };
    let mut models = vec![model("character.glb")?];
    for kind in PropKind::ALL {
        models.push(model(&format!("props/{}", kind.file()))?);
    }
    let maps = head::Maps {
        albedo: true,
        normal: true,
    };
    models.push(head::load_from(read, maps).map_err(|e| e.to_string())?);
    Ok(models)
}

pub fn run(args: TexturesArgs) -> Result<(), String> {
    let assets = crate::paths::assets_dir();
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let features = gpu.device.features();
    let mut rows = Vec::new();
    for way in &WAYS {
        let files = dir_reader(&assets);
        let read_bytes = std::cell::Cell::new(0usize);
        let read = |p: &str| -> Result<Vec<u8>, String> {
            if (way.hidden)(p) {
                return Err(format!("{p} hidden"));
            }
            let bytes = files(p)?;
            read_bytes.set(read_bytes.get() + bytes.len());
            Ok(bytes)
        };
        let (mut load_ms, mut upload_ms) = (Vec::new(), Vec::new());
        let (mut gpu_bytes, mut blocks, mut disk) = (0, 0, 0);
        for _ in 0..args.rounds {
            read_bytes.set(0);
            let t = Instant::now();
            let models = load(&read)?;
            load_ms.push(t.elapsed().as_secs_f64() * 1e3);
            disk = read_bytes.get();
            let before = uploaded_bytes();
            let t = Instant::now();
            let mut views = Vec::new();
            for m in &models {
                for tex in &m.textures {
                    views.push(upload_texture(&gpu.device, &gpu.queue, tex, "bench"));
                }
            }
            gpu.wait();
            upload_ms.push(t.elapsed().as_secs_f64() * 1e3);
            gpu_bytes = uploaded_bytes() - before;
            blocks = models
                .iter()
                .flat_map(|m| &m.textures)
                .filter(|t| matches!(t.texels, Texels::Blocks(_)))
                .count();
        }
        rows.push(json!({
            "way": way.name,
            "bytes_read": disk,
            "textures_in_block_formats": blocks,
            "load_ms_median": median(&load_ms),
            "upload_ms_median": median(&upload_ms),
            "total_ms_median": median(&load_ms) + median(&upload_ms),
            "gpu_bytes": gpu_bytes,
        }));
    }
    let report = json!({
        "adapter": gpu.adapter_name(),
        "samples": {
            "bc": features.contains(wgpu::Features::TEXTURE_COMPRESSION_BC),
            "etc2": features.contains(wgpu::Features::TEXTURE_COMPRESSION_ETC2),
            "astc": features.contains(wgpu::Features::TEXTURE_COMPRESSION_ASTC),
        },
        "rounds": args.rounds,
        "ways": rows,
    });
    if args.json {
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        println!("{text}");
        return Ok(());
    }
    println!(
        "adapter: {} (samples BC {}, ETC2 {}, ASTC {}); the character, 5 props and the head, \
         medians of {} rounds:",
        gpu.adapter_name(),
        report["samples"]["bc"],
        report["samples"]["etc2"],
        report["samples"]["astc"],
        args.rounds
    );
    println!(
        "  {:<46} {:>10} {:>8} {:>9} {:>10} {:>11}",
        "way", "read MiB", "load ms", "upload ms", "total ms", "GPU MiB"
    );
    let mib = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN) / (1 << 20) as f64;
    for r in report["ways"].as_array().into_iter().flatten() {
        let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
        println!(
            "  {:<46} {:>10.2} {:>8.1} {:>9.1} {:>10.1} {:>11.2}",
            r["way"].as_str().unwrap_or("?"),
            mib(&r["bytes_read"]),
            f("load_ms_median"),
            f("upload_ms_median"),
            f("total_ms_median"),
            mib(&r["gpu_bytes"]),
        );
    }
    Ok(())
}
