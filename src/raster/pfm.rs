//! PFM files (Portable FloatMap, colour): written little-endian, read in
//! either byte order, rows bottom to top; `io` reads and writes them
//! through these.

use std::io::Write;

use super::memory::check_size;
use super::Image;

/// Standard PFM: little-endian (scale -1.0), rows bottom to top.
pub(crate) fn write_pfm(out: &mut (impl Write + ?Sized), img: &Image) -> std::io::Result<()> {
    write!(out, "PF\n{} {}\n-1.0\n", img.width, img.height)?;
    for row in img.pixels.chunks(img.width as usize).rev() {
        for c in row.iter().flatten() {
            out.write_all(&c.to_le_bytes())?;
        }
    }
    Ok(())
}

/// A PFM header: width, height, whether little-endian, and where the
/// pixels start.
pub(crate) fn pfm_header(bytes: &[u8]) -> Result<(u32, u32, bool, usize), String> {
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
    if fields[0] != "PF" {
        return Err(format!("expected \"PF\" (colour), found \"{}\"", fields[0]));
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
    let (w, h, little, pos) = pfm_header(bytes)?;
    let count = w as usize * h as usize;
    let data = bytes.get(pos..).unwrap_or_default();
    if data.len() != count * 12 {
        return Err(format!(
            "expected {} bytes of pixels for {w}x{h}, found {}",
            count * 12,
            data.len()
        ));
    }
    let mut pixels = vec![[0.0f32; 3]; count];
    for (k, chunk) in data.chunks_exact(4).enumerate() {
        let b = [chunk[0], chunk[1], chunk[2], chunk[3]];
        let v = if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        };
        let (pixel, channel) = (k / 3, k % 3);
        let (row_from_bottom, x) = (pixel / w as usize, pixel % w as usize);
        let y = h as usize - 1 - row_from_bottom;
        pixels[y * w as usize + x][channel] = v;
    }
    Ok(Image::new(w, h, pixels))
}
