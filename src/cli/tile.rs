//! `render --tile I/N | auto/N` and `--region X,Y,W,H`: one piece of a
//! render, written with its sidecar (docs/scale-out.md).

use clap::Args;

use glint::raster::region::Region;
use glint::scene::Scene;
use glint::tiles::{scene_hash, GpuKey, RenderKey, Sidecar};

#[derive(Args, Default)]
pub struct TileArgs {
    /// Render tile I of N (bands of whole 8-row workgroups), or auto/N: I from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX. Writes EXR or PFM with a sidecar OUTPUT.json.
    #[arg(long, value_name = "I/N", conflicts_with = "region")]
    pub tile: Option<String>,
    /// Render only the pixels X..X+W, Y..Y+H, written as with --tile.
    #[arg(long, value_name = "X,Y,W,H")]
    pub region: Option<String>,
}

/// The environment variables an engine gives an array task its index in.
const INDEX_VARS: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

impl TileArgs {
    pub fn is_set(&self) -> bool {
        self.tile.is_some() || self.region.is_some()
    }

    /// The region asked for in a `width`×`height` image, and the tile's
    /// `I/N` where it is one.
    pub fn resolve(&self, width: u32, height: u32) -> anyhow::Result<(Region, Option<String>)> {
        if let Some(spec) = &self.tile {
            let (i, n) = spec
                .split_once('/')
                .ok_or_else(|| anyhow::anyhow!("--tile {spec}: expected I/N or auto/N"))?;
            let n: u32 = n
                .parse()
                .map_err(|_| anyhow::anyhow!("--tile {spec}: N is not a count"))?;
            let i: u32 = if i == "auto" {
                engine_index().map_err(|e| anyhow::anyhow!("--tile {spec}: {e}"))?
            } else {
                i.parse()
                    .map_err(|_| anyhow::anyhow!("--tile {spec}: I is not an index"))?
            };
            let r =
                Region::tile(i, n, width, height).map_err(|e| anyhow::anyhow!("--tile: {e}"))?;
            return Ok((r, Some(format!("{i}/{n}"))));
        }
        let spec = self.region.as_deref().unwrap_or_default();
        let v: Vec<u32> = spec
            .split(',')
            .map(|s| s.trim().parse())
            .collect::<Result<_, _>>()
            .map_err(|_| anyhow::anyhow!("--region {spec}: expected X,Y,W,H in pixels"))?;
        let [x, y, w, h] = v[..] else {
            anyhow::bail!("--region {spec}: expected X,Y,W,H in pixels");
        };
        let r = Region {
            x,
            y,
            width: w,
            height: h,
        }
        .within(width, height)
        .map_err(|e| anyhow::anyhow!("--region: {e}"))?;
        Ok((r, None))
    }
}

/// The array task's index, from Slurm or a Kubernetes Indexed Job.
fn engine_index() -> Result<u32, String> {
    for var in INDEX_VARS {
        if let Ok(v) = std::env::var(var) {
            return v
                .trim()
                .parse()
                .map_err(|_| format!("{var}={v} is not an index"));
        }
    }
    Err(format!(
        "auto needs the task's index in {} (Slurm job arrays) or {} (Kubernetes Indexed Jobs), and neither is set",
        INDEX_VARS[0], INDEX_VARS[1]
    ))
}

/// The sidecar of a tile of `scene` rendered on the GPU with what `gpu`
/// says of it (None: on the CPU) in `precision`.
pub fn sidecar(
    scene_arg: &std::path::Path,
    scene: &Scene,
    precision: &str,
    gpu: Option<GpuKey>,
    region: Region,
    tile: Option<String>,
    image: &glint::raster::Image,
) -> Sidecar {
    Sidecar {
        glint: env!("CARGO_PKG_VERSION").to_owned(),
        scene: scene_arg.display().to_string(),
        scene_hash: scene_hash(scene),
        width: scene.width,
        height: scene.height,
        srgb: scene.srgb,
        render: RenderKey {
            backend: if gpu.is_some() { "gpu" } else { "cpu" }.to_owned(),
            precision: precision.to_owned(),
            gpu,
        },
        region,
        tile,
        pixels: glint::tiles::pixels_hash(image),
    }
}
