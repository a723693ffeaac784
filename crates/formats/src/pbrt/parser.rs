//! The pbrt-v4 parser: reads directives and their arguments from the token stream (which
//! follows `Include`d files) and hands them to the [`SceneBuilder`].
//!
//! Syntax lives here (what each directive takes: numbers, a bracketed matrix, a quoted
//! name, a parameter list); meaning lives in the builder.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;

use super::builder::SceneBuilder;
use super::params::{number, Param, ParamSet};
use super::tokenizer::{Token, TokenKind, Tokenizer};
use super::{LoadOptions, LoadedScene};
use crate::error::{io_error_text, Location, SceneError};
use crate::transform::{from_pbrt_array, look_at, rotate, scale, translate};

/// How deeply `Include` may nest (a file including itself hits this).
const MAX_INCLUDE_DEPTH: usize = 64;

/// One open file: its tokenizer and directory.
#[derive(Debug)]
struct Input {
    tokens: Tokenizer,
    dir: PathBuf,
}

/// Parses a scene, following `Include`s.
#[derive(Debug)]
pub struct Parser {
    inputs: Vec<Input>,
    peeked: Option<Token>,
    /// Where the most recently finished file ended.
    last_end: Location,
    builder: SceneBuilder,
}

impl Parser {
    /// A parser for `source`, shown as `name` in messages; relative file names are resolved
    /// against `base_dir`.
    #[must_use]
    pub fn new(source: &str, name: &str, base_dir: &Path, options: &LoadOptions) -> Self {
        let file: Arc<str> = name.into();
        Self {
            last_end: Location::new(file.clone(), 1, 1),
            inputs: vec![Input {
                tokens: Tokenizer::new(source, file),
                dir: base_dir.to_path_buf(),
            }],
            peeked: None,
            builder: SceneBuilder::new(base_dir, options.files.clone(), options.limits),
        }
    }

    /// Parse everything and build the scene.
    ///
    /// # Errors
    /// The first problem found, with its location.
    pub fn run(mut self) -> Result<LoadedScene, SceneError> {
        while let Some(tok) = self.next()? {
            // The file a directive comes from is still on top of the stack (files are only
            // popped when reading past their end), so its directory is the one to resolve
            // the directive's file names against, even if reading the directive's arguments
            // runs off the end of an included file.
            if let Some(input) = self.inputs.last() {
                self.builder.input.current_dir.clone_from(&input.dir);
            }
            match tok.kind {
                TokenKind::Word(w) => self.directive(&w, tok.loc)?,
                other => {
                    return Err(SceneError::syntax(
                        &tok.loc,
                        format!("expected a directive, found {other}"),
                    ))
                }
            }
        }
        let end = self.last_end.clone();
        self.builder.finish(&end)
    }

    // --- Token stream -----------------------------------------------------------------

    fn next(&mut self) -> Result<Option<Token>, SceneError> {
        if let Some(t) = self.peeked.take() {
            return Ok(Some(t));
        }
        while let Some(input) = self.inputs.last_mut() {
            if let Some(t) = input.tokens.next_token()? {
                return Ok(Some(t));
            }
            self.last_end = input.tokens.location();
            self.inputs.pop();
        }
        Ok(None)
    }

    fn peek(&mut self) -> Result<Option<&Token>, SceneError> {
        if self.peeked.is_none() {
            self.peeked = self.next()?;
        }
        Ok(self.peeked.as_ref())
    }

    /// The next token; `what` names what was expected if there is none.
    fn expect_token(&mut self, what: &str) -> Result<Token, SceneError> {
        match self.next()? {
            Some(t) => Ok(t),
            None => Err(SceneError::syntax(
                &self.last_end,
                format!("expected {what}, found end of file"),
            )),
        }
    }

    fn expect_string(&mut self, what: &str) -> Result<(String, Location), SceneError> {
        let tok = self.expect_token(what)?;
        match tok.kind {
            TokenKind::Str(s) => Ok((s, tok.loc)),
            other => Err(SceneError::syntax(&tok.loc, format!("expected {what}, found {other}"))),
        }
    }

