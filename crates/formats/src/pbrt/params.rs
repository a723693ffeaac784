//! Parameter lists of pbrt-v4 directives: `"type name" value` or `"type name" [ values ]`.
//!
//! [`Param::from_tokens`] checks the values against the declared type (integers are
//! integers, numbers are finite, point3 comes in threes, ...). A [`ParamSet`] holds the
//! parameters of one directive; its typed getters mark what they read, so that afterwards
//! [`ParamSet::unused_warnings`] names every parameter that was ignored.

use std::cell::Cell;

use glam::Vec3;
use mcrender_core::color::Rgb;

use super::tokenizer::{parse_number, Token, TokenKind};
use crate::error::{Location, SceneError};
use crate::spectra::{blackbody_rgb, sampled_spectrum, spectrum_pairs, spectrum_to_rgb, SpectrumRole};

/// The declared type of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// `integer`
    Integer,
    /// `float`
    Float,
    /// `point2`
    Point2,
    /// `vector2`
    Vector2,
    /// `point3` (also `point`)
    Point3,
    /// `vector3` (also `vector`)
    Vector3,
    /// `normal` (also `normal3`)
    Normal,
    /// `rgb` (also `color`)
    Rgb,
    /// `blackbody`: a colour temperature in Kelvin.
    Blackbody,
    /// `spectrum`: wavelength/value pairs or a named spectrum.
    Spectrum,
    /// `string`
    String,
    /// `bool`
    Bool,
    /// `texture`: the name of a texture.
    Texture,
}

impl ParamType {
    /// The type for a declaration word, accepting pbrt-v3 spellings.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "integer" => Self::Integer,
            "float" => Self::Float,
            "point2" => Self::Point2,
            "vector2" => Self::Vector2,
            "point3" | "point" => Self::Point3,
            "vector3" | "vector" => Self::Vector3,
            "normal" | "normal3" => Self::Normal,
            "rgb" | "color" => Self::Rgb,
            "blackbody" => Self::Blackbody,
            "spectrum" => Self::Spectrum,
            "string" => Self::String,
            "bool" => Self::Bool,
            "texture" => Self::Texture,
            _ => return None,
        })
    }

    /// The canonical pbrt-v4 name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Integer => "integer",
            Self::Float => "float",
            Self::Point2 => "point2",
            Self::Vector2 => "vector2",
            Self::Point3 => "point3",
            Self::Vector3 => "vector3",
            Self::Normal => "normal",
            Self::Rgb => "rgb",
            Self::Blackbody => "blackbody",
            Self::Spectrum => "spectrum",
            Self::String => "string",
            Self::Bool => "bool",
            Self::Texture => "texture",
        }
    }

    /// Numbers per item for numeric types (1 for all others).
    #[must_use]
    pub fn arity(self) -> usize {
        match self {
            Self::Point2 | Self::Vector2 => 2,
            Self::Point3 | Self::Vector3 | Self::Normal | Self::Rgb => 3,
            _ => 1,
        }
    }
}

/// The values of a parameter, already checked against its type.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValues {
    /// `integer`
    Ints(Vec<i32>),
    /// Every numeric type except `integer`; also `spectrum` given as numbers.
    Floats(Vec<f32>),
    /// `string`, `texture`; also `spectrum` given by name.
    Strings(Vec<String>),
    /// `bool`
    Bools(Vec<bool>),
}

impl ParamValues {
    fn len(&self) -> usize {
        match self {
            Self::Ints(v) => v.len(),
            Self::Floats(v) => v.len(),
            Self::Strings(v) => v.len(),
            Self::Bools(v) => v.len(),
        }
    }
}

/// One parameter of a directive.
#[derive(Debug)]
pub struct Param {
    /// Declared type.
    pub ty: ParamType,
    /// The type as written in the file (for messages).
    pub type_text: String,
    /// Parameter name.
    pub name: String,
    /// Location of the `"type name"` declaration.
    pub loc: Location,
    /// Values.
    pub values: ParamValues,
    used: Cell<bool>,
    /// Set for parameters inherited from an `Attribute` directive: not warned about when
    /// unused, as in pbrt.
    pub may_be_unused: bool,
}

