//! YAML text → a small tree in which every node knows its line and column.
//!
//! The scene reader needs positions for every value it complains about, so the events
//! of `saphyr-parser` are assembled here into [`Yaml`] nodes instead of going through a
//! generic YAML document type that forgets where things were.

use std::collections::HashMap;

use saphyr_parser::{Event, Parser, ScalarStyle, Span};

use crate::native::lexer::Pos;

/// Most nodes one file may expand to; aliases (`*name`) copy their anchor's subtree, so
/// without a limit a few lines could expand exponentially ("billion laughs").
pub const MAX_YAML_NODES: usize = 1_000_000;

/// A YAML node and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Yaml {
    /// What the node is.
    pub value: Value,
    /// Where it starts.
    pub pos: Pos,
}

/// The three kinds of YAML node.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A scalar; `plain` is false for quoted and block scalars, which are always text.
    Scalar { text: String, plain: bool },
    /// `[a, b]` or a block of `- a` lines.
    Seq(Vec<Yaml>),
    /// `{k: v}` or a block of `k: v` lines, in written order; keys are scalars and unique.
    Map(Vec<(Yaml, Yaml)>),
}

impl Yaml {
    /// How the node reads in an error message: "a list", "a mapping", "'abc'".
    pub fn describe(&self) -> String {
        match &self.value {
            Value::Scalar { text, .. } if text.is_empty() => "nothing".to_owned(),
            Value::Scalar { text, .. } => format!("'{text}'"),
            Value::Seq(items) => format!("a list of {} item{}", items.len(), if items.len() == 1 { "" } else { "s" }),
            Value::Map(_) => "a mapping (key: value lines)".to_owned(),
        }
    }

    /// The text of a scalar node.
    pub fn scalar(&self) -> Option<&str> {
        match &self.value {
            Value::Scalar { text, .. } => Some(text),
            _ => None,
        }
    }

    /// The entries of a mapping node.
    pub fn map(&self) -> Option<&[(Yaml, Yaml)]> {
        match &self.value {
            Value::Map(entries) => Some(entries),
            _ => None,
        }
    }

    /// The items of a sequence node.
    pub fn seq(&self) -> Option<&[Yaml]> {
        match &self.value {
            Value::Seq(items) => Some(items),
            _ => None,
        }
    }

    /// The value of `key` in a mapping node.
    pub fn get(&self, key: &str) -> Option<&Yaml> {
        self.map()?.iter().find(|(k, _)| k.scalar() == Some(key)).map(|(_, v)| v)
    }

    /// Whether this is the empty plain scalar YAML gives for `key:` with nothing after it.
    pub fn is_null(&self) -> bool {
        matches!(&self.value, Value::Scalar { text, plain: true } if text.is_empty() || text == "~" || text == "null")
    }
}

/// A YAML syntax error at a position.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct YamlError {
    /// Where the problem is.
    pub pos: Pos,
    /// What is wrong.
    pub message: String,
}

/// Parses the first (and only) YAML document of `text`; `None` for a file with no
/// document at all (empty or only comments).
///
/// # Errors
///
/// Malformed YAML, a repeated mapping key, a non-scalar key, an unknown alias, a second
/// document, or more than [`MAX_YAML_NODES`] nodes.
pub fn parse(text: &str) -> Result<Option<Yaml>, YamlError> {
    let mut builder = TreeBuilder::default();
    for event in Parser::new_from_str(text) {
        let (event, span) = event
            .map_err(|e| YamlError { pos: pos_of(*e.marker()), message: format!("invalid YAML: {}", e.info()) })?;
        builder.event(event, span)?;
    }
    Ok(builder.root)
}

fn pos_of(marker: saphyr_parser::Marker) -> Pos {
    Pos { line: marker.line() as u32, column: marker.col() as u32 + 1 }
}

/// A container still being read.
enum Frame {
    Seq { pos: Pos, anchor: usize, items: Vec<Yaml> },
    Map { pos: Pos, anchor: usize, entries: Vec<(Yaml, Yaml)>, key: Option<Yaml> },
}

#[derive(Default)]
struct TreeBuilder {
    stack: Vec<Frame>,
    root: Option<Yaml>,
    anchors: HashMap<usize, Yaml>,
    nodes: usize,
    documents: usize,
}

