//! Reading Mitsuba XML into a plain [`Element`] tree, with the document-level directives
//! already applied: `<default name value>` (unless a `-D name=value` define overrides it),
//! `$name` substitution in attribute values, `<include filename>` (the included scene's
//! children spliced in place; cycles are errors) and `<path value>` (a directory added to
//! the file resolver). Every element keeps its `file:line:col`. Files come from a
//! [`FileSource`] (the disk, or files in memory for tests and fuzzing).

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use crate::error::{escape_control, io_error_text, quoted, Location, SceneError, QUOTE_MAX_CHARS};
use crate::source::FileSource;

/// Deepest nesting of `<include>`s.
const MAX_INCLUDE_DEPTH: usize = 64;
/// Most files one scene reads through `<include>` (a file may be included many times;
/// nested, that is exponential).
const MAX_INCLUDES: usize = 4096;

/// One XML element after directive processing.
#[derive(Clone, Debug)]
pub struct Element {
    /// Tag name (`shape`, `float`, ...).
    pub tag: String,
    /// Attributes in document order, `$name`s substituted.
    pub attrs: Vec<(String, String)>,
    /// Child elements (includes spliced in).
    pub children: Vec<Element>,
    /// Where the element starts.
    pub loc: Location,
}

impl Element {
    /// The value of attribute `name`.
    #[must_use]
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    /// The value of attribute `name`, or an error naming the element.
    pub fn required(&self, name: &str) -> Result<&str, SceneError> {
        self.attr(name)
            .ok_or_else(|| SceneError::syntax(&self.loc, format!("<{}> needs a \"{name}\" attribute", self.tag)))
    }

    /// `<tag type="...">` as a short description for messages.
    #[must_use]
    pub fn describe(&self) -> String {
        let tag = short(&self.tag);
        match self.attr("type") {
            Some(t) => format!("<{tag} type={}>", quoted(t)),
            None => match self.attr("name") {
                Some(n) => format!("<{tag} name={}>", quoted(n)),
                None => format!("<{tag}>"),
            },
        }
    }
}

/// `text` for a message outside quotes (a tag or parameter name, which XML keeps free of
/// control characters): cut after [`QUOTE_MAX_CHARS`] characters with the length noted.
fn short(text: &str) -> String {
    match text.char_indices().nth(QUOTE_MAX_CHARS) {
        None => escape_control(text),
        Some((at, _)) => format!(
            "{}... ({} characters)",
            escape_control(&text[..at]),
            text.chars().count()
        ),
    }
}

/// Reads a scene file and what it includes.
pub struct Reader {
    /// `-D name=value` (win over `<default>`).
    defines: HashMap<String, String>,
    /// Values from `<default>` elements seen so far.
    defaults: HashMap<String, String>,
    /// Files being read, outermost first (for cycle detection).
    stack: Vec<PathBuf>,
    /// Directories from `<path>`, in the order added.
    search_paths: Vec<PathBuf>,
    /// The top-level file.
    top: Option<PathBuf>,
    /// Where files are read from.
    files: Arc<dyn FileSource>,
    /// Files read through `<include>` so far.
    includes: usize,
}

impl Reader {
    /// A reader with command-line defines, reading from `files`.
    #[must_use]
    pub fn new(defines: &[(String, String)], files: Arc<dyn FileSource>) -> Self {
        Self {
            defines: defines.iter().cloned().collect(),
            defaults: HashMap::new(),
            stack: Vec::new(),
            search_paths: Vec::new(),
            top: None,
            files,
            includes: 0,
        }
    }

    /// Where the scene's files are read from.
    #[must_use]
    pub fn files(&self) -> &dyn FileSource {
        &*self.files
    }

    /// The directories a relative file name is looked up in: `<path>` directories (the
    /// latest first), then the directory of the top-level file.
    #[must_use]
    pub fn search_paths(&self) -> Vec<PathBuf> {
        let mut dirs: Vec<PathBuf> = self.search_paths.iter().rev().cloned().collect();
        if let Some(top) = &self.top {
            dirs.push(top.parent().map(Path::to_path_buf).unwrap_or_default());
        }
        dirs
    }

    /// Read the top-level scene file into its `<scene>` element.
    ///
    /// # Errors
    /// Unreadable or malformed files, a root other than `<scene>`, an unsupported version,
    /// undefined `$name`s, include cycles.
    pub fn read_scene(&mut self, path: &Path) -> Result<Element, SceneError> {
        self.top = Some(path.to_path_buf());
        self.read_file(path, &Location::file_only(path.display().to_string().into()))
    }

