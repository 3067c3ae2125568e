//! The directives of a pbrt-v4 file, read in order into a [`Description`]: the options before
//! `WorldBegin` (camera, film, sampler, integrator, filter), then the world's shapes, lights,
//! materials, textures and object instances, each with the graphics state it was given in
//! (transform, orientation, material, area light), as pbrt-v4's `BasicSceneBuilder` keeps it.
//!
//! `AttributeBegin` saves the whole graphics state and `AttributeEnd` restores it; pbrt-v4
//! reads the deprecated `TransformBegin`/`TransformEnd` as the same (and warns once), so they
//! save more than the transform here too. Named coordinate systems, materials, textures, media
//! and objects are global, not part of the state. `Include` reads a file in place; `Import`
//! too, its graphics state left behind when it ends, as pbrt-v4's import builds with a copy.
//! Every file name resolves in the top-level file's folder, as pbrt-v4 resolves it.
//!
//! The current transformation matrix is a pair, the transform at `TransformTimes`' start and
//! at its end; `ActiveTransform` picks which of them the transform directives change. A
//! shape, an object instance or the camera given under a pair that differs moves (motion
//! blur); a light, a medium or a texture stands at the start transform, with a warning, as
//! pbrt-v4 has them (`BasicScene::AddLight`, `AddMedium`, and its textures).

use super::input::{Files, Loc};
use super::lexer::Kind;
use super::params::{self, Param, Params};
use super::stream::Stream;
use crate::error::SceneError;
use glam::{DMat4, DVec3, DVec4};
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

/// How deep `AttributeBegin`, `TransformBegin` and `ObjectBegin` may nest.
pub const MAX_NESTING: usize = 10_000;

/// A directive with its name (`Shape "sphere"`'s `sphere`), parameters and place.
#[derive(Debug)]
pub struct Entity {
    /// The type it names.
    pub name: String,
    /// Its parameters.
    pub params: Params,
    /// Where the directive is.
    pub loc: Loc,
    /// The directive, for messages (`Shape`).
    pub directive: &'static str,
}

impl Entity {
    /// How messages name it: `Shape "sphere"`.
    pub fn what(&self) -> String {
        format!("{} \"{}\"", self.directive, self.name)
    }

    /// An error at the directive.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        self.loc.error(Some(self.directive), message)
    }
}

/// Which material a shape takes.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialRef {
    /// The `Material` directive of this index in [`Description::materials`] (0: pbrt's
    /// default, a diffuse surface of reflectance 0.5).
    Index(usize),
    /// The material `MakeNamedMaterial` made under this name, named at `Loc`.
    Named(String, Loc),
}

/// A shape and the graphics state it was given in.
#[derive(Debug)]
pub struct ShapeEntity {
    /// The directive.
    pub entity: Entity,
    /// From the shape's space to the world at `TransformTimes`' start.
    pub world_from_object: DMat4,
    /// The same at its end, where that differs: the shape moves (`ActiveTransform`).
    pub world_from_object_end: Option<DMat4>,
    /// `ReverseOrientation` in force: the shape's front is its other side.
    pub reverse: bool,
    /// Its material.
    pub material: MaterialRef,
    /// The area light in force, shared by every shape in its scope.
    pub area_light: Option<Rc<Entity>>,
    /// The `MediumInterface` in force, where one names a medium.
    pub media: Option<MediaNames>,
}

/// A `MediumInterface`: the media inside and outside (empty: vacuum), and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct MediaNames {
    /// The inside medium's name.
    pub inside: String,
    /// The outside medium's name.
    pub outside: String,
    /// The directive.
    pub loc: Loc,
}

/// A light and where it stands.
#[derive(Debug)]
pub struct LightEntity {
    /// The directive.
    pub entity: Entity,
    /// From the light's space to the world.
    pub world_from_light: DMat4,
}

