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
        println!("{}", serde_json::json!({ "devices": devices }));
        return Ok(ExitCode::SUCCESS);
    }
    if devices.is_empty() {
        println!("no Vulkan devices (glint render --backend cpu still works)");
    }
    for (i, d) in devices.iter().enumerate() {
        let default = if i == 0 { "  (default)" } else { "" };
        println!("{i}: {}{default}", d.name);
        println!("   type              {}", d.kind);
        println!("   Vulkan            {}", d.api_version);
        println!("   driver            {}", d.driver);
        println!(
            "   shaderFloat64     {}",
            if d.shader_float64 { "yes" } else { "no" }
        );
        println!(
            "   loop budget       {}",
            if d.loop_budget {
                "may cut long loops short: shaders carry the canary"
            } else {
                "none (every loop runs to its end)"
            }
        );
        println!("   storage range     {} bytes", d.max_storage_buffer_range);
        println!("   uniform range     {} bytes", d.max_uniform_buffer_range);
        println!(
            "   texel buffers     {} texels",
            d.max_texel_buffer_elements
        );
        let [x, y, z] = d.max_compute_work_group_count;
        println!(
            "   workgroups        {x} x {y} x {z}, {} invocations each",
            d.max_compute_work_group_invocations
        );
        println!(
            "   compute queue     {}",
            d.compute_queue_family
                .map_or("none".into(), |q| format!("family {q}"))
        );
        println!(
            "   timestamps        {}",
            d.timestamps
                .map_or("none on the compute queue".to_owned(), |(period, bits)| {
                    format!("{bits} bits, {period} ns a tick")
                })
        );
    }
    Ok(ExitCode::SUCCESS)
}