    fn read_file(&mut self, path: &Path, from: &Location) -> Result<Element, SceneError> {
        let canonical = path.canonicalize().unwrap_or_else(|_| lexically_normal(path));
        if self.stack.contains(&canonical) {
            return Err(SceneError::invalid(
                from,
                format!("cyclic <include> of {}", quoted(&path.to_string_lossy())),
            ));
        }
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(SceneError::invalid(
                from,
                format!("<include>s nested deeper than {MAX_INCLUDE_DEPTH}"),
            ));
        }
        let name: Arc<str> = path.display().to_string().into();
        let cannot_read = |why: String| {
            SceneError::io(
                from,
                format!("cannot read scene file {}: {why}", quoted(&path.to_string_lossy())),
            )
        };
        let bytes = self.files.read(path).map_err(|e| cannot_read(io_error_text(&e)))?;
        let text = String::from_utf8(bytes).map_err(|_| cannot_read("stream did not contain valid UTF-8".into()))?;
        let doc = roxmltree::Document::parse(&text).map_err(|e| {
            let p = e.pos();
            SceneError::syntax(
                &Location::new(name.clone(), p.row, p.col),
                format!("malformed XML: {e}"),
            )
        })?;
        let root = doc.root_element();
        let loc = location(&doc, &name, root.range().start);
        if root.tag_name().name() != "scene" {
            return Err(SceneError::syntax(
                &loc,
                format!("the root element must be <scene>, found <{}>", root.tag_name().name()),
            ));
        }
        if let Some(v) = root.attribute("version") {
            let major = v.split('.').next().and_then(|m| m.parse::<u32>().ok());
            if !matches!(major, Some(2 | 3)) {
                return Err(SceneError::unsupported(
                    &loc,
                    format!("scene version \"{v}\" (mcrender reads the Mitsuba 2 and 3 formats, versions 2.x and 3.x)"),
                ));
            }
        }
        self.stack.push(canonical);
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut children = Vec::new();
        let result = self.children_of(&doc, &name, &dir, root, &mut children);
        self.stack.pop();
        result?;
        Ok(Element {
            tag: "scene".into(),
            attrs: Vec::new(),
            children,
            loc,
        })
    }

    fn children_of(
        &mut self,
        doc: &roxmltree::Document,
        name: &Arc<str>,
        dir: &Path,
        node: roxmltree::Node,
        out: &mut Vec<Element>,
    ) -> Result<(), SceneError> {
        for child in node.children().filter(roxmltree::Node::is_element) {
            let loc = location(doc, name, child.range().start);
            let mut attrs = Vec::new();
            for a in child.attributes() {
                let value = self.substitute(a.value(), &location(doc, name, a.range().start))?;
                attrs.push((a.name().to_string(), value));
            }
            let get = |k: &str| attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
            match child.tag_name().name() {
                "default" => {
                    let (Some(n), Some(v)) = (get("name"), get("value")) else {
                        return Err(SceneError::syntax(
                            &loc,
                            "<default> needs \"name\" and \"value\" attributes",
                        ));
                    };
                    if !self.defines.contains_key(&n) {
                        self.defaults.entry(n).or_insert(v);
                    }
                }
                "path" => {
                    let Some(v) = get("value") else {
                        return Err(SceneError::syntax(&loc, "<path> needs a \"value\" attribute"));
                    };
                    self.search_paths.push(dir.join(v));
                }
                "include" => {
                    let Some(f) = get("filename") else {
                        return Err(SceneError::syntax(&loc, "<include> needs a \"filename\" attribute"));
                    };
                    self.includes += 1;
                    if self.includes > MAX_INCLUDES {
                        return Err(SceneError::invalid(
                            &loc,
                            format!("more than {MAX_INCLUDES} <include>s in one scene"),
                        ));
                    }
                    let path = self.resolve_from(&f, dir);
                    let included = self.read_file(&path, &loc)?;
                    out.extend(included.children);
                }
                tag => {
                    let mut element = Element {
                        tag: tag.to_string(),
                        attrs,
                        children: Vec::new(),
                        loc,
                    };
                    self.children_of(doc, name, dir, child, &mut element.children)?;
                    out.push(element);
                }
            }
        }
        Ok(())
    }

    /// Replace every `$name` in `value` by its define or default.
    fn substitute(&self, value: &str, loc: &Location) -> Result<String, SceneError> {
        if !value.contains('$') {
            return Ok(value.to_string());
        }
        let mut out = String::new();
        let mut rest = value;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let key = &after[..len];
            let v = self
                .defines
                .get(key)
                .or_else(|| self.defaults.get(key))
                .ok_or_else(|| {
                    SceneError::invalid(
                        loc,
                        format!(
                            "undefined parameter {} (no <default> and no -D {}=...)",
                            quoted(&format!("${key}")),
                            short(key)
                        ),
                    )
                })?;
            out.push_str(v);
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// Resolve a file name: absolute as is; else the first existing of the `<path>`
    /// directories (latest first), `dir`, and the top-level file's directory.
    #[must_use]
    pub fn resolve_from(&self, file: &str, dir: &Path) -> PathBuf {
        let p = Path::new(file);
        if p.is_absolute() {
            return p.to_path_buf();
        }
        let mut dirs: Vec<PathBuf> = self.search_paths.iter().rev().cloned().collect();
        dirs.push(dir.to_path_buf());
        dirs.extend(self.search_paths());
        dirs.iter()
            .map(|d| d.join(p))
            .find(|c| self.files.exists(c))
            .unwrap_or_else(|| dir.join(p))
    }
}

/// `path` with `.` components dropped and `..` applied where it can be (what identifies a
/// file that cannot be canonicalised, e.g. one in memory, for cycle detection).
fn lexically_normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.components().next_back(), Some(Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The location of byte `pos` of `doc`.
fn location(doc: &roxmltree::Document, name: &Arc<str>, pos: usize) -> Location {
    let p = doc.text_pos_at(pos);
    Location::new(name.clone(), p.row, p.col)
}
