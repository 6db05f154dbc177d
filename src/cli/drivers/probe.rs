//! One driver's run, in a child process of its own (`glint driver-probe`,
//! hidden): it opens the one device `VK_DRIVER_FILES` leaves, renders one
//! scene (or none, to name the device) and writes what happened as JSON
//! beside the image. A driver that crashes or hangs takes only this
//! process with it; the parent reads the signal or the missing file.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::Args;

use glint::drivers::{Ended, Identity, ProbeReport, Seen, IMAGE};
use glint::gpu::{GpuError, Renderer};
use glint::raster::io;
use glint::scene::Scene;

use super::super::{DeviceArgs, OverrideArgs};

/// The hidden command's arguments.
#[derive(Args)]
pub struct ProbeArgs {
    /// The folder to write probe.json (and gpu.pfm) into.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// The scene to render; without it the probe names the device only.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    #[command(flatten)]
    overrides: OverrideArgs,
    #[command(flatten)]
    device: DeviceArgs,
}

const REPORT: &str = "probe.json";

/// The child's side: runs the probe and writes probe.json; its exit status
/// is 0 whenever that file is written, whatever the probe found.
pub fn run(a: &ProbeArgs) -> anyhow::Result<ExitCode> {
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let probe = probe(a);
    let text = serde_json::to_string_pretty(&probe)?;
    let path = a.out.join(REPORT);
    std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(ExitCode::SUCCESS)
}

fn probe(a: &ProbeArgs) -> ProbeReport {
    let options = match a.device.options() {
        Ok(o) => o,
        Err(e) => return errored(None, format!("{e:#}")),
    };
    let mut renderer = match Renderer::new(&options) {
        Ok(r) => r,
        Err(e) if refuses_to_open(&e) => {
            return failed(
                None,
                Seen::NoDevice {
                    message: e.to_string(),
                },
            )
        }
        Err(e) => return failed(None, seen_of(e)),
    };
    let d = renderer.device_info();
    let device = Some(Identity {
        name: d.name.clone(),
        kind: d.kind.clone(),
        driver: d.driver.clone(),
        api_version: d.api_version.clone(),
    });
    let Some(scene) = &a.scene else {
        return ProbeReport {
            device,
            seen: Seen::Rendered {
                variant: None,
                seconds: 0.0,
                driver_compile_s: 0.0,
            },
        };
    };
    let scene = match Scene::load(scene, &a.overrides.overrides()) {
        Ok(s) => s,
        Err(e) => return errored(device, format!("{e:#}")),
    };
    let rendered = renderer
        .prepare(&scene, &options.settings)
        .and_then(|mut p| {
            let r = p.render(None, &|_| {})?;
            Ok((p.variant().name(), r))
        });
    match rendered {
        Ok((variant, r)) => {
            if let Err(e) = io::write(&a.out.join(IMAGE), &r.image, false) {
                return errored(device, e.to_string());
            }
            ProbeReport {
                device,
                seen: Seen::Rendered {
                    variant: Some(variant),
                    seconds: r.times.total_s(),
                    driver_compile_s: r.times.setup.driver_compile_s,
                },
            }
        }
        Err(e) => failed(device, seen_of(e)),
    }
}

/// A probe that went wrong for a reason of glint's or the input's.
fn errored(device: Option<Identity>, message: String) -> ProbeReport {
    failed(device, Seen::Error { message })
}

fn failed(device: Option<Identity>, seen: Seen) -> ProbeReport {
    ProbeReport { device, seen }
}

/// Whether opening the renderer failed the way a driver says it offers
/// nothing glint can use: no device, or a Vulkan result that means so.
/// A lost device or an unlisted result there is a fault (`seen_of`).
fn refuses_to_open(e: &GpuError) -> bool {
    use ash::vk::Result as R;
    match e {
        GpuError::NoDevice | GpuError::NoLoader(_) | GpuError::NoMatchingDevice { .. } => true,
        GpuError::Vk { result, .. } => [
            R::ERROR_INCOMPATIBLE_DRIVER,
            R::ERROR_INITIALIZATION_FAILED,
            R::ERROR_EXTENSION_NOT_PRESENT,
            R::ERROR_FEATURE_NOT_PRESENT,
            R::ERROR_LAYER_NOT_PRESENT,
        ]
        .iter()
        .any(|r| r.as_raw() == result.code),
        _ => false,
    }
}

/// Sorts the renderer's errors into what the matrix reports. A Vulkan
/// error is a driver's fault unless it is running out of memory, which a
/// correct driver may do (a limit, so refused); so are an unwritten or
/// garbled image (these were "error", glint's own).
fn seen_of(e: GpuError) -> Seen {
    use ash::vk::Result as R;
    let message = e.to_string();
    match e {
        GpuError::LoopBudget { .. } | GpuError::Unsupported(_) => Seen::Refused { message },
        GpuError::Timeout { .. } | GpuError::CompileTimeout { .. } | GpuError::Lost => {
            Seen::Hung { message }
        }
        GpuError::Validation(messages) => Seen::Validation { messages },
        GpuError::NoDevice | GpuError::NoLoader(_) | GpuError::NoMatchingDevice { .. } => {
            Seen::NoDevice { message }
        }
        GpuError::Vk { ref result, .. }
            if [R::ERROR_OUT_OF_HOST_MEMORY, R::ERROR_OUT_OF_DEVICE_MEMORY]
                .iter()
                .any(|r| r.as_raw() == result.code) =>
        {
            Seen::Refused { message }
        }
        GpuError::Vk { .. } | GpuError::Unwritten { .. } | GpuError::Garbled { .. } => {
            Seen::Fault { message }
        }
        _ => Seen::Error { message },
    }
}

