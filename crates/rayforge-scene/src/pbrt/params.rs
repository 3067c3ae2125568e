//! pbrt-v4's typed parameter lists: `"type name" value` or `"type name" [ values ]`, after a
//! directive's own arguments, up to the next token that is not a quoted string.
//!
//! Each parameter remembers where it was written and whether the scene's build read it: a
//! parameter nothing reads is reported as a warning naming it and its line, as pbrt-v4
//! reports it (a misspelt name, or one rayforge does not render). A parameter asked for under
//! another type than the file gives it is not read either, and its warning says which type
//! was expected. Parameters set by `Attribute` may go unused without a warning.

use super::input::{Loc, ValueBudget};
use super::lexer::Kind;
use super::stream::{number, Stream};
use crate::error::SceneError;
use glam::{DVec2, DVec3};
use std::cell::{Cell, RefCell};

/// A parameter's declared type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamType {
    /// `float`.
    Float,
    /// `integer`.
    Integer,
    /// `bool`.
    Bool,
    /// `string`.
    String,
    /// `texture`: the name of a texture.
    Texture,
    /// `point2`.
    Point2,
    /// `vector2`.
    Vector2,
    /// `point3` (also written `point`).
    Point3,
    /// `vector3` (also written `vector`).
    Vector3,
    /// `normal` (also written `normal3`).
    Normal,
    /// `rgb` (also written `color`).
    Rgb,
    /// `spectrum`: a named spectrum, a file, or wavelength–value pairs.
    Spectrum,
    /// `blackbody`: a temperature in kelvin.
    Blackbody,
}

/// The type names pbrt-v4 reads, for messages.
const TYPE_NAMES: &str = "float, integer, bool, string, texture, point2, vector2, point3, \
                          vector3, normal, rgb, spectrum, blackbody (and the older point, \
                          vector, normal3, color)";

impl ParamType {
    /// The type a declaration's first word names.
    fn parse(word: &str) -> Option<Self> {
        Some(match word {
            "float" => Self::Float,
            "integer" => Self::Integer,
            "bool" => Self::Bool,
            "string" => Self::String,
            "texture" => Self::Texture,
            "point2" => Self::Point2,
            "vector2" => Self::Vector2,
            "point3" | "point" => Self::Point3,
            "vector3" | "vector" => Self::Vector3,
            "normal" | "normal3" => Self::Normal,
            "rgb" | "color" => Self::Rgb,
            "spectrum" => Self::Spectrum,
            "blackbody" => Self::Blackbody,
            _ => return None,
        })
    }

    /// The type's name as pbrt-v4 writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Float => "float",
            Self::Integer => "integer",
            Self::Bool => "bool",
            Self::String => "string",
            Self::Texture => "texture",
            Self::Point2 => "point2",
            Self::Vector2 => "vector2",
            Self::Point3 => "point3",
            Self::Vector3 => "vector3",
            Self::Normal => "normal",
            Self::Rgb => "rgb",
            Self::Spectrum => "spectrum",
            Self::Blackbody => "blackbody",
        }
    }

    /// How many numbers one value of the type takes (0 for types of strings or booleans).
    fn arity(self) -> usize {
        match self {
            Self::Float | Self::Integer | Self::Blackbody => 1,
            Self::Point2 | Self::Vector2 => 2,
            Self::Point3 | Self::Vector3 | Self::Normal | Self::Rgb => 3,
            Self::Spectrum => 2,
            Self::Bool | Self::String | Self::Texture => 0,
        }
    }
}

/// A parameter's values.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// Numbers (every numeric type, a spectrum's wavelength–value pairs).
    Numbers(Vec<f64>),
    /// Quoted strings (`string`, `texture`, a named `spectrum`).
    Strings(Vec<String>),
    /// `true` and `false`.
    Bools(Vec<bool>),
}

/// One parameter as written.
#[derive(Debug, Clone)]
pub struct Param {
    /// Its declared type.
    pub ty: ParamType,
    /// Its name.
    pub name: String,
    /// Its values.
    pub values: Values,
    /// Where its declaration is.
    pub loc: Loc,
    /// Whether the build read it.
    used: Cell<bool>,
    /// Set by `Attribute`: it may go unused without a warning.
    may_be_unused: bool,
}

impl Param {
    /// `"type name"` as written, for messages.
    pub fn declaration(&self) -> String {
        format!("{} {}", self.ty.name(), self.name)
    }

