//! A reproducer for each failure, in its own folder: what a driver's bug
//! tracker asks for (docs/drivers.md, Reproducers). The image is first
//! shrunk while the failure stays the same.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::raster::{diff, io, Image};
use crate::scene::{Overrides, Scene};

use super::error::{write as write_file, DriversError};
use super::probe::Identity;
use super::verdict::Verdict;

/// The size a reproducer renders at, and its samples where shrinking set
/// them (None: the scene's own sampling, adaptive or uniform).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Size {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Samples a pixel side, where shrinking set them.
    pub samples: Option<u32>,
}

impl Size {
    /// The scene's own size and sampling.
    pub fn of(scene: &Scene) -> Self {
        Self {
            width: scene.width,
            height: scene.height,
            samples: None,
        }
    }

    /// The next smaller size to try for `scene`: half the image down to 8
    /// pixels a side, then one sample a pixel; None where nothing is left.
    pub fn smaller(self, scene: &Scene) -> Option<Self> {
        if self.width >= 16 && self.height >= 16 {
            Some(Self {
                width: self.width / 2,
                height: self.height / 2,
                ..self
            })
        } else if self.samples.is_none() && scene.samples > 1 {
            Some(Self {
                samples: Some(1),
                ..self
            })
        } else {
            None
        }
    }

    /// The scene's overrides for this size.
    pub fn overrides(self) -> Overrides {
        Overrides {
            width: Some(self.width),
            height: Some(self.height),
            samples: self.samples,
            max_depth: None,
        }
    }

    /// As arguments of `glint compare` and `render`.
    pub fn args(self) -> Vec<String> {
        let mut v = vec![
            "--width".into(),
            self.width.to_string(),
            "--height".into(),
            self.height.to_string(),
        ];
        if let Some(n) = self.samples {
            v.extend(["--samples".into(), n.to_string()]);
        }
        v
    }

    /// `64x48` and the samples where set.
    pub fn describe(self) -> String {
        match self.samples {
            Some(n) => format!("{}x{}, {n}x{n} samples a pixel", self.width, self.height),
            None => format!("{}x{}, the scene's own sampling", self.width, self.height),
        }
    }
}

/// What one reproducer holds.
pub struct Failure<'a> {
    /// The scene as the run named it.
    pub scene_path: &'a Path,
    /// The driver's ICD file.
    pub icd: &'a Path,
    /// The device the driver named.
    pub identity: &'a Identity,
    /// What was wrong.
    pub verdict: &'a Verdict,
    /// The size it fails at (after shrinking).
    pub size: Size,
    /// The run's own device options, as words (`DeviceArgs::forward`).
    pub device_args: &'a [std::ffi::OsString],
    /// The driver's image, where it made one.
    pub gpu: Option<&'a Image>,
    /// The CPU f64 image.
    pub reference: &'a Image,
    /// The child's stderr, where it crashed or hung.
    pub stderr: Option<&'a Path>,
    /// The size the failure was first seen at.
    pub first_size: Size,
    /// The scene's objects before and after shrinking, where it was.
    pub objects: Option<(usize, usize)>,
}

/// Writes `f`'s reproducer into `dir`, beside the scene's copy there
/// (`copy_scene`); the shader variant comes from `shader_dump`, a function
/// that runs `glint shader dump` on the failing driver into the folder it
/// is given.
pub fn write(
    f: &Failure,
    dir: &Path,
    scene_copy: &Path,
    shader_dump: &dyn Fn(&Path, &Path) -> Result<(), String>,
) -> Result<(), DriversError> {
    let shader_dir = dir.join("shader");
    let shader = shader_dump(scene_copy, &shader_dir);
    if let Some(img) = f.gpu {
        io::write(&dir.join("gpu.pfm"), img, false)?;
        io::write(
            &dir.join("heat.png"),
            &diff::heat_map(img, f.reference)?,
            false,
        )?;
    }
    io::write(&dir.join("reference.pfm"), f.reference, false)?;
    if let Some(stderr) = f.stderr {
        let _ = std::fs::copy(stderr, dir.join("stderr.txt"));
    }
    let manifest = manifest_text(f.icd);
    let driver = serde_json::json!({
        "icd": f.icd,
        "icd_manifest": manifest,
        "device": f.identity,
    });
    write_file(
        &dir.join("driver.json"),
        serde_json::to_string_pretty(&driver)?,
    )?;
    let command = command_line(f, scene_copy);
    write_file(
        &dir.join("command.sh"),
        format!("#!/bin/sh\n# Run from this folder.\n{command}\n"),
    )?;
    write_file(&dir.join("README.md"), readme(f, &command, shader.err()))?;
    Ok(())
}