impl Clone for Param {
    fn clone(&self) -> Self {
        Self {
            ty: self.ty,
            type_text: self.type_text.clone(),
            name: self.name.clone(),
            loc: self.loc.clone(),
            values: self.values.clone(),
            used: Cell::new(self.used.get()),
            may_be_unused: self.may_be_unused,
        }
    }
}

impl Param {
    /// Build a parameter from its declaration string and its value tokens.
    ///
    /// # Errors
    /// A malformed declaration, an unknown type, a value of the wrong kind, a number that is
    /// not finite or an integer out of range, or a count that is not a multiple of the
    /// type's arity.
    pub fn from_tokens(decl: &str, loc: Location, values: &[Token]) -> Result<Self, SceneError> {
        let words: Vec<&str> = decl.split_whitespace().collect();
        let [type_text, name] = words[..] else {
            return Err(SceneError::syntax(
                &loc,
                format!("expected a parameter declaration \"type name\", found string \"{decl}\""),
            ));
        };
        let Some(ty) = ParamType::from_name(type_text) else {
            return Err(SceneError::syntax(
                &loc,
                format!("unknown parameter type \"{type_text}\" in \"{decl}\""),
            ));
        };
        let values = match ty {
            ParamType::Integer => ParamValues::Ints(values.iter().map(integer).collect::<Result<_, _>>()?),
            ParamType::String | ParamType::Texture => {
                ParamValues::Strings(values.iter().map(string).collect::<Result<_, _>>()?)
            }
            ParamType::Bool => ParamValues::Bools(values.iter().map(boolean).collect::<Result<_, _>>()?),
            ParamType::Spectrum
                if matches!(
                    values.first(),
                    Some(Token {
                        kind: TokenKind::Str(_),
                        ..
                    })
                ) =>
            {
                ParamValues::Strings(values.iter().map(string).collect::<Result<_, _>>()?)
            }
            _ => ParamValues::Floats(values.iter().map(number).collect::<Result<_, _>>()?),
        };
        let per_item = if ty == ParamType::Spectrum && matches!(values, ParamValues::Floats(_)) {
            2
        } else {
            ty.arity()
        };
        if values.len() % per_item != 0 {
            return Err(SceneError::syntax(
                &loc,
                format!(
                    "parameter \"{type_text} {name}\" needs a multiple of {per_item} values, found {}",
                    values.len()
                ),
            ));
        }
        Ok(Self {
            ty,
            type_text: type_text.to_string(),
            name: name.to_string(),
            loc,
            values,
            used: Cell::new(false),
            may_be_unused: false,
        })
    }

    /// `"type name"` as written, for messages.
    #[must_use]
    pub fn decl(&self) -> String {
        format!("{} {}", self.type_text, self.name)
    }

    /// Mark as read.
    pub fn mark_used(&self) {
        self.used.set(true);
    }

    /// Was it read?
    #[must_use]
    pub fn is_used(&self) -> bool {
        self.used.get()
    }

    /// The numbers of a numeric parameter.
    #[must_use]
    pub fn floats(&self) -> &[f32] {
        match &self.values {
            ParamValues::Floats(v) => v,
            _ => &[],
        }
    }

    /// The integers of an `integer` parameter.
    #[must_use]
    pub fn ints(&self) -> &[i32] {
        match &self.values {
            ParamValues::Ints(v) => v,
            _ => &[],
        }
    }

    /// The strings of a `string`, `texture` or named `spectrum` parameter.
    #[must_use]
    pub fn strings(&self) -> &[String] {
        match &self.values {
            ParamValues::Strings(v) => v,
            _ => &[],
        }
    }

    pub(super) fn expect_single(&self) -> Result<(), SceneError> {
        let n = self.values.len() / self.ty.arity();
        if n == 1 {
            Ok(())
        } else {
            Err(SceneError::syntax(
                &self.loc,
                format!("parameter \"{}\" needs exactly one value, found {n}", self.decl()),
            ))
        }
    }
}

fn integer(tok: &Token) -> Result<i32, SceneError> {
    if let TokenKind::Number { text, .. } = &tok.kind {
        let digits = text.strip_prefix(['-', '+']).unwrap_or(text);
        if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
            return text
                .parse::<i32>()
                .map_err(|_| SceneError::invalid(&tok.loc, format!("integer \"{text}\" is out of range")));
        }
    }
    Err(SceneError::syntax(
        &tok.loc,
        format!("expected an integer, found {}", tok.kind),
    ))
}