    /// The parameter's numbers, or an error saying it holds none.
    fn numbers(&self) -> Result<&[f64], SceneError> {
        match &self.values {
            Values::Numbers(v) => Ok(v),
            _ => Err(self.error("takes numbers")),
        }
    }

    /// An error at the parameter, naming it.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        self.loc.error(Some(&self.declaration()), message)
    }
}

/// Reads the parameter list after a directive's arguments, up to the first token that is not
/// a quoted string (the next directive, or the end of the file); each value spends one of
/// `budget` as it is lexed, before it is kept.
pub fn parse(
    stream: &mut Stream<'_>,
    directive: &str,
    budget: &ValueBudget,
) -> Result<Vec<Param>, SceneError> {
    let mut list = Vec::new();
    while let Some(declaration) = stream.peek()? {
        if declaration.kind != Kind::Str {
            break;
        }
        stream.next()?;
        let loc = stream.loc(&declaration);
        let decl = declaration.string();
        let mut words = decl.split([' ', '\t']).filter(|w| !w.is_empty());
        let (Some(ty_word), Some(name), None) = (words.next(), words.next(), words.next()) else {
            return Err(loc.error(
                Some(directive),
                format!(
                    "a parameter of `{directive}` is declared as \"type name\" (such as \
                     \"float fov\"); found {}",
                    declaration.shown()
                ),
            ));
        };
        let ty = ParamType::parse(ty_word).ok_or_else(|| {
            loc.error(
                Some(&format!("{ty_word} {name}")),
                format!(
                    "unknown parameter type `{ty_word}` in `{directive}`; pbrt-v4's types are \
                     {TYPE_NAMES}"
                ),
            )
        })?;
        let key = format!("{} {name}", ty.name());
        let values = values(stream, directive, &key, ty, &loc, budget)?;
        list.push(Param {
            ty,
            name: name.to_string(),
            values,
            loc,
            used: Cell::new(false),
            may_be_unused: false,
        });
    }
    Ok(list)
}

/// The values after the declaration `key` of type `ty`: one token, or a bracketed list.
fn values(
    stream: &mut Stream<'_>,
    directive: &str,
    key: &str,
    ty: ParamType,
    loc: &Loc,
    budget: &ValueBudget,
) -> Result<Values, SceneError> {
    let first = stream.required(directive, &format!("the value of \"{key}\""))?;
    let mut tokens = Vec::new();
    if first.kind == Kind::Open {
        loop {
            let t = stream.required(directive, &format!("the `]` closing \"{key}\"'s values"))?;
            match t.kind {
                Kind::Close => break,
                Kind::Open => {
                    return Err(stream
                        .loc(&t)
                        .error(Some(key), "a `[` inside a parameter's values"))
                }
                _ => {
                    spend(stream, budget, &t, key)?;
                    tokens.push(t);
                }
            }
        }
    } else if first.kind == Kind::Close {
        return Err(stream.loc(&first).error(Some(key), "a `]` without its `[`"));
    } else {
        spend(stream, budget, &first, key)?;
        tokens.push(first);
    }
    let bad = |t: &super::lexer::Token<'_>, wanted: &str| {
        stream.loc(t).error(
            Some(key),
            format!("\"{key}\" takes {wanted}; found {}", t.shown()),
        )
    };
    let values = match ty {
        ParamType::Bool => Values::Bools(
            tokens
                .iter()
                .map(|t| match t.string().as_ref() {
                    "true" => Ok(true),
                    "false" => Ok(false),
                    _ => Err(bad(t, "`true` or `false`")),
                })
                .collect::<Result<_, _>>()?,
        ),
        ParamType::String | ParamType::Texture => Values::Strings(
            tokens
                .iter()
                .map(|t| match t.kind {
                    Kind::Str => Ok(t.string().into_owned()),
                    _ => Err(bad(t, "strings in quotes")),
                })
                .collect::<Result<_, _>>()?,
        ),
        ParamType::Spectrum if tokens.first().is_some_and(|t| t.kind == Kind::Str) => {
            Values::Strings(
                tokens
                    .iter()
                    .map(|t| match t.kind {
                        Kind::Str => Ok(t.string().into_owned()),
                        _ => Err(bad(t, "one spectrum's name or file in quotes")),
                    })
                    .collect::<Result<_, _>>()?,
            )
        }
        ParamType::Integer => Values::Numbers(
            tokens
                .iter()
                .map(|t| integer(t).ok_or_else(|| bad(t, "whole numbers")))
                .collect::<Result<_, _>>()?,
        ),
        _ => Values::Numbers(
            tokens
                .iter()
                .map(|t| number(t).ok_or_else(|| bad(t, "numbers")))
                .collect::<Result<_, _>>()?,
        ),
    };
    if let Values::Numbers(v) = &values {
        let arity = ty.arity();
        if arity > 1 && v.len() % arity != 0 {
            return Err(loc.error(
                Some(key),
                format!(
                    "\"{key}\" takes its numbers in groups of {arity}; {} is not a multiple \
                     of {arity}",
                    v.len()
                ),
            ));
        }
    }
    Ok(values)
}

