//! One-channel images (an AOV's depth, a pixel's ray count): written and
//! read as a PFM of one channel (`Pf`) or an EXR of one channel `Y`. A
//! PNG has no float channel to hold a depth, so it is refused for them.

use std::io::{Read, Write};
use std::path::Path;

use super::io::{fits, io_err, pfm_file, Format, ImageIoError};
use super::memory::check_size;
use super::pfm::{read_values, write_values, Kind};

/// A one-channel image: `values` row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row by row, from the top.
    pub values: Vec<f32>,
}

/// Whether the PFM or EXR file at `path` holds one channel (a PNG never
/// does here: glint reads it as RGB).
pub fn is_plane(path: &Path) -> Result<bool, ImageIoError> {
    match Format::of(path)? {
        Format::Png => Ok(false),
        Format::Pfm => {
            let mut head = [0u8; 2];
            crate::input::open(path, crate::input::ReadAs::Pfm)
                .and_then(|mut f| f.read_exact(&mut head))
                .map_err(io_err(path))?;
            Ok(&head == b"Pf")
        }
        Format::Exr => {
            crate::input::check(path, crate::input::ReadAs::Image).map_err(io_err(path))?;
            let meta =
                exr::meta::MetaData::read_from_file(path, false).map_err(|e| exr_err(path, e))?;
            Ok(meta
                .headers
                .first()
                .is_some_and(|h| h.channels.list.len() == 1))
        }
    }
}

fn exr_err(path: &Path, e: exr::error::Error) -> ImageIoError {
    ImageIoError::Codec {
        path: path.to_owned(),
        cause: image::ImageError::Decoding(image::error::DecodingError::new(
            image::error::ImageFormatHint::Exact(image::ImageFormat::OpenExr),
            e.to_string(),
        )),
    }
}

/// Writes `plane` as `path`'s format names (PFM or EXR), whole or not at
/// all, as every output is.
pub fn write_plane(path: &Path, plane: &Plane) -> Result<(), ImageIoError> {
    let mut outputs = crate::output::Outputs::new::<&Path>([], false);
    stage_plane(&mut outputs, path, plane)?;
    Ok(outputs.commit()?)
}

/// Stages `plane` as the output `path` of `outputs` (PFM or EXR), to be
/// committed with the others.
pub fn stage_plane(
    outputs: &mut crate::output::Outputs,
    path: &Path,
    plane: &Plane,
) -> Result<(), ImageIoError> {
    let format = Format::of_output(path)?;
    if format == Format::Png {
        return Err(ImageIoError::OneChannel(path.to_owned()));
    }
    outputs.stage(path, |out: &mut dyn Write| match format {
        Format::Pfm => write_values(out, Kind::Plane, plane.width, plane.height, &plane.values)
            .map_err(io_err(path)),
        _ => write_exr(out, plane, path),
    })
}

fn write_exr(out: &mut dyn Write, p: &Plane, path: &Path) -> Result<(), ImageIoError> {
    use exr::prelude::*;
    let channel = AnyChannel::new("Y", FlatSamples::F32(p.values.clone()));
    let layer = Layer::new(
        Vec2(p.width as usize, p.height as usize),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    exr::prelude::Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| exr_err(path, e))?;
    out.write_all(bytes.get_ref()).map_err(io_err(path))
}

