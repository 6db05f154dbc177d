//! Cache entries sealed with their length and a checksum of their content
//! (the SPIR-V cache, the Vulkan pipeline cache's file). A file in
//! `~/.cache` may be damaged by a bad sector, a torn copy or a sync tool:
//! one bit flipped in a cached SPIR-V constant rendered a wrong image with
//! exit 0, and an entry cut in half failed every render of its variant
//! with the driver's "unknown error". A sealed entry that does not match
//! is compiled again and replaced, and [`notices`] says so.
//!
//! The checksum is FNV-1a over the content: each step of it is a bijection
//! of its state, so a change confined to one byte always changes the sum,
//! and the length catches a cut.

use std::hash::Hasher;
use std::path::Path;
use std::sync::Mutex;

/// The first bytes of a sealed entry, then its length and checksum.
const MAGIC: &[u8; 8] = b"glint\x01\x00\x00";
/// Magic, length, checksum.
const HEADER: usize = 24;

/// `content` sealed: the header, then the content.
pub fn seal(content: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER + content.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&(content.len() as u64).to_le_bytes());
    out.extend_from_slice(&checksum(content).to_le_bytes());
    out.extend_from_slice(content);
    out
}

/// The content of a sealed entry, or what is wrong with it.
pub fn open(bytes: &[u8]) -> Result<&[u8], &'static str> {
    if bytes.len() < HEADER || &bytes[..8] != MAGIC {
        return Err("it has no glint cache header");
    }
    let word = |i: usize| {
        let mut w = [0u8; 8];
        w.copy_from_slice(&bytes[i..i + 8]);
        u64::from_le_bytes(w)
    };
    let content = &bytes[HEADER..];
    if word(8) != content.len() as u64 {
        return Err("it is not the length it was written at");
    }
    if word(16) != checksum(content) {
        return Err("its content does not match its checksum");
    }
    Ok(content)
}

fn checksum(content: &[u8]) -> u64 {
    let mut h = crate::fnv::Fnv::default();
    h.write(content);
    h.finish()
}

/// Reads the sealed entry at `path`: its content; `None` where there is
/// none, or where it is damaged (said in [`notices`], as `what`).
pub fn read(path: &Path, what: &str) -> Option<Vec<u8>> {
    let mut bytes = std::fs::read(path).ok()?;
    match open(&bytes) {
        Ok(_) => {
            bytes.drain(..HEADER);
            Some(bytes)
        }
        Err(why) => {
            notice(format!(
                "{what} {} was damaged ({why}): made again and replaced",
                crate::printable::path(path)
            ));
            None
        }
    }
}

/// Writes `content` sealed at `path`: into a temporary file beside it,
/// renamed over it once whole, so that a reader never sees half an entry.
/// A cache that cannot be written is only a slower next start: failures
/// are ignored.
pub fn write(path: &Path, content: &[u8]) {
    let Some(dir) = path.parent() else {
        return;
    };
    if std::fs::create_dir_all(dir).is_err() {
        return;
    }
    if let Ok(tmp) = tempfile::NamedTempFile::new_in(dir) {
        if std::fs::write(tmp.path(), seal(content)).is_ok() {
            let _ = tmp.persist(path);
        }
    }
}

static NOTICES: Mutex<Vec<String>> = Mutex::new(Vec::new());

fn notice(line: String) {
    NOTICES.lock().unwrap_or_else(|e| e.into_inner()).push(line);
}

/// What the caches repaired since the last call, a line each, for the
/// command line to print at INFO level (and the Python module to log).
pub fn notices() -> Vec<String> {
    std::mem::take(&mut *NOTICES.lock().unwrap_or_else(|e| e.into_inner()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sealed_entry_opens_and_any_damage_is_found() {
        let content: Vec<u8> = (0..4096u32).map(|i| (i * 7 % 251) as u8).collect();
        let sealed = seal(&content);
        assert_eq!(open(&sealed).unwrap(), &content[..]);
        // Every single bit of the content and the header, flipped.
        for i in 0..sealed.len() {
            for bit in 0..8 {
                let mut bad = sealed.clone();
                bad[i] ^= 1 << bit;
                assert!(open(&bad).is_err(), "byte {i} bit {bit}");
            }
        }
        for cut in [
            0,
            1,
            8,
            HEADER,
            HEADER + 1,
            sealed.len() / 2,
            sealed.len() - 1,
        ] {
            assert!(open(&sealed[..cut]).is_err(), "cut at {cut}");
        }
        let mut longer = sealed.clone();
        longer.push(0);
        assert!(open(&longer).is_err());
        assert_eq!(open(&seal(&[])).unwrap(), &[] as &[u8]);
    }

    #[test]
    fn a_damaged_file_is_a_notice_and_no_content() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.bin");
        write(&path, b"spirv words");
        assert_eq!(read(&path, "the entry").unwrap(), b"spirv words");
        let mut bytes = std::fs::read(&path).unwrap();
        let last = bytes.len() - 1;
        bytes[last] ^= 4;
        std::fs::write(&path, &bytes).unwrap();
        let _ = notices();
        assert!(read(&path, "the entry").is_none());
        let said = notices();
        assert!(
            said.iter()
                .any(|n| n.contains("x.bin") && n.contains("checksum")),
            "{said:?}"
        );
        assert!(read(&dir.path().join("none"), "the entry").is_none());
    }
}
