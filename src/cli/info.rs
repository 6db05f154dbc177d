use crate::cli::console::outln;
use std::process::ExitCode;

use clap::Args;

use glint::gpu;

#[derive(Args)]
pub struct InfoArgs {
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &InfoArgs) -> anyhow::Result<ExitCode> {
    let devices = gpu::list_devices()?;
    if a.json {
        outln!("{}", serde_json::json!({ "devices": devices }));
        return Ok(ExitCode::SUCCESS);
    }
    if devices.is_empty() {
        outln!("no Vulkan devices (glint render --backend cpu still works)");
    }
    for (i, d) in devices.iter().enumerate() {
        let default = if i == 0 { "  (default)" } else { "" };
        outln!("{i}: {}{default}", d.name);
        outln!("   type              {}", d.kind);
        outln!("   Vulkan            {}", d.api_version);
        outln!("   driver            {}", d.driver);
        outln!(
            "   shaderFloat64     {}",
            if d.shader_float64 { "yes" } else { "no" }
        );
        outln!(
            "   loop budget       {}",
            if d.loop_budget {
                "may cut long loops short: shaders carry the canary"
            } else {
                "none (every loop runs to its end)"
            }
        );
        outln!("   storage range     {} bytes", d.max_storage_buffer_range);
        outln!("   uniform range     {} bytes", d.max_uniform_buffer_range);
        outln!(
            "   texel buffers     {} texels",
            d.max_texel_buffer_elements
        );
        let [x, y, z] = d.max_compute_work_group_count;
        outln!(
            "   workgroups        {x} x {y} x {z}, {} invocations each",
            d.max_compute_work_group_invocations
        );
        outln!(
            "   compute queue     {}",
            d.compute_queue_family
                .map_or("none".into(), |q| format!("family {q}"))
        );
        outln!(
            "   timestamps        {}",
            d.timestamps
                .map_or("none on the compute queue".to_owned(), |(period, bits)| {
                    format!("{bits} bits, {period} ns a tick")
                })
        );
    }
    Ok(ExitCode::SUCCESS)
}
