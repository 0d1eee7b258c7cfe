//! Scene text: `--set` overrides, strict deserialisation, and locating keys by line.

use super::error::{KeyError, SceneError};
use super::types::Scene;

/// Deserialise scene text (strictly: unknown keys are errors) without validating it.
pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
    let de = toml::Deserializer::parse(text).map_err(|e| toml_error(text, file, "", &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = clean_path(&e.path().to_string());
        toml_error(text, file, &path, e.inner())
    })
}

/// The error `(key path, message)` found in scene text, located by line.
pub fn at(text: &str, file: &str, KeyError { path, message }: KeyError) -> SceneError {
    SceneError {
        file: file.to_string(),
        line: locate(text, &path),
        path,
        message,
    }
}

fn toml_error(text: &str, file: &str, path: &str, e: &toml::de::Error) -> SceneError {
    let line = e
        .span()
        .map(|s| line_of(text, s.start))
        .or_else(|| locate(text, path));
    SceneError {
        file: file.to_string(),
        path: path.to_string(),
        line,
        message: name_the_key(text, e.message(), e.span()),
    }
}

/// A TOML parser's message, with the key it points at named where the message does
/// not (`duplicate key` says which key only through its span).
fn name_the_key(text: &str, message: &str, span: Option<std::ops::Range<usize>>) -> String {
    let message = message.trim();
    let key = span
        .and_then(|s| text.get(s))
        .map(|k| k.trim().trim_matches('"'))
        .filter(|k| !k.is_empty() && !k.contains('\n'));
    match key {
        Some(k) if message.starts_with("duplicate key") && !message.contains('`') => {
            format!("duplicate key `{k}`: each key may be given once per table")
        }
        _ => message.to_string(),
    }
}

/// The error `(key path, message)` of a scene read from `source` with `overrides`
/// applied, located where its value came from: the `--set` argument that set the key
/// (or a key above it), else the key's line in the file as written (`line`, the
/// location in the text after overrides, when the key cannot be found there).
pub fn attribute(
    source: &str,
    file: &str,
    overrides: &[String],
    KeyError { path, message }: KeyError,
    line: Option<usize>,
) -> SceneError {
    let at = segments(&path);
    let set = overrides.iter().find(|o| {
        let key = segments(o.split_once('=').map_or(o.as_str(), |(k, _)| k));
        !key.is_empty() && at.starts_with(&key)
    });
    match set {
        Some(o) => SceneError {
            file: format!("--set {o}"),
            path,
            line: None,
            message,
        },
        None => SceneError {
            file: file.to_string(),
            line: locate(source, &path).or(line),
            path,
            message,
        },
    }
}

/// [`attribute`] for an error already located in the text after overrides.
pub fn reattribute(source: &str, overrides: &[String], e: SceneError) -> SceneError {
    if overrides.is_empty() {
        return e;
    }
    let line = e.line;
    let file = e.file.clone();
    attribute(
        source,
        &file,
        overrides,
        KeyError::new(e.path, e.message),
        line,
    )
}

