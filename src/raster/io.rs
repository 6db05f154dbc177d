//! PNG, PFM and EXR files (docs/scene-format.md, Outputs). Writes go
//! through [`crate::output`]: to a temporary file beside the target, renamed
//! over it, so a failed run leaves the old file whole.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

pub use super::pfm::read_pfm;
use super::pfm::{pfm_header, write_pfm, Kind};
use super::{quantize_pixels, Image};
use crate::input::{MAX_PIXELS, MAX_SIDE};
use crate::output::{self, OutputError, Outputs, TargetKind};

/// An image file that cannot be read or written; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImageIoError {
    /// An image whose pixels do not fit in this process's memory.
    #[error(transparent)]
    TooLarge(super::memory::TooLarge),
    /// An extension other than .png, .pfm and .exr.
    #[error("{}: unsupported image type (expected .png, .pfm or .exr)", crate::printable::path(.0))]
    Format(PathBuf),
    // Causes are part of the message rather than a `source`, so that a
    // report of the error chain does not print them twice.
    /// The file system refused.
    #[error("{}: {cause}", crate::printable::path(path))]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        cause: std::io::Error,
    },
    /// The PNG or EXR codec refused.
    #[error("{}: {cause}", crate::printable::path(path))]
    Codec {
        /// The file.
        path: PathBuf,
        /// What the codec said.
        cause: image::ImageError,
    },
    /// A file whose content is another format than its extension names:
    /// decoded by its content and read as its name says, its values would
    /// take the wrong colour curve.
    #[error(
        "{}: its content is {content}, not the {named} its extension names: rename it, or \
         convert it",
        crate::printable::path(path)
    )]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// The format its extension names.
        named: &'static str,
        /// The format of its content.
        content: String,
    },
    /// An EXR with more channels than glint decodes: each channel of a
    /// block is inflated before the unused ones are dropped (4,000
    /// channels took 48 s).
    #[error(
        "{}: has {count} channels, more than the {MAX_EXR_CHANNELS} glint decodes (it reads R, G \
         and B): keep those in the file",
        crate::printable::path(path)
    )]
    Channels {
        /// The file.
        path: PathBuf,
        /// Its largest layer's channels.
        count: usize,
    },
    /// A PFM file that breaks the format.
    #[error("{}: not a valid PFM file: {reason}", crate::printable::path(path))]
    BadPfm {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A one-channel image and a file that cannot hold one (a PNG), or
    /// a file of more channels read as one.
    #[error(
        "{}: a one-channel image (depth, ray counts) is a .pfm or .exr file of one channel",
        crate::printable::path(.0)
    )]
    OneChannel(PathBuf),
    /// An output that may not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// An image file's format, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// 8-bit sRGB (or linear, as the scene says); values are clamped to 0..1.
    Png,
    /// 32-bit float, linear, uncompressed.
    Pfm,
    /// 32-bit float, linear, OpenEXR.
    Exr,
}

impl Format {
    /// The format `path` names by its extension (in any case).
    pub fn of(path: &Path) -> Result<Format, ImageIoError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("pfm") => Ok(Format::Pfm),
            Some("exr") => Ok(Format::Exr),
            _ => Err(ImageIoError::Format(path.to_owned())),
        }
    }

    /// The format an output at `path` is written in: by its extension, or
    /// PNG (the default output) where `path` is a character device or FIFO
    /// whose name has none (`-o /dev/null`, `-o /dev/stdout`).
    pub fn of_output(path: &Path) -> Result<Format, ImageIoError> {
        let streamed =
            || path.extension().is_none() && output::target_kind(path) == Some(TargetKind::Stream);
        match Format::of(path) {
            Err(_) if streamed() => Ok(Format::Png),
            other => other,
        }
    }
}

/// The `ImageIoError::Io` of `path`, for `map_err`.
pub fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ImageIoError + '_ {
    move |cause| ImageIoError::Io {
        path: path.to_owned(),
        cause,
    }
}

/// Writes `img` to `path` in the format its extension names, refusing a
/// read-only file (see `write_forced`).
pub fn write(path: &Path, img: &Image, srgb: bool) -> Result<(), ImageIoError> {
    write_forced(path, img, srgb, false)
}

/// Writes `img` to `path` at once, as [`stage`] and a commit do. An
/// existing read-only target is refused unless `force`.
pub fn write_forced(path: &Path, img: &Image, srgb: bool, force: bool) -> Result<(), ImageIoError> {
    let mut outputs = Outputs::new::<&Path>([], force);
    stage(&mut outputs, path, img, srgb)?;
    Ok(outputs.commit()?)
}

