//! Whether images of a size fit in the memory this process may use,
//! checked before they are allocated: an allocation that fails aborts the
//! process (`drivers` at 16384x16384; `render` and the Python module, the
//! interpreter with it).

/// What the rest of a process takes, besides its images.
pub const OVERHEAD: u64 = 256 << 20;

/// Bytes of one image of `pixels` pixels (three f32 a pixel).
pub fn image_bytes(pixels: u64) -> u64 {
    pixels * std::mem::size_of::<[f32; 3]>() as u64
}

/// The most this process may use, and what says so: its address-space
/// limit (`ulimit -v`) or the memory the machine has available, whichever
/// is less; None where neither is known.
pub fn limit() -> Option<(u64, &'static str)> {
    let mut limits = Vec::new();
    let mut rl = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: a query into a struct of the right type.
    if unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut rl) } == 0
        && rl.rlim_cur != libc::RLIM_INFINITY
    {
        limits.push((rl.rlim_cur, "its address-space limit (ulimit -v)"));
    }
    if let Some(kb) = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| available_kb(&t))
    {
        limits.push((kb * 1024, "the memory available on this machine"));
    }
    limits.into_iter().min_by_key(|(bytes, _)| *bytes)
}

/// MemAvailable of /proc/meminfo, in kB.
fn available_kb(meminfo: &str) -> Option<u64> {
    meminfo
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .trim()
        .strip_suffix("kB")?
        .trim()
        .parse()
        .ok()
}

/// Work that does not fit: what it is, what it needs and what there is.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{what} needs {:.1} GB, and this process may use {:.1} GB ({limit}); choose a smaller size", gb(*.need), gb(*.have))]
pub struct TooLarge {
    /// The work, in words (`a 16384x16384 render`).
    pub what: String,
    /// Bytes it needs.
    pub need: u64,
    /// Bytes there are.
    pub have: u64,
    /// What sets that.
    pub limit: &'static str,
}

/// Refuses `what`, which needs `need` bytes besides `OVERHEAD`, where it
/// does not fit.
pub fn check(what: impl FnOnce() -> String, need: u64) -> Result<(), TooLarge> {
    let need = need.saturating_add(OVERHEAD);
    match limit() {
        Some((have, limit)) if need > have => Err(TooLarge {
            what: what(),
            need,
            have,
            limit,
        }),
        _ => Ok(()),
    }
}

/// Images a render holds at once, at most: the image, its copy for the
/// output file, and the device's tiles and readback (lavapipe's device
/// memory is the host's).
pub const RENDER_IMAGES: u64 = 3;

/// Refuses a render of `width`×`height` (with `samples`² rays a pixel)
/// whose images do not fit.
pub fn check_render(width: u32, height: u32) -> Result<(), TooLarge> {
    let pixels = u64::from(width) * u64::from(height);
    check(
        || format!("a {width}x{height} render"),
        RENDER_IMAGES * image_bytes(pixels),
    )
}

fn gb(bytes: u64) -> f64 {
    bytes as f64 / 1e9
}

/// Refuses an image file's size outside what glint reads: 1 to `MAX_SIDE`
/// a side and `MAX_PIXELS` in all (`io` and `pfm` check a header's with it).
pub(crate) fn check_size(w: u32, h: u32) -> Result<(), String> {
    use crate::input::{MAX_PIXELS, MAX_SIDE};
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || u64::from(w) * u64::from(h) > MAX_PIXELS
    {
        return Err(format!(
            "size {w}x{h} is outside 1..={MAX_SIDE} a side and {MAX_PIXELS} pixels in all"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn available_memory_is_read_from_meminfo() {
        let text = "MemTotal:       24000000 kB\nMemAvailable:   20123456 kB\n";
        assert_eq!(available_kb(text), Some(20_123_456));
        assert_eq!(available_kb("MemTotal: 1 kB\n"), None);
    }

    #[test]
    fn a_render_past_the_machine_is_refused_and_a_small_one_is_not() {
        assert!(check_render(64, 48).is_ok());
        let e = check(|| "a test".into(), u64::MAX / 2).unwrap_err();
        assert!(e.to_string().starts_with("a test needs"), "{e}");
    }
}