/// The reproducer of a driver that failed before it named a device (it
/// crashed or hung as the loader opened it): its manifest, its last words
/// and the command, in `dir`.
pub fn write_load(
    icd: &Path,
    verdict: &Verdict,
    stderr: &Path,
    dir: &Path,
) -> Result<(), DriversError> {
    crate::output::interrupt::create_dir_all(dir).map_err(DriversError::file("create", dir))?;
    let manifest = manifest_text(icd);
    let driver = serde_json::json!({ "icd": icd, "icd_manifest": manifest });
    write_file(
        &dir.join("driver.json"),
        serde_json::to_string_pretty(&driver)?,
    )?;
    let _ = std::fs::copy(stderr, dir.join("stderr.txt"));
    let absolute = std::path::absolute(icd).unwrap_or_else(|_| icd.to_owned());
    let command = format!(
        "VK_DRIVER_FILES={} {} info",
        quote(&absolute.to_string_lossy()),
        glint_on(icd)
    );
    write_file(&dir.join("command.sh"), format!("#!/bin/sh\n{command}\n"))?;
    let readme = format!(
        "# {}: {} when loaded\n\n- What went wrong: {}, before the driver named a device; no scene was rendered on it.\n- Files: `driver.json` (the ICD file and its manifest), `stderr.txt` (the process's last words).\n\nTo see it again:\n\n```\n{command}\n```\n",
        crate::printable::path(icd),
        verdict.word(),
        crate::printable::one_line(&verdict.detail())
    );
    write_file(&dir.join("README.md"), readme)?;
    Ok(())
}

/// Copies the scene and the files it reads into `dir`, each at its path
/// relative to the scene's folder where it is below it; the copy's path.
pub fn copy_scene(path: &Path, scene: &Scene, dir: &Path) -> Result<PathBuf, DriversError> {
    crate::output::interrupt::create_dir_all(dir).map_err(DriversError::file("create", dir))?;
    // A scene is read from a file, so its path has a name.
    let copy = dir.join(path.file_name().unwrap_or(path.as_os_str()));
    std::fs::copy(path, &copy).map_err(DriversError::file("copy", path))?;
    // Compared resolved, as the scene's own paths and the scene's folder
    // may be spelt differently ("s.toml" is in ".", and its "mesh.obj"
    // did not start with "./", so it was not copied).
    let resolved = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_owned());
    let home = resolved(crate::files::folder_of(path));
    for input in &scene.input_files {
        if let Ok(rel) = resolved(input).strip_prefix(&home) {
            let to = dir.join(rel);
            if let Some(parent) = to.parent() {
                crate::output::interrupt::create_dir_all(parent)
                    .map_err(DriversError::file("create", parent))?;
            }
            let _ = std::fs::copy(input, to);
        }
    }
    Ok(copy)
}

/// The line that shows the failure again: `glint compare` on the copy of
/// the scene, with the failing driver alone.
fn command_line(f: &Failure, scene_copy: &Path) -> String {
    // The manifest by its absolute path: the command runs from the
    // reproducer's folder, not where `drivers` ran.
    let icd = std::path::absolute(f.icd).unwrap_or_else(|_| f.icd.to_owned());
    let mut words = vec![format!("VK_DRIVER_FILES={}", quote(&icd.to_string_lossy()))];
    if let Ok(e) = std::env::var("GLINT_EXPERIMENT") {
        words.push(format!("GLINT_EXPERIMENT={}", quote(&e)));
    }
    words.push(format!("{} compare", glint_on(f.icd)));
    words.push(quote(
        &scene_copy
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    ));
    words.extend(f.size.args());
    words.extend(f.device_args.iter().map(|a| quote(&a.to_string_lossy())));
    words.join(" ")
}

/// How a command line runs glint on the driver of `icd`: `glint`, or for
/// a driver of another system's tree, glint through that tree's loader,
/// which takes the program by its path (`drivers::tree`).
fn glint_on(icd: &Path) -> String {
    match super::tree::root_of(icd) {
        Some(root) => {
            let launcher = super::tree::launcher(&root);
            let mut words: Vec<String> = launcher
                .iter()
                .map(|w| quote(&w.to_string_lossy()))
                .collect();
            words.push("\"$(command -v glint)\"".into());
            words.join(" ")
        }
        None => "glint".into(),
    }
}

