//! Whether a run at the size asked for fits in the memory this process
//! may use, checked before minutes of rendering (16384x16384 aborted on
//! an allocation after the reference was made).

use glint::raster::memory::{image_bytes, limit, OVERHEAD};

/// The images of one scene the parent holds at once, at most: the CPU
/// reference, the driver's image, and what judging a wrong one adds (the
/// conditioning trials, the heat map). Measured: 220 MB at the peak of a
/// passing 2048x2048 run and 293 MB of a failing one, 50 MB an image.
pub const IMAGES_AT_ONCE: u64 = 6;

/// Bytes the parent needs for images of `pixels` pixels.
pub fn needed(pixels: u64) -> u64 {
    IMAGES_AT_ONCE * image_bytes(pixels) + OVERHEAD
}

/// Refuses a size whose images do not fit, in one line that says what
/// would be needed and what there is.
pub fn check(width: u32, height: u32) -> anyhow::Result<()> {
    let need = needed(u64::from(width) * u64::from(height));
    if let Some((have, what)) = limit().filter(|(have, _)| need > *have) {
        anyhow::bail!(
            "--width {width} --height {height}: checking a driver at this size holds up to {IMAGES_AT_ONCE} images of {:.1} GB at once ({:.1} GB in all), and this process may use {:.1} GB ({what}); choose a smaller size",
            gb(need.saturating_sub(OVERHEAD) / IMAGES_AT_ONCE),
            gb(need),
            gb(have)
        );
    }
    Ok(())
}

fn gb(bytes: u64) -> f64 {
    bytes as f64 / 1e9
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_size_needs_six_images() {
        let n = 16384u64 * 16384;
        assert_eq!(needed(n), 6 * n * 12 + (256 << 20));
    }
}
