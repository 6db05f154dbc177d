//! PFM files (Portable FloatMap): colour (`PF`, three floats a pixel) and
//! one channel (`Pf`, one float), written little-endian, read in either
//! byte order, rows bottom to top; `io` and `plane` read and write them
//! through these.

use std::io::Write;

use super::memory::check_size;
use super::Image;

/// The two kinds of PFM: their magic and their floats a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `PF`: red, green and blue.
    Colour,
    /// `Pf`: one channel.
    Plane,
}

impl Kind {
    fn magic(self) -> &'static str {
        match self {
            Kind::Colour => "PF",
            Kind::Plane => "Pf",
        }
    }

    /// Floats a pixel.
    pub(crate) fn channels(self) -> usize {
        match self {
            Kind::Colour => 3,
            Kind::Plane => 1,
        }
    }
}

/// Standard PFM: little-endian (scale -1.0), rows bottom to top.
pub(crate) fn write_pfm(out: &mut (impl Write + ?Sized), img: &Image) -> std::io::Result<()> {
    let values: &[f32] = bytemuck::cast_slice(&img.pixels);
    write_values(out, Kind::Colour, img.width, img.height, values)
}

/// `values` (row by row from the top, `kind.channels()` a pixel) as a PFM
/// of `kind`: little-endian, rows bottom to top.
pub(crate) fn write_values(
    out: &mut (impl Write + ?Sized),
    kind: Kind,
    width: u32,
    height: u32,
    values: &[f32],
) -> std::io::Result<()> {
    write!(out, "{}\n{width} {height}\n-1.0\n", kind.magic())?;
    for row in values
        .chunks((width as usize * kind.channels()).max(1))
        .rev()
    {
        for v in row {
            out.write_all(&v.to_le_bytes())?;
        }
    }
    Ok(())
}

/// A PFM header of `kind`: width, height, whether little-endian, and
/// where the pixels start.
pub(crate) fn pfm_header(bytes: &[u8], kind: Kind) -> Result<(u32, u32, bool, usize), String> {
    // The header is three whitespace-separated tokens after "PF".
    let mut fields = Vec::new();
    let mut pos = 0;
    while fields.len() < 4 {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos {
            return Err("truncated header".into());
        }
        fields.push(String::from_utf8_lossy(&bytes[start..pos]).into_owned());
    }
    pos += 1; // the single whitespace byte that ends the header
    if fields[0] != kind.magic() {
        let what = match kind {
            Kind::Colour => "colour",
            Kind::Plane => "one channel",
        };
        return Err(format!(
            "expected \"{}\" ({what}), found \"{}\"",
            kind.magic(),
            fields[0]
        ));
    }
    let parse = |s: &str, what: &str| s.parse::<u32>().map_err(|_| format!("bad {what} \"{s}\""));
    let (w, h) = (parse(&fields[1], "width")?, parse(&fields[2], "height")?);
    let scale: f32 = fields[3]
        .parse()
        .map_err(|_| format!("bad scale \"{}\"", fields[3]))?;
    // The scale's sign gives the byte order; 0 or NaN gives none.
    if !scale.is_finite() || scale == 0.0 {
        return Err(format!(
            "bad scale \"{}\" (a finite non-zero number: negative for little-endian)",
            fields[3]
        ));
    }
    check_size(w, h)?;
    Ok((w, h, scale < 0.0, pos))
}

/// A PFM file's image (colour, either byte order, rows bottom-up), or what is wrong with it.
pub fn read_pfm(bytes: &[u8]) -> Result<Image, String> {
    let (w, h, values) = read_values(bytes, Kind::Colour)?;
    let pixels = values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(Image::new(w, h, pixels))
}

/// A PFM file of `kind`: its width, height and values row by row from the
/// top (`kind.channels()` a pixel), or what is wrong with it.
pub(crate) fn read_values(bytes: &[u8], kind: Kind) -> Result<(u32, u32, Vec<f32>), String> {
    let (w, h, little, pos) = pfm_header(bytes, kind)?;
    let row = w as usize * kind.channels();
    let count = row * h as usize;
    let data = bytes.get(pos..).unwrap_or_default();
    if data.len() != count * 4 {
        return Err(format!(
            "expected {} bytes of pixels for {w}x{h}, found {}",
            count * 4,
            data.len()
        ));
    }
    let mut values = vec![0.0f32; count];
    for (k, chunk) in data.chunks_exact(4).enumerate() {
        let b = [chunk[0], chunk[1], chunk[2], chunk[3]];
        let v = if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        };
        let (row_from_bottom, x) = (k / row, k % row);
        values[(h as usize - 1 - row_from_bottom) * row + x] = v;
    }
    Ok((w, h, values))
}
