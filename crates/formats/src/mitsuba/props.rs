//! Typed access to the properties of one Mitsuba plugin element (`<float name="alpha"
//! value="0.1"/>`, `<rgb>`, `<point>`, `<transform>`, ...), remembering which were read so
//! that the rest can be reported (`file:line:col: warning: ... is not used`).

use mcrender_core::math::{Vec3, Vec4};

use super::xml::Element;
use crate::error::{Location, SceneError};
use glam::Mat4;

/// Tags of property elements (as opposed to nested plugins).
const PROPERTY_TAGS: &[&str] = &[
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
];

/// The properties of a plugin element.
pub struct Props<'a> {
    /// The plugin element.
    pub el: &'a Element,
    used: Vec<bool>,
}

impl<'a> Props<'a> {
    /// Properties of `el`.
    #[must_use]
    pub fn new(el: &'a Element) -> Self {
        Self {
            el,
            used: vec![false; el.children.len()],
        }
    }

    /// The child named `name` (a property, a named nested plugin or a named `<ref>`),
    /// marked as used.
    pub fn get(&mut self, name: &str) -> Option<&'a Element> {
        let i = self.el.children.iter().position(|c| c.attr("name") == Some(name))?;
        self.used[i] = true;
        Some(&self.el.children[i])
    }

    /// True when a child named `name` exists (does not mark it).
    #[must_use]
    pub fn has(&self, name: &str) -> bool {
        self.el.children.iter().any(|c| c.attr("name") == Some(name))
    }

    /// Unnamed nested plugins with tag `tag` and unnamed `<ref>`s, marked as used.
    pub fn nested(&mut self, tag: &str) -> Vec<&'a Element> {
        let mut out = Vec::new();
        for (i, c) in self.el.children.iter().enumerate() {
            if c.attr("name").is_none() && (c.tag == tag || c.tag == "ref") {
                if c.tag == tag {
                    self.used[i] = true;
                }
                out.push(c);
            }
        }
        out
    }

    /// Mark unnamed `<ref>` children as used (the caller resolved them).
    pub fn use_refs(&mut self) {
        for (i, c) in self.el.children.iter().enumerate() {
            if c.tag == "ref" && c.attr("name").is_none() {
                self.used[i] = true;
            }
        }
    }

    /// A `float` (or `integer`) property.
    pub fn float(&mut self, name: &str, default: f32) -> Result<f32, SceneError> {
        match self.get(name) {
            None => Ok(default),
            Some(e) => scalar(e, &["float", "integer"]),
        }
    }

    /// An `integer` property.
    pub fn int(&mut self, name: &str, default: i64) -> Result<i64, SceneError> {
        match self.get(name) {
            None => Ok(default),
            Some(e) => {
                expect_tag(e, &["integer"])?;
                let v = e.required("value")?;
                v.trim().parse::<i64>().map_err(|_| {
                    SceneError::syntax(&e.loc, format!("expected an integer for \"{name}\", found \"{v}\""))
                })
            }
        }
    }

    /// A `boolean` property.
    pub fn bool(&mut self, name: &str, default: bool) -> Result<bool, SceneError> {
        match self.get(name) {
            None => Ok(default),
            Some(e) => {
                expect_tag(e, &["boolean"])?;
                match e.required("value")?.trim() {
                    "true" | "1" => Ok(true),
                    "false" | "0" => Ok(false),
                    v => Err(SceneError::syntax(
                        &e.loc,
                        format!("expected true or false for \"{name}\", found \"{v}\""),
                    )),
                }
            }
        }
    }

    /// A `string` property with its location.
    pub fn string(&mut self, name: &str) -> Result<Option<(String, Location)>, SceneError> {
        match self.get(name) {
            None => Ok(None),
            Some(e) => {
                expect_tag(e, &["string"])?;
                Ok(Some((e.required("value")?.to_string(), e.loc.clone())))
            }
        }
    }

    /// A `point` or `vector` property.
    pub fn vec3(&mut self, name: &str) -> Result<Option<Vec3>, SceneError> {
        match self.get(name) {
            None => Ok(None),
            Some(e) => {
                expect_tag(e, &["point", "vector"])?;
                Ok(Some(xyz(e, 0.0)?))
            }
        }
    }

    /// A `transform` property as a matrix.
    pub fn transform(&mut self, name: &str) -> Result<Option<Mat4>, SceneError> {
        match self.get(name) {
            None => Ok(None),
            Some(e) => {
                expect_tag(e, &["transform"])?;
                Ok(Some(transform(e)?))
            }
        }
    }

    /// Warnings for the named children nobody read.
    #[must_use]
    pub fn unused_warnings(&self) -> Vec<String> {
        self.el
            .children
            .iter()
            .zip(&self.used)
            .filter(|(c, used)| !**used && (PROPERTY_TAGS.contains(&c.tag.as_str()) || c.attr("name").is_some()))
            .map(|(c, _)| {
                format!(
                    "{}: warning: {} of {} is not used by mcrender (ignored)",
                    c.loc,
                    c.describe(),
                    self.el.describe()
                )
            })
            .collect()
    }
}

