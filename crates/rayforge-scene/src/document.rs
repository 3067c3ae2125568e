//! The scene file's top-level list, handed out one item at a time.
//!
//! A scene is one YAML list of items, and a generated scene may hold a hundred thousand of
//! them. saphyr's tree of a whole file costs about 5 KB an item (the nodes of its twenty-odd
//! keys and numbers), and it was held while the world was built: most of the memory of a scene
//! that places one instance per item. So the list is read from the parser's stream of events,
//! each item's events built into a small tree of its own that the reader drops once the item
//! is read (it keeps a `define:`, which later items name). The parser reads the file once; the
//! nesting limit is checked as the events come, before any tree is built.
//!
//! Two kinds of file are still built whole, the way saphyr loads any document: one with an
//! alias (`*name`, so any file with a `*`), which may name an anchor (`&name`) in an earlier
//! item that a tree built per item would not hold, and one whose top level is not a plain
//! list, which is an error the whole tree describes best. Neither is common in scenes, and
//! neither changes what is read. A syntax error late in a streamed file is found when the
//! reader reaches it, after the items before it have been read.

use crate::error::SceneError;
use crate::source::{Node, Source, MAX_ITEM_VALUES, MAX_NESTING};
use saphyr::{LoadableYamlNode, MarkedYaml, ScanError, YamlData, YamlLoader};
use saphyr_parser::{Event, Parser, Span, SpannedEventReceiver, StrInput};

/// The items of a scene file's top-level list, in document order (see the [module](self)).
pub struct Items<'s> {
    how: How<'s>,
}

enum How<'s> {
    /// Items built one at a time from the parser's events, which stand just inside the list
    /// (boxed: the parser's state is large, and there is one per file).
    Stream(Box<Events<'s>>),
    /// The items of a tree built whole.
    Built(std::vec::IntoIter<Node<'s>>),
    /// Nothing more (the list and what follows it have been read).
    Done,
}

/// Refused when a file holds a second document; a scene is one list.
const SECOND_DOCUMENT: &str =
    "the file holds more than one YAML document (`---`); a scene is one list of items";

/// The file's events, read one at a time.
type Events<'s> = Parser<'s, StrInput<'s>>;

impl<'s> Items<'s> {
    /// The items of `source`'s file.
    pub fn open(source: &Source<'s>) -> Result<Self, SceneError> {
        if !source.text().contains('*') {
            let mut parser = Parser::new_from_str(source.text());
            loop {
                match parser.next() {
                    Some(Ok((Event::StreamStart | Event::DocumentStart(_), _))) => continue,
                    Some(Ok((Event::SequenceStart(0, None), _))) => {
                        return Ok(Self {
                            how: How::Stream(Box::new(parser)),
                        })
                    }
                    _ => break,
                }
            }
        }
        source.check_nesting()?;
        Self::built(source)
    }

    /// The whole document as one tree: the empty file, a second document and a top level that
    /// is not a list are refused here.
    fn built(source: &Source<'s>) -> Result<Self, SceneError> {
        let documents =
            MarkedYaml::load_from_str(source.text()).map_err(|e| source.syntax_error(&e))?;
        let mut documents = documents.into_iter();
        let Some(root) = documents.next() else {
            return Err(SceneError::new(
                source.path,
                "the scene file is empty: expected a list of `- add:` and `- define:` items",
            ));
        };
        // A second document (after `---`) would be silently ignored: refuse it instead.
        if let Some(extra) = documents.find(|d| !d.data.is_null()) {
            return Err(source.error(&extra, "", SECOND_DOCUMENT));
        }
        match root.data {
            YamlData::Sequence(items) => Ok(Self {
                how: How::Built(items.into_iter()),
            }),
            _ => Err(source.error(
                &root,
                "",
                "the top level must be a list of `- add:` and `- define:` items",
            )),
        }
    }

    /// The next item, or `None` after the last.
    pub fn next_item(&mut self, source: &Source<'s>) -> Option<Result<Node<'s>, SceneError>> {
        let item = match &mut self.how {
            How::Built(items) => return items.next().map(Ok),
            How::Done => return None,
            How::Stream(parser) => next_streamed(source, parser),
        };
        if !matches!(item, Ok(Some(_))) {
            self.how = How::Done;
        }
        item.transpose()
    }
}

/// The next item of the list the parser stands in; at the list's end, `None` once what follows
/// it has been checked (a second document is refused).
fn next_streamed<'s>(
    source: &Source<'s>,
    parser: &mut Events<'s>,
) -> Result<Option<Node<'s>>, SceneError> {
    let Some((first, span)) = next_event(source, parser)? else {
        return Ok(None);
    };
    if first == Event::SequenceEnd {
        check_rest(source, parser)?;
        return Ok(None);
    }
    let mut loader = YamlLoader::default();
    loader.on_event(Event::DocumentStart(false), span);
    // The item sits one level inside the list.
    let end = feed_node(source, parser, &mut loader, (first, span), 1)?;
    loader.on_event(Event::DocumentEnd, end);
    finish(source, loader)
}

