//! How many triangles a file may make. A polygon of n corners is split
//! into n − 2 triangles, so a face of short indices (`f 1 2 3 4 2 3 4 …`)
//! makes a triangle for every 2 bytes of file, and each costs some 300
//! bytes once loaded (400 on the GPU): a 2 MB file took 400 MB. A file
//! may make one triangle per [`BYTES_PER_TRIANGLE`] bytes of its own, past
//! the first [`FREE`]: within 20 times its size in memory (docs/guarantees.md).

use std::io::BufRead;

/// Triangles any file may make, whatever its size.
pub const FREE: u64 = 1 << 16;
/// Bytes of file a triangle past [`FREE`] needs.
pub const BYTES_PER_TRIANGLE: u64 = 20;

/// The triangles a file of `bytes` may make.
pub fn allowed(bytes: u64) -> u64 {
    FREE + bytes / BYTES_PER_TRIANGLE
}

/// Where a file passes its allowance: the 1-based line of the face that
/// does, and the triangles counted with it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Past {
    pub line: usize,
    pub triangles: u64,
}

/// Counts the triangles an OBJ's faces (`f` lines) make, without keeping
/// them, up to the first face that passes `allowed`.
pub fn obj_past(text: impl BufRead, allowed: u64) -> std::io::Result<Option<Past>> {
    let mut triangles = 0u64;
    for (i, line) in text.split(b'\n').enumerate() {
        let line = line?;
        let mut words = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty());
        if words.next() != Some(b"f") {
            continue;
        }
        let corners = words.take_while(|w| w[0] != b'#').count() as u64;
        triangles += corners.saturating_sub(2);
        if triangles > allowed {
            return Ok(Some(Past {
                line: i + 1,
                triangles,
            }));
        }
    }
    Ok(None)
}

/// Why a file is refused at `past` (the caller names the line).
pub fn message(past: Past, bytes: u64) -> String {
    format!(
        "this face brings the file to {} triangles, past the {} that a file of {bytes} bytes may \
         make (one per {BYTES_PER_TRIANGLE} bytes past the first {FREE}); split the polygon",
        past.triangles,
        allowed(bytes)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fan_is_counted_to_the_face_that_passes() {
        let text = b"v 0 0 0\nf 1 2 3\n# f 1 2 3 4 5 6\nf 1 2 3 4 5 6 # comment 7 8\nf 1 2 3\n";
        assert_eq!(obj_past(&text[..], 100).unwrap(), None);
        assert_eq!(
            obj_past(&text[..], 4).unwrap(),
            Some(Past {
                line: 4,
                triangles: 5
            })
        );
        assert_eq!(allowed(20 * 1000), FREE + 1000);
    }
}