/// An error unless `e` has one of the tags.
pub fn expect_tag(e: &Element, tags: &[&str]) -> Result<(), SceneError> {
    if tags.contains(&e.tag.as_str()) {
        Ok(())
    } else {
        Err(SceneError::syntax(
            &e.loc,
            format!("{} must be one of <{}>", e.describe(), tags.join(">, <")),
        ))
    }
}

/// The numbers of a list such as `"0.2, 0.5 0.3"`.
pub fn numbers(e: &Element, text: &str) -> Result<Vec<f32>, SceneError> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f32>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
                SceneError::syntax(&e.loc, format!("expected a number in {}, found \"{t}\"", e.describe()))
            })
        })
        .collect()
}

/// The single number of a `float`/`integer` element.
pub fn scalar(e: &Element, tags: &[&str]) -> Result<f32, SceneError> {
    expect_tag(e, tags)?;
    let v = numbers(e, e.required("value")?)?;
    match v.as_slice() {
        [x] => Ok(*x),
        _ => Err(SceneError::syntax(
            &e.loc,
            format!("{} needs exactly one number", e.describe()),
        )),
    }
}

/// A 3-vector from `value="x, y, z"` (one number fills all three) or `x=`, `y=`, `z=`
/// attributes (missing ones take `default`).
pub fn xyz(e: &Element, default: f32) -> Result<Vec3, SceneError> {
    if let Some(v) = e.attr("value") {
        let n = numbers(e, v)?;
        return match n.as_slice() {
            [a] => Ok(Vec3::splat(*a)),
            [a, b, c] => Ok(Vec3::new(*a, *b, *c)),
            _ => Err(SceneError::syntax(
                &e.loc,
                format!("{} needs 1 or 3 numbers", e.describe()),
            )),
        };
    }
    let mut out = [default; 3];
    for (i, k) in ["x", "y", "z"].iter().enumerate() {
        if let Some(v) = e.attr(k) {
            out[i] = *numbers(e, v)?
                .first()
                .ok_or_else(|| SceneError::syntax(&e.loc, format!("empty \"{k}\" in {}", e.describe())))?;
        }
    }
    Ok(Vec3::from(out))
}

/// The matrix of a `<transform>`: its operations applied in order (each one
/// left-multiplies what came before).
pub fn transform(e: &Element) -> Result<Mat4, SceneError> {
    let mut m = Mat4::IDENTITY;
    for op in &e.children {
        let step = match op.tag.as_str() {
            "translate" => Mat4::from_translation(xyz(op, 0.0)?),
            "scale" => Mat4::from_scale(xyz(op, 1.0)?),
            "rotate" => {
                let axis = xyz(op, 0.0)?;
                let angle = op
                    .attr("angle")
                    .map(|a| numbers(op, a))
                    .transpose()?
                    .and_then(|v| v.first().copied())
                    .unwrap_or(0.0);
                let Some(axis) = axis.try_normalize() else {
                    return Err(SceneError::invalid(&op.loc, "<rotate> needs a non-zero axis"));
                };
                Mat4::from_axis_angle(axis, angle.to_radians())
            }
            "matrix" => {
                let v = numbers(op, op.required("value")?)?;
                match v.len() {
                    16 => Mat4::from_cols_array(&v.try_into().expect("16 numbers")).transpose(),
                    9 => {
                        let r = |i: usize| Vec4::new(v[3 * i], v[3 * i + 1], v[3 * i + 2], 0.0);
                        Mat4::from_cols(r(0), r(1), r(2), Vec4::W).transpose()
                    }
                    _ => {
                        return Err(SceneError::syntax(
                            &op.loc,
                            "<matrix> needs 16 (or 9) numbers, row by row",
                        ))
                    }
                }
            }
            "lookat" => look_at(op)?,
            _ => {
                return Err(SceneError::unsupported(
                    &op.loc,
                    format!(
                        "<{}> in a <transform> (expected translate, scale, rotate, matrix or lookat)",
                        op.tag
                    ),
                ))
            }
        };
        m = step * m;
    }
    Ok(m)
}

/// Mitsuba's `lookat`: columns `left = up x dir`, `up' = dir x left`, `dir`, `origin`.
fn look_at(op: &Element) -> Result<Mat4, SceneError> {
    let vec = |k: &str| -> Result<Option<Vec3>, SceneError> {
        match op.attr(k) {
            None => Ok(None),
            Some(v) => match numbers(op, v)?.as_slice() {
                [a, b, c] => Ok(Some(Vec3::new(*a, *b, *c))),
                _ => Err(SceneError::syntax(
                    &op.loc,
                    format!("\"{k}\" of <lookat> needs 3 numbers"),
                )),
            },
        }
    };
    let origin = vec("origin")?.unwrap_or(Vec3::ZERO);
    let target = vec("target")?.unwrap_or(Vec3::Z);
    let Some(dir) = (target - origin).try_normalize() else {
        return Err(SceneError::invalid(&op.loc, "<lookat> origin and target coincide"));
    };
    let up = vec("up")?.unwrap_or_else(|| dir.any_orthonormal_vector());
    let Some(left) = up.cross(dir).try_normalize() else {
        return Err(SceneError::invalid(
            &op.loc,
            "<lookat> up is parallel to the viewing direction",
        ));
    };
    let new_up = dir.cross(left);
    Ok(Mat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}
