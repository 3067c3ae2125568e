//! The YAML document with positions: typed access to nodes, every failure a located error.

use crate::budget::Budget;
use crate::error::{SceneError, Span};
use crate::stop::StopFlag;
use saphyr::{MarkedYaml, Marker, Scalar, ScanError, YamlData};
use saphyr_parser::{Event, Parser};
use std::collections::HashMap;
use std::path::Path;

/// How deeply lists and mappings may nest, counting what aliases bring in. saphyr builds and
/// drops its tree recursively, about 2 KiB of stack a level, so a file of a few hundred
/// thousand `- ` would overflow the stack; a real scene nests fewer than 20 levels (a pattern
/// nested in a pattern in a material in a group in a group is 12).
pub const MAX_NESTING: usize = 128;

/// The most YAML values (scalars, lists and mappings, each counted once) one item of the
/// top-level list may hold, counted as its parser events arrive, before its tree is built:
/// a tree costs about 110 bytes a value, so an item is read within about 200 MB. The parts
/// budget (every transform entry and object) would refuse such an item, but only once its
/// whole tree was built: a 60 MB line of transforms held 2.3 GB first. No scene comes near
/// (the book's cover holds about 2,000 values in all).
pub const MAX_ITEM_VALUES: usize = 1_000_000;

/// The most values a file read whole (one with aliases, see the `document` module) may hold,
/// an alias counting as the values of what it repeats: YAML's exponential aliases (a list of
/// ten aliases of a list of ten aliases …) are refused before saphyr copies them out.
pub const MAX_FILE_VALUES: usize = 4 * MAX_ITEM_VALUES;

/// A scene file being read: its text (for byte offsets) and its path (for messages).
pub struct Source<'s> {
    /// The file's name, as errors show it.
    pub path: &'s Path,
    text: &'s str,
    /// Problems the reader worked around, reported to the user but not fatal.
    warnings: std::cell::RefCell<Vec<SceneError>>,
    /// What the scene may still build.
    budget: Budget,
    /// The flag that stops the reading, looked at for each parser event and each part built.
    stop: StopFlag,
    /// Whether the text is ASCII (character and byte offsets agree).
    ascii: bool,
}

/// The most warnings one file reports: enough to see the pattern of a mistake.
pub const MAX_WARNINGS: usize = 100;

/// A node of the document.
pub type Node<'s> = MarkedYaml<'s>;

impl<'s> Source<'s> {
    /// A scene file's text, `path` naming it in messages. Its items are read by
    /// [`Items`](crate::document::Items).
    pub fn new(path: &'s Path, text: &'s str, stop: StopFlag) -> Self {
        Self {
            path,
            text,
            warnings: Default::default(),
            budget: Budget::default(),
            stop,
            ascii: text.is_ascii(),
        }
    }

    /// `Err` at the parser's position `at` once the stop flag is set (see [`StopFlag`]).
    pub fn stop_at(&self, at: Marker) -> Result<(), SceneError> {
        self.stop
            .check(self.path)
            .map_err(|e| e.at(self.span_at(at.index(), at.line(), at.col(), 0)))
    }