/// A finite number from a token.
///
/// # Errors
/// When the token is not a number or is not finite as a 32-bit float.
pub fn number(tok: &Token) -> Result<f32, SceneError> {
    match &tok.kind {
        TokenKind::Number { value, text } => {
            let v = *value as f32;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(SceneError::invalid(
                    &tok.loc,
                    format!("expected a finite number, found \"{text}\""),
                ))
            }
        }
        TokenKind::Word(w) if parse_number(w).is_some() => Err(SceneError::invalid(
            &tok.loc,
            format!("expected a finite number, found \"{w}\""),
        )),
        other => Err(SceneError::syntax(
            &tok.loc,
            format!("expected a number, found {other}"),
        )),
    }
}

fn string(tok: &Token) -> Result<String, SceneError> {
    match &tok.kind {
        TokenKind::Str(s) => Ok(s.clone()),
        other => Err(SceneError::syntax(
            &tok.loc,
            format!("expected a quoted string, found {other}"),
        )),
    }
}

fn boolean(tok: &Token) -> Result<bool, SceneError> {
    match &tok.kind {
        TokenKind::Word(w) | TokenKind::Str(w) if w == "true" => Ok(true),
        TokenKind::Word(w) | TokenKind::Str(w) if w == "false" => Ok(false),
        other => Err(SceneError::syntax(
            &tok.loc,
            format!("expected true or false, found {other}"),
        )),
    }
}

/// The parameters of one directive, with typed getters that record what was read.
#[derive(Debug)]
pub struct ParamSet {
    /// The directive, for messages, e.g. `Shape "sphere"`.
    pub owner: String,
    /// Location of the directive.
    pub loc: Location,
    params: Vec<Param>,
}

impl ParamSet {
    /// A parameter set for the directive `owner` (e.g. `Shape "sphere"`) at `loc`.
    #[must_use]
    pub fn new(owner: String, loc: Location, params: Vec<Param>) -> Self {
        Self { owner, loc, params }
    }

    /// Append parameters inherited from `Attribute` directives: they are looked up after the
    /// directive's own parameters and never warned about.
    pub fn add_inherited(&mut self, inherited: &[Param]) {
        for p in inherited {
            let mut p = p.clone();
            p.may_be_unused = true;
            self.params.push(p);
        }
    }

    /// The parameters, consumed.
    #[must_use]
    pub fn into_params(self) -> Vec<Param> {
        self.params
    }

    /// All parameters, in order.
    #[must_use]
    pub fn params(&self) -> &[Param] {
        &self.params
    }

