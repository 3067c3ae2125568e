//! A PLY file's header: its format, and the elements the body holds with their properties,
//! each remembered with the header line that declared it, so that errors about the body can
//! still point at the declaration that set them up.

use crate::error::{SceneError, Span};
use crate::text_line::TextLine;
use std::path::Path;

/// The longest header read (a header is a few hundred bytes; comments may add some). Bounded
/// so that a file of a gigabyte of `property` lines is refused before it is read as a header.
pub const MAX_HEADER_BYTES: usize = 1 << 20;

/// How the body is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Numbers as text, one element to a line.
    Ascii,
    /// Binary, least significant byte first.
    LittleEndian,
    /// Binary, most significant byte first.
    BigEndian,
}

/// A scalar type of the format, by any of its two names (`uchar` or `uint8`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn named(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Its size in a binary body.
    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// Whether it holds whole numbers (list counts and vertex indices must).
    pub fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// Its range, for whole numbers written as text.
    pub fn range(self) -> (i64, i64) {
        match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => (i64::MIN, i64::MAX),
        }
    }
}

/// What a property holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// One value.
    Scalar(Scalar),
    /// A count, then that many values.
    List {
        /// The count's type (a whole number).
        count: Scalar,
        /// The values' type.
        item: Scalar,
    },
}

/// A declared property of an element.
#[derive(Debug, Clone, PartialEq)]
pub struct Property {
    pub name: String,
    pub kind: Kind,
}

/// A declared element: a name, how many the body holds, and the properties of each.
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    pub name: String,
    pub count: u64,
    pub properties: Vec<Property>,
    /// Where the `element` line is (errors about the count point there).
    pub span: Span,
}

impl Element {
    /// The fewest bytes one element takes in a body of `format`: each value in binary, and a
    /// digit and a separator per value as text; a list at least its count (it may be empty).
    pub fn min_bytes(&self, format: Format) -> u64 {
        self.properties
            .iter()
            .map(|p| match (format, p.kind) {
                (Format::Ascii, _) => 2,
                (_, Kind::Scalar(s)) | (_, Kind::List { count: s, .. }) => s.size() as u64,
            })
            .sum()
    }
}

/// A parsed header.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    pub format: Format,
    pub elements: Vec<Element>,
    /// Where the body starts: the byte after `end_header`'s line break.
    pub body_start: usize,
    /// How many lines the header has (the body's first line is the next).
    pub lines: usize,
}

impl Header {
    /// The element called `name`, if the header declares it.
    pub fn element(&self, name: &str) -> Option<&Element> {
        self.elements.iter().find(|e| e.name == name)
    }
}

/// Reads the header at the start of `bytes`; `path` names the file in errors, each at the
/// header line and word it is about.
pub fn parse(bytes: &[u8], path: &Path) -> Result<Header, SceneError> {
    let not_ply = || {
        SceneError::new(
            path,
            format!(
                "`{}` is not a PLY model: it does not start with the line `ply`",
                path.display()
            ),
        )
    };
    if !(bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n")) {
        return Err(not_ply());
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut offset = 0;
    let mut number = 0;
    loop {
        // Only the header's bytes are searched for its lines' ends.
        let rest = &bytes[offset..bytes.len().min(MAX_HEADER_BYTES)];
        let Some(end) = rest.iter().position(|&b| b == b'\n') else {
            let at = Span {
                line: number + 1,
                column: 1,
                offset,
                len: 0,
            };
            let message = if bytes.len() > MAX_HEADER_BYTES {
                format!("the header is longer than {MAX_HEADER_BYTES} bytes")
            } else {
                "the header ends without `end_header` (the file is cut short, or it is not a \
                 PLY model)"
                    .to_string()
            };
            return Err(SceneError::new(path, message).at(at).with_key("end_header"));
        };
        number += 1;
        let raw = &rest[..end];
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        let line = TextLine {
            path,
            number,
            offset,
            text: std::str::from_utf8(raw).map_err(|_| {
                SceneError::new(path, "the header is not text")
                    .at(Span {
                        line: number,
                        column: 1,
                        offset,
                        len: 0,
                    })
                    .with_key("header")
            })?,
        };
        offset += end + 1;
        let words: Vec<(usize, &str)> = line.words().collect();
        let Some(&(col, keyword)) = words.first() else {
            continue;
        };
        match keyword {
            "ply" if number == 1 => {}
            "comment" | "obj_info" => {}
            "format" => {
                if format.is_some() {
                    return Err(line.error(
                        col,
                        keyword.len(),
                        "format",
                        "a second `format` line".into(),
                    ));
                }
                format = Some(parse_format(&line, &words)?);
            }
            "element" => {
                if format.is_none() {
                    return Err(line.error(
                        col,
                        keyword.len(),
                        "element",
                        "an `element` before the `format` line".into(),
                    ));
                }
                let element = parse_element(&line, &words)?;
                if elements.iter().any(|e| e.name == element.name) {
                    let (c, w) = words[1];
                    return Err(line.error(
                        c,
                        w.len(),
                        "element",
                        format!("a second element `{w}`"),
                    ));
                }
                elements.push(element);
            }
            "property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(line.error(
                        col,
                        keyword.len(),
                        "property",
                        "a `property` before any `element`".into(),
                    ));
                };
                let property = parse_property(&line, &words)?;
                if element.properties.iter().any(|p| p.name == property.name) {
                    let (c, w) = *words.last().expect("a property has a name");
                    return Err(line.error(
                        c,
                        w.len(),
                        "property",
                        format!("a second property `{w}` in element `{}`", element.name),
                    ));
                }
                element.properties.push(property);
            }
            "end_header" => {
                let format = format.ok_or_else(|| {
                    line.error(
                        col,
                        keyword.len(),
                        "format",
                        "the header has no `format` line".into(),
                    )
                })?;
                return Ok(Header {
                    format,
                    elements,
                    body_start: offset,
                    lines: number,
                });
            }
            other => {
                return Err(line.error(
                    col,
                    other.len(),
                    "header",
                    format!(
                        "unknown header line `{other}`; expected `format`, `element`, `property`, \
                         `comment`, `obj_info` or `end_header`"
                    ),
                ))
            }
        }
    }
}

