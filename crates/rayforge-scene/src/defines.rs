//! `define:` items: named materials, transform lists and object templates, with `extend:`.
//!
//! Defines are resolved in document order (a name must be defined before it is used, as in the
//! book's files). Resolution follows references through other defines, so a chain that comes
//! back to itself is reported as a cycle instead of recursing forever.

use crate::error::SceneError;
use crate::source::{as_str, check_keys, is_mapping, Entry, Node, Source};
use std::collections::HashMap;

/// How deep references may nest before the file is judged to be unreasonable.
const MAX_REFERENCE_DEPTH: usize = 64;

/// One named define.
#[derive(Clone, Copy)]
struct Define<'n, 's> {
    /// The define it extends, with the node naming it.
    extend: Option<(&'n str, &'n Node<'s>)>,
    /// Its `value:`.
    value: &'n Node<'s>,
}

/// The table of defines seen so far.
#[derive(Default)]
pub struct Defines<'n, 's> {
    table: HashMap<&'n str, Define<'n, 's>>,
    /// The `medium:` items read so far, by name (a medium is built when it is read, and
    /// later items name it as they name defines).
    media: HashMap<String, rayforge::media::MediumId>,
}

/// A trail of names being resolved, to detect cycles.
pub type Trail<'n> = Vec<&'n str>;

impl<'n, 's> Defines<'n, 's> {
    /// Records a `define:` item.
    pub fn add(
        &mut self,
        source: &Source<'s>,
        entries: &[Entry<'n, 's>],
    ) -> Result<(), SceneError> {
        check_keys(source, entries, "a define", &["define", "extend", "value"])?;
        let get = |k: &str| entries.iter().find(|e| e.name == k);
        let define = get("define").expect("caller checked");
        let name = source.string(define.value, "define")?;
        let value = get("value").ok_or_else(|| {
            source.error(
                define.value,
                "value",
                format!("define `{name}` has no `value:`"),
            )
        })?;
        let extend = match get("extend") {
            Some(e) => {
                if !is_mapping(value.value) {
                    return Err(source.error(
                        e.key,
                        "extend",
                        format!(
                            "`{name}` extends another define, so its `value:` must be a mapping \
                             (a material, pattern or object); a transform list uses another by \
                             naming it as an entry"
                        ),
                    ));
                }
                Some((source.string(e.value, "extend")?, e.value))
            }
            None => None,
        };
        self.table.insert(
            name,
            Define {
                extend,
                value: value.value,
            },
        );
        Ok(())
    }

    /// Records the medium `name` as `id` (a later one of the same name replaces it).
    pub fn add_medium(&mut self, name: &str, id: rayforge::media::MediumId) {
        self.media.insert(name.to_string(), id);
    }

    /// The medium named `name`, if one has been read.
    pub fn medium(&self, name: &str) -> Option<rayforge::media::MediumId> {
        self.media.get(name).copied()
    }

    /// Whether `name` has been defined.
    pub fn contains(&self, name: &str) -> bool {
        self.table.contains_key(name)
    }

    /// The value of the define named by `reference` (a string node), with the trail extended.
    pub fn lookup(
        &self,
        source: &Source<'s>,
        reference: &'n Node<'s>,
        key: &str,
        trail: &mut Trail<'n>,
    ) -> Result<&'n Node<'s>, SceneError> {
        let name = source.string(reference, key)?;
        self.enter(source, reference, key, name, trail)?;
        Ok(self.table[name].value)
    }

    /// Pushes `name` onto the trail, failing for undefined names, cycles and runaway depth.
    fn enter(
        &self,
        source: &Source<'s>,
        at: &'n Node<'s>,
        key: &str,
        name: &'n str,
        trail: &mut Trail<'n>,
    ) -> Result<(), SceneError> {
        if !self.table.contains_key(name) {
            return Err(source.error(
                at,
                key,
                format!("`{name}` is not defined (a `define:` must come before its use)"),
            ));
        }
        if trail.contains(&name) {
            trail.push(name);
            return Err(source.error(at, key, format!("define cycle: {}", trail.join(" → "))));
        }
        if trail.len() >= MAX_REFERENCE_DEPTH {
            return Err(source.error(
                at,
                key,
                format!("references nest deeper than {MAX_REFERENCE_DEPTH} levels"),
            ));
        }
        source.spend(at, key)?;
        trail.push(name);
        Ok(())
    }

    /// The merged entries of a mapping define: what it extends first, its own keys overriding.
    pub fn mapping_entries(
        &self,
        source: &Source<'s>,
        reference: &'n Node<'s>,
        key: &str,
        trail: &mut Trail<'n>,
    ) -> Result<Vec<Entry<'n, 's>>, SceneError> {
        let name = source.string(reference, key)?;
        self.enter(source, reference, key, name, trail)?;
        let define = self.table[name];
        let mut merged = match define.extend {
            Some((_, parent)) => self.mapping_entries(source, parent, "extend", trail)?,
            None => Vec::new(),
        };
        for entry in source.entries(define.value, key)? {
            merge(&mut merged, entry);
        }
        trail.pop();
        Ok(merged)
    }
}

/// Sets `entry` in `entries`, replacing an entry with the same name.
pub fn merge<'n, 's>(entries: &mut Vec<Entry<'n, 's>>, entry: Entry<'n, 's>) {
    match entries.iter_mut().find(|e| e.name == entry.name) {
        Some(existing) => *existing = entry,
        None => entries.push(entry),
    }
}

/// Whether a node is a reference (a bare name) rather than an inline value.
pub fn is_reference(node: &Node<'_>) -> bool {
    as_str(node).is_some()
}