    /// The first parameter called `name`, whatever its type, without marking it.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name)
    }

    /// The first parameter called `name`, marked as used; an error when its type is not one
    /// of `accepted`.
    ///
    /// # Errors
    /// When the parameter exists with another type.
    pub fn lookup(&self, name: &str, accepted: &[ParamType]) -> Result<Option<&Param>, SceneError> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        p.mark_used();
        if accepted.contains(&p.ty) {
            return Ok(Some(p));
        }
        let expected: Vec<String> = accepted.iter().map(|t| format!("\"{} {}\"", t.name(), name)).collect();
        Err(SceneError::syntax(
            &p.loc,
            format!(
                "parameter \"{}\" of {} has the wrong type: expected {}",
                p.decl(),
                self.owner,
                expected.join(" or ")
            ),
        ))
    }

    /// A single `float`.
    ///
    /// # Errors
    /// Wrong type or not exactly one value.
    pub fn float(&self, name: &str, default: f32) -> Result<f32, SceneError> {
        match self.lookup(name, &[ParamType::Float])? {
            Some(p) => p.expect_single().map(|()| p.floats()[0]),
            None => Ok(default),
        }
    }

    /// A single `integer`.
    ///
    /// # Errors
    /// Wrong type or not exactly one value.
    pub fn int(&self, name: &str, default: i32) -> Result<i32, SceneError> {
        match self.lookup(name, &[ParamType::Integer])? {
            Some(p) => p.expect_single().map(|()| p.ints()[0]),
            None => Ok(default),
        }
    }

    /// A single `bool`.
    ///
    /// # Errors
    /// Wrong type or not exactly one value.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        match self.lookup(name, &[ParamType::Bool])? {
            Some(p) => p.expect_single().map(|()| match &p.values {
                ParamValues::Bools(b) => b[0],
                _ => default,
            }),
            None => Ok(default),
        }
    }

    /// A single `string` and where it was given.
    ///
    /// # Errors
    /// Wrong type or not exactly one value.
    pub fn string(&self, name: &str) -> Result<Option<(String, Location)>, SceneError> {
        match self.lookup(name, &[ParamType::String])? {
            Some(p) => p
                .expect_single()
                .map(|()| Some((p.strings()[0].clone(), p.loc.clone()))),
            None => Ok(None),
        }
    }

    /// All numbers of a `float` parameter.
    ///
    /// # Errors
    /// Wrong type.
    pub fn floats(&self, name: &str) -> Result<Option<&Param>, SceneError> {
        self.lookup(name, &[ParamType::Float])
    }

    /// All integers of an `integer` parameter.
    ///
    /// # Errors
    /// Wrong type.
    pub fn ints(&self, name: &str) -> Result<Option<&Param>, SceneError> {
        self.lookup(name, &[ParamType::Integer])
    }

    /// A single `point3`.
    ///
    /// # Errors
    /// Wrong type or not exactly one value.
    pub fn point3(&self, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
        match self.lookup(name, &[ParamType::Point3])? {
            Some(p) => p.expect_single().map(|()| Vec3::from_slice(p.floats())),
            None => Ok(default),
        }
    }

    /// All values of a `point3` parameter.
    ///
    /// # Errors
    /// Wrong type.
    pub fn point3s(&self, name: &str) -> Result<Option<(Vec<Vec3>, Location)>, SceneError> {
        Ok(self.lookup(name, &[ParamType::Point3])?.map(|p| {
            (
                p.floats().chunks_exact(3).map(Vec3::from_slice).collect(),
                p.loc.clone(),
            )
        }))
    }

    /// All values of a `normal` parameter.
    ///
    /// # Errors
    /// Wrong type.
    pub fn normals(&self, name: &str) -> Result<Option<(Vec<Vec3>, Location)>, SceneError> {
        Ok(self.lookup(name, &[ParamType::Normal])?.map(|p| {
            (
                p.floats().chunks_exact(3).map(Vec3::from_slice).collect(),
                p.loc.clone(),
            )
        }))
    }

    /// A single colour: `rgb` as given; `spectrum` as (wavelength nm, value) pairs, or
    /// `blackbody` (a temperature in Kelvin), converted to linear sRGB once by `role` (see
    /// [`crate::spectra`]). Named spectra and `texture` are left to the callers that
    /// accept them and reported here as not supported.
    ///
    /// # Errors
    /// Another form or type, not exactly one value, or a malformed spectrum.
    pub fn color(&self, name: &str, default: Rgb, role: SpectrumRole) -> Result<Rgb, SceneError> {
        let forms = [
            ParamType::Rgb,
            ParamType::Spectrum,
            ParamType::Blackbody,
            ParamType::Texture,
        ];
        let Some(p) = self.lookup(name, &forms)? else {
            return Ok(default);
        };
        color_of(p, &self.owner, role)
    }

    /// One warning per parameter that no getter read (parameters from `Attribute` excepted):
    /// `file:line:col: warning: parameter "float foo" of Shape "sphere" is not supported and was ignored`.
    #[must_use]
    pub fn unused_warnings(&self) -> Vec<String> {
        self.params
            .iter()
            .filter(|p| !p.is_used() && !p.may_be_unused)
            .map(|p| {
                format!(
                    "{}: warning: parameter \"{}\" of {} is not supported and was ignored",
                    p.loc,
                    p.decl(),
                    self.owner
                )
            })
            .collect()
    }
}

