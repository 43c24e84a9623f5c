//! A small JSON reader (RFC 8259) that keeps the line and column of every value and key,
//! so that a scene's meaning errors ("`translate` needs 3 numbers") can point at the
//! place in the file, not only its syntax errors.

use super::Pos;

/// Arrays and objects nested deeper than this are refused (a scene needs a few dozen);
/// the reader is recursive and must not exhaust the stack on hostile input.
pub const MAX_NESTING: usize = 512;

/// A JSON value and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Value {
    pub kind: Kind,
    pub pos: Pos,
}

/// The JSON types.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    Null,
    Bool(bool),
    Number(f64),
    String(String),
    Array(Vec<Value>),
    /// Members in written order; duplicates are kept (the caller decides).
    Object(Vec<Member>),
}

/// One `"key": value` of an object.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    pub key: String,
    pub key_pos: Pos,
    pub value: Value,
}

impl Value {
    /// The JSON type's name with an article, for messages ("a string", "an array").
    pub fn describe(&self) -> &'static str {
        match self.kind {
            Kind::Null => "null",
            Kind::Bool(_) => "a boolean",
            Kind::Number(_) => "a number",
            Kind::String(_) => "a string",
            Kind::Array(_) => "an array",
            Kind::Object(_) => "an object",
        }
    }
}

/// Malformed JSON text: where and what.
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    pub pos: Pos,
    pub message: String,
}

/// Parses a whole document: exactly one value, surrounded by whitespace only.
pub fn parse(text: &str) -> Result<Value, SyntaxError> {
    let mut p = Parser { chars: text.trim_start_matches('\u{feff}').chars().peekable(), line: 1, column: 1 };
    p.skip_whitespace();
    let value = p.value(0)?;
    p.skip_whitespace();
    if let Some(c) = p.peek() {
        return Err(p.error(format!("unexpected {} after the end of the document", describe_char(c))));
    }
    Ok(value)
}

struct Parser<'a> {
    chars: std::iter::Peekable<std::str::Chars<'a>>,
    line: u32,
    column: u32,
}

