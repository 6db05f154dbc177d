use crate::cli::console::{errln, outln};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, Subcommand};

use glint::gpu::variant::Variant;
use glint::gpu::{compile, GpuError, Renderer};
use glint::output::{self, Outputs};

use super::{DeviceArgs, SceneArgs};

#[derive(Args)]
pub struct ShaderArgs {
    #[command(subcommand)]
    command: ShaderCommand,
}

#[derive(Subcommand)]
enum ShaderCommand {
    /// Compile FILE as the main shader (the generic variant) and report errors as file:line: message.
    Check {
        file: PathBuf,
        /// Look for included files in DIR before the built-in ones; repeatable.
        #[arg(short = 'I', long = "include", value_name = "DIR")]
        include: Vec<PathBuf>,
        /// Add a preprocessor define; repeatable.
        #[arg(short = 'D', value_name = "NAME[=VALUE]")]
        define: Vec<String>,
    },
    /// Write the scene's variant as preprocessed GLSL and as SPIR-V into DIR.
    Dump {
        #[command(flatten)]
        scene: SceneArgs,
        #[arg(short, long, value_name = "DIR")]
        output: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
    },
}

pub fn run(a: &ShaderArgs) -> anyhow::Result<ExitCode> {
    match &a.command {
        ShaderCommand::Check {
            file,
            include,
            define,
        } => {
            anyhow::ensure!(
                file.is_file(),
                "{}: no such file",
                glint::printable::path(file)
            );
            // Includes beside the file are found, as `render --shader` finds them.
            let mut dirs = include.clone();
            dirs.push(glint::files::folder_of(file).to_owned());
            let sources = compile::Sources {
                dirs,
                main: Some(file.clone()),
                main_builtin: None,
                generated: Variant::generic().generated(),
            };
            let defines = define
                .iter()
                .map(|d| super::parse_define(d))
                .collect::<anyhow::Result<Vec<_>>>()?;
            match compile::compile(&sources, &defines) {
                Ok(c) => {
                    outln!(
                        "{}: compiles ({} words of SPIR-V)",
                        file.display(),
                        c.spirv.len()
                    );
                    Ok(ExitCode::SUCCESS)
                }
                Err(GpuError::Shader(log)) => {
                    errln!("{log}");
                    Ok(ExitCode::from(1))
                }
                Err(e) => Err(e.into()),
            }
        }
        ShaderCommand::Dump {
            scene: scene_args,
            output,
            device,
        } => {
            output::check_folder(output)?;
            let scene = scene_args.load()?;
            let options = device.options()?;
            let renderer = Renderer::new(&options)?;
            let (variant, defines) = renderer.variant(&scene, &options.settings);
            let sources = compile::Sources {
                dirs: options.include_dirs.clone(),
                main: options.main_shader.clone(),
                main_builtin: None,
                generated: variant.generated(),
            };
            let name = variant.name();
            let glsl = output.join(format!("{name}.comp"));
            let spv = output.join(format!("{name}.spv"));
            let mut outputs = Outputs::new(super::inputs(&scene_args.scene, &scene, device), false);
            let mut compiled = compile::compile(&sources, &defines)?;
            if options.spec_worst {
                let (words, report) =
                    glint::spec_worst::apply(&compiled.spirv, &glint::spec_worst::BOUNDS)
                        .map_err(GpuError::Shader)?;
                compiled.spirv = words;
                errln!("--spec-worst: {}", report.line());
            }
            std::fs::create_dir_all(output)
                .with_context(|| format!("cannot create {}", output.display()))?;
            let header: String = defines
                .iter()
                .map(|(n, v)| {
                    format!(
                        "// -D {n}{}\n",
                        v.as_ref().map(|v| format!("={v}")).unwrap_or_default()
                    )
                })
                .collect();
            let text = format!("{header}{}", compiled.preprocessed);
            for (path, bytes) in [
                (&glsl, text.as_bytes()),
                (&spv, &compile::spirv_bytes(&compiled.spirv)[..]),
            ] {
                outputs.stage(path, |out: &mut dyn Write| {
                    out.write_all(bytes).map_err(output::io_err(path))
                })?;
            }
            outputs.commit()?;
            outln!("{}\n{}", glsl.display(), spv.display());
            Ok(ExitCode::SUCCESS)
        }
    }
}