/// A texture.
#[derive(Debug)]
pub struct TextureEntity {
    /// `float` or `spectrum`.
    pub kind: String,
    /// Its name.
    pub name: String,
    /// The directive (its name is the texture's class: `imagemap`, `checkerboard`, …).
    pub entity: Entity,
    /// From the texture's space to the world (where the 3D mappings read points).
    pub world_from_texture: DMat4,
}

/// One use of a named object.
#[derive(Debug)]
pub struct InstanceUse {
    /// The object's name.
    pub name: String,
    /// Where `ObjectInstance` is.
    pub loc: Loc,
    /// From the object's space to the world at `TransformTimes`' start.
    pub world_from_instance: DMat4,
    /// The same at its end, where that differs: the instance moves.
    pub world_from_instance_end: Option<DMat4>,
}

/// `TransformTimes`: the instants of the transform pair's two ends (pbrt-v4's default 0 and
/// 1), and where they were given.
#[derive(Debug, Clone, PartialEq)]
pub struct TransformTimes {
    /// When the first transform holds.
    pub start: f64,
    /// When the second does.
    pub end: f64,
    /// The directive (`None`: the default).
    pub loc: Option<Loc>,
}

impl Default for TransformTimes {
    fn default() -> Self {
        Self {
            start: 0.0,
            end: 1.0,
            loc: None,
        }
    }
}

/// The options block: what comes before `WorldBegin`.
#[derive(Debug, Default)]
pub struct Options {
    /// `Camera`, with its camera-from-world transform (at `TransformTimes`' start).
    pub camera: Option<(Entity, DMat4)>,
    /// The camera's camera-from-world transform at `TransformTimes`' end, where that differs:
    /// the camera moves.
    pub camera_end: Option<DMat4>,
    /// The `TransformTimes` in force at `Camera`, which its two transforms hold at.
    pub camera_times: TransformTimes,
    /// The last `TransformTimes` (it is read only before `WorldBegin`): the times of the
    /// world's transform pairs.
    pub transform_times: TransformTimes,
    /// `Film`.
    pub film: Option<Entity>,
    /// `Sampler`.
    pub sampler: Option<Entity>,
    /// `Integrator`.
    pub integrator: Option<Entity>,
    /// `PixelFilter`.
    pub filter: Option<Entity>,
    /// `Option "name" value`: each name, its value's token text, and where.
    pub options: Vec<(String, String, Loc)>,
    /// The `MediumInterface` in force at `Camera`, whose outside the camera sits in.
    pub camera_medium: Option<MediaNames>,
}

/// Everything a scene's files say.
#[derive(Debug, Default)]
pub struct Description {
    /// The options block.
    pub options: Options,
    /// Whether `WorldBegin` was read.
    pub world_begun: bool,
    /// The `Material` directives, in order; the first is pbrt's default material.
    pub materials: Vec<Option<Entity>>,
    /// `MakeNamedMaterial`'s materials.
    pub named_materials: HashMap<String, Entity>,
    /// `Texture`'s textures, in the order they were made (a texture may read only those
    /// before it, as in pbrt-v4).
    pub textures: Vec<TextureEntity>,
    /// Each texture's place in `textures`, by its type (`float`, `spectrum`) and name.
    pub texture_index: HashMap<(String, String), usize>,
    /// `MakeNamedMedium`'s media, by name, with the transform in force there (from the
    /// medium's space to the world).
    pub media: HashMap<String, (Entity, DMat4)>,
    /// The world's shapes.
    pub shapes: Vec<ShapeEntity>,
    /// The world's lights.
    pub lights: Vec<LightEntity>,
    /// Named objects: their shapes, in the objects' own space.
    pub objects: HashMap<String, (Vec<ShapeEntity>, Loc)>,
    /// The uses of named objects.
    pub instances: Vec<InstanceUse>,
    /// What the reader worked around.
    pub warnings: Vec<SceneError>,
}

