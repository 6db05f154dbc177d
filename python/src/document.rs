//! A scene file's TOML text as `params` and `to_dict` read and change it:
//! its `[[spheres]]` blocks apart from the rest of the file (the head), a
//! block parsed only when a key names it. The toml crate's document of a
//! whole file is 20–40 times its text; a change of one value on 200,000
//! spheres (17 MB of TOML) peaked at 727 MB when it parsed the whole
//! file, where loading it takes 115 MB. A change confined to blocks keeps
//! the rest of the text as it was, comments and all.

use std::collections::BTreeMap;

use pyo3::prelude::*;

use crate::errors;
use crate::params::{self, Key, SPHERES};

pub struct Document<'t> {
    text: &'t str,
    /// The `[[spheres]]` blocks' byte ranges (`scene::sphere_blocks`):
    /// none where the text is read whole, as one head.
    blocks: Vec<(usize, usize)>,
}

/// Where a key's value is kept in a document.
pub enum Place {
    /// In the head: the file but its sphere blocks.
    Head,
    /// In the sphere block of this index.
    Sphere(usize),
    /// In the spheres' array as a whole: read from the whole text.
    Whole,
}

/// A root entry of the file, in the toml crate's order (its keys sorted):
/// one of the head's, or the spheres' array, whose entries are the blocks.
pub enum Root<'h> {
    Head(&'h str, &'h toml::Value),
    Spheres,
}

impl<'t> Document<'t> {
    pub fn new(text: &'t str) -> Self {
        Document {
            text,
            blocks: glint::scene::sphere_blocks(text).unwrap_or_default(),
        }
    }

    /// The text read as one head, its blocks not kept apart.
    pub fn whole_of(text: &'t str) -> Self {
        Document {
            text,
            blocks: Vec::new(),
        }
    }

    /// Where `key`'s value is kept.
    pub fn place(&self, key: &Key) -> Place {
        if self.blocks.is_empty() || !key.of_spheres() {
            return Place::Head;
        }
        match key.in_sphere() {
            Some(i) => Place::Sphere(i),
            None => Place::Whole,
        }
    }

    /// The head's tables: the whole file's where it has no blocks.
    pub fn head(&self) -> PyResult<toml::Table> {
        if self.blocks.is_empty() {
            return self.whole();
        }
        let mut head = String::new();
        let mut last = 0;
        for &(start, end) in &self.blocks {
            head.push_str(&self.text[last..start]);
            last = end;
        }
        head.push_str(&self.text[last..]);
        toml::from_str(&head).map_err(errors::other)
    }

    /// The whole file's tables.
    pub fn whole(&self) -> PyResult<toml::Table> {
        toml::from_str(self.text).map_err(errors::other)
    }

    /// How many sphere blocks it has.
    pub fn spheres(&self) -> usize {
        self.blocks.len()
    }

    /// Sphere block `i`'s table; None where there is no such block.
    pub fn sphere(&self, i: usize) -> PyResult<Option<toml::Table>> {
        let Some(&(start, end)) = self.blocks.get(i) else {
            return Ok(None);
        };
        let block: toml::Table = toml::from_str(&self.text[start..end]).map_err(errors::other)?;
        match block.into_iter().next() {
            Some((_, toml::Value::Array(a))) => match a.into_iter().next() {
                Some(toml::Value::Table(t)) => Ok(Some(t)),
                _ => Ok(None),
            },
            _ => Ok(None),
        }
    }

    /// The root entries in the toml crate's order, the spheres' array
    /// among them where the file has blocks.
    pub fn roots<'h>(&self, head: &'h toml::Table) -> Vec<Root<'h>> {
        let mut roots: Vec<Root<'h>> = Vec::with_capacity(head.len() + 1);
        let mut spheres = !self.blocks.is_empty();
        for (k, v) in head {
            if spheres && k.as_str() > SPHERES {
                roots.push(Root::Spheres);
                spheres = false;
            }
            roots.push(Root::Head(k, v));
        }
        if spheres {
            roots.push(Root::Spheres);
        }
        roots
    }

    /// Calls `out` with each key `params` lists and its value, in the
    /// file's order, a block parsed at a time.
    pub fn list(
        &self,
        head: &toml::Table,
        out: &mut dyn FnMut(String, &toml::Value) -> PyResult<()>,
    ) -> PyResult<()> {
        for root in self.roots(head) {
            match root {
                Root::Head(k, v) => params::list(v, params::root_key(k), out)?,
                Root::Spheres => {
                    for i in 0..self.spheres() {
                        if let Some(t) = self.sphere(i)? {
                            params::list(&toml::Value::Table(t), params::sphere_key(i), out)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The text with the changes made: the head's tables where they were
    /// changed (written out, the blocks after them), and each changed
    /// block written in its place; the rest as it was.
    pub fn written(
        &self,
        head: Option<&toml::Table>,
        changed: &BTreeMap<usize, toml::Table>,
    ) -> PyResult<String> {
        let mut out = String::with_capacity(self.text.len() + 64);
        let mut last = 0;
        if let Some(head) = head {
            out.push_str(&toml::to_string(head).map_err(errors::other)?);
        }
        for (i, &(start, end)) in self.blocks.iter().enumerate() {
            if head.is_none() {
                out.push_str(&self.text[last..start]);
            }
            last = end;
            match changed.get(&i) {
                Some(t) => {
                    let mut block = toml::Table::new();
                    block.insert(
                        SPHERES.to_owned(),
                        toml::Value::Array(vec![toml::Value::Table(t.clone())]),
                    );
                    out.push_str(&toml::to_string(&block).map_err(errors::other)?);
                }
                None => {
                    out.push_str(&self.text[start..end]);
                    // The file's last block may end without a newline.
                    if !out.ends_with('\n') {
                        out.push('\n');
                    }
                }
            }
        }
        if head.is_none() {
            out.push_str(&self.text[last..]);
        }
        Ok(out)
    }
}