/// Spends one value of `budget` on `token` of the parameter `key`: an error at the token once
/// none is left.
fn spend(
    stream: &Stream<'_>,
    budget: &ValueBudget,
    token: &super::lexer::Token<'_>,
    key: &str,
) -> Result<(), SceneError> {
    if !budget.take() {
        return Err(stream.loc(token).error(Some(key), budget.spent()));
    }
    match budget.stop_due() {
        Some(stop) => stream.loc(token).stopped(stop, key),
        None => Ok(()),
    }
}

/// A whole number as pbrt-v4 reads an `integer` (optional sign, digits, 32 bits).
fn integer(token: &super::lexer::Token<'_>) -> Option<f64> {
    if token.kind != Kind::Word {
        return None;
    }
    token.text.parse::<i32>().ok().map(f64::from)
}

/// A directive's parameters, with those `Attribute` set for its kind after them (a
/// directive's own come first, so they win), and what the build asked for.
#[derive(Debug, Default)]
pub struct Params {
    list: Vec<Param>,
    /// Names the build asked for, with the type it asked under.
    asked: RefCell<Vec<(String, ParamType)>>,
}

impl Params {
    /// The parameters `own`, then the `inherited` ones from `Attribute`.
    pub fn new(own: Vec<Param>, inherited: &[Param]) -> Self {
        let mut list = own;
        list.extend(inherited.iter().map(|p| Param {
            used: Cell::new(false),
            may_be_unused: true,
            ..p.clone()
        }));
        Self {
            list,
            asked: RefCell::new(Vec::new()),
        }
    }

    /// The parameters of `Attribute`, kept for the directives after it.
    pub fn into_attributes(self) -> Vec<Param> {
        self.list
    }

    /// The first parameter named `name` of one of the types `types`, marked as read.
    pub fn find(&self, name: &str, types: &[ParamType]) -> Option<&Param> {
        self.asked
            .borrow_mut()
            .extend(types.iter().map(|&t| (name.to_string(), t)));
        let found = self
            .list
            .iter()
            .find(|p| p.name == name && types.contains(&p.ty))?;
        found.used.set(true);
        Some(found)
    }

    /// A parameter that takes one value of `ty`, its numbers.
    fn one_number(&self, name: &str, ty: ParamType) -> Result<Option<(f64, &Param)>, SceneError> {
        let Some(p) = self.find(name, &[ty]) else {
            return Ok(None);
        };
        match p.numbers()? {
            [v] => Ok(Some((*v, p))),
            v => Err(p.error(format!("takes one value, not {}", v.len()))),
        }
    }

    /// A `float` parameter of one value.
    pub fn float(&self, name: &str) -> Result<Option<f64>, SceneError> {
        Ok(self.one_number(name, ParamType::Float)?.map(|(v, _)| v))
    }

    /// A `float` parameter of one value, with the parameter (for its place).
    pub fn float_at(&self, name: &str) -> Result<Option<(f64, &Param)>, SceneError> {
        self.one_number(name, ParamType::Float)
    }

    /// A `float` parameter of one value, `default` when absent.
    pub fn float_or(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    /// An `integer` parameter of one value, with the parameter (for its place).
    pub fn integer(&self, name: &str) -> Result<Option<(i64, &Param)>, SceneError> {
        Ok(self
            .one_number(name, ParamType::Integer)?
            .map(|(v, p)| (v as i64, p)))
    }

    /// A `bool` parameter of one value, `default` when absent.
    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        let Some(p) = self.find(name, &[ParamType::Bool]) else {
            return Ok(default);
        };
        match &p.values {
            Values::Bools(b) if b.len() == 1 => Ok(b[0]),
            _ => Err(p.error("takes one value, `true` or `false`")),
        }
    }