/// Stages `img` as the output `path` of `outputs`, in the format
/// `Format::of_output` names. Where `path` is a symbolic link, the file
/// it points to is replaced at the commit and the link stays; the new file
/// keeps the old one's permissions. Other hard links to the old file keep
/// the old image: a rename replaces a name, not the file's contents.
pub fn stage(
    outputs: &mut Outputs,
    path: &Path,
    img: &Image,
    srgb: bool,
) -> Result<(), ImageIoError> {
    let format = Format::of_output(path)?;
    outputs.stage(path, |out: &mut dyn Write| match format {
        Format::Png => write_png(out, img, srgb, path),
        Format::Pfm => write_pfm(out, img).map_err(io_err(path)),
        Format::Exr => write_exr(out, img, path),
    })
}

/// `img` as the PNG that `render -o x.png` writes, in memory.
pub fn png_bytes(img: &Image, srgb: bool) -> Vec<u8> {
    let mut out = Vec::new();
    // Writing to memory fails only where the encoder refuses the size,
    // which no image glint makes has.
    write_png(&mut out, img, srgb, Path::new("(in memory)")).expect("a PNG in memory");
    out
}

fn write_png(
    out: &mut dyn Write,
    img: &Image,
    srgb: bool,
    path: &Path,
) -> Result<(), ImageIoError> {
    let bytes = quantize_pixels(&img.pixels, srgb);
    let encoder = image::codecs::png::PngEncoder::new(out);
    image::ImageEncoder::write_image(
        encoder,
        &bytes,
        img.width,
        img.height,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|cause| ImageIoError::Codec {
        path: path.to_owned(),
        cause,
    })
}

fn write_exr(out: &mut dyn Write, img: &Image, path: &Path) -> Result<(), ImageIoError> {
    let floats: Vec<f32> = img.pixels.iter().flatten().copied().collect();
    let buffer = image::Rgb32FImage::from_raw(img.width, img.height, floats)
        .expect("buffer size matches image");
    let mut seekable = std::io::Cursor::new(Vec::new());
    buffer
        .write_to(&mut seekable, image::ImageFormat::OpenExr)
        .map_err(|cause| ImageIoError::Codec {
            path: path.to_owned(),
            cause,
        })?;
    out.write_all(seekable.get_ref()).map_err(io_err(path))
}

/// Reads a PNG, PFM or EXR file as linear values: a PNG is sRGB-encoded
/// (docs/scene-format.md, Colour), so its levels are decoded; PFM and EXR
/// hold linear values as they are.
pub fn read(path: &Path) -> Result<Image, ImageIoError> {
    read_as(path, true)
}

/// Reads a PNG, PFM or EXR file; a PNG's levels are decoded from sRGB
/// where `srgb`, else read as level/255 (a tile written with `srgb =
/// false`, a texture that decodes itself).
pub fn read_as(path: &Path, srgb: bool) -> Result<Image, ImageIoError> {
    let mut image = read_levels(path)?;
    if srgb && Format::of(path)? == Format::Png {
        for p in &mut image.pixels {
            *p = p.map(super::srgb_decode_level);
        }
    }
    Ok(image)
}

/// Reads a PNG (as level/255, no curve undone), PFM or EXR file.
fn read_levels(path: &Path) -> Result<Image, ImageIoError> {
    let format = Format::of(path)?;
    match format {
        Format::Pfm => {
            let bytes = pfm_file(path, Kind::Colour)?;
            read_pfm(&bytes).map_err(|reason| ImageIoError::BadPfm {
                path: path.to_owned(),
                reason,
            })
        }
        Format::Png | Format::Exr => {
            // The header is read once, within `HEADER_BYTES` (a colour
            // profile that inflates to gigabytes is dropped there); the
            // pixels may then take the image's own size, 16 bytes a pixel
            // (its widest form), and `HEADER_BYTES` more.
            let codec = |cause| ImageIoError::Codec {
                path: path.to_owned(),
                cause,
            };
            let mut decoder = reader_of(path, format)?.into_decoder().map_err(codec)?;
            let (w, h) = image::ImageDecoder::dimensions(&decoder);
            // The decode (16 bytes a pixel at most) and the image.
            fits(path, w, h, 16 + 12)?;
            let pixels = (u64::from(w) * u64::from(h)).min(MAX_PIXELS);
            let mut bound = limits(pixels * 16 + HEADER_BYTES);
            bound
                .reserve(image::ImageDecoder::total_bytes(&decoder))
                .map_err(codec)?;
            image::ImageDecoder::set_limits(&mut decoder, bound).map_err(codec)?;
            let decoded = image::DynamicImage::from_decoder(decoder).map_err(codec)?;
            // Straight into the image's pixels: a float copy of the whole
            // decode first would hold every pixel twice more (12 bytes each).
            let (w, h) = (decoded.width(), decoded.height());
            let pixels = match decoded {
                image::DynamicImage::ImageRgb8(rgb) => rgb
                    .pixels()
                    .map(|p| p.0.map(|c| f32::from(c) / 255.0))
                    .collect(),
                image::DynamicImage::ImageRgb32F(rgb) => rgb.pixels().map(|p| p.0).collect(),
                other => other.to_rgb32f().pixels().map(|p| p.0).collect(),
            };
            Ok(Image::new(w, h, pixels))
        }
    }
}

