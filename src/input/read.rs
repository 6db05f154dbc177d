//! How glint reads a file (docs/guarantees.md, Reads): only a regular file
//! (a FIFO could block forever, a device such as /dev/zero never ends),
//! and never more than the bound of its kind, checked against the file's
//! size before anything is allocated and enforced while reading, so that a
//! file that grows meanwhile stops at the bound too.

use std::io::Read;
use std::path::Path;

/// The largest image any reader accepts: a side of 65,536 pixels and 2^28
/// pixels in all (16384², the largest image glint renders), so that a
/// crafted header can neither overflow the size arithmetic nor ask for
/// more memory than such an image takes (3 GiB of f32 RGB).
pub const MAX_SIDE: u32 = 1 << 16;
/// The most pixels in all (see `MAX_SIDE`).
pub const MAX_PIXELS: u64 = 1 << 28;

/// What a file is read as, and how large it may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadAs {
    /// A TOML or NFF scene: 256 MiB (the largest scene in the repository,
    /// the level-4 sphereflake, is 0.8 MB; a million spheres are 100 MB).
    Scene,
    /// An OBJ mesh: 256 MiB.
    Mesh,
    /// A tile's sidecar: 1 MiB.
    Sidecar,
    /// A Vulkan driver's manifest (an ICD's JSON file): 1 MiB (Mesa's
    /// are under 200 bytes).
    Manifest,
    /// A shader source (`--shader`, a file in an `-I` folder): 16 MiB
    /// (glint's own together are 0.2 MB).
    Shader,
    /// A PFM image: the largest image any reader accepts
    /// (`MAX_PIXELS`, 12 bytes a pixel) and its header.
    Pfm,
    /// A PNG or EXR image, whose decoder bounds its own allocations
    /// (`image::Limits`): a regular file of any size.
    Image,
}

impl ReadAs {
    /// The most bytes a file of this kind may have.
    pub const fn limit(self) -> u64 {
        match self {
            ReadAs::Scene | ReadAs::Mesh => 256 << 20,
            ReadAs::Sidecar | ReadAs::Manifest => 1 << 20,
            ReadAs::Shader => 16 << 20,
            ReadAs::Pfm => MAX_PIXELS * 12 + 4096,
            ReadAs::Image => u64::MAX >> 1,
        }
    }

    fn name(self) -> &'static str {
        match self {
            ReadAs::Scene => "a scene file",
            ReadAs::Mesh => "a mesh file",
            ReadAs::Sidecar => "a sidecar",
            ReadAs::Manifest => "a driver manifest",
            ReadAs::Shader => "a shader file",
            ReadAs::Pfm | ReadAs::Image => "an image",
        }
    }
}

/// Fails unless `path` is a regular file of at most `kind`'s bound.
pub fn check(path: &Path, kind: ReadAs) -> std::io::Result<()> {
    let (limit, what) = (kind.limit(), kind.name());
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::other(format!(
            "is {}, not a regular file ({what} is read from a regular file only)",
            file_type(&meta)
        )));
    }
    let too_large = |size: u64| {
        std::io::Error::other(format!(
            "is {size} bytes, over the {} MiB that {what} may have",
            limit >> 20
        ))
    };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    Ok(())
}

/// Opens `path` for reading as `kind` (see `check`); the reader fails past
/// the bound.
pub fn open(path: &Path, kind: ReadAs) -> std::io::Result<impl Read> {
    check(path, kind)?;
    let file = std::fs::File::open(path)?;
    Ok(Bounded {
        inner: file.take(kind.limit() + 1),
        limit: kind.limit(),
        read: 0,
        what: kind.name(),
    })
}

/// `path`'s bytes, read as `kind`.
pub fn read(path: &Path, kind: ReadAs) -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    open(path, kind)?.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// `path`'s text (UTF-8), read as `kind`.
pub fn read_text(path: &Path, kind: ReadAs) -> std::io::Result<String> {
    String::from_utf8(read(path, kind)?)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()))
}

/// A reader that fails once it has passed its limit.
struct Bounded<R> {
    inner: std::io::Take<R>,
    limit: u64,
    read: u64,
    what: &'static str,
}

impl<R: Read> Read for Bounded<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read += n as u64;
        if self.read > self.limit {
            return Err(std::io::Error::other(format!(
                "grew past the {} MiB that {} may have while it was read",
                self.limit >> 20,
                self.what
            )));
        }
        Ok(n)
    }
}

fn file_type(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_fifos_and_directories_are_refused_and_sizes_bounded() {
        let dir = tempfile::tempdir().unwrap();
        let e = read(Path::new("/dev/zero"), ReadAs::Scene).unwrap_err();
        assert!(e.to_string().contains("a character device"), "{e}");
        let e = read(dir.path(), ReadAs::Mesh).unwrap_err();
        assert!(e.to_string().contains("a directory"), "{e}");
        let fifo = dir.path().join("pipe");
        if std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success())
        {
            // Refused without opening it: an open would wait for a writer.
            let e = read(&fifo, ReadAs::Scene).unwrap_err();
            assert!(e.to_string().contains("a FIFO"), "{e}");
        }
        let big = dir.path().join("big.json");
        std::fs::write(&big, vec![b' '; (ReadAs::Sidecar.limit() + 1) as usize]).unwrap();
        let e = read(&big, ReadAs::Sidecar).unwrap_err();
        assert!(e.to_string().contains("over the 1 MiB"), "{e}");
        let ok = dir.path().join("ok.json");
        std::fs::write(&ok, "{}").unwrap();
        assert_eq!(read_text(&ok, ReadAs::Sidecar).unwrap(), "{}");
    }
}