/// After the list: the end of its document, then any further documents, each of which must be
/// empty.
fn check_rest<'s>(source: &Source<'s>, parser: &mut Events<'s>) -> Result<(), SceneError> {
    while let Some((event, span)) = next_event(source, parser)? {
        if !matches!(event, Event::DocumentStart(_)) {
            continue;
        }
        let mut loader = YamlLoader::default();
        loader.on_event(event, span);
        let (first, span) = next_event(source, parser)?.ok_or_else(|| unexpected_end(source))?;
        if first != Event::DocumentEnd {
            feed_node(source, parser, &mut loader, (first, span), 0)?;
            let (end, span) = next_event(source, parser)?.ok_or_else(|| unexpected_end(source))?;
            loader.on_event(end, span);
        } else {
            loader.on_event(first, span);
        }
        if let Some(extra) = finish(source, loader)? {
            if !extra.data.is_null() {
                return Err(source.error(&extra, "", SECOND_DOCUMENT));
            }
        }
    }
    Ok(())
}

/// Gives `loader` the events of one node, starting with `first`, and returns the last one's
/// span; a node that takes the document deeper than [`MAX_NESTING`], counting the `outer`
/// levels around it, or that holds more than [`MAX_ITEM_VALUES`] values, is refused before
/// it is built.
fn feed_node<'s>(
    source: &Source<'s>,
    parser: &mut Events<'s>,
    loader: &mut YamlLoader<'s, MarkedYaml<'s>>,
    first: (Event<'s>, Span),
    outer: usize,
) -> Result<Span, SceneError> {
    let mut depth = 0usize;
    let mut values = 0usize;
    let (mut event, mut span) = first;
    loop {
        match event {
            Event::SequenceStart(..) | Event::MappingStart(..) => {
                depth += 1;
                values += 1;
                if outer + depth > MAX_NESTING {
                    return Err(source.too_deep(span.start));
                }
            }
            Event::SequenceEnd | Event::MappingEnd => depth = depth.saturating_sub(1),
            Event::Scalar(..) | Event::Alias(_) => values += 1,
            _ => {}
        }
        if values > MAX_ITEM_VALUES {
            return Err(source.too_many_values(span.start, MAX_ITEM_VALUES, "an item"));
        }
        loader.on_event(event, span);
        if depth == 0 {
            return Ok(span);
        }
        (event, span) = next_event(source, parser)?.ok_or_else(|| unexpected_end(source))?;
    }
}

/// The one document a loader was given, or the error it found (a key given twice).
fn finish<'s>(
    source: &Source<'s>,
    loader: YamlLoader<'s, MarkedYaml<'s>>,
) -> Result<Option<Node<'s>>, SceneError> {
    if let Some(e) = loader.error() {
        return Err(source.syntax_error(e));
    }
    Ok(loader.into_documents().pop())
}

/// The parser's next event; its syntax errors are located like the loader's.
fn next_event<'s>(
    source: &Source<'s>,
    parser: &mut Events<'s>,
) -> Result<Option<(Event<'s>, Span)>, SceneError> {
    let event = parser
        .next()
        .transpose()
        .map_err(|e: ScanError| source.syntax_error(&e))?;
    if let Some((_, span)) = &event {
        source.stop_at(span.start)?;
    }
    Ok(event)
}

/// The events stopped inside a node, which the parser reports as a syntax error first; an
/// error rather than a panic all the same.
fn unexpected_end(source: &Source<'_>) -> SceneError {
    SceneError::new(
        source.path,
        "not valid YAML: the file ends inside a list or mapping",
    )
}