/// The graphics state (see the [module](self)).
#[derive(Debug, Clone)]
struct GraphicsState {
    /// The current transformation matrix at the shutter's opening and closing.
    ctm: [DMat4; 2],
    /// Which of the two the transform directives change.
    active: [bool; 2],
    reverse: bool,
    material: MaterialRef,
    area_light: Option<Rc<Entity>>,
    media: Option<MediaNames>,
    /// `Attribute`'s parameters for shapes, lights, materials, media and textures.
    attributes: [Rc<Vec<Param>>; 5],
}

/// Which kind of directive an `Attribute` target is (an index into the state's attributes).
fn attribute_target(name: &str) -> Option<usize> {
    ["shape", "light", "material", "medium", "texture"]
        .iter()
        .position(|t| *t == name)
}

/// What a nesting directive opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Opened {
    Attribute,
    Object,
}

/// The reader's state across files.
struct Reader<'f> {
    files: &'f mut Files,
    out: Description,
    state: GraphicsState,
    stack: Vec<(GraphicsState, Opened, Loc)>,
    named_systems: HashMap<String, [DMat4; 2]>,
    /// The object being defined (`ObjectBegin`), its name and shapes.
    object: Option<(String, Loc, Vec<ShapeEntity>)>,
    /// Stop at `WorldBegin` (to read only the options).
    options_only: bool,
    warned_transform_begin: bool,
}

/// Reads the scene whose top-level file `files` names.
pub fn read(files: &mut Files) -> Result<Description, SceneError> {
    read_with(files, false)
}

/// Reads the top-level file's options block only, up to `WorldBegin`.
pub fn read_options(files: &mut Files) -> Result<Description, SceneError> {
    read_with(files, true)
}

fn read_with(files: &mut Files, options_only: bool) -> Result<Description, SceneError> {
    let text = files.read_main()?;
    let main: Rc<Path> = Rc::from(files.main_path());
    let mut reader = Reader {
        files,
        out: Description {
            materials: vec![None],
            ..Description::default()
        },
        state: GraphicsState {
            ctm: [DMat4::IDENTITY; 2],
            active: [true; 2],
            reverse: false,
            material: MaterialRef::Index(0),
            area_light: None,
            media: None,
            attributes: Default::default(),
        },
        stack: Vec::new(),
        named_systems: HashMap::new(),
        object: None,
        options_only,
        warned_transform_begin: false,
    };
    let mut stream = Stream::new(&text, main.clone());
    reader.read_stream(&mut stream, 0)?;
    if options_only {
        return Ok(reader.out);
    }
    let end = Loc {
        file: main,
        span: stream_end(&text),
    };
    if let Some((_, opened, loc)) = reader.stack.last() {
        let what = match opened {
            Opened::Attribute => "AttributeBegin",
            Opened::Object => "ObjectBegin",
        };
        return Err(loc.error(
            Some(what),
            format!("this `{what}` has no matching end before the scene's files end"),
        ));
    }
    if !reader.out.world_begun {
        return Err(end.error(
            Some("WorldBegin"),
            "the scene's files end before `WorldBegin`: a pbrt scene describes its world \
             after it",
        ));
    }
    Ok(reader.out)
}

/// The place just past the end of `text`.
fn stream_end(text: &str) -> crate::error::Span {
    let line = 1 + text.matches('\n').count();
    let last = text.rsplit('\n').next().unwrap_or("");
    crate::error::Span {
        line,
        column: last.chars().count() + 1,
        offset: text.len(),
        len: 0,
    }
}