/// serde_path_to_error prints `?` for untracked segments; drop them.
fn clean_path(p: &str) -> String {
    if p == "." || p == "?" {
        return String::new();
    }
    p.replace(".?", "")
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

/// Split `a.b[2].c` into segments `a`, `b`, `2`, `c`.
fn segments(path: &str) -> Vec<String> {
    path.replace('[', ".")
        .replace(']', "")
        .split('.')
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

/// Why a key path such as `a..b`, `.a` or `a[0]x` is malformed (an empty segment, or
/// text after an index), if it is.
fn empty_segment(key: &str) -> Option<String> {
    let mut rest = key;
    let mut first = true;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix('[') {
            let Some((index, after)) = r.split_once(']') else {
                return Some(format!("unclosed `[` in the key path `{key}`"));
            };
            if index.parse::<usize>().is_err() {
                return Some(format!("`[{index}]` is not an array index"));
            }
            rest = after;
        } else {
            if !first {
                match rest.strip_prefix('.') {
                    Some(r) => rest = r,
                    None => return Some(format!("unexpected `{rest}` after an index")),
                }
            }
            let end = rest.find(['.', '[']).unwrap_or(rest.len());
            if rest[..end].trim().is_empty() {
                return Some(format!(
                    "empty segment in the key path `{key}`: write e.g. simulation.dp"
                ));
            }
            rest = &rest[end..];
        }
        first = false;
    }
    None
}

/// Line of the deepest existing key on `path`, if any.
pub fn locate(text: &str, path: &str) -> Option<usize> {
    use toml_edit::{Item, Table, Value};
    enum Node<'a> {
        Item(&'a Item),
        Table(&'a Table),
        Value(&'a Value),
    }
    let doc = toml_edit::Document::parse(text).ok()?;
    let mut node = Node::Table(doc.as_table());
    let mut best = None;
    for seg in segments(path) {
        let index = seg.parse::<usize>().ok();
        let (span, next) = match (&node, index) {
            (Node::Item(Item::ArrayOfTables(a)), Some(i)) => match a.get(i) {
                Some(t) => (t.span(), Node::Table(t)),
                None => break,
            },
            (Node::Item(Item::Value(Value::Array(a))), Some(i))
            | (Node::Value(Value::Array(a)), Some(i)) => match a.get(i) {
                Some(v) => (v.span(), Node::Value(v)),
                None => break,
            },
            (Node::Item(item), None) => {
                match item.as_table_like().and_then(|t| t.get_key_value(&seg)) {
                    Some((k, v)) => (k.span().or(v.span()), Node::Item(v)),
                    None => break,
                }
            }
            (Node::Table(t), None) => match t.get_key_value(&seg) {
                Some((k, v)) => (k.span().or(v.span()), Node::Item(v)),
                None => break,
            },
            (Node::Value(Value::InlineTable(t)), None) => match t.get_key_value(&seg) {
                Some((k, v)) => (k.span().or(v.span()), Node::Item(v)),
                None => break,
            },
            _ => break,
        };
        if let Some(s) = span {
            best = Some(line_of(text, s.start));
        }
        node = next;
    }
    best
}

/// The deepest key path an override may name: the schema's deepest keys are five
/// segments (`water.regions[0].shape.min`), and a path thousands deep would build a
/// table that the parser then refuses as the scene file's fault.
const MAX_KEY_DEPTH: usize = 16;

/// Apply `key.path=value` overrides. The value is parsed as TOML (`0.3`, `[1, 2]`,
/// `"name"`, `true`), falling back to a bare string.
pub fn apply_overrides(text: &str, file: &str, overrides: &[String]) -> Result<String, SceneError> {
    if overrides.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut =
        text.parse().map_err(|e: toml_edit::TomlError| SceneError {
            file: file.to_string(),
            path: String::new(),
            line: e.span().map(|s| line_of(text, s.start)),
            message: name_the_key(text, e.message(), e.span()),
        })?;
    for expr in overrides {
        let err = |message: String| SceneError {
            file: format!("--set {expr}"),
            path: String::new(),
            line: None,
            message,
        };
        let (key, raw) = expr
            .split_once('=')
            .ok_or_else(|| err("expected key.path=value".to_string()))?;
        let raw = raw.trim();
        let value: toml_edit::Value = raw
            .parse()
            .unwrap_or_else(|_| toml_edit::Value::from(raw.to_string()));
        let segs = segments(key.trim());
        if segs.is_empty() {
            return Err(err("empty key path".to_string()));
        }
        if let Some(bad) = empty_segment(key.trim()) {
            return Err(err(bad));
        }
        if segs.len() > MAX_KEY_DEPTH {
            return Err(err(format!(
                "a key path of {} segments: no scene key is more than {MAX_KEY_DEPTH} deep \
                 (e.g. water.regions[0].shape.min)",
                segs.len()
            )));
        }
        set_path(doc.as_item_mut(), &segs, value).map_err(|e| err(e.to_string()))?;
    }
    Ok(doc.to_string())
}

/// Why an override's key path cannot be set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum SetError {
    #[error("index {index} out of range (array has {len} entries)")]
    OutOfRange { index: usize, len: usize },
    #[error("`{0}` indexes something that is not an array")]
    NotAnArray(String),
    #[error("cannot set `{0}`: parent is not a table")]
    NotATable(String),
}

fn set_in_table(
    t: &mut toml_edit::Table,
    rest: &[String],
    value: toml_edit::Value,
) -> Result<(), SetError> {
    let mut item = toml_edit::Item::Table(std::mem::take(t));
    let r = set_path(&mut item, rest, value);
    if let toml_edit::Item::Table(back) = item {
        *t = back;
    }
    r
}

fn set_path(
    item: &mut toml_edit::Item,
    segs: &[String],
    value: toml_edit::Value,
) -> Result<(), SetError> {
    let seg = &segs[0];
    let last = segs.len() == 1;
    if let Ok(i) = seg.parse::<usize>() {
        match item {
            toml_edit::Item::Value(toml_edit::Value::Array(a)) if last => {
                if i >= a.len() {
                    return Err(SetError::OutOfRange {
                        index: i,
                        len: a.len(),
                    });
                }
                a.replace(i, value);
                Ok(())
            }
            toml_edit::Item::ArrayOfTables(a) if !last => {
                let n = a.len();
                let t = a
                    .get_mut(i)
                    .ok_or(SetError::OutOfRange { index: i, len: n })?;
                set_in_table(t, &segs[1..], value)
            }
            _ => Err(SetError::NotAnArray(seg.clone())),
        }
    } else {
        let t = item
            .as_table_like_mut()
            .ok_or_else(|| SetError::NotATable(seg.clone()))?;
        if last {
            t.insert(seg, toml_edit::Item::Value(value));
            return Ok(());
        }
        if t.get(seg).is_none() {
            t.insert(seg, toml_edit::Item::Table(toml_edit::Table::new()));
        }
        set_path(t.get_mut(seg).expect("present"), &segs[1..], value)
    }
}