/// The bytes of the PFM file of `kind` at `path`, read within what its
/// header promises: a 1x1 header over a gigabyte is refused once 14 bytes
/// are read, not the gigabyte, and an image that does not fit in memory
/// before its pixels are read.
pub(super) fn pfm_file(path: &Path, kind: Kind) -> Result<Vec<u8>, ImageIoError> {
    let bad = |reason| ImageIoError::BadPfm {
        path: path.to_owned(),
        reason,
    };
    let mut file = crate::input::open(path, crate::input::ReadAs::Pfm).map_err(io_err(path))?;
    let mut bytes = Vec::new();
    (&mut file)
        .take(128)
        .read_to_end(&mut bytes)
        .map_err(io_err(path))?;
    let (w, h, _, pos) = pfm_header(&bytes, kind).map_err(bad)?;
    // The bytes and the image made of them.
    let pixel = 4 * kind.channels() as u64;
    fits(path, w, h, 2 * pixel)?;
    // The pixels the header promises and one byte more, which shows any
    // excess.
    let want = pos as u64 + u64::from(w) * u64::from(h) * pixel;
    file.take((want + 1).saturating_sub(bytes.len() as u64))
        .read_to_end(&mut bytes)
        .map_err(io_err(path))?;
    if bytes.len() as u64 > want {
        return Err(bad(format!(
            "the file is longer than the {w}x{h} pixels its header promises ({want} bytes)"
        )));
    }
    Ok(bytes)
}

/// Refuses to read `path`, a `w`×`h` image, where `per_pixel` bytes a
/// pixel do not fit in this process's memory (a 783 KB PNG that
/// declares 16384² aborted the Python interpreter).
pub(super) fn fits(path: &Path, w: u32, h: u32, per_pixel: u64) -> Result<(), ImageIoError> {
    let pixels = (u64::from(w) * u64::from(h)).min(MAX_PIXELS);
    super::memory::check(
        || {
            format!(
                "{}: reading its {w}x{h} pixels",
                crate::printable::path(path)
            )
        },
        pixels * per_pixel,
    )
    .map_err(ImageIoError::TooLarge)
}

/// The most channels an EXR layer may have: RGBA and a few more (depth,
/// normals, ids) that renderers write beside them.
pub const MAX_EXR_CHANNELS: usize = 64;

/// What a decoder may allocate besides the pixels: a header, chunks such as
/// a colour profile.
const HEADER_BYTES: u64 = 16 << 20;

/// A decoder's limits: images up to `MAX_SIDE` a side, `max_alloc` bytes.
fn limits(max_alloc: u64) -> image::Limits {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(max_alloc);
    limits
}

/// A decoder of the PNG or EXR at `path`, once its content is found to be
/// the format its extension names (`format`).
fn reader_of(
    path: &Path,
    format: Format,
) -> Result<image::ImageReader<std::io::BufReader<std::fs::File>>, ImageIoError> {
    // A FIFO would block the open, a device never end.
    crate::input::check(path, crate::input::ReadAs::Image).map_err(io_err(path))?;
    let mut reader = image::ImageReader::open(path)
        .map_err(io_err(path))?
        .with_guessed_format()
        .map_err(io_err(path))?;
    // Reading the header alone allocates no pixels.
    reader.limits(limits(HEADER_BYTES));
    let (named, want) = match format {
        Format::Png => ("PNG", image::ImageFormat::Png),
        _ => ("OpenEXR", image::ImageFormat::OpenExr),
    };
    // Content the decoder does not know keeps the extension's format, and
    // its decode fails on its own.
    match reader.format() {
        Some(found) if found != want => {
            return Err(ImageIoError::Mismatch {
                path: path.to_owned(),
                named,
                content: format!("{found:?}"),
            })
        }
        // A header that does not read is the decoder's to report.
        Some(image::ImageFormat::OpenExr) => {
            if let Ok(meta) = exr::meta::MetaData::read_from_file(path, false) {
                let count = meta.headers.iter().map(|h| h.channels.list.len()).max();
                if let Some(count) = count.filter(|&c| c > MAX_EXR_CHANNELS) {
                    return Err(ImageIoError::Channels {
                        path: path.to_owned(),
                        count,
                    });
                }
            }
        }
        _ => {}
    }
    Ok(reader)
}