impl Reader<'_> {
    fn warn(&mut self, error: SceneError) {
        self.out.warnings.push(error);
    }

    /// Reads one file's directives; `depth` counts the files including it.
    fn read_stream(&mut self, stream: &mut Stream<'_>, depth: usize) -> Result<(), SceneError> {
        while let Some(token) = stream.next()? {
            let loc = stream.loc(&token);
            if token.kind != Kind::Word {
                return Err(loc.error(
                    None,
                    format!(
                        "expected a directive (such as `Shape`), found {}",
                        token.shown()
                    ),
                ));
            }
            if self.options_only && token.text == "WorldBegin" {
                return Ok(());
            }
            loc.stopped(self.files.stop(), token.text)?;
            self.directive(token.text, loc, stream, depth)?;
        }
        Ok(())
    }

    /// Refuses `name` inside the world block (`VERIFY_OPTIONS`).
    fn options_block(&self, name: &str, loc: &Loc) -> Result<(), SceneError> {
        if self.out.world_begun {
            return Err(loc.error(
                Some(name),
                format!("`{name}` sets an option: it belongs before `WorldBegin`"),
            ));
        }
        Ok(())
    }

    /// Refuses `name` before `WorldBegin` (`VERIFY_WORLD`).
    fn world_block(&self, name: &str, loc: &Loc) -> Result<(), SceneError> {
        if !self.out.world_begun {
            return Err(loc.error(
                Some(name),
                format!("`{name}` describes the world: it belongs after `WorldBegin`"),
            ));
        }
        Ok(())
    }

    /// An entity: the directive's quoted name and its parameters, with `attributes` after.
    fn entity(
        &self,
        stream: &mut Stream<'_>,
        directive: &'static str,
        loc: Loc,
        attributes: &[Param],
    ) -> Result<Entity, SceneError> {
        let (name, _) = stream.string(directive, "a type in quotes")?;
        let own = params::parse(stream, directive, self.files.values())?;
        Ok(Entity {
            name,
            params: Params::new(own, attributes),
            loc,
            directive,
        })
    }

    /// The current transform at `TransformTimes`' end, where it differs from the start's.
    fn moving_end(&self) -> Option<DMat4> {
        let [start, end] = self.state.ctm;
        (start != end).then_some(end)
    }

    /// Warns that `entity`, a `what` (light, medium, texture), is given under a moving
    /// transform and stands where the start transform puts it, as pbrt-v4 does.
    fn note_animated(&mut self, entity: &Entity, what: &str) {
        if self.moving_end().is_some() {
            self.warn(entity.error(format!(
                "the transform moves (`ActiveTransform`), and a {what} does not: it stands \
                 where the start transform puts it, as in pbrt-v4"
            )));
        }
    }

    /// Applies `f` to the active transforms.
    fn transform(&mut self, f: impl Fn(DMat4) -> DMat4) {
        for i in 0..2 {
            if self.state.active[i] {
                self.state.ctm[i] = f(self.state.ctm[i]);
            }
        }
    }

    fn push(&mut self, opened: Opened, loc: Loc, name: &str) -> Result<(), SceneError> {
        if self.stack.len() >= MAX_NESTING {
            return Err(loc.error(
                Some(name),
                format!("more than {MAX_NESTING} levels of nesting"),
            ));
        }
        self.stack.push((self.state.clone(), opened, loc));
        Ok(())
    }

    fn pop(&mut self, opened: Opened, loc: &Loc, name: &str) -> Result<(), SceneError> {
        match self.stack.last() {
            None => Err(loc.error(
                Some(name),
                format!("`{name}` without an open `{}`", opening(opened)),
            )),
            Some((_, o, at)) if *o != opened => Err(loc.error(
                Some(name),
                format!(
                    "`{name}` closes the `{}` at line {}, column {}, which needs its own end",
                    opening(*o),
                    at.span.line,
                    at.span.column
                ),
            )),
            Some(_) => {
                let (state, _, _) = self.stack.pop().expect("just looked");
                self.state = state;
                Ok(())
            }
        }
    }

    /// Reads one directive named `name` at `loc`.
    fn directive(
        &mut self,
        name: &str,
        loc: Loc,
        stream: &mut Stream<'_>,
        depth: usize,
    ) -> Result<(), SceneError> {
        match name {
            "AttributeBegin" => {
                self.world_block(name, &loc)?;
                self.push(Opened::Attribute, loc, name)?;
            }
            "AttributeEnd" => {
                self.world_block(name, &loc)?;
                self.pop(Opened::Attribute, &loc, name)?;
            }
            "TransformBegin" | "TransformEnd" => {
                if !self.warned_transform_begin {
                    self.warned_transform_begin = true;
                    self.warn(loc.error(
                        Some(name),
                        "TransformBegin/End are deprecated in pbrt-v4, which reads them as \
                         AttributeBegin/End (they save the whole graphics state)",
                    ));
                }
                if name == "TransformBegin" {
                    self.push(Opened::Attribute, loc, name)?;
                } else {
                    self.pop(Opened::Attribute, &loc, name)?;
                }
            }
            "Attribute" => {
                let (target, target_loc) = stream.string(name, "a target in quotes")?;
                let own = params::parse(stream, name, self.files.values())?;
                let index = attribute_target(&target).ok_or_else(|| {
                    target_loc.error(
                        Some(name),
                        format!(
                            "unknown `Attribute` target \"{target}\": it is \"shape\", \
                             \"light\", \"material\", \"medium\" or \"texture\""
                        ),
                    )
                })?;
                let mut list = (*self.state.attributes[index]).clone();
                list.extend(Params::new(own, &[]).into_attributes());
                self.state.attributes[index] = Rc::new(list);
            }
            "ActiveTransform" => {
                let token = stream.required(name, "All, StartTime or EndTime")?;
                self.state.active = match token.text {
                    "All" => [true, true],
                    "StartTime" => [true, false],
                    "EndTime" => [false, true],
                    _ => {
                        return Err(stream.loc(&token).error(
                            Some(name),
                            format!(
                                "`ActiveTransform` takes All, StartTime or EndTime, found {}",
                                token.shown()
                            ),
                        ))
                    }
                };
            }
            "TransformTimes" => {
                self.options_block(name, &loc)?;
                let [start, end] = stream.numbers::<2>(name)?;
                self.out.options.transform_times = TransformTimes {
                    start,
                    end,
                    loc: Some(loc),
                };
            }
            "Identity" => self.transform(|_| DMat4::IDENTITY),
            "Translate" => {
                let [x, y, z] = stream.numbers::<3>(name)?;
                self.transform(|m| m * DMat4::from_translation(DVec3::new(x, y, z)));
            }
            "Scale" => {
                let [x, y, z] = stream.numbers::<3>(name)?;
                self.transform(|m| m * DMat4::from_scale(DVec3::new(x, y, z)));
            }
            "Rotate" => {
                let [angle, x, y, z] = stream.numbers::<4>(name)?;
                let axis = DVec3::new(x, y, z).try_normalize().ok_or_else(|| {
                    loc.error(Some(name), "`Rotate` turns about an axis of length 0")
                })?;
                let r = DMat4::from_axis_angle(axis, angle.to_radians());
                self.transform(|m| m * r);
            }
            "LookAt" => {
                let v = stream.numbers::<9>(name)?;
                let look = look_at(
                    DVec3::new(v[0], v[1], v[2]),
                    DVec3::new(v[3], v[4], v[5]),
                    DVec3::new(v[6], v[7], v[8]),
                )
                .ok_or_else(|| {
                    loc.error(
                        Some(name),
                        "`LookAt` needs an eye apart from the point it looks at, and an up \
                         vector not along the line of sight",
                    )
                })?;
                self.transform(|m| m * look);
            }
            "Transform" => {
                let m = DMat4::from_cols_array(&stream.matrix(name)?);
                self.transform(|_| m);
            }
            "ConcatTransform" => {
                let m = DMat4::from_cols_array(&stream.matrix(name)?);
                self.transform(|c| c * m);
            }
            "CoordinateSystem" => {
                let (system, _) = stream.string(name, "a name in quotes")?;
                self.named_systems.insert(system, self.state.ctm);
            }
            "CoordSysTransform" => {
                let (system, at) = stream.string(name, "a name in quotes")?;
                match self.named_systems.get(&system) {
                    Some(ctm) => self.state.ctm = *ctm,
                    None => self.warn(at.error(
                        Some(name),
                        format!(
                            "no coordinate system is named \"{system}\"; the transform is \
                                 left as it is"
                        ),
                    )),
                }
            }
            "ReverseOrientation" => {
                self.world_block(name, &loc)?;
                self.state.reverse = !self.state.reverse;
            }
            "ColorSpace" => {
                let (space, at) = stream.string(name, "a colour space's name in quotes")?;
                if space != "srgb" {
                    return Err(at.error(
                        Some(name),
                        format!(
                            "colour space \"{space}\": rayforge renders in linear sRGB and \
                             reads only \"srgb\""
                        ),
                    ));
                }
            }
            "Option" => {
                let (option, _) = stream.string(name, "an option's name in quotes")?;
                let value = stream.required(name, "the option's value")?;
                self.out
                    .options
                    .options
                    .push((option, value.string().into_owned(), loc));
            }
            "Camera" => {
                self.options_block(name, &loc)?;
                let entity = self.entity(stream, "Camera", loc, &[])?;
                let camera_from_world = self.state.ctm[0];
                if camera_from_world.determinant().abs() < 1e-300 || !camera_from_world.is_finite()
                {
                    return Err(entity.error("the transform before `Camera` is singular"));
                }
                let camera_end = self.moving_end();
                if camera_end.is_some_and(|m| m.determinant().abs() < 1e-300 || !m.is_finite()) {
                    return Err(entity.error(
                        "the transform before `Camera` is singular at `TransformTimes`' end",
                    ));
                }
                self.named_systems
                    .insert("camera".into(), self.state.ctm.map(|m| m.inverse()));
                self.out.options.camera = Some((entity, camera_from_world));
                self.out.options.camera_end = camera_end;
                self.out.options.camera_times = self.out.options.transform_times.clone();
                // pbrt-v4: the camera sits in the outside medium of the interface in force.
                self.out.options.camera_medium = self.state.media.clone();
            }
            "Film" | "Sampler" | "Integrator" | "PixelFilter" | "Accelerator" => {
                self.options_block(name, &loc)?;
                let directive = match name {
                    "Film" => "Film",
                    "Sampler" => "Sampler",
                    "Integrator" => "Integrator",
                    "PixelFilter" => "PixelFilter",
                    _ => "Accelerator",
                };
                let entity = self.entity(stream, directive, loc, &[])?;
                let options = &mut self.out.options;
                match name {
                    "Film" => options.film = Some(entity),
                    "Sampler" => options.sampler = Some(entity),
                    "Integrator" => options.integrator = Some(entity),
                    "PixelFilter" => options.filter = Some(entity),
                    // rayforge builds its own BVH: the accelerator's choice means nothing.
                    _ => {}
                }
            }
            "WorldBegin" => {
                self.options_block(name, &loc)?;
                self.out.world_begun = true;
                self.state.ctm = [DMat4::IDENTITY; 2];
                self.state.active = [true; 2];
                self.named_systems.insert("world".into(), self.state.ctm);
            }
            "WorldEnd" => self.warn(loc.error(
                Some(name),
                "`WorldEnd` is pbrt-v3's; pbrt-v4 has none (the world ends with the file): \
                 ignored",
            )),
            "Include" | "Import" => {
                let (file, at) = stream.string(name, "a file name in quotes")?;
                if name == "Import" {
                    self.world_block(name, &loc)?;
                }
                let most = self.files.limits().include_depth;
                if depth + 1 >= most {
                    return Err(at.error(
                        Some(name),
                        format!(
                            "files included more than {most} deep (does a file include \
                             itself? `--max-pbrt-include-depth`)"
                        ),
                    ));
                }
                let path = self.files.resolve(&file);
                let text = self.files.read_named(&path, &at, name)?;
                let mut inner = Stream::new(&text, Rc::from(path.as_path()));
                if name == "Import" {
                    let (state, depth_before) = (self.state.clone(), self.stack.len());
                    self.read_stream(&mut inner, depth + 1)?;
                    if self.stack.len() != depth_before {
                        return Err(at.error(
                            Some(name),
                            "the imported file leaves an `AttributeBegin` or `ObjectBegin` \
                             open",
                        ));
                    }
                    self.state = state;
                } else {
                    self.read_stream(&mut inner, depth + 1)?;
                }
            }
            "Material" => {
                self.world_block(name, &loc)?;
                let attributes = self.state.attributes[2].clone();
                let entity = self.entity(stream, "Material", loc, &attributes)?;
                self.out.materials.push(Some(entity));
                self.state.material = MaterialRef::Index(self.out.materials.len() - 1);
            }
            "MakeNamedMaterial" => {
                self.world_block(name, &loc)?;
                let attributes = self.state.attributes[2].clone();
                let entity = self.entity(stream, "MakeNamedMaterial", loc, &attributes)?;
                if self.out.named_materials.contains_key(&entity.name) {
                    return Err(
                        entity.error(format!("the material \"{}\" is made twice", entity.name))
                    );
                }
                self.out.named_materials.insert(entity.name.clone(), entity);
            }
            "NamedMaterial" => {
                self.world_block(name, &loc)?;
                let (material, at) = stream.string(name, "a material's name in quotes")?;
                self.state.material = MaterialRef::Named(material, at);
            }
            "Texture" => {
                self.world_block(name, &loc)?;
                let (texture, _) = stream.string(name, "the texture's name in quotes")?;
                let (kind, kind_at) = stream.string(
                    name,
                    "the texture's type in quotes (\"float\" or \"spectrum\")",
                )?;
                if kind != "float" && kind != "spectrum" {
                    return Err(kind_at.error(
                        Some(name),
                        format!("a texture is \"float\" or \"spectrum\", not \"{kind}\""),
                    ));
                }
                let attributes = self.state.attributes[4].clone();
                let entity = self.entity(stream, "Texture", loc, &attributes)?;
                self.note_animated(&entity, "texture");
                // Float and spectrum textures have a name space each, as in pbrt-v4.
                let key = (kind.clone(), texture.clone());
                if self.out.texture_index.contains_key(&key) {
                    return Err(entity.error(format!(
                        "the {kind} texture \"{}\" is made twice",
                        crate::error::clip_to(&texture, 60)
                    )));
                }
                self.out.texture_index.insert(key, self.out.textures.len());
                self.out.textures.push(TextureEntity {
                    kind,
                    name: texture,
                    entity,
                    world_from_texture: self.state.ctm[0],
                });
            }
            "MakeNamedMedium" => {
                let attributes = self.state.attributes[3].clone();
                let entity = self.entity(stream, "MakeNamedMedium", loc, &attributes)?;
                self.note_animated(&entity, "medium");
                if self.out.media.contains_key(&entity.name) {
                    return Err(
                        entity.error(format!("the medium \"{}\" is made twice", entity.name))
                    );
                }
                self.out
                    .media
                    .insert(entity.name.clone(), (entity, self.state.ctm[0]));
            }
            "MediumInterface" => {
                let (inside, _) = stream.string(name, "the inside medium's name in quotes")?;
                let outside = match stream.peek()? {
                    Some(t) if t.kind == Kind::Str => {
                        stream.next()?;
                        t.string().into_owned()
                    }
                    _ => inside.clone(),
                };
                self.state.media =
                    (!inside.is_empty() || !outside.is_empty()).then_some(MediaNames {
                        inside,
                        outside,
                        loc,
                    });
            }
            "LightSource" => {
                self.world_block(name, &loc)?;
                let attributes = self.state.attributes[1].clone();
                let entity = self.entity(stream, "LightSource", loc, &attributes)?;
                self.note_animated(&entity, "light");
                self.out.lights.push(LightEntity {
                    entity,
                    world_from_light: self.state.ctm[0],
                });
            }
            "AreaLightSource" => {
                self.world_block(name, &loc)?;
                let attributes = self.state.attributes[1].clone();
                let entity = self.entity(stream, "AreaLightSource", loc, &attributes)?;
                self.state.area_light = Some(Rc::new(entity));
            }
            "Shape" => {
                self.world_block(name, &loc)?;
                let attributes = self.state.attributes[0].clone();
                let entity = self.entity(stream, "Shape", loc, &attributes)?;
                let shape = ShapeEntity {
                    entity,
                    world_from_object: self.state.ctm[0],
                    world_from_object_end: self.moving_end(),
                    reverse: self.state.reverse,
                    material: self.state.material.clone(),
                    area_light: self.state.area_light.clone(),
                    media: self.state.media.clone(),
                };
                match &mut self.object {
                    Some((_, _, shapes)) => shapes.push(shape),
                    None => self.out.shapes.push(shape),
                }
            }
            "ObjectBegin" => {
                self.world_block(name, &loc)?;
                let (object, at) = stream.string(name, "the object's name in quotes")?;
                if self.object.is_some() {
                    return Err(at.error(Some(name), "`ObjectBegin` inside another object"));
                }
                if self.out.objects.contains_key(&object) {
                    return Err(at.error(
                        Some(name),
                        format!("the object \"{object}\" is defined twice"),
                    ));
                }
                self.push(Opened::Object, loc.clone(), name)?;
                self.object = Some((object, loc, Vec::new()));
            }
            "ObjectEnd" => {
                self.world_block(name, &loc)?;
                self.pop(Opened::Object, &loc, name)?;
                let (object, at, shapes) = self.object.take().expect("an object is open");
                self.out.objects.insert(object, (shapes, at));
            }
            "ObjectInstance" => {
                self.world_block(name, &loc)?;
                let (object, _) = stream.string(name, "the object's name in quotes")?;
                if self.object.is_some() {
                    return Err(
                        loc.error(Some(name), "`ObjectInstance` inside an object's definition")
                    );
                }
                self.out.instances.push(InstanceUse {
                    name: object,
                    loc,
                    world_from_instance: self.state.ctm[0],
                    world_from_instance_end: self.moving_end(),
                });
            }
            _ => {
                return Err(loc.error(
                    Some(name),
                    format!("unknown directive `{}`", crate::error::clip_to(name, 60)),
                ))
            }
        }
        Ok(())
    }
}

