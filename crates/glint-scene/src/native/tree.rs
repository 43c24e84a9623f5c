//! Tokens → a generic node tree.
//!
//! The grammar is deliberately scene-agnostic (`name value* { node* }?`), so the
//! syntax can be checked, and reported, separately from what the nodes mean; the
//! builder gives the tree its meaning.

use super::lexer::{Pos, SyntaxError, Tok, Token};

/// Blocks nested deeper than this are refused, so hostile input cannot overflow the stack
/// of the recursive parser (and of the builder that walks the tree).
pub const MAX_NESTING: usize = 64;

/// A value written after a node name.
#[derive(Clone, Debug, PartialEq)]
pub enum ValueKind {
    /// A finite number.
    Number(f64),
    /// A quoted string.
    Str(String),
    /// `[a b c]`: finite numbers, any count (the builder checks the count).
    Vector(Vec<f64>),
    /// `true` / `false`.
    Bool(bool),
}

/// A value and where it starts, so the builder can point at a bad value.
#[derive(Clone, Debug, PartialEq)]
pub struct Value {
    /// The value itself.
    pub kind: ValueKind,
    /// Position of its first character (the `[` for vectors).
    pub pos: Pos,
}

impl Value {
    /// How the value reads in an error message ("a string", "3 numbers", …).
    pub fn describe(&self) -> String {
        match &self.kind {
            ValueKind::Number(_) => "a number".to_owned(),
            ValueKind::Str(_) => "a string".to_owned(),
            ValueKind::Vector(items) => match items.len() {
                0 => "an empty vector".to_owned(),
                1 => "a vector of 1 number".to_owned(),
                n => format!("a vector of {n} numbers"),
            },
            ValueKind::Bool(_) => "a boolean".to_owned(),
        }
    }
}

/// The first and one-past-last positions of a node's text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    /// Position of the node name.
    pub start: Pos,
    /// Position just after the node's last token (its last value or closing brace).
    pub end: Pos,
}

/// `{ node* }` with the position of its `{`, which errors about the block point at.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// Position of the opening brace.
    pub open: Pos,
    /// The nodes inside, in written order.
    pub nodes: Vec<Node>,
}

/// One node of the generic tree: `name value* block?`.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The node name.
    pub name: String,
    /// The values after the name, in written order.
    pub args: Vec<Value>,
    /// The block, if one was written (an empty `{}` is `Some` with no nodes).
    pub block: Option<Block>,
    /// Where the node's text starts and ends; `span.start` is the name's position.
    pub span: Span,
}

impl Node {
    /// Position of the node name, where most errors about the node point.
    pub fn pos(&self) -> Pos {
        self.span.start
    }

    /// The nodes of its block (none when it has no block).
    pub fn children(&self) -> &[Node] {
        self.block.as_ref().map_or(&[], |b| b.nodes.as_slice())
    }
}

/// Parses a whole file's tokens (as [`super::lexer::tokenize`] returns them, ending with
/// [`Tok::Eof`]) into its top-level nodes.
///
/// # Errors
///
/// The first syntax error: a stray token, an unclosed block or vector (reported at its
/// opening bracket), or blocks nested deeper than [`MAX_NESTING`].
pub fn parse(tokens: &[Token]) -> Result<Vec<Node>, SyntaxError> {
    // Tokens from elsewhere may lack the final `Eof`; the parser must still stop there.
    let end = tokens.last().map_or(Pos { line: 1, column: 1 }, |t| t.end);
    let eof = Token { tok: Tok::Eof, pos: end, end };
    let mut parser = Parser { tokens, index: 0, eof };
    parser.nodes(None, 0)
}

/// Cursor over the tokens of one file.
struct Parser<'t> {
    tokens: &'t [Token],
    index: usize,
    /// Returned once the tokens run out.
    eof: Token,
}