/// A probe to run in a child: the ICD file, the scene's arguments and the
/// device arguments, as words of a command line.
pub struct Job<'a> {
    pub icd: &'a Path,
    pub args: Vec<std::ffi::OsString>,
    pub out: PathBuf,
    pub deadline: Duration,
}

impl Job<'_> {
    /// The command that runs the probe.
    fn command(&self) -> anyhow::Result<Command> {
        let mut c = on_driver(self.icd)?;
        c.arg("driver-probe")
            .arg("--out")
            .arg(&self.out)
            .args(&self.args)
            .env(
                "GLINT_VALIDATION",
                if validation_layer() { "1" } else { "0" },
            );
        Ok(c)
    }

    /// Runs the probe and waits for it, at most `deadline`.
    pub fn run(&self) -> anyhow::Result<Ended> {
        glint::output::interrupt::create_dir_all(&self.out)
            .with_context(|| format!("cannot create {}", self.out.display()))?;
        let report = self.out.join(REPORT);
        let _ = std::fs::remove_file(&report);
        let stderr_path = self.out.join("stderr.txt");
        let start = Instant::now();
        let status = match bounded(self.command()?, &stderr_path, self.deadline)? {
            Some(s) => s,
            None => {
                return Ok(Ended::Hung {
                    seconds: start.elapsed().as_secs_f64(),
                })
            }
        };
        if status.success() {
            if let Ok(text) = std::fs::read_to_string(&report) {
                if let Ok(probe) = serde_json::from_str(&text) {
                    return Ok(Ended::Wrote(probe));
                }
            }
        }
        use std::os::unix::process::ExitStatusExt;
        Ok(Ended::Crashed {
            signal: status.signal(),
            status: status.to_string(),
            stderr: tail(&stderr_path),
        })
    }
}

/// A child glint that sees the driver of `icd` alone, its stdin and stdout
/// closed: both names, VK_DRIVER_FILES for current loaders and
/// VK_ICD_FILENAMES for older ones, and no filter of the user's that could
/// hide it; the device is the first the ICD offers.
pub fn on_driver(icd: &Path) -> anyhow::Result<Command> {
    let exe = std::env::current_exe().context("cannot find glint's own executable")?;
    // A driver of another system's tree: glint through that tree's loader
    // (`glint::drivers::tree`).
    let mut c = match glint::drivers::tree::root_of(icd) {
        Some(root) => {
            let mut words = glint::drivers::tree::launcher(&root).into_iter();
            let mut c = Command::new(words.next().expect("the loader"));
            c.args(words).arg(exe);
            c
        }
        None => Command::new(exe),
    };
    c.env("VK_DRIVER_FILES", icd)
        .env("VK_ICD_FILENAMES", icd)
        .env_remove("VK_LOADER_DRIVERS_SELECT")
        .stdin(Stdio::null())
        .stdout(Stdio::null());
    Ok(c)
}

/// Runs `c` with its stderr into the file `stderr`, and waits for it at
/// most `limit`: its status, or None where it ran past that and was killed.
pub fn bounded(
    mut c: Command,
    stderr: &Path,
    limit: Duration,
) -> anyhow::Result<Option<ExitStatus>> {
    let file = std::fs::File::create(stderr)
        .with_context(|| format!("cannot create {}", stderr.display()))?;
    let mut child =
        glint::output::interrupt::spawn(c.stderr(file)).context("cannot start a child glint")?;
    wait(&mut child, limit)
}

/// Waits for `child` (started by `interrupt::spawn`) at most `limit`;
/// kills it and returns None past that. Until it is reaped, an interrupted
/// run kills it (`interrupt`).
fn wait(child: &mut Child, limit: Duration) -> anyhow::Result<Option<ExitStatus>> {
    let pid = child.id();
    let status = wait_for(child, limit);
    glint::output::interrupt::child_ended(pid);
    status
}

fn wait_for(child: &mut Child, limit: Duration) -> anyhow::Result<Option<ExitStatus>> {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().context("cannot wait for a child glint")? {
            return Ok(Some(status));
        }
        if start.elapsed() >= limit {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The last lines of a child's stderr, for the table and the reproducer.
fn tail(path: &Path) -> String {
    let text = std::fs::read(path).unwrap_or_default();
    let text = String::from_utf8_lossy(&text[text.len().saturating_sub(4000)..]).into_owned();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    lines[lines.len().saturating_sub(5)..].join("\n")
}

/// Whether the Khronos validation layer is installed where the loader
/// finds it: then every probe runs under it, and a message is a result.
/// Asked of the loader, once (three fixed folders were guessed, and with
/// $XDG_DATA_DIRS elsewhere every child then failed asking for a layer its
/// loader could not find). Without it the probes run without validation,
/// and the tables say so.
pub fn validation_layer() -> bool {
    static HAS: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *HAS.get_or_init(|| glint::gpu::validation_layer_installed().unwrap_or(false))
}