/// What a PLY header adds to a line's errors.
impl TextLine<'_> {
    /// The error for a line that lacks its `what`, pointing past its last word.
    fn missing(&self, key: &str, what: &str, usage: &str) -> SceneError {
        self.error(
            self.text.trim_end().len(),
            0,
            key,
            format!("`{key}` needs {what}: `{usage}`"),
        )
    }
}

fn parse_format(line: &TextLine<'_>, words: &[(usize, &str)]) -> Result<Format, SceneError> {
    const USAGE: &str = "format ascii|binary_little_endian|binary_big_endian 1.0";
    let &(col, name) = words
        .get(1)
        .ok_or_else(|| line.missing("format", "an encoding", USAGE))?;
    let format = match name {
        "ascii" => Format::Ascii,
        "binary_little_endian" => Format::LittleEndian,
        "binary_big_endian" => Format::BigEndian,
        _ => {
            return Err(line.error(
                col,
                name.len(),
                "format",
                format!("unknown encoding `{name}`; expected `ascii`, `binary_little_endian` or `binary_big_endian`"),
            ))
        }
    };
    let &(col, version) = words
        .get(2)
        .ok_or_else(|| line.missing("format", "a version", USAGE))?;
    if version != "1.0" {
        return Err(line.error(
            col,
            version.len(),
            "format",
            format!("PLY version `{version}` is not read; only 1.0 is"),
        ));
    }
    if let Some(&(col, extra)) = words.get(3) {
        return Err(line.error(
            col,
            extra.len(),
            "format",
            format!("unexpected `{extra}` after the version"),
        ));
    }
    Ok(format)
}

fn parse_element(line: &TextLine<'_>, words: &[(usize, &str)]) -> Result<Element, SceneError> {
    const USAGE: &str = "element NAME COUNT";
    let &(_, name) = words
        .get(1)
        .ok_or_else(|| line.missing("element", "a name", USAGE))?;
    let &(col, count) = words
        .get(2)
        .ok_or_else(|| line.missing("element", "a count", USAGE))?;
    let count: u64 = count.parse().map_err(|_| {
        line.error(
            col,
            count.len(),
            "element",
            format!("the count of `{name}` must be a whole number of at least 0, not `{count}`"),
        )
    })?;
    if let Some(&(c, extra)) = words.get(3) {
        return Err(line.error(
            c,
            extra.len(),
            "element",
            format!("unexpected `{extra}` after the count"),
        ));
    }
    Ok(Element {
        name: name.to_string(),
        count,
        properties: Vec::new(),
        span: line.span(col, words[2].1.len()),
    })
}

fn parse_property(line: &TextLine<'_>, words: &[(usize, &str)]) -> Result<Property, SceneError> {
    const USAGE: &str = "property TYPE NAME` or `property list COUNT_TYPE TYPE NAME";
    let scalar = |i: usize| -> Result<Scalar, SceneError> {
        let &(col, name) = words
            .get(i)
            .ok_or_else(|| line.missing("property", "a type", USAGE))?;
        Scalar::named(name).ok_or_else(|| {
            line.error(
                col,
                name.len(),
                "property",
                format!(
                    "unknown type `{name}`; expected one of char, uchar, short, ushort, int, uint, \
                     float, double (or int8, uint8, int16, uint16, int32, uint32, float32, float64)"
                ),
            )
        })
    };
    let (kind, name_at) = if words.get(1).map(|w| w.1) == Some("list") {
        let count = scalar(2)?;
        if !count.is_integer() {
            let (c, w) = words[2];
            return Err(line.error(
                c,
                w.len(),
                "property",
                format!("a list's count must be a whole-number type, not `{w}`"),
            ));
        }
        (
            Kind::List {
                count,
                item: scalar(3)?,
            },
            4,
        )
    } else {
        (Kind::Scalar(scalar(1)?), 2)
    };
    let &(_, name) = words
        .get(name_at)
        .ok_or_else(|| line.missing("property", "a name", USAGE))?;
    if let Some(&(c, extra)) = words.get(name_at + 1) {
        return Err(line.error(
            c,
            extra.len(),
            "property",
            format!("unexpected `{extra}` after the name"),
        ));
    }
    Ok(Property {
        name: name.to_string(),
        kind,
    })
}