    fn numbers<const N: usize>(&mut self) -> Result<[f32; N], SceneError> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = number(&self.expect_token("a number")?)?;
        }
        Ok(out)
    }

    /// `[ 16 numbers ]`
    fn matrix(&mut self) -> Result<[f32; 16], SceneError> {
        let open = self.expect_token("\"[\"")?;
        if open.kind != TokenKind::OpenBracket {
            return Err(SceneError::syntax(
                &open.loc,
                format!("expected \"[\", found {}", open.kind),
            ));
        }
        let m = self.numbers::<16>()?;
        let close = self.expect_token("\"]\" after 16 numbers")?;
        if close.kind != TokenKind::CloseBracket {
            return Err(SceneError::syntax(
                &close.loc,
                format!("expected \"]\" after 16 numbers, found {}", close.kind),
            ));
        }
        Ok(m)
    }

    /// `"type name" value-or-[values]` pairs until the next token that is not a string.
    fn param_list(&mut self) -> Result<Vec<Param>, SceneError> {
        let mut params = Vec::new();
        while matches!(
            self.peek()?,
            Some(Token {
                kind: TokenKind::Str(_),
                ..
            })
        ) {
            let Some(Token {
                kind: TokenKind::Str(decl),
                loc,
            }) = self.next()?
            else {
                break;
            };
            let values = self.param_values(&decl)?;
            params.push(Param::from_tokens(&decl, loc, &values)?);
        }
        Ok(params)
    }

    fn param_values(&mut self, decl: &str) -> Result<Vec<Token>, SceneError> {
        let first = self.expect_token(&format!("a value for parameter \"{decl}\""))?;
        match first.kind {
            TokenKind::OpenBracket => {
                let mut values = Vec::new();
                loop {
                    let t = self.expect_token(&format!("\"]\" closing the values of parameter \"{decl}\""))?;
                    match t.kind {
                        TokenKind::CloseBracket => return Ok(values),
                        TokenKind::OpenBracket => {
                            return Err(SceneError::syntax(&t.loc, "expected a value or \"]\", found \"[\""))
                        }
                        _ => values.push(t),
                    }
                }
            }
            TokenKind::CloseBracket => Err(SceneError::syntax(
                &first.loc,
                format!("expected a value for parameter \"{decl}\", found \"]\""),
            )),
            _ => Ok(vec![first]),
        }
    }

    /// `Name "kind" params...`: the kind and the parameter set.
    fn kind_and_params(
        &mut self,
        directive: &str,
        what: &str,
        loc: &Location,
    ) -> Result<(String, ParamSet), SceneError> {
        let (kind, _) = self.expect_string(what)?;
        let params = self.param_list()?;
        Ok((
            kind.clone(),
            ParamSet::new(format!("{directive} \"{kind}\""), loc.clone(), params),
        ))
    }

    // --- Directives -------------------------------------------------------------------

    fn directive(&mut self, name: &str, loc: Location) -> Result<(), SceneError> {
        let b = &mut self.builder;
        match name {
            "Identity" => b.identity(),
            "Translate" => {
                let [x, y, z] = self.numbers()?;
                self.builder.concat(translate(Vec3::new(x, y, z)));
            }
            "Scale" => {
                let [x, y, z] = self.numbers()?;
                self.builder.concat(scale(Vec3::new(x, y, z)));
            }
            "Rotate" => {
                let [angle, x, y, z] = self.numbers()?;
                let m = rotate(angle, Vec3::new(x, y, z))
                    .ok_or_else(|| SceneError::invalid(&loc, "Rotate: the rotation axis has zero length"))?;
                self.builder.concat(m);
            }
            "LookAt" => {
                let v: [f32; 9] = self.numbers()?;
                let m = look_at(
                    Vec3::new(v[0], v[1], v[2]),
                    Vec3::new(v[3], v[4], v[5]),
                    Vec3::new(v[6], v[7], v[8]),
                )
                .map_err(|msg| SceneError::invalid(&loc, msg))?;
                self.builder.concat(m);
            }
            "Transform" => {
                let m = self.matrix()?;
                self.builder.set_transform(from_pbrt_array(&m));
            }
            "ConcatTransform" => {
                let m = self.matrix()?;
                self.builder.concat(from_pbrt_array(&m));
            }
            "CoordinateSystem" => {
                let (n, _) = self.expect_string("a quoted coordinate system name")?;
                self.builder.coordinate_system(n);
            }
            "CoordSysTransform" => {
                let (n, _) = self.expect_string("a quoted coordinate system name")?;
                self.builder.coord_sys_transform(&n, &loc);
            }
            "ActiveTransform" => {
                let t = self.expect_token("All, StartTime or EndTime")?;
                match &t.kind {
                    TokenKind::Word(w) if w == "All" => {}
                    TokenKind::Word(w) if w == "StartTime" || w == "EndTime" => {
                        return Err(SceneError::unsupported(
                            &loc,
                            format!("ActiveTransform {w}: animated transforms (motion blur) are not supported yet"),
                        ));
                    }
                    other => {
                        return Err(SceneError::syntax(
                            &t.loc,
                            format!("expected All, StartTime or EndTime, found {other}"),
                        ))
                    }
                }
            }
            "TransformTimes" => {
                let [_, _] = self.numbers()?;
                self.builder.require_options("TransformTimes", &loc)?;
                self.builder
                    .warn(&loc, "TransformTimes ignored: animated transforms are not supported");
            }
            "ReverseOrientation" => b.reverse_orientation(&loc)?,
            "AttributeBegin" => b.attribute_begin("AttributeBegin", &loc)?,
            "TransformBegin" => b.attribute_begin("TransformBegin", &loc)?,
            "AttributeEnd" => b.attribute_end("AttributeEnd", &loc)?,
            "TransformEnd" => b.attribute_end("TransformEnd", &loc)?,
            "WorldBegin" => b.world_begin(&loc)?,
            "WorldEnd" => b.warn(&loc, "WorldEnd is pbrt-v3 syntax and was ignored"),
            "Camera" => {
                let (kind, params) = self.kind_and_params(name, "a quoted camera type", &loc)?;
                self.builder.camera(&kind, &params, &loc)?;
            }
            "Film" => {
                let (kind, params) = self.kind_and_params(name, "a quoted film type", &loc)?;
                self.builder.film(&kind, &params, &loc)?;
            }
            "PixelFilter" => {
                let (kind, params) = self.kind_and_params(name, "a quoted filter name", &loc)?;
                self.builder.pixel_filter(&kind, &params, &loc)?;
            }
            "Sampler" => {
                let (kind, params) = self.kind_and_params(name, "a quoted sampler name", &loc)?;
                self.builder.sampler(&kind, &params, &loc)?;
            }
            "Integrator" => {
                let (kind, params) = self.kind_and_params(name, "a quoted integrator name", &loc)?;
                self.builder.integrator(&kind, &params, &loc)?;
            }
            "Accelerator" => {
                let (kind, params) = self.kind_and_params(name, "a quoted accelerator name", &loc)?;
                self.builder.accelerator(&kind, &params, &loc)?;
            }
            "Shape" => {
                let (kind, mut params) = self.kind_and_params(name, "a quoted shape name", &loc)?;
                self.builder.shape(&kind, &mut params, &loc)?;
            }
            "Material" => {
                let (kind, mut params) = self.kind_and_params(name, "a quoted material type", &loc)?;
                self.builder.material(&kind, &mut params, &loc)?;
            }
            "MakeNamedMaterial" => {
                let (material, mut params) = self.kind_and_params(name, "a quoted material name", &loc)?;
                self.builder.make_named_material(&material, &mut params, &loc)?;
            }
            "NamedMaterial" => {
                let (material, _) = self.expect_string("a quoted material name")?;
                self.builder.named_material(material, &loc)?;
            }
            "AreaLightSource" => {
                let (kind, mut params) = self.kind_and_params(name, "a quoted area light type", &loc)?;
                self.builder.area_light_source(&kind, &mut params, &loc)?;
            }
            "LightSource" => {
                let (kind, mut params) = self.kind_and_params(name, "a quoted light type", &loc)?;
                self.builder.light_source(&kind, &mut params, &loc)?;
            }
            "Attribute" => {
                let (target, params) = self.kind_and_params(name, "a quoted attribute target", &loc)?;
                self.builder.attribute(&target, params, &loc)?;
            }
            "Texture" => {
                let (tex, _) = self.expect_string("a quoted texture name")?;
                let (ty, ty_loc) = self.expect_string("a quoted texture type (\"float\" or \"spectrum\")")?;
                let (class, class_loc) = self.expect_string("a quoted texture class")?;
                let params = self.param_list()?;
                let mut params = ParamSet::new(format!("Texture \"{tex}\" (\"{class}\")"), loc.clone(), params);
                self.builder
                    .texture(&tex, (&ty, &ty_loc), &class, &mut params, &class_loc)?;
            }
            "Include" | "Import" => self.include(name, &loc)?,
            "ObjectBegin" => {
                let (object, _) = self.expect_string("a quoted object name")?;
                self.builder.object_begin(&object, &loc)?;
            }
            "ObjectInstance" => {
                let (object, _) = self.expect_string("a quoted object name")?;
                self.builder.object_instance(&object, &loc)?;
            }
            "ObjectEnd" => self.builder.object_end(&loc)?,
            "MakeNamedMedium" => {
                let (medium, _) = self.kind_and_params(name, "a quoted medium name", &loc)?;
                return Err(SceneError::unsupported(
                    &loc,
                    format!("MakeNamedMedium \"{medium}\": participating media are not supported yet"),
                ));
            }
            "MediumInterface" => {
                let (inside, _) = self.expect_string("a quoted medium name")?;
                let mut outside = inside.clone();
                if matches!(
                    self.peek()?,
                    Some(Token {
                        kind: TokenKind::Str(_),
                        ..
                    })
                ) {
                    outside = self.expect_string("a quoted medium name")?.0;
                }
                if !inside.is_empty() || !outside.is_empty() {
                    return Err(SceneError::unsupported(
                        &loc,
                        format!(
                            "MediumInterface \"{inside}\" \"{outside}\": participating media are not supported yet"
                        ),
                    ));
                }
            }
            "ColorSpace" => {
                let (space, _) = self.expect_string("a quoted color space name")?;
                self.builder.color_space(&space, &loc)?;
            }
            "Option" => {
                let (option, _) = self.expect_string("a quoted option name")?;
                let value = self.expect_token("an option value")?;
                let text = match value.kind {
                    TokenKind::Word(w) | TokenKind::Str(w) | TokenKind::Number { text: w, .. } => w,
                    other => {
                        return Err(SceneError::syntax(
                            &value.loc,
                            format!("expected an option value, found {other}"),
                        ))
                    }
                };
                self.builder.option(&option, &text, &loc)?;
            }
            _ => return Err(SceneError::syntax(&loc, format!("unknown directive \"{name}\""))),
        }
        Ok(())
    }

    /// `Include "file"` / `Import "file"`: continue with the tokens of that file.
    fn include(&mut self, directive: &str, loc: &Location) -> Result<(), SceneError> {
        let (name, _) = self.expect_string("a quoted file name")?;
        if directive == "Import" {
            self.builder.require_world("Import", loc)?;
        }
        if self.inputs.len() >= MAX_INCLUDE_DEPTH {
            return Err(SceneError::invalid(
                loc,
                format!("{directive} \"{name}\": files are nested too deeply (does a file include itself?)"),
            ));
        }
        let path = self.builder.resolve(&name);
        let bytes = self.builder.input.files.read(&path).map_err(|e| {
            SceneError::io(
                loc,
                format!("cannot open included file \"{name}\": {}", io_error_text(&e)),
            )
        })?;
        let file: Arc<str> = path.display().to_string().into();
        let source = decode(&bytes, &file)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        // Nothing is peeked here (the file name was just consumed), so the included tokens
        // come next.
        self.inputs.push(Input {
            tokens: Tokenizer::new(&source, file),
            dir,
        });
        Ok(())
    }
}

/// The text of a scene file; an error with the location of the first bad byte when it is
/// not UTF-8 (or is compressed, which is not supported yet).
///
/// # Errors
/// When the bytes are gzip data, UTF-16 or otherwise not UTF-8.
pub fn decode(bytes: &[u8], file: &Arc<str>) -> Result<String, SceneError> {
    if bytes.starts_with(&[0x1f, 0x8b]) {
        return Err(SceneError::unsupported(
            &Location::file_only(file.clone()),
            "gzip-compressed scene files are not supported yet",
        ));
    }
    if bytes.starts_with(&[0xfe, 0xff]) || bytes.starts_with(&[0xff, 0xfe]) {
        return Err(SceneError::syntax(
            &Location::file_only(file.clone()),
            "the file is UTF-16 encoded; pbrt scene files must be UTF-8",
        ));
    }
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.to_string()),
        Err(e) => {
            let valid = &bytes[..e.valid_up_to()];
            let text = String::from_utf8_lossy(valid);
            let line = text.matches('\n').count() + 1;
            let column = text.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            Err(SceneError::syntax(
                &Location::new(file.clone(), line as u32, column as u32),
                "the file is not valid UTF-8",
            ))
        }
    }
}