impl Parser<'_> {
    /// The current token, or `Eof` forever once the end is reached.
    fn peek(&self) -> &Token {
        self.tokens.get(self.index).unwrap_or(&self.eof)
    }

    fn bump(&mut self) -> Token {
        let token = self.peek().clone();
        if self.index < self.tokens.len() {
            self.index += 1;
        }
        token
    }

    /// Nodes up to the `}` that closes the block opened at `open`, or up to end of file
    /// at the top level (`open == None`).
    fn nodes(&mut self, open: Option<Pos>, depth: usize) -> Result<Vec<Node>, SyntaxError> {
        let mut nodes = Vec::new();
        loop {
            let token = self.peek();
            match &token.tok {
                Tok::Ident(_) => nodes.push(self.node(depth)?),
                Tok::RBrace => {
                    if open.is_some() {
                        return Ok(nodes);
                    }
                    return Err(SyntaxError::new(token.pos, "unexpected '}': there is no open block to close"));
                }
                Tok::Eof => {
                    if let Some(open) = open {
                        return Err(SyntaxError::new(
                            open,
                            "missing '}': the block opened here is still open at the end of the file",
                        ));
                    }
                    return Ok(nodes);
                }
                Tok::Comma => {
                    return Err(SyntaxError::new(
                        token.pos,
                        "unexpected ','; commas are only allowed between the numbers of a [vector]",
                    ));
                }
                Tok::LBrace => {
                    return Err(SyntaxError::new(
                        token.pos,
                        "unexpected '{'; a block must follow a node name, as in `group { … }`",
                    ));
                }
                Tok::RBracket => {
                    return Err(SyntaxError::new(token.pos, "unexpected ']' without a matching '['"));
                }
                other => {
                    return Err(SyntaxError::new(
                        token.pos,
                        format!(
                            "unexpected {}; expected a node name (a letter or '_' followed by \
                             letters, digits, '_' or '-')",
                            other.describe()
                        ),
                    ));
                }
            }
        }
    }

    /// `name value* block?`; the node ends at anything that is neither a value nor `{`.
    fn node(&mut self, depth: usize) -> Result<Node, SyntaxError> {
        let name_token = self.bump();
        let Tok::Ident(name) = name_token.tok else {
            return Err(SyntaxError::new(name_token.pos, "expected a node name"));
        };
        let mut end = name_token.end;
        let mut args = Vec::new();
        loop {
            let token = self.peek().clone();
            let kind = match token.tok {
                Tok::Number(value) => ValueKind::Number(value),
                Tok::Str(text) => ValueKind::Str(text),
                Tok::Bool(value) => ValueKind::Bool(value),
                Tok::LBracket => {
                    let (items, vector_end) = self.vector()?;
                    end = vector_end;
                    args.push(Value { kind: ValueKind::Vector(items), pos: token.pos });
                    continue;
                }
                _ => break,
            };
            self.bump();
            end = token.end;
            args.push(Value { kind, pos: token.pos });
        }
        let mut block = None;
        if self.peek().tok == Tok::LBrace {
            let open = self.bump().pos;
            if depth + 1 > MAX_NESTING {
                return Err(SyntaxError::new(
                    open,
                    format!("blocks are nested too deeply; at most {MAX_NESTING} levels are allowed"),
                ));
            }
            let nodes = self.nodes(Some(open), depth + 1)?;
            end = self.bump().end; // the closing brace, checked by `nodes`
            block = Some(Block { open, nodes });
        }
        Ok(Node { name, args, block, span: Span { start: name_token.pos, end } })
    }

    /// `[ number (,? number)* ,? ]`, called with `[` as the current token.
    fn vector(&mut self) -> Result<(Vec<f64>, Pos), SyntaxError> {
        let open = self.bump().pos;
        let mut items = Vec::new();
        let mut comma_allowed = false;
        loop {
            let token = self.bump();
            match token.tok {
                Tok::Number(value) => {
                    items.push(value);
                    comma_allowed = true;
                }
                Tok::Comma if comma_allowed => comma_allowed = false,
                Tok::RBracket => return Ok((items, token.end)),
                Tok::Eof => {
                    return Err(SyntaxError::new(
                        open,
                        "missing ']': the vector opened here is still open at the end of the file",
                    ));
                }
                other => {
                    return Err(SyntaxError::new(
                        token.pos,
                        format!(
                            "expected a number or ']' in the vector opened at {}:{}, found {}",
                            open.line,
                            open.column,
                            other.describe()
                        ),
                    ));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::lexer::tokenize;
    use super::*;

    fn parse_str(source: &str) -> Result<Vec<Node>, SyntaxError> {
        parse(&tokenize(source)?)
    }

    #[test]
    fn nodes_end_at_the_next_name() {
        let nodes = parse_str("a 1 \"s\" [1, 2 3] true b { c } d").expect("parses");
        let names: Vec<_> = nodes.iter().map(|n| n.name.as_str()).collect();
        assert_eq!(names, ["a", "b", "d"]);
        assert_eq!(
            nodes[0].args.iter().map(|v| v.kind.clone()).collect::<Vec<_>>(),
            vec![
                ValueKind::Number(1.0),
                ValueKind::Str("s".to_owned()),
                ValueKind::Vector(vec![1.0, 2.0, 3.0]),
                ValueKind::Bool(true)
            ]
        );
        assert_eq!(nodes[1].children()[0].name, "c");
        assert_eq!(nodes[1].span.end, Pos { line: 1, column: 30 });
        assert!(nodes[2].block.is_none());
    }

    #[test]
    fn unclosed_block_points_at_its_brace() {
        let err = parse_str("a {\n  b { }\n  c {\n}\n").expect_err("unclosed");
        assert_eq!(err.pos, Pos { line: 1, column: 3 });
    }

    #[test]
    fn stray_tokens_are_refused() {
        for (source, column) in [("a }", 3), ("a {} 5", 6), ("a , 1", 3), ("[1]", 1), ("a 1]", 4)] {
            let err = parse_str(source).expect_err(source);
            assert_eq!(err.pos.column, column, "{source}: {}", err.message);
        }
    }

    #[test]
    fn tokens_without_eof_still_end() {
        let mut tokens = tokenize("a { b 1").expect("lexes");
        tokens.pop();
        let err = parse(&tokens).expect_err("unclosed");
        assert_eq!(err.pos, Pos { line: 1, column: 3 });
        assert_eq!(parse(&[]), Ok(Vec::new()));
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowed() {
        let source = "a {".repeat(10_000);
        let err = parse_str(&source).expect_err("too deep");
        assert!(err.message.contains("nested too deeply"), "{}", err.message);
    }
}
