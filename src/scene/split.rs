//! Parses a scene with many spheres without holding a document of the
//! whole file: the toml crate builds one (about 20 times the text) before
//! it deserializes. Each `[[spheres]]` block is parsed on its own, the rest
//! of the file as one, so only a block's document is alive at a time.
//! Where the text could fool a line scan (multi-line strings, a `spheres`
//! key written another way), the whole file is parsed as before.

use super::file::SceneFile;
use crate::prim::sphere::SphereFile;

const HEADER: &str = "[[spheres]]";

/// Where a block failed: its parse error and the block's byte offset.
pub struct BlockError {
    pub error: toml::de::Error,
    pub offset: usize,
}

/// The scene file, parsed block by block where that is safe.
pub fn parse(text: &str) -> Result<SceneFile, BlockError> {
    let whole = |text: &str| toml::from_str(text).map_err(|error| BlockError { error, offset: 0 });
    let Some(blocks) = sphere_blocks(text) else {
        return whole(text);
    };
    if blocks.len() < 64 {
        return whole(text);
    }
    let mut head = String::with_capacity(text.len());
    let mut last = 0;
    for &(start, end) in &blocks {
        head.push_str(&text[last..start]);
        // Blank the block byte for byte, newlines kept, so that an error's
        // position in the head is its position in the file.
        head.extend(
            text.as_bytes()[start..end]
                .iter()
                .map(|&b| if b == b'\n' { '\n' } else { ' ' }),
        );
        last = end;
    }
    head.push_str(&text[last..]);
    let mut scene: SceneFile = whole(&head)?;
    let mut spheres = Vec::with_capacity(blocks.len());
    #[derive(serde::Deserialize)]
    struct Block {
        spheres: Vec<SphereFile>,
    }
    for &(start, end) in &blocks {
        let block: Block = toml::from_str(&text[start..end]).map_err(|error| BlockError {
            error,
            offset: start,
        })?;
        spheres.extend(block.spheres);
    }
    scene.spheres = spheres;
    Ok(scene)
}

/// The byte ranges of the `[[spheres]]` blocks, each from its header to the
/// next line that starts a table; None where a line scan is not safe.
fn sphere_blocks(text: &str) -> Option<Vec<(usize, usize)>> {
    if text.contains("\"\"\"") || text.contains("'''") {
        return None;
    }
    let mut blocks = Vec::new();
    let mut open: Option<usize> = None;
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim();
        if t.starts_with('[') {
            // Only the scene format's own headers, written plainly: any
            // other line that starts with '[' (a header with a comment, a
            // line of a multi-line array) leaves the file to the whole parse.
            if !is_header(t) {
                return None;
            }
            if let Some(start) = open.take() {
                blocks.push((start, offset));
            }
            if t == HEADER {
                open = Some(offset);
            }
        } else if open.is_none() && t.starts_with("spheres") {
            // A root key `spheres = [...]` beside the blocks.
            return None;
        }
        offset += line.len();
    }
    if let Some(start) = open {
        blocks.push((start, text.len()));
    }
    Some(blocks)
}

fn is_header(t: &str) -> bool {
    matches!(t, "[[lights]]" | "[image]" | "[render]" | "[camera]")
        || crate::prim::KINDS.iter().any(|k| {
            t.len() == k.key.len() + 4
                && t[2..t.len() - 2] == *k.key
                && t.starts_with("[[")
                && t.ends_with("]]")
        })
        || (t.starts_with("[materials.")
            && t.ends_with(']')
            && !t.ends_with("]]")
            && !t[1..t.len() - 1].contains(['[', ']', '#']))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(n: usize) -> String {
        let mut t = String::from(
            "[image]\nwidth = 4\nheight = 4\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 40\n[materials.m]\n",
        );
        for i in 0..n {
            t += &format!("[[spheres]]\ncenter = [{i}, 0, 0]\nradius = 0.5\nmaterial = \"m\"\n");
            if i == n / 2 {
                t += "[[planes]]\npoint = [0, -1, 0]\nnormal = [0, 1, 0]\nmaterial = \"m\"\n";
            }
        }
        t
    }

    #[test]
    fn blocks_parse_to_what_the_whole_file_parses_to() {
        let text = scene(200);
        let split = parse(&text).ok().unwrap();
        let whole: SceneFile = toml::from_str(&text).unwrap();
        assert_eq!(split.spheres.len(), 200);
        assert_eq!(format!("{split:?}"), format!("{whole:?}"));
    }

    #[test]
    fn texts_a_line_scan_could_misread_are_parsed_whole() {
        assert!(sphere_blocks("a = \"\"\"\n[[spheres]]\n\"\"\"\n").is_none());
        assert!(sphere_blocks("spheres = []\n").is_none());
        assert!(sphere_blocks("[spheres.x]\n").is_none());
        assert!(sphere_blocks("[image] # comment\n").is_none());
        assert!(sphere_blocks("[[spheres]]\ncenter = [\n[1],\n]\n").is_none());
        assert_eq!(
            sphere_blocks("[[spheres]]\nradius = 1\n[image]\n").unwrap(),
            vec![(0, 23)]
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config {
            cases: 128,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x73706c),
            failure_persistence: None,
            ..Default::default()
        })]

        /// Damaged anywhere, a large scene parses block by block to what it
        /// parses to whole, or both fail.
        #[test]
        fn block_parse_agrees_with_the_whole_parse(at in 0usize..6000, junk in "\\PC{0,12}") {
            let mut text = scene(100);
            let at = (0..=at.min(text.len())).rev().find(|i| text.is_char_boundary(*i)).unwrap_or(0);
            text.insert_str(at, &junk);
            let split = parse(&text).map(|s| format!("{s:?}")).ok();
            let whole = toml::from_str::<SceneFile>(&text).map(|s| format!("{s:?}")).ok();
            proptest::prop_assert_eq!(split, whole);
        }
    }
}