/// Reads the one-channel PFM or EXR at `path`, within what its header
/// promises and the memory there is, as a colour image is read.
pub fn read_plane(path: &Path) -> Result<Plane, ImageIoError> {
    let bad = |reason: String| ImageIoError::BadPfm {
        path: path.to_owned(),
        reason,
    };
    match Format::of(path)? {
        Format::Pfm => {
            let bytes = pfm_file(path, Kind::Plane)?;
            let (width, height, values) = read_values(&bytes, Kind::Plane).map_err(bad)?;
            Ok(Plane {
                width,
                height,
                values,
            })
        }
        Format::Exr => {
            crate::input::check(path, crate::input::ReadAs::Image).map_err(io_err(path))?;
            // The size from the header, checked before any pixel is read.
            let meta =
                exr::meta::MetaData::read_from_file(path, false).map_err(|e| exr_err(path, e))?;
            let size = meta
                .headers
                .first()
                .map_or((0, 0), |h| (h.layer_size.0, h.layer_size.1));
            let (w, h) = (
                u32::try_from(size.0).unwrap_or(u32::MAX),
                u32::try_from(size.1).unwrap_or(u32::MAX),
            );
            check_size(w, h)
                .map_err(|reason| exr_err(path, exr::error::Error::Invalid(reason.into())))?;
            // The decode (its widest samples, 4 bytes) and the plane.
            fits(path, w, h, 8)?;
            let image = exr::prelude::read_first_flat_layer_from_file(path)
                .map_err(|e| exr_err(path, e))?;
            let layer = image.layer_data;
            let [channel] = layer.channel_data.list.as_slice() else {
                return Err(ImageIoError::OneChannel(path.to_owned()));
            };
            let values = match &channel.sample_data {
                exr::prelude::FlatSamples::F16(v) => v.iter().map(|x| x.to_f32()).collect(),
                exr::prelude::FlatSamples::F32(v) => v.clone(),
                exr::prelude::FlatSamples::U32(v) => v.iter().map(|&x| x as f32).collect(),
            };
            Ok(Plane {
                width: w,
                height: h,
                values,
            })
        }
        Format::Png => Err(ImageIoError::OneChannel(path.to_owned())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Plane {
        Plane {
            width: 3,
            height: 2,
            values: vec![0.5, f32::INFINITY, 1e30, -2.0, 0.0, 7.25],
        }
    }

    #[test]
    fn a_plane_reads_back_as_written_in_pfm_and_exr() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["d.pfm", "d.exr"] {
            let path = dir.path().join(name);
            write_plane(&path, &sample()).unwrap();
            assert!(is_plane(&path).unwrap(), "{name}");
            assert_eq!(read_plane(&path).unwrap(), sample(), "{name}");
        }
        // The rows are bottom-up in a PFM: the first written is the last.
        let bytes = std::fs::read(dir.path().join("d.pfm")).unwrap();
        assert!(bytes.starts_with(b"Pf\n3 2\n-1.0\n"));
        assert_eq!(
            &bytes[bytes.len() - 12..bytes.len() - 8],
            &0.5f32.to_le_bytes()
        );
    }

    #[test]
    fn a_png_takes_no_plane_and_a_colour_file_is_no_plane() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("d.png");
        assert!(matches!(
            write_plane(&png, &sample()),
            Err(ImageIoError::OneChannel(_))
        ));
        assert!(!png.exists());
        let colour = dir.path().join("c.pfm");
        let image = crate::raster::Image::new(1, 1, vec![[1.0, 2.0, 3.0]]);
        crate::raster::io::write(&colour, &image, false).unwrap();
        assert!(!is_plane(&colour).unwrap());
        let exr = dir.path().join("c.exr");
        crate::raster::io::write(&exr, &image, false).unwrap();
        assert!(!is_plane(&exr).unwrap());
    }

    #[test]
    fn a_short_long_or_bad_pfm_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.pfm");
        write_plane(&path, &sample()).unwrap();
        let whole = std::fs::read(&path).unwrap();
        let mut longer = whole.clone();
        longer.push(0);
        for bytes in [
            &whole[..whole.len() - 1],
            &longer[..],
            b"Pf\n1 1\n0\n\0\0\0\0",
            b"PF\n1 1\n-1\n\0\0\0\0\0\0\0\0\0\0\0\0",
        ] {
            std::fs::write(&path, bytes).unwrap();
            assert!(read_plane(&path).is_err(), "{bytes:?}");
        }
    }
}