    /// A `string` parameter of one value, with the parameter.
    pub fn string(&self, name: &str) -> Result<Option<(&str, &Param)>, SceneError> {
        self.one_string(name, ParamType::String)
    }

    /// A `string` or `texture` parameter of one value of type `ty`.
    pub fn one_string(
        &self,
        name: &str,
        ty: ParamType,
    ) -> Result<Option<(&str, &Param)>, SceneError> {
        let Some(p) = self.find(name, &[ty]) else {
            return Ok(None);
        };
        match &p.values {
            Values::Strings(s) if s.len() == 1 => Ok(Some((s[0].as_str(), p))),
            _ => Err(p.error("takes one string")),
        }
    }

    /// The numbers of a parameter of type `ty` (any count, in groups of its arity).
    pub fn numbers(
        &self,
        name: &str,
        ty: ParamType,
    ) -> Result<Option<(&[f64], &Param)>, SceneError> {
        let Some(p) = self.find(name, &[ty]) else {
            return Ok(None);
        };
        Ok(Some((p.numbers()?, p)))
    }

    /// A `point3` (or `vector3`, `normal`) parameter's points.
    pub fn points3(
        &self,
        name: &str,
        ty: ParamType,
    ) -> Result<Option<(Vec<DVec3>, &Param)>, SceneError> {
        Ok(self.numbers(name, ty)?.map(|(v, p)| {
            (
                v.chunks_exact(3)
                    .map(|c| DVec3::new(c[0], c[1], c[2]))
                    .collect(),
                p,
            )
        }))
    }

    /// A `point2` parameter's points.
    pub fn points2(&self, name: &str) -> Result<Option<(Vec<DVec2>, &Param)>, SceneError> {
        Ok(self.numbers(name, ParamType::Point2)?.map(|(v, p)| {
            (
                v.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect(),
                p,
            )
        }))
    }

    /// A `point3` parameter of one point, `default` when absent.
    pub fn point3_or(&self, name: &str, default: DVec3) -> Result<DVec3, SceneError> {
        match self.points3(name, ParamType::Point3)? {
            None => Ok(default),
            Some((v, _)) if v.len() == 1 => Ok(v[0]),
            Some((v, p)) => Err(p.error(format!("takes one point, not {}", v.len()))),
        }
    }

    /// Whether the build asked for any parameter (a material no shape uses is never read).
    pub fn was_read(&self) -> bool {
        !self.asked.borrow().is_empty()
    }