impl Parser<'_> {
    fn pos(&self) -> Pos {
        Pos { line: self.line, column: self.column }
    }

    fn error(&self, message: impl Into<String>) -> SyntaxError {
        SyntaxError { pos: self.pos(), message: message.into() }
    }

    fn peek(&mut self) -> Option<char> {
        self.chars.peek().copied()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.chars.next()?;
        if c == '\n' {
            self.line += 1;
            self.column = 1;
        } else {
            self.column += 1;
        }
        Some(c)
    }

    fn skip_whitespace(&mut self) {
        while matches!(self.peek(), Some(' ' | '\t' | '\n' | '\r')) {
            self.bump();
        }
    }

    fn expect(&mut self, wanted: char, context: &str) -> Result<(), SyntaxError> {
        match self.peek() {
            Some(c) if c == wanted => {
                self.bump();
                Ok(())
            }
            Some(c) => Err(self.error(format!("expected '{wanted}' {context}, found {}", describe_char(c)))),
            None => Err(self.error(format!("expected '{wanted}' {context}, found the end of the file"))),
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, SyntaxError> {
        let pos = self.pos();
        let kind = match self.peek() {
            None => return Err(self.error("expected a value, found the end of the file")),
            Some('{') => {
                self.nest(depth)?;
                Kind::Object(self.object(depth)?)
            }
            Some('[') => {
                self.nest(depth)?;
                Kind::Array(self.array(depth)?)
            }
            Some('"') => Kind::String(self.string()?),
            Some('-' | '0'..='9') => Kind::Number(self.number()?),
            Some(c) if c.is_ascii_alphabetic() => self.word()?,
            Some(c) => return Err(self.error(format!("expected a value, found {}", describe_char(c)))),
        };
        Ok(Value { kind, pos })
    }

    fn nest(&self, depth: usize) -> Result<(), SyntaxError> {
        if depth >= MAX_NESTING {
            return Err(self.error(format!("arrays and objects are nested more than {MAX_NESTING} deep")));
        }
        Ok(())
    }

    fn object(&mut self, depth: usize) -> Result<Vec<Member>, SyntaxError> {
        self.bump(); // '{'
        let mut members = Vec::new();
        self.skip_whitespace();
        if self.peek() == Some('}') {
            self.bump();
            return Ok(members);
        }
        loop {
            self.skip_whitespace();
            let key_pos = self.pos();
            match self.peek() {
                Some('"') => {}
                Some('}') => return Err(self.error("a trailing comma is not allowed before '}'")),
                Some(c) => {
                    return Err(self.error(format!("expected a key in double quotes, found {}", describe_char(c))));
                }
                None => return Err(self.error("expected a key, found the end of the file (an object is not closed)")),
            }
            let key = self.string()?;
            self.skip_whitespace();
            self.expect(':', &format!("after the key \"{key}\""))?;
            self.skip_whitespace();
            let value = self.value(depth + 1)?;
            members.push(Member { key, key_pos, value });
            self.skip_whitespace();
            match self.bump() {
                Some(',') => {}
                Some('}') => return Ok(members),
                Some(c) => {
                    return Err(SyntaxError {
                        pos: self.back_one(),
                        message: format!("expected ',' or '}}' after an object member, found {}", describe_char(c)),
                    });
                }
                None => {
                    return Err(self.error("expected ',' or '}', found the end of the file (an object is not closed)"));
                }
            }
        }
    }

    fn array(&mut self, depth: usize) -> Result<Vec<Value>, SyntaxError> {
        self.bump(); // '['
        let mut items = Vec::new();
        self.skip_whitespace();
        if self.peek() == Some(']') {
            self.bump();
            return Ok(items);
        }
        loop {
            self.skip_whitespace();
            if self.peek() == Some(']') {
                return Err(self.error("a trailing comma is not allowed before ']'"));
            }
            items.push(self.value(depth + 1)?);
            self.skip_whitespace();
            match self.bump() {
                Some(',') => {}
                Some(']') => return Ok(items),
                Some(c) => {
                    return Err(SyntaxError {
                        pos: self.back_one(),
                        message: format!("expected ',' or ']' after an array element, found {}", describe_char(c)),
                    });
                }
                None => {
                    return Err(self.error("expected ',' or ']', found the end of the file (an array is not closed)"));
                }
            }
        }
    }

    /// The position of the character just consumed (never across a newline here).
    fn back_one(&self) -> Pos {
        Pos { line: self.line, column: self.column.saturating_sub(1).max(1) }
    }

    fn string(&mut self) -> Result<String, SyntaxError> {
        self.bump(); // '"'
        let mut out = String::new();
        loop {
            let pos = self.pos();
            match self.bump() {
                None => return Err(self.error("a string is not closed before the end of the file")),
                Some('"') => return Ok(out),
                Some('\\') => {
                    let escape = self.bump();
                    match escape {
                        Some('"') => out.push('"'),
                        Some('\\') => out.push('\\'),
                        Some('/') => out.push('/'),
                        Some('b') => out.push('\u{8}'),
                        Some('f') => out.push('\u{c}'),
                        Some('n') => out.push('\n'),
                        Some('r') => out.push('\r'),
                        Some('t') => out.push('\t'),
                        Some('u') => out.push(self.unicode_escape(pos)?),
                        Some(c) => {
                            return Err(SyntaxError {
                                pos,
                                message: format!(
                                    "unknown escape '\\{c}' in a string; allowed: \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX"
                                ),
                            });
                        }
                        None => return Err(self.error("a string is not closed before the end of the file")),
                    }
                }
                Some(c) if (c as u32) < 0x20 => {
                    return Err(SyntaxError {
                        pos,
                        message: "a string may not contain a line break or control character; \
                                  close it on the same line or write \\n"
                            .to_owned(),
                    });
                }
                Some(c) => out.push(c),
            }
        }
    }

    /// `\uXXXX`, with surrogate pairs combined.
    fn unicode_escape(&mut self, pos: Pos) -> Result<char, SyntaxError> {
        let high = self.hex4(pos)?;
        let code = if (0xD800..0xDC00).contains(&high) {
            let paired = self.bump() == Some('\\') && self.bump() == Some('u');
            let low = if paired { self.hex4(pos)? } else { 0 };
            if !(0xDC00..0xE000).contains(&low) {
                return Err(SyntaxError {
                    pos,
                    message: "a \\u escape of a high surrogate must be followed by a low surrogate".into(),
                });
            }
            0x10000 + ((high - 0xD800) << 10) + (low - 0xDC00)
        } else {
            high
        };
        char::from_u32(code).ok_or_else(|| SyntaxError { pos, message: format!("\\u{code:04X} is not a character") })
    }

    fn hex4(&mut self, pos: Pos) -> Result<u32, SyntaxError> {
        let mut code = 0;
        for _ in 0..4 {
            let digit = self.bump().and_then(|c| c.to_digit(16));
            let Some(digit) = digit else {
                return Err(SyntaxError { pos, message: "a \\u escape needs exactly 4 hexadecimal digits".into() });
            };
            code = code * 16 + digit;
        }
        Ok(code)
    }

    fn number(&mut self) -> Result<f64, SyntaxError> {
        let start = self.pos();
        let mut text = String::new();
        while let Some(c) = self.peek() {
            if c.is_ascii_digit() || matches!(c, '-' | '+' | '.' | 'e' | 'E') {
                text.push(c);
                self.bump();
            } else {
                break;
            }
        }
        let bad =
            || SyntaxError { pos: start, message: format!("'{text}' is not a JSON number (like 1, -2.5 or 1e-3)") };
        if !valid_number(&text) {
            return Err(bad());
        }
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(SyntaxError { pos: start, message: format!("the number {text} is too large") }),
            Err(_) => Err(bad()),
        }
    }

    fn word(&mut self) -> Result<Kind, SyntaxError> {
        let start = self.pos();
        let mut word = String::new();
        while let Some(c) = self.peek().filter(char::is_ascii_alphanumeric) {
            word.push(c);
            self.bump();
        }
        match word.as_str() {
            "true" => Ok(Kind::Bool(true)),
            "false" => Ok(Kind::Bool(false)),
            "null" => Ok(Kind::Null),
            _ => Err(SyntaxError {
                pos: start,
                message: format!(
                    "unexpected word '{word}'; a value is a number, a \"string\", true, false, null, [...] or {{...}}"
                ),
            }),
        }
    }
}