/// The colour a single `rgb`, `spectrum` (wavelength, value pairs) or `blackbody` parameter
/// gives, converted by `role` (see [`ParamSet::color`]).
///
/// # Errors
/// Another form or type, not exactly one value, or a malformed spectrum.
pub fn color_of(p: &Param, owner: &str, role: SpectrumRole) -> Result<Rgb, SceneError> {
    let bad = |what: String| SceneError::invalid(&p.loc, format!("\"{}\" of {}: {what}", p.decl(), owner));
    match p.ty {
            ParamType::Rgb => {
                p.expect_single()?;
                let v = p.floats();
                Ok(Rgb::new(v[0], v[1], v[2]))
            }
            ParamType::Blackbody => {
                p.expect_single()?;
                let c = blackbody_rgb(p.floats()[0]).map_err(bad)?;
                // A blackbody is an emission spectrum; elsewhere pbrt-v4 uses it as given,
                // normalised to a peak of 1, which has no RGB meaning without a light.
                if role == SpectrumRole::Illuminant {
                    Ok(c)
                } else {
                    Err(bad("a blackbody is only accepted as an emission (L or I)".into()))
                }
            }
            ParamType::Spectrum if matches!(p.values, ParamValues::Floats(_)) => {
                let pairs = spectrum_pairs(p.floats());
                let s = sampled_spectrum(&pairs).map_err(bad)?;
                Ok(spectrum_to_rgb(s, role))
            }
            _ => Err(SceneError::unsupported(
                &p.loc,
                format!(
                    "\"{}\" of {} is not supported yet; only \"rgb {}\", \"spectrum {}\" as (wavelength, value) pairs and \"blackbody {}\" (emission) are",
                    p.decl(),
                    owner,
                    p.name,
                    p.name,
                    p.name
                ),
            )),
        }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::tokenizer::Tokenizer;

    /// Parse `"decl" values...` from source text into a parameter.
    fn param(src: &str) -> Result<Param, SceneError> {
        let mut t = Tokenizer::new(src, "p.pbrt".into());
        let decl = t.next_token().unwrap().unwrap();
        let TokenKind::Str(d) = decl.kind else { panic!() };
        let mut vals = Vec::new();
        while let Some(tok) = t.next_token().unwrap() {
            if !matches!(tok.kind, TokenKind::OpenBracket | TokenKind::CloseBracket) {
                vals.push(tok);
            }
        }
        Param::from_tokens(&d, decl.loc, &vals)
    }

    fn set(srcs: &[&str]) -> ParamSet {
        ParamSet::new(
            "Shape \"sphere\"".into(),
            Location::new("p.pbrt".into(), 1, 1),
            srcs.iter().map(|s| param(s).unwrap()).collect(),
        )
    }

    #[test]
    fn typed_getters_read_values_and_defaults() {
        let s = set(&[
            "\"float radius\" 2",
            "\"integer n\" [ -3 ]",
            "\"bool on\" \"true\"",
            "\"bool off\" false",
            "\"string s\" \"x\"",
            "\"point p\" [1 2 3]",
            "\"rgb c\" [0.1 0.2 0.3]",
        ]);
        assert_eq!(s.float("radius", 1.0).unwrap(), 2.0);
        assert_eq!(s.float("missing", 7.0).unwrap(), 7.0);
        assert_eq!(s.int("n", 0).unwrap(), -3);
        assert!(s.bool("on", false).unwrap());
        assert!(!s.bool("off", true).unwrap());
        assert_eq!(s.string("s").unwrap().unwrap().0, "x");
        assert_eq!(s.point3("p", Vec3::ZERO).unwrap(), Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(
            s.color("c", Rgb::BLACK, SpectrumRole::Albedo).unwrap(),
            Rgb::new(0.1, 0.2, 0.3)
        );
        assert!(s.unused_warnings().is_empty());
    }

    #[test]
    fn unused_parameters_are_named_in_warnings() {
        let s = set(&["\"float radius\" 2", "\"float foo\" 1"]);
        s.float("radius", 1.0).unwrap();
        assert_eq!(
            s.unused_warnings(),
            vec!["p.pbrt:1:1: warning: parameter \"float foo\" of Shape \"sphere\" is not supported and was ignored"]
        );
    }

    #[test]
    fn wrong_type_is_an_error() {
        let s = set(&["\"integer radius\" 2"]);
        assert_eq!(
            s.float("radius", 1.0).unwrap_err().to_string(),
            "p.pbrt:1:1: parameter \"integer radius\" of Shape \"sphere\" has the wrong type: expected \"float radius\""
        );
    }

    #[test]
    fn wrong_arity_and_values_are_errors() {
        assert_eq!(
            param("\"point3 P\" [1 2 3 4]").unwrap_err().to_string(),
            "p.pbrt:1:1: parameter \"point3 P\" needs a multiple of 3 values, found 4"
        );
        assert_eq!(
            param("\"integer n\" [1 2.5]").unwrap_err().to_string(),
            "p.pbrt:1:16: expected an integer, found \"2.5\""
        );
        assert_eq!(
            param("\"float x\" [1 abc]").unwrap_err().to_string(),
            "p.pbrt:1:14: expected a number, found \"abc\""
        );
        assert_eq!(
            param("\"float x\" 1e40").unwrap_err().to_string(),
            "p.pbrt:1:11: expected a finite number, found \"1e40\""
        );
        assert_eq!(
            param("\"bool b\" 1").unwrap_err().to_string(),
            "p.pbrt:1:10: expected true or false, found \"1\""
        );
        assert_eq!(
            param("\"floaty x\" 1").unwrap_err().to_string(),
            "p.pbrt:1:1: unknown parameter type \"floaty\" in \"floaty x\""
        );
        assert_eq!(
            param("\"float\" 1").unwrap_err().to_string(),
            "p.pbrt:1:1: expected a parameter declaration \"type name\", found string \"float\""
        );
        let s = set(&["\"float fov\" [1 2]"]);
        assert_eq!(
            s.float("fov", 90.0).unwrap_err().to_string(),
            "p.pbrt:1:1: parameter \"float fov\" needs exactly one value, found 2"
        );
    }

    #[test]
    fn sampled_spectra_and_blackbodies_become_rgb() {
        let s = set(&["\"spectrum reflectance\" [300 .3 800 .3]"]);
        let c = s.color("reflectance", Rgb::splat(0.5), SpectrumRole::Albedo).unwrap();
        assert!((0..3).all(|ch| (c[ch] - 0.3).abs() < 1e-5), "{c:?}");
        let s = set(&["\"blackbody L\" [ 2700 ]"]);
        let c = s.color("L", Rgb::WHITE, SpectrumRole::Illuminant).unwrap();
        assert!(c.r > c.g && c.g > c.b, "{c:?}");
        assert_eq!(
            s.color("L", Rgb::WHITE, SpectrumRole::Albedo).unwrap_err().to_string(),
            "p.pbrt:1:1: \"blackbody L\" of Shape \"sphere\": a blackbody is only accepted as an emission (L or I)"
        );
        let s = set(&["\"blackbody L\" [ -5 ]"]);
        let e = s
            .color("L", Rgb::WHITE, SpectrumRole::Illuminant)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("p.pbrt:1:1:") && e.contains("must be positive"), "{e}");
        let s = set(&["\"spectrum reflectance\" [500 .3 400 .3]"]);
        let e = s
            .color("reflectance", Rgb::WHITE, SpectrumRole::Albedo)
            .unwrap_err()
            .to_string();
        assert!(e.contains("wavelengths must increase"), "{e}");
    }

    #[test]
    fn other_colour_forms_are_unsupported() {
        let s = set(&["\"texture reflectance\" \"checks\""]);
        assert!(s.color("reflectance", Rgb::splat(0.5), SpectrumRole::Albedo).is_err());
        let s = set(&["\"spectrum eta\" \"metal-Ag-eta\""]);
        assert_eq!(
            s.color("eta", Rgb::splat(0.5), SpectrumRole::Albedo).unwrap_err().to_string(),
            "p.pbrt:1:1: \"spectrum eta\" of Shape \"sphere\" is not supported yet; only \"rgb eta\", \"spectrum eta\" as (wavelength, value) pairs and \"blackbody eta\" (emission) are"
        );
    }

    #[test]
    fn inherited_parameters_come_last_and_are_not_warned_about() {
        let mut s = set(&["\"float radius\" 2"]);
        let inherited = [
            param("\"float radius\" 5").unwrap(),
            param("\"float other\" 1").unwrap(),
        ];
        s.add_inherited(&inherited);
        assert_eq!(s.float("radius", 1.0).unwrap(), 2.0);
        assert!(s.unused_warnings().is_empty());
    }
}
