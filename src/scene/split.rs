//! Parses a scene with many spheres without holding a document of the
//! whole file: the toml crate builds one (about 20 times the text) before
//! it deserializes. Each `[[spheres]]` block is parsed on its own, the rest
//! of the file as one, so only a block's document is alive at a time.
//! The scan follows TOML's strings, comments and multi-line values, so a
//! comment (`# """`, `[[spheres]] # x`) or a string that looks like a
//! header splits nothing wrongly. Where the text could still fool it (a
//! `spheres` key written another way, a header it does not know), the
//! whole file is parsed as before.

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
/// Python's `params` reads and edits a scene's text through them.
pub fn sphere_blocks(text: &str) -> Option<Vec<(usize, usize)>> {
    let mut blocks = Vec::new();
    let mut open: Option<usize> = None;
    let mut offset = 0;
    let mut scan = Scan::default();
    for line in text.split_inclusive('\n') {
        let inside = scan.inside();
        let header = !inside && line.trim_start().starts_with('[');
        let code = scan.line(line, header);
        let t = code.trim();
        if header {
            // Only the scene format's own headers, written plainly: any
            // other header leaves the file to the whole parse.
            if !is_header(t) {
                return None;
            }
            if let Some(start) = open.take() {
                blocks.push((start, offset));
            }
            if t == HEADER {
                open = Some(offset);
            }
        } else if !inside && open.is_none() && is_spheres_key(t) {
            // A root key `spheres = [...]` beside the blocks.
            return None;
        }
        offset += line.len();
    }
    if scan.inside() {
        // An unclosed string or array: the whole parse names the error.
        return None;
    }
    if let Some(start) = open {
        blocks.push((start, text.len()));
    }
    Some(blocks)
}

/// A key line that may name the root's `spheres`, however it is quoted.
fn is_spheres_key(t: &str) -> bool {
    ["spheres", "\"spheres\"", "'spheres'"]
        .iter()
        .any(|k| t.starts_with(k))
}

/// Where a line scan stands in TOML's syntax at the start of a line: in a
/// multi-line string, or in a value's brackets that span lines.
#[derive(Default)]
struct Scan {
    /// The quote of the multi-line string the line starts in.
    string: Option<u8>,
    /// Open `[` and `{` of a value.
    depth: usize,
}

impl Scan {
    /// Whether the next line starts inside a value, where nothing is a header.
    fn inside(&self) -> bool {
        self.string.is_some() || self.depth > 0
    }

    /// Follows `line`'s strings, brackets and comment; returns the line
    /// with its comment cut. A header's brackets are its own, not a value's.
    fn line<'t>(&mut self, line: &'t str, header: bool) -> &'t str {
        let b = line.as_bytes();
        let mut i = 0;
        let mut single: Option<u8> = None;
        while i < b.len() {
            let c = b[i];
            if let Some(q) = self.string {
                if b[i..].starts_with(&[q; 3]) {
                    self.string = None;
                    i += 3;
                } else {
                    i += if q == b'"' && c == b'\\' { 2 } else { 1 };
                }
                continue;
            }
            if let Some(q) = single {
                if c == q || c == b'\n' {
                    single = None;
                }
                i += if q == b'"' && c == b'\\' { 2 } else { 1 };
                continue;
            }
            match c {
                b'#' => return &line[..i],
                b'"' | b'\'' if b[i..].starts_with(&[c; 3]) => {
                    self.string = Some(c);
                    i += 3;
                    continue;
                }
                b'"' | b'\'' => single = Some(c),
                b'[' | b'{' if !header => self.depth += 1,
                b']' | b'}' if !header => self.depth = self.depth.saturating_sub(1),
                _ => {}
            }
            i += 1;
        }
        line
    }
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
        assert!(sphere_blocks("spheres = []\n").is_none());
        assert!(sphere_blocks("\"spheres\" = []\n").is_none());
        assert!(sphere_blocks("[spheres.x]\n").is_none());
        assert!(sphere_blocks("a = \"\"\"\n").is_none());
        assert_eq!(
            sphere_blocks("[[spheres]]\nradius = 1\n[image]\n").unwrap(),
            vec![(0, 23)]
        );
    }

    /// Comments, strings and multi-line values are followed, not taken for
    /// a reason to parse the whole file (one `# """` line made a 14 MB
    /// scene take 445 MB instead of 71).
    #[test]
    fn comments_and_strings_do_not_defeat_the_scan() {
        let text =
            "# \"\"\" a comment\n[[spheres]] # x\nradius = 1 # [image]\nname = \"[x] # y\"\n\
                    note = '''\n[image]\n'''\ncenter = [\n[1],\n]\n[image]\nwidth = 4\n";
        let blocks = sphere_blocks(text).expect("scanned");
        assert_eq!(blocks.len(), 1);
        let (start, end) = blocks[0];
        assert!(text[start..end].starts_with("[[spheres]] # x\n"));
        assert!(text[end..].starts_with("[image]\nwidth"));
        let mut big = String::from("# \"\"\"\n");
        big += &scene(100);
        big = big.replacen("[[spheres]]\n", "[[spheres]] # the first\n", 1);
        let split = parse(&big).ok().unwrap();
        let whole: SceneFile = toml::from_str(&big).unwrap();
        assert_eq!(format!("{split:?}"), format!("{whole:?}"));
        assert_eq!(sphere_blocks(&big).map(|b| b.len()), Some(100));
    }

    /// A 100-sphere scene with `junk` inserted near byte `at`, parsed
    /// block by block and whole (each as its Debug text, None on failure).
    fn parsed_with_junk(at: usize, junk: &str) -> (Option<String>, Option<String>) {
        let mut text = scene(100);
        let at = (0..=at.min(text.len()))
            .rev()
            .find(|i| text.is_char_boundary(*i))
            .unwrap_or(0);
        text.insert_str(at, junk);
        let split = parse(&text).map(|s| format!("{s:?}")).ok();
        let whole = toml::from_str::<SceneFile>(&text)
            .map(|s| format!("{s:?}"))
            .ok();
        (split, whole)
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config {
            cases: 512,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x73706c),
            failure_persistence: None,
            ..Default::default()
        })]

        /// Damaged anywhere, a large scene parses block by block to what it
        /// parses to whole, or both fail.
        #[test]
        fn block_parse_agrees_with_the_whole_parse(at in 0usize..6000, junk in "\\PC{0,12}") {
            let (split, whole) = parsed_with_junk(at, &junk);
            proptest::prop_assert_eq!(split, whole);
        }

        /// The same with junk made of what the scan follows: quotes,
        /// comments, brackets, escapes and newlines.
        #[test]
        fn block_parse_agrees_with_the_whole_parse_on_toml_syntax(
            at in 0usize..6000,
            junk in "[#\"'\\\\\\[\\]{}\n =a1]{0,12}",
        ) {
            let (split, whole) = parsed_with_junk(at, &junk);
            proptest::prop_assert_eq!(split, whole);
        }
    }
}
