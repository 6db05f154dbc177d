//! Reading an OBJ's MTL files within the OBJ's needs: a file of a million
//! materials is parsed one material at a time, each checked, and only the
//! materials the OBJ uses (its `usemtl` names) are kept (issue 31: such a
//! file used to peak at 34–67× its size).

use std::collections::HashSet;
use std::io::BufRead;

/// The material names an OBJ's `usemtl` lines give, as tobj reads them
/// (the rest of the line after the first space, trimmed).
pub fn used_names(obj: impl BufRead) -> HashSet<String> {
    obj.split(b'\n')
        .map_while(Result::ok)
        .filter_map(|line| {
            let line = String::from_utf8(line).ok()?;
            let mut words = line.split_whitespace();
            (words.next() == Some("usemtl"))
                .then(|| line.split_once(' ').map(|(_, n)| n.trim().to_owned()))
                .flatten()
        })
        .filter(|n| !n.is_empty())
        .collect()
}

/// One material's lines of an MTL file: from its `newmtl` line to the
/// next; `name` None for the lines before the first `newmtl`.
pub struct Block<'a> {
    pub name: Option<String>,
    pub text: &'a [u8],
}

/// The blocks of an MTL file, in order, each a slice of `text` (so their
/// lines and line numbers are the file's), one at a time: a file of a
/// million materials never holds a million names.
pub fn blocks(text: &[u8]) -> impl Iterator<Item = Block<'_>> {
    let mut lines = text.split_inclusive(|&b| b == b'\n');
    // The current block's start and name; `at`, the end of what is read.
    let (mut start, mut name, mut at, mut ended) = (0, None, 0, false);
    std::iter::from_fn(move || loop {
        let Some(line) = lines.next() else {
            if ended || (at == start && name.is_none()) {
                return None;
            }
            ended = true;
            return Some(Block {
                name: name.take(),
                text: &text[start..at],
            });
        };
        let here = at;
        at += line.len();
        if let Some(next) = newmtl(line) {
            let previous = name.replace(next);
            let done = (here > start || previous.is_some()).then(|| Block {
                name: previous,
                text: &text[start..here],
            });
            start = here;
            if done.is_some() {
                return done;
            }
        }
    })
}

/// The material a `newmtl` line names, as tobj reads it.
fn newmtl(line: &[u8]) -> Option<String> {
    let line = std::str::from_utf8(line).ok()?.trim();
    let first = line.split_whitespace().next()?;
    (first == "newmtl").then(|| line[6..].trim().to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_split_at_each_newmtl_and_keep_every_byte() {
        let text = b"# top\nnewmtl a\nKd 1 0 0\n  newmtl  b c \nNs 3\n";
        let b: Vec<Block> = blocks(text).collect();
        let names: Vec<Option<&str>> = b.iter().map(|b| b.name.as_deref()).collect();
        assert_eq!(names, [None, Some("a"), Some("b c")]);
        let joined: Vec<u8> = b.iter().flat_map(|b| b.text.iter().copied()).collect();
        assert_eq!(joined, text);
        assert_eq!(blocks(b"").count(), 0);
        let names: Vec<Option<String>> = blocks(b"newmtl a\nKd 1 1 1\nnewmtl b\n")
            .map(|b| b.name)
            .collect();
        assert_eq!(names, [Some("a".to_owned()), Some("b".to_owned())]);
        assert_eq!(
            blocks(b"newmtl a").map(|b| b.text).collect::<Vec<_>>(),
            [b"newmtl a"]
        );
    }

    #[test]
    fn used_names_are_read_as_tobj_reads_them() {
        let obj = b"v 0 0 0\nusemtl red\nusemtl  two words \nusemtl\nf 1 1 1\n";
        let names = used_names(&obj[..]);
        let mut v: Vec<&str> = names.iter().map(String::as_str).collect();
        v.sort();
        assert_eq!(v, ["red", "two words"]);
    }
}