/// An image file's width and height, from its header alone: `diff`
/// compares them before it decodes either image.
pub fn dimensions(path: &Path) -> Result<(u32, u32), ImageIoError> {
    match Format::of(path)? {
        Format::Pfm => {
            // The header fits in 4 tokens of at most 16 characters each.
            let mut head = Vec::new();
            crate::input::open(path, crate::input::ReadAs::Pfm)
                .and_then(|f| f.take(128).read_to_end(&mut head))
                .map_err(io_err(path))?;
            let (w, h, _, _) =
                pfm_header(&head, Kind::Colour).map_err(|reason| ImageIoError::BadPfm {
                    path: path.to_owned(),
                    reason,
                })?;
            Ok((w, h))
        }
        format @ (Format::Png | Format::Exr) => {
            reader_of(path, format)?
                .into_dimensions()
                .map_err(|cause| ImageIoError::Codec {
                    path: path.to_owned(),
                    cause,
                })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Image {
        let pixels = (0..6)
            .map(|i| [i as f32, -(i as f32) * 1e30, f32::MIN_POSITIVE])
            .collect();
        Image::new(3, 2, pixels)
    }

    #[test]
    fn pfm_round_trips_exactly_hdr_values_included() {
        let img = sample();
        let mut bytes = Vec::new();
        write_pfm(&mut bytes, &img).unwrap();
        assert_eq!(read_pfm(&bytes).unwrap(), img);
    }

    #[test]
    fn pfm_rows_run_bottom_to_top() {
        let img = sample();
        let mut bytes = Vec::new();
        write_pfm(&mut bytes, &img).unwrap();
        let header = b"PF\n3 2\n-1.0\n".len();
        let first = f32::from_le_bytes(bytes[header..header + 4].try_into().unwrap());
        assert_eq!(first, img.get(0, 1)[0]);
    }

    #[test]
    fn big_endian_pfm_reads_too() {
        let mut bytes = b"PF\n1 1\n1.0\n".to_vec();
        for v in [0.5f32, 1.5, 2.5] {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        assert_eq!(read_pfm(&bytes).unwrap().pixels, vec![[0.5, 1.5, 2.5]]);
    }

    /// A PFM's header is checked before its pixels are read: a 1x1 header
    /// over a gigabyte (sparse) is refused after a few bytes.
    #[test]
    fn a_pfm_longer_than_its_header_is_refused_unread() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("long.pfm");
        std::fs::write(&path, b"PF\n1 1\n-1\n").unwrap();
        std::fs::OpenOptions::new()
            .write(true)
            .open(&path)
            .unwrap()
            .set_len(1 << 30)
            .unwrap();
        let start = std::time::Instant::now();
        let err = read(&path).unwrap_err().to_string();
        assert!(err.contains("longer than the 1x1 pixels"), "{err}");
        assert!(start.elapsed() < std::time::Duration::from_secs(1));
        // One whole pixel, and one short of it, as before.
        let mut whole = b"PF\n1 1\n-1\n".to_vec();
        whole.extend([0u8; 12]);
        std::fs::write(&path, &whole).unwrap();
        assert_eq!(read(&path).unwrap().pixels, vec![[0.0; 3]]);
        std::fs::write(&path, &whole[..whole.len() - 1]).unwrap();
        assert!(read(&path)
            .unwrap_err()
            .to_string()
            .contains("expected 12 bytes"));
    }

    #[test]
    fn crafted_pfm_sizes_are_errors_not_panics() {
        for header in [
            "PF\n2147483648 2147483648\n-1.0\n",
            "PF\n4294967295 4294967295\n-1.0\n",
            "PF\n1431655766 1\n-1.0\n",
            "PF\n65537 1\n-1.0\n",
            "PF\n65536 65536\n-1.0\n",
            "PF\n0 5\n-1.0\n",
        ] {
            let err = read_pfm(header.as_bytes()).unwrap_err();
            assert!(
                err.contains("size") || err.contains("bad"),
                "{header}: {err}"
            );
        }
    }

    #[test]
    fn a_pfm_scale_of_nan_or_zero_has_no_byte_order() {
        for scale in ["nan", "0", "-0.0", "inf"] {
            let mut bytes = format!("PF\n1 1\n{scale}\n").into_bytes();
            bytes.extend_from_slice(&[0; 12]);
            assert!(
                read_pfm(&bytes).unwrap_err().contains("bad scale"),
                "{scale}"
            );
        }
    }

    #[test]
    fn truncated_pfm_is_an_error() {
        let mut bytes = Vec::new();
        write_pfm(&mut bytes, &sample()).unwrap();
        bytes.pop();
        assert!(read_pfm(&bytes).unwrap_err().contains("expected"));
        assert!(read_pfm(b"P6\n1 1\n255\n").is_err());
    }

    #[test]
    fn a_failed_write_leaves_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        std::fs::write(&path, b"old").unwrap();
        // A PNG of a zero-sized image is refused by the encoder.
        let empty = Image {
            width: 0,
            height: 0,
            pixels: Vec::new(),
        };
        assert!(write(&path, &empty, false).is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