    /// The file's text.
    pub fn text(&self) -> &'s str {
        self.text
    }

    /// A syntax error of the parser or the loader, located where it says.
    pub fn syntax_error(&self, e: &ScanError) -> SceneError {
        let m = e.marker();
        let mut span = self.span_at(m.index(), m.line(), m.col(), 0);
        if e.info().contains("tab") {
            // saphyr marks where the token that holds the tab began (the end of the
            // line before, for a tab that indents); the user needs the tab itself.
            if let Some(tab) = self.text[span.offset..].find('\t') {
                span = self.position_of(span.offset + tab);
            }
        }
        SceneError::new(self.path, format!("not valid YAML: {}", e.info())).at(span)
    }

    /// The error for an item or a file past `limit` values, at the value past it.
    pub fn too_many_values(&self, start: Marker, limit: usize, what: &str) -> SceneError {
        SceneError::new(
            self.path,
            format!(
                "{what} holds more than {limit} YAML values (scalars, lists and mappings{}); a \
                 scene is not that large",
                if limit == MAX_FILE_VALUES {
                    ", an alias counting as what it repeats"
                } else {
                    ""
                }
            ),
        )
        .at(self.span_at(start.index(), start.line(), start.col(), 0))
    }

    /// The error for a list or mapping, starting at `start`, nested deeper than
    /// [`MAX_NESTING`].
    pub fn too_deep(&self, start: Marker) -> SceneError {
        SceneError::new(
            self.path,
            format!("lists and mappings nest deeper than {MAX_NESTING} levels"),
        )
        .at(self.span_at(start.index(), start.line(), start.col(), 0))
    }

    /// Refuses a document that nests deeper than [`MAX_NESTING`] or holds more than
    /// [`MAX_FILE_VALUES`] values, before saphyr builds its tree. Reads the parser's events (a
    /// loop, no recursion); an alias counts as deep as the node its anchor names, and as many
    /// values. Syntax errors are left for the loader to report.
    pub fn check_nesting(&self) -> Result<(), SceneError> {
        // Per open collection: its anchor (0: none), the deepest level reached inside it, and
        // the values counted before it began.
        let mut open: Vec<(usize, usize, usize)> = Vec::new();
        // Per anchor: how many levels its node spans (0 for a scalar), and how many values.
        let mut anchored: HashMap<usize, (usize, usize)> = HashMap::new();
        let mut values = 0usize;
        for event in Parser::new_from_str(self.text) {
            let Ok((event, span)) = event else {
                return Ok(());
            };
            let depth = open.len();
            let reached = match event {
                Event::SequenceStart(anchor, _) | Event::MappingStart(anchor, _) => {
                    open.push((anchor, depth + 1, values));
                    values += 1;
                    depth + 1
                }
                Event::SequenceEnd | Event::MappingEnd => {
                    if let Some((anchor, deepest, before)) = open.pop() {
                        // This collection was at level `depth`.
                        if anchor != 0 {
                            anchored.insert(anchor, (deepest + 1 - depth, values - before));
                        }
                        if let Some(parent) = open.last_mut() {
                            parent.1 = parent.1.max(deepest);
                        }
                    }
                    continue;
                }
                Event::Alias(anchor) => {
                    let (height, count) = anchored.get(&anchor).copied().unwrap_or((0, 1));
                    values = values.saturating_add(count);
                    depth + height
                }
                Event::Scalar(_, _, anchor, _) => {
                    values += 1;
                    if anchor != 0 {
                        anchored.insert(anchor, (0, 1));
                    }
                    depth
                }
                _ => continue,
            };
            if values > MAX_FILE_VALUES {
                return Err(self.too_many_values(span.start, MAX_FILE_VALUES, "the file"));
            }
            if let Some(parent) = open.last_mut() {
                parent.1 = parent.1.max(reached);
            }
            if reached > MAX_NESTING {
                return Err(self.too_deep(span.start));
            }
        }
        Ok(())
    }

    /// Spends one part of the scene's budget (see the `budget` module) on something built at
    /// `node` for `key`; stops there once the stop flag is set.
    pub fn spend(&self, node: &Node<'_>, key: &str) -> Result<(), SceneError> {
        self.stop
            .check(self.path)
            .map_err(|e| e.at(self.span(node)))?;
        self.budget
            .spend()
            .map_err(|message| self.error(node, key, message))
    }

    fn span_at(&self, char_index: usize, line: usize, col: usize, char_len: usize) -> Span {
        let offset = self.byte_offset(char_index);
        let end = self.byte_offset(char_index + char_len);
        Span {
            line: line.max(1),
            column: col + 1,
            offset,
            len: end.saturating_sub(offset),
        }
    }

    /// The position (line, column in characters) of byte `offset`, one character long.
    fn position_of(&self, offset: usize) -> Span {
        let before = &self.text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let len = self.text[offset..].chars().next().map_or(0, char::len_utf8);
        Span {
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
            offset,
            len,
        }
    }

    /// Byte offset of a character index (the parser counts characters). The same number in
    /// ASCII text; otherwise a walk from the start, which only errors and warnings take.
    fn byte_offset(&self, char_index: usize) -> usize {
        if self.ascii {
            return char_index.min(self.text.len());
        }
        self.text
            .char_indices()
            .nth(char_index)
            .map_or(self.text.len(), |(b, _)| b)
    }

    /// The position of a node.
    pub fn span(&self, node: &Node<'_>) -> Span {
        let (start, end) = (node.span.start, node.span.end);
        let len = end.index().saturating_sub(start.index());
        // Collections span many lines; underline only their first line's worth.
        let len = if matches!(node.data, YamlData::Value(_)) {
            len
        } else {
            len.min(1)
        };
        self.span_at(start.index(), start.line(), start.col(), len)
    }

    /// Records a warning located at `node`, about `key`.
    /// After [`MAX_WARNINGS`], one more says that the rest are not shown.
    pub fn warn(&self, node: &Node<'_>, key: &str, message: impl Into<String>) {
        let mut warnings = self.warnings.borrow_mut();
        match warnings.len() {
            n if n < MAX_WARNINGS => warnings.push(self.error(node, key, message)),
            MAX_WARNINGS => warnings.push(self.error(
                node,
                key,
                format!("more than {MAX_WARNINGS} warnings; the rest are not shown"),
            )),
            _ => {}
        }
    }

    /// The warnings recorded so far.
    pub fn take_warnings(&self) -> Vec<SceneError> {
        std::mem::take(&mut self.warnings.borrow_mut())
    }

    /// An error located at `node`, about `key`.
    pub fn error(&self, node: &Node<'_>, key: &str, message: impl Into<String>) -> SceneError {
        let e = SceneError::new(self.path, message).at(self.span(node));
        if key.is_empty() {
            e
        } else {
            e.with_key(key)
        }
    }

    /// A number: any YAML integer or float spelling, finite.
    pub fn number(&self, node: &Node<'_>, key: &str) -> Result<f64, SceneError> {
        let value = match &node.data {
            YamlData::Value(Scalar::Integer(i)) => Some(*i as f64),
            YamlData::Value(Scalar::FloatingPoint(f)) => Some(f.into_inner()),
            // Spellings the core schema leaves as strings but a reader means as numbers
            // (`+.5`, `1_000`) are not accepted: say what was found instead.
            _ => None,
        };
        match value {
            Some(v) if v.is_finite() => Ok(v),
            Some(v) => Err(self.error(node, key, format!("expected a finite number, found {v}"))),
            None => Err(self.error(
                node,
                key,
                format!("expected a number, found {}", describe(node)),
            )),
        }
    }

    /// A whole number no smaller than `min`.
    pub fn integer(&self, node: &Node<'_>, key: &str, min: u64) -> Result<u64, SceneError> {
        let v = self.number(node, key)?;
        if v.fract() != 0.0 || v < min as f64 || v > u32::MAX as f64 {
            return Err(self.error(
                node,
                key,
                format!("expected a whole number of at least {min}, found {v}"),
            ));
        }
        Ok(v as u64)
    }

    /// A boolean.
    pub fn boolean(&self, node: &Node<'_>, key: &str) -> Result<bool, SceneError> {
        match &node.data {
            YamlData::Value(Scalar::Boolean(b)) => Ok(*b),
            _ => Err(self.error(
                node,
                key,
                format!("expected true or false, found {}", describe(node)),
            )),
        }
    }

    /// A string.
    pub fn string<'n>(&self, node: &'n Node<'_>, key: &str) -> Result<&'n str, SceneError> {
        as_str(node).ok_or_else(|| {
            self.error(
                node,
                key,
                format!("expected a name, found {}", describe(node)),
            )
        })
    }

    /// A list.
    pub fn sequence<'n>(
        &self,
        node: &'n Node<'s>,
        key: &str,
    ) -> Result<&'n [Node<'s>], SceneError> {
        match &node.data {
            YamlData::Sequence(items) => Ok(items),
            _ => Err(self.error(
                node,
                key,
                format!("expected a list, found {}", describe(node)),
            )),
        }
    }

    /// `[x, y, z]`.
    pub fn triple(&self, node: &Node<'_>, key: &str) -> Result<[f64; 3], SceneError> {
        let items = self.sequence(node, key)?;
        if items.len() != 3 {
            return Err(self.error(
                node,
                key,
                format!("expected a list of 3 numbers, found {} items", items.len()),
            ));
        }
        Ok([
            self.number(&items[0], key)?,
            self.number(&items[1], key)?,
            self.number(&items[2], key)?,
        ])
    }

    /// The entries of a mapping as (key name, key node, value node), in document order.
    pub fn entries<'n>(
        &self,
        node: &'n Node<'s>,
        key: &str,
    ) -> Result<Vec<Entry<'n, 's>>, SceneError> {
        match &node.data {
            YamlData::Mapping(map) => map
                .iter()
                .map(|(k, v)| {
                    let name = as_str(k).ok_or_else(|| self.error(k, key, "keys must be names"))?;
                    Ok(Entry {
                        name,
                        key: k,
                        value: v,
                    })
                })
                .collect(),
            _ => Err(self.error(
                node,
                key,
                format!(
                    "expected a mapping of keys to values, found {}",
                    describe(node)
                ),
            )),
        }
    }
}