/// The JSON number grammar: `-? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`.
fn valid_number(text: &str) -> bool {
    let b = text.as_bytes();
    let mut i = 0;
    let digits = |i: &mut usize| {
        let start = *i;
        while *i < b.len() && b[*i].is_ascii_digit() {
            *i += 1;
        }
        *i > start
    };
    if b.first() == Some(&b'-') {
        i += 1;
    }
    if b.get(i) == Some(&b'0') {
        i += 1;
    } else if !digits(&mut i) {
        return false;
    }
    if b.get(i) == Some(&b'.') {
        i += 1;
        if !digits(&mut i) {
            return false;
        }
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if !digits(&mut i) {
            return false;
        }
    }
    i == b.len()
}

fn describe_char(c: char) -> String {
    match c {
        '\n' => "a line break".to_owned(),
        c if c.is_control() => format!("the control character U+{:04X}", c as u32),
        c => format!("'{c}'"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: u32, column: u32) -> Pos {
        Pos { line, column }
    }

    #[test]
    fn values_keep_their_positions() {
        let v = parse("{\n  \"a\": [1, -2.5e1],\n  \"b\": \"x\\u00e9\"\n}").unwrap();
        let Kind::Object(members) = &v.kind else { panic!() };
        assert_eq!(members[0].key, "a");
        assert_eq!(members[0].key_pos, at(2, 3));
        let Kind::Array(items) = &members[0].value.kind else { panic!() };
        assert_eq!(items[1], Value { kind: Kind::Number(-25.0), pos: at(2, 12) });
        assert_eq!(members[1].value.kind, Kind::String("xé".into()));
        assert_eq!(members[1].value.pos, at(3, 8));
    }

    #[test]
    fn malformed_text_is_located() {
        let cases = [
            ("{\"a\": 1,}", at(1, 9), "trailing comma"),
            ("{\"a\" 1}", at(1, 6), "expected ':'"),
            ("[1 2]", at(1, 4), "expected ',' or ']'"),
            ("{\"a\": 01}", at(1, 7), "not a JSON number"),
            ("{\"a\": tru}", at(1, 7), "unexpected word 'tru'"),
            ("\n\n  [1,", at(3, 6), "expected a value"),
            ("{} x", at(1, 4), "after the end"),
            ("\"ab\ncd\"", at(1, 4), "line break"),
        ];
        for (text, pos, fragment) in cases {
            let e = parse(text).unwrap_err();
            assert_eq!(e.pos, pos, "{text:?}: {}", e.message);
            assert!(e.message.contains(fragment), "{text:?}: {}", e.message);
        }
    }

    #[test]
    fn number_grammar() {
        for ok in ["0", "-0", "1.5", "1e3", "1E-3", "-12.25e+2"] {
            assert!(valid_number(ok), "{ok}");
        }
        for bad in ["", "-", "01", "1.", ".5", "1e", "+1", "1-2", "--1"] {
            assert!(!valid_number(bad), "{bad}");
        }
    }

    #[test]
    fn deep_nesting_is_refused_not_a_crash() {
        let text = "[".repeat(MAX_NESTING + 10);
        assert!(parse(&text).unwrap_err().message.contains("nested"));
    }
}