/// What opens a nesting of kind `opened`.
fn opening(opened: Opened) -> &'static str {
    match opened {
        Opened::Attribute => "AttributeBegin",
        Opened::Object => "ObjectBegin",
    }
}

/// pbrt's `LookAt`: the camera-from-world transform of an eye at `eye` looking at `at` with
/// `up` up (the camera looks down its +z, +y up, +x to the right in pbrt's left-handed
/// space). `None` when the eye is at the point or `up` lies along the line of sight.
pub fn look_at(eye: DVec3, at: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (at - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(eye.x, eye.y, eye.z, 1.0),
    );
    Some(world_from_camera.inverse())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_sees_down_its_z() {
        let m = look_at(DVec3::new(0.0, 0.0, -5.0), DVec3::ZERO, DVec3::Y).unwrap();
        // The point looked at is straight ahead on the camera's +z.
        let p = m.transform_point3(DVec3::ZERO);
        assert!((p - DVec3::new(0.0, 0.0, 5.0)).length() < 1e-12, "{p}");
        // World +x is the camera's right (+x) for a camera looking down world +z.
        let r = m.transform_vector3(DVec3::X);
        assert!((r - DVec3::X).length() < 1e-12, "{r}");
        assert!(look_at(DVec3::ZERO, DVec3::Y, DVec3::Y).is_none());
    }
}