/// A word as sh reads it.
fn quote(word: &str) -> String {
    if !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c))
    {
        word.to_owned()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

/// A name or a driver's words as the README shows them: control
/// characters escaped.
fn shown(s: &str) -> String {
    crate::printable::text(s)
}

fn readme(f: &Failure, command: &str, shader_problem: Option<String>) -> String {
    let mut r = String::new();
    let scene = f
        .scene_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let _ = writeln!(
        r,
        "# {} on {}: {}\n",
        shown(&scene),
        shown(&f.identity.name),
        f.verdict.word()
    );
    let _ = writeln!(
        r,
        "- Device: {} ({}), driver {}, Vulkan {}; ICD file `{}`.",
        shown(&f.identity.name),
        shown(&f.identity.kind),
        shown(&f.identity.driver),
        shown(&f.identity.api_version),
        crate::printable::path(f.icd)
    );
    let _ = writeln!(
        r,
        "- What went wrong: {}.",
        crate::printable::one_line(&f.verdict.detail())
    );
    if let Verdict::Fail { violations, .. } = f.verdict {
        let _ = writeln!(
            r,
            "- Held to `glint compare`'s tolerance against the CPU f64 reference: {}.",
            violations.join("; ")
        );
    }
    let shrunk = if f.size == f.first_size {
        String::new()
    } else {
        format!(
            " (first seen at {}; shrunk while it still failed the same way)",
            f.first_size.describe()
        )
    };
    let _ = writeln!(r, "- Size: {}{shrunk}.", f.size.describe());
    if let Some((before, after)) = f.objects.filter(|(b, a)| a < b) {
        let _ = writeln!(
            r,
            "- Objects: {after} of the scene's {before} primitives, meshes and lights, the rest left out while it still failed the same way."
        );
    }
    let _ = writeln!(r, "\nFiles: the scene ({scene}) and what it reads; `shader/`, the variant's GLSL and SPIR-V as `glint shader dump` writes them; `gpu.pfm` (the driver's image, where it made one), `reference.pfm` (CPU f64) and `heat.png` (their difference: black where they agree, blue to red to white from 1e-7 through 1/255 to 1); `driver.json` (the ICD and the device); `explain.txt` where the image is wrong (its worst pixel's ray tree on the driver beside the CPU's, down to the first number that differs, as `glint explain` prints it); `stderr.txt` where the process crashed or hung.");
    if let Some(p) = shader_problem {
        let _ = writeln!(r, "\nThe shader could not be dumped here: {p}");
    }
    let _ = writeln!(
        r,
        "\nTo see it again, from this folder:\n\n```\n{command}\n```"
    );
    r
}

/// A driver's manifest as the reproducer keeps it, read as every input is
/// (a regular file, at most 1 MiB): a FIFO or a link to /dev/zero among
/// the loader's folders would block the run or fill its memory. What
/// cannot be read is said in its place.
fn manifest_text(icd: &Path) -> String {
    crate::input::read_text(icd, crate::input::ReadAs::Manifest)
        .unwrap_or_else(|e| format!("(not read: {e})"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_shrink_to_eight_pixels_then_one_sample() {
        let mut scene = Scene::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/seed-fig3.toml"),
            &Overrides::default(),
        )
        .unwrap();
        scene.samples = 2;
        let mut s = Size {
            width: 64,
            height: 48,
            samples: None,
        };
        let mut seen = vec![];
        while let Some(t) = s.smaller(&scene) {
            seen.push((t.width, t.height, t.samples));
            s = t;
        }
        assert_eq!(
            seen,
            vec![(32, 24, None), (16, 12, None), (16, 12, Some(1))]
        );
    }

    /// A driver of another system's tree is run through its loader, the
    /// machine's own with the glint on the path.
    #[test]
    fn a_trees_driver_runs_glint_through_its_loader() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("sid");
        let icd = root.join("usr/share/vulkan/icd.d/lvp_icd.json");
        std::fs::create_dir_all(icd.parent().unwrap()).unwrap();
        std::fs::create_dir_all(root.join("lib64")).unwrap();
        std::fs::write(&icd, "{}").unwrap();
        std::fs::write(root.join(super::super::tree::LOADER), "").unwrap();
        let words = glint_on(&icd);
        assert!(
            words.starts_with(&format!(
                "{} --library-path ",
                root.join("lib64/ld-linux-x86-64.so.2").display()
            )),
            "{words}"
        );
        assert!(words.ends_with(" \"$(command -v glint)\""), "{words}");
        assert_eq!(
            glint_on(Path::new("/usr/share/vulkan/icd.d/lvp_icd.json")),
            "glint"
        );
    }

    #[test]
    fn words_are_quoted_for_sh() {
        assert_eq!(quote("/a/b-c.json"), "/a/b-c.json");
        assert_eq!(quote("it's here"), r"'it'\''s here'");
        assert_eq!(quote(""), "''");
    }
}