impl TreeBuilder {
    /// Takes one event.
    fn event(&mut self, event: Event<'_>, span: Span) -> Result<(), YamlError> {
        let pos = pos_of(span.start);
        match event {
            Event::DocumentStart(_) => {
                self.documents += 1;
                if self.documents > 1 {
                    return Err(YamlError {
                        pos,
                        message: "a scene file holds one YAML document; remove the second '---' and what follows, \
                                  or put it in its own file"
                            .to_owned(),
                    });
                }
            }
            Event::DocumentEnd => {}
            Event::StreamStart | Event::StreamEnd | Event::Nothing => {}
            Event::Scalar(text, style, anchor, _) => {
                let plain = style == ScalarStyle::Plain;
                self.value(Yaml { value: Value::Scalar { text: text.into_owned(), plain }, pos }, anchor)?;
            }
            Event::Alias(id) => {
                let Some(node) = self.anchors.get(&id).cloned() else {
                    return Err(YamlError {
                        pos,
                        message: "alias to an anchor that is not defined before it".to_owned(),
                    });
                };
                self.count(pos, count_nodes(&node))?;
                self.value(node, 0)?;
            }
            Event::SequenceStart(anchor, _) => self.stack.push(Frame::Seq { pos, anchor, items: Vec::new() }),
            Event::MappingStart(anchor, _) => {
                self.stack.push(Frame::Map { pos, anchor, entries: Vec::new(), key: None });
            }
            Event::SequenceEnd | Event::MappingEnd => {
                let (node, anchor) = match self.stack.pop() {
                    Some(Frame::Seq { pos, anchor, items }) => (Yaml { value: Value::Seq(items), pos }, anchor),
                    Some(Frame::Map { pos, anchor, entries, .. }) => (Yaml { value: Value::Map(entries), pos }, anchor),
                    None => return Ok(()),
                };
                self.value(node, anchor)?;
            }
        }
        Ok(())
    }

    fn count(&mut self, pos: Pos, added: usize) -> Result<(), YamlError> {
        self.nodes = self.nodes.saturating_add(added);
        if self.nodes > MAX_YAML_NODES {
            return Err(YamlError {
                pos,
                message: format!("the file expands to more than {MAX_YAML_NODES} YAML nodes; reduce nested aliases"),
            });
        }
        Ok(())
    }

    /// Places a finished node into its parent (or as the root).
    fn value(&mut self, node: Yaml, anchor: usize) -> Result<(), YamlError> {
        self.count(node.pos, 1)?;
        if anchor != 0 {
            self.anchors.insert(anchor, node.clone());
        }
        match self.stack.last_mut() {
            None => self.root = Some(node),
            Some(Frame::Seq { items, .. }) => items.push(node),
            Some(Frame::Map { entries, key, .. }) => match key.take() {
                Some(k) => entries.push((k, node)),
                None => {
                    let Some(name) = node.scalar() else {
                        return Err(YamlError {
                            pos: node.pos,
                            message: format!("a mapping key must be a plain word, found {}", node.describe()),
                        });
                    };
                    if let Some((first, _)) = entries.iter().find(|(k, _)| k.scalar() == Some(name)) {
                        return Err(YamlError {
                            pos: node.pos,
                            message: format!(
                                "key '{name}' is given twice in the same mapping; the first is at line {}, column {}",
                                first.pos.line, first.pos.column
                            ),
                        });
                    }
                    *key = Some(node);
                }
            },
        }
        Ok(())
    }
}

fn count_nodes(node: &Yaml) -> usize {
    1 + match &node.value {
        Value::Scalar { .. } => 0,
        Value::Seq(items) => items.iter().map(count_nodes).sum(),
        Value::Map(entries) => entries.iter().map(|(k, v)| count_nodes(k) + count_nodes(v)).sum(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: u32, column: u32) -> Pos {
        Pos { line, column }
    }

    #[test]
    fn nodes_know_their_positions() {
        let doc = parse("# c\n- add: sphere\n  at: [1, 2.5, -3]\n").unwrap().unwrap();
        let items = doc.seq().unwrap();
        assert_eq!(items.len(), 1);
        let add = items[0].get("add").unwrap();
        assert_eq!((add.scalar(), add.pos), (Some("sphere"), at(2, 8)));
        let v = items[0].get("at").unwrap().seq().unwrap();
        assert_eq!((v[1].scalar(), v[1].pos), (Some("2.5"), at(3, 11)));
    }

    #[test]
    fn quoted_scalars_are_not_plain_and_empty_values_are_null() {
        let doc = parse("a: '1'\nb:\n").unwrap().unwrap();
        assert_eq!(doc.get("a").unwrap().value, Value::Scalar { text: "1".into(), plain: false });
        assert!(doc.get("b").unwrap().is_null());
    }

    #[test]
    fn errors_are_located() {
        let err = parse("- add: sphere\n  x: [1, 2\n").unwrap_err();
        assert!(err.message.starts_with("invalid YAML"), "{}", err.message);
        let err = parse("a: 1\nb: 2\na: 3\n").unwrap_err();
        assert_eq!(err.pos, at(3, 1));
        assert!(err.message.contains("twice"), "{}", err.message);
        let err = parse("- 1\n---\n- 2\n").unwrap_err();
        assert_eq!(err.pos.line, 2);
    }

    #[test]
    fn aliases_copy_anchors_and_empty_files_have_no_document() {
        let doc = parse("a: &x [1, 2]\nb: *x\n").unwrap().unwrap();
        assert_eq!(doc.get("b").unwrap().seq().unwrap().len(), 2);
        assert_eq!(parse("# only a comment\n").unwrap(), None);
    }
}