/// One `key: value` of a mapping.
#[derive(Clone, Copy)]
pub struct Entry<'n, 's> {
    /// The key's name.
    pub name: &'n str,
    /// The key node (for positions).
    pub key: &'n Node<'s>,
    /// The value node.
    pub value: &'n Node<'s>,
}

/// Whether the node is a list.
pub fn is_sequence(node: &Node<'_>) -> bool {
    matches!(node.data, YamlData::Sequence(_))
}

/// Whether the node is a number (integer or float, finite or not).
pub fn is_number(node: &Node<'_>) -> bool {
    matches!(
        node.data,
        YamlData::Value(Scalar::Integer(_) | Scalar::FloatingPoint(_))
    )
}

/// Whether the node is a mapping.
pub fn is_mapping(node: &Node<'_>) -> bool {
    matches!(node.data, YamlData::Mapping(_))
}

/// The node as a string, if it is one.
pub fn as_str<'n>(node: &'n Node<'_>) -> Option<&'n str> {
    match &node.data {
        YamlData::Value(Scalar::String(s)) => Some(s.as_ref()),
        _ => None,
    }
}

/// What a node is, for messages: "a list", "the text `abc`", "the number 3".
pub fn describe(node: &Node<'_>) -> String {
    match &node.data {
        YamlData::Value(Scalar::String(s)) => format!("the text `{s}`"),
        YamlData::Value(Scalar::Integer(i)) => format!("the number {i}"),
        YamlData::Value(Scalar::FloatingPoint(f)) => format!("the number {}", f.into_inner()),
        YamlData::Value(Scalar::Boolean(b)) => format!("`{b}`"),
        YamlData::Value(Scalar::Null) => "nothing".to_string(),
        YamlData::Sequence(_) => "a list".to_string(),
        YamlData::Mapping(_) => "a mapping".to_string(),
        _ => "an unsupported YAML value".to_string(),
    }
}

/// The value of `key`, which `what` (the mapping at `node`) must have; when it is missing, an
/// error that names the key and points at the mapping.
pub fn required<'n, 's>(
    source: &Source<'_>,
    entries: &[Entry<'n, 's>],
    node: &Node<'_>,
    key: &str,
    what: &str,
) -> Result<&'n Node<'s>, SceneError> {
    entries
        .iter()
        .find(|e| e.name == key)
        .map(|e| e.value)
        .ok_or_else(|| source.error(node, key, format!("{what} needs `{key}:`")))
}

/// Rejects any key not in `allowed`, naming the ones that are.
pub fn check_keys(
    source: &Source<'_>,
    entries: &[Entry<'_, '_>],
    what: &str,
    allowed: &[&str],
) -> Result<(), SceneError> {
    for e in entries {
        if !allowed.contains(&e.name) {
            return Err(source.error(
                e.key,
                e.name,
                format!(
                    "unknown key for {what}; expected one of: {}",
                    allowed.join(", ")
                ),
            ));
        }
    }
    Ok(())
}