    /// Warnings for the parameters nothing read, `what` naming the directive (`Shape
    /// "sphere"`).
    pub fn unused(&self, what: &str) -> Vec<SceneError> {
        let asked = self.asked.borrow();
        self.list
            .iter()
            .filter(|p| !p.used.get() && !p.may_be_unused)
            .map(|p| {
                let other: Vec<&str> = asked
                    .iter()
                    .filter(|(n, _)| *n == p.name)
                    .map(|(_, t)| t.name())
                    .collect();
                let hint = if other.is_empty() {
                    String::new()
                } else {
                    format!(
                        " (it is read as {}, not {})",
                        other.join(" or "),
                        p.ty.name()
                    )
                };
                p.loc.error(
                    Some(&p.declaration()),
                    format!(
                        "{what}: parameter \"{}\" is not used{hint}",
                        p.declaration()
                    ),
                )
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use std::rc::Rc;

    fn params(text: &str) -> Result<Params, SceneError> {
        let mut stream = Stream::new(text, Rc::from(Path::new("t.pbrt")));
        Ok(Params::new(
            parse(&mut stream, "Shape", &ValueBudget::new(1000))?,
            &[],
        ))
    }

    #[test]
    fn every_type_with_or_without_brackets() {
        let p = params(
            "\"float radius\" 2 \"integer n\" [ 3 ] \"bool on\" true \"bool off\" \"false\" \
             \"string name\" \"x\" \"point3 P\" [0 0 0 1 1 1] \"rgb L\" [1 2 3] \
             \"spectrum eta\" \"glass-BK7\" \"point2 uv\" [0 1] \"blackbody T\" 6500 \
             \"normal N\" [0 0 1] \"texture tex\" \"t\" \"vector3 v\" [1 0 0]",
        )
        .expect("parse");
        assert_eq!(p.float("radius").unwrap(), Some(2.0));
        assert_eq!(p.integer("n").unwrap().map(|x| x.0), Some(3));
        assert!(p.bool_or("on", false).unwrap());
        assert!(!p.bool_or("off", true).unwrap());
        assert_eq!(p.string("name").unwrap().map(|x| x.0), Some("x"));
        let (points, _) = p.points3("P", ParamType::Point3).unwrap().unwrap();
        assert_eq!(points, vec![DVec3::ZERO, DVec3::ONE]);
        assert_eq!(
            p.points2("uv").unwrap().unwrap().0,
            vec![DVec2::new(0.0, 1.0)]
        );
        let (rgb, _) = p.numbers("L", ParamType::Rgb).unwrap().unwrap();
        assert_eq!(rgb, &[1.0, 2.0, 3.0]);
        assert!(p.find("eta", &[ParamType::Spectrum]).is_some());
        assert!(p.find("T", &[ParamType::Blackbody]).is_some());
        assert!(p.find("N", &[ParamType::Normal]).is_some());
        assert!(p.one_string("tex", ParamType::Texture).unwrap().is_some());
        assert!(p.find("v", &[ParamType::Vector3]).is_some());
        assert!(p.unused("Shape").is_empty());
    }

    #[test]
    fn unused_and_mistyped_parameters_are_warned_about_by_line() {
        let p = params("\"float radius\" 2\n\"integer radius\" 3\n\"float colour\" 1").unwrap();
        assert_eq!(p.float("radius").unwrap(), Some(2.0));
        let warnings = p.unused("Shape \"sphere\"");
        assert_eq!(warnings.len(), 2);
        assert_eq!(warnings[0].span.map(|s| s.line), Some(2));
        assert!(
            warnings[0].message.contains("read as float"),
            "{}",
            warnings[0]
        );
        assert!(
            warnings[1].to_string().contains("t.pbrt:3:1"),
            "{}",
            warnings[1]
        );
        assert!(warnings[1].message.contains("\"float colour\" is not used"));
    }

    #[test]
    fn bad_parameters_are_located_errors() {
        let err = params("\"floaat fov\" 45").unwrap_err();
        assert!(err.to_string().contains("t.pbrt:1:1"), "{err}");
        assert!(
            err.message.contains("unknown parameter type `floaat`"),
            "{err}"
        );
        let err = params("\"float fov\" [ 45 x ]").unwrap_err();
        assert!(err.to_string().contains("1:18"), "{err}");
        let err = params("\"integer n\" 2.5").unwrap_err();
        assert!(err.message.contains("whole numbers"), "{err}");
        let err = params("\"point3 P\" [ 0 0 ]").unwrap_err();
        assert!(err.message.contains("groups of 3"), "{err}");
        let err = params("\"float fov\" [ 45").unwrap_err();
        assert!(err.message.contains("`]`"), "{err}");
        let err = params("\"fov\" 45").unwrap_err();
        assert!(err.message.contains("\"type name\""), "{err}");
        let err = params("\"bool b\" yes").unwrap_err();
        assert!(err.message.contains("`true` or `false`"), "{err}");
        let err = params("\"float a\" [1 2]").unwrap().float("a").unwrap_err();
        assert!(err.message.contains("one value"), "{err}");
        assert!(params("\"float nan\" nan").is_err());
    }

    #[test]
    fn attributes_come_after_and_may_go_unused() {
        let mut stream = Stream::new("\"float radius\" 3", Rc::from(Path::new("a.pbrt")));
        let inherited = parse(&mut stream, "Attribute", &ValueBudget::new(1000)).unwrap();
        let p = Params::new(Vec::new(), &inherited);
        assert!(p.unused("Shape").is_empty());
        assert_eq!(p.float("radius").unwrap(), Some(3.0));
        let mut stream = Stream::new("\"float radius\" 1", Rc::from(Path::new("a.pbrt")));
        let own = parse(&mut stream, "Shape", &ValueBudget::new(1000)).unwrap();
        assert_eq!(
            Params::new(own, &inherited).float("radius").unwrap(),
            Some(1.0)
        );
    }
}
