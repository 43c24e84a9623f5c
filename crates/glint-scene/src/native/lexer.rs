//! Characters → tokens for the `.glint` format.
//!
//! The lexer knows nothing about scenes; it only guarantees that every number it hands on
//! is finite in `f32` (so NaN and infinity can never reach the renderer) and that every
//! token knows the line and column where it starts.

pub use crate::source::Pos;

/// What a token is; the text of names and strings is kept decoded.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A node name: `[A-Za-z_][A-Za-z0-9_-]*`, not `true`/`false`.
    Ident(String),
    /// A number, guaranteed finite when narrowed to `f32`; kept as `f64` so that integer
    /// properties (image width, …) can be checked exactly.
    Number(f64),
    /// A quoted string with its escapes resolved.
    Str(String),
    /// `true` or `false`.
    Bool(bool),
    /// `[`
    LBracket,
    /// `]`
    RBracket,
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `,` (only meaningful between vector elements).
    Comma,
    /// End of input; always the last token, so the parser never runs off the end.
    Eof,
}

impl Tok {
    /// How the token reads in an error message ("name 'scale'", "'}'", …).
    pub fn describe(&self) -> String {
        match self {
            Tok::Ident(name) => format!("name '{name}'"),
            Tok::Number(value) => format!("number {value}"),
            Tok::Str(text) => format!("string \"{text}\""),
            Tok::Bool(value) => format!("'{value}'"),
            Tok::LBracket => "'['".to_owned(),
            Tok::RBracket => "']'".to_owned(),
            Tok::LBrace => "'{'".to_owned(),
            Tok::RBrace => "'}'".to_owned(),
            Tok::Comma => "','".to_owned(),
            Tok::Eof => "end of file".to_owned(),
        }
    }
}

/// A token and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// The token itself.
    pub tok: Tok,
    /// Position of its first character.
    pub pos: Pos,
    /// Position just after its last character, so nodes can record their full span.
    pub end: Pos,
}

/// A syntax error (from the lexer or the tree parser) before it is given a file name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    /// Where the problem is.
    pub pos: Pos,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl SyntaxError {
    /// Shorthand used throughout the lexer and parser.
    pub fn new(pos: Pos, message: impl Into<String>) -> Self {
        Self { pos, message: message.into() }
    }
}

/// Spellings that other formats accept as numbers; named here so the error can say why
/// they are refused instead of treating them as node names.
const NON_FINITE_WORDS: [&str; 3] = ["nan", "inf", "infinity"];

/// What a number looks like, for error messages.
const NUMBER_FORMS: &str = "numbers look like 1, -2.5, .5 or 1e-3";

/// Splits `source` into tokens, ending with [`Tok::Eof`].
///
/// # Errors
///
/// The first malformed token: an unexpected character, an unterminated string, an
/// unknown escape, or a number that is malformed, out of `f32` range, or not finite.
pub fn tokenize(source: &str) -> Result<Vec<Token>, SyntaxError> {
    let mut lexer = Lexer {
        chars: source.strip_prefix('\u{feff}').unwrap_or(source).chars().collect(),
        index: 0,
        pos: Pos { line: 1, column: 1 },
    };
    let mut tokens = Vec::new();
    loop {
        lexer.skip_blanks();
        let start = lexer.pos;
        let Some(c) = lexer.peek(0) else {
            tokens.push(Token { tok: Tok::Eof, pos: start, end: start });
            return Ok(tokens);
        };
        let tok = match c {
            '[' | ']' | '{' | '}' | ',' => {
                lexer.bump();
                match c {
                    '[' => Tok::LBracket,
                    ']' => Tok::RBracket,
                    '{' => Tok::LBrace,
                    '}' => Tok::RBrace,
                    _ => Tok::Comma,
                }
            }
            '"' => lexer.string()?,
            c if c.is_ascii_digit() || c == '-' || c == '.' => lexer.number()?,
            c if c.is_ascii_alphabetic() || c == '_' => lexer.word()?,
            other => {
                return Err(SyntaxError::new(
                    start,
                    format!(
                        "unexpected character '{}'; expected a node name, a number, a \"string\", \
                         '[', ']', '{{', '}}' or a '#' comment",
                        other.escape_debug()
                    ),
                ));
            }
        };
        tokens.push(Token { tok, pos: start, end: lexer.pos });
    }
}

/// Cursor over the characters of one source.
struct Lexer {
    chars: Vec<char>,
    index: usize,
    pos: Pos,
}

impl Lexer {
    fn peek(&self, ahead: usize) -> Option<char> {
        self.chars.get(self.index + ahead).copied()
    }

    /// Consumes one character, keeping line and column in step.
    fn bump(&mut self) -> Option<char> {
        let c = self.peek(0)?;
        self.index += 1;
        if c == '\n' {
            self.pos.line = self.pos.line.saturating_add(1);
            self.pos.column = 1;
        } else {
            self.pos.column = self.pos.column.saturating_add(1);
        }
        Some(c)
    }

    /// Skips whitespace and `#` comments, which only separate tokens.
    fn skip_blanks(&mut self) {
        while let Some(c) = self.peek(0) {
            if c == '#' {
                while self.peek(0).is_some_and(|c| c != '\n') {
                    self.bump();
                }
            } else if c.is_whitespace() {
                self.bump();
            } else {
                break;
            }
        }
    }

    /// `"..."` with `\"` and `\\`; a string may not span lines, so a missing quote is
    /// reported at the string's own line instead of somewhere far below.
    fn string(&mut self) -> Result<Tok, SyntaxError> {
        let open = self.pos;
        self.bump();
        let mut text = String::new();
        loop {
            match self.peek(0) {
                None | Some('\n') | Some('\r') => {
                    return Err(SyntaxError::new(open, "unterminated string: add the closing '\"' on the same line"));
                }
                Some('"') => {
                    self.bump();
                    return Ok(Tok::Str(text));
                }
                Some('\\') => {
                    let escape_pos = self.pos;
                    self.bump();
                    match self.peek(0) {
                        Some(c @ ('"' | '\\')) => {
                            self.bump();
                            text.push(c);
                        }
                        other => {
                            let shown =
                                other.map_or_else(|| "end of line".to_owned(), |c| format!("'\\{}'", c.escape_debug()));
                            return Err(SyntaxError::new(
                                escape_pos,
                                format!("unknown escape {shown} in string; only \\\" and \\\\ are allowed"),
                            ));
                        }
                    }
                }
                Some(c) => {
                    self.bump();
                    text.push(c);
                }
            }
        }
    }

    /// `-?(digits)?(.digits)?([eE][+-]?digits)?` with at least one mantissa digit.
    fn number(&mut self) -> Result<Tok, SyntaxError> {
        let start = self.pos;
        let first = self.index;
        if self.peek(0) == Some('-') {
            self.bump();
        }
        let mut digits = self.digits();
        if self.peek(0) == Some('.') {
            self.bump();
            digits += self.digits();
        }
        if digits > 0
            && matches!(self.peek(0), Some('e' | 'E'))
            && (self.peek(1).is_some_and(|c| c.is_ascii_digit())
                || (matches!(self.peek(1), Some('+' | '-')) && self.peek(2).is_some_and(|c| c.is_ascii_digit())))
        {
            self.bump();
            if matches!(self.peek(0), Some('+' | '-')) {
                self.bump();
            }
            self.digits();
        }
        // Glued trailing characters ("1.2.3", "3px", "-x") make the whole word invalid.
        while self.peek(0).is_some_and(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-')) {
            digits = 0;
            self.bump();
        }
        let text: String = self.chars[first..self.index].iter().collect();
        if digits == 0 {
            return Err(SyntaxError::new(start, format!("'{text}' is not a number; {NUMBER_FORMS}")));
        }
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() && (value as f32).is_finite() => Ok(Tok::Number(value)),
            _ => Err(SyntaxError::new(
                start,
                format!("number {text} is out of range; numbers must lie within ±{:e}", f32::MAX),
            )),
        }
    }

    /// Consumes ASCII digits and returns how many there were.
    fn digits(&mut self) -> usize {
        let mut count = 0;
        while self.peek(0).is_some_and(|c| c.is_ascii_digit()) {
            self.bump();
            count += 1;
        }
        count
    }

    /// A name, a boolean, or one of the refused non-finite spellings.
    fn word(&mut self) -> Result<Tok, SyntaxError> {
        let start = self.pos;
        let mut text = String::new();
        while let Some(c) = self.peek(0).filter(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-')) {
            self.bump();
            text.push(c);
        }
        if NON_FINITE_WORDS.contains(&text.to_ascii_lowercase().as_str()) {
            return Err(SyntaxError::new(
                start,
                format!("'{text}' is not a number: every number must be finite; {NUMBER_FORMS}"),
            ));
        }
        Ok(match text.as_str() {
            "true" => Tok::Bool(true),
            "false" => Tok::Bool(false),
            _ => Tok::Ident(text),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(source: &str) -> Vec<Tok> {
        tokenize(source).expect("source should lex").into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn numbers_in_all_forms() {
        assert_eq!(
            toks("-1 2.5 1e-3 .5 -.25 3E2 7."),
            vec![
                Tok::Number(-1.0),
                Tok::Number(2.5),
                Tok::Number(1e-3),
                Tok::Number(0.5),
                Tok::Number(-0.25),
                Tok::Number(300.0),
                Tok::Number(7.0),
                Tok::Eof
            ]
        );
    }

    #[test]
    fn malformed_numbers_are_refused_at_their_start() {
        for (source, column) in [("x -", 3), ("1.2.3", 1), ("  3px", 3), ("-", 1), ("1e", 1)] {
            let err = tokenize(source).expect_err(source);
            assert_eq!(err.pos, Pos { line: 1, column }, "{source}");
        }
        let err = tokenize("1e39").expect_err("overflows f32");
        assert!(err.message.contains("out of range"), "{}", err.message);
    }

    #[test]
    fn positions_count_lines_and_characters() {
        let tokens = tokenize("a # comment ü\n  \"é\" b-c_1").expect("lexes");
        let positions: Vec<_> = tokens.iter().map(|t| (t.pos.line, t.pos.column)).collect();
        assert_eq!(positions, vec![(1, 1), (2, 3), (2, 7), (2, 12)]);
        assert_eq!(tokens[1].tok, Tok::Str("é".to_owned()));
        assert_eq!(tokens[2].tok, Tok::Ident("b-c_1".to_owned()));
    }

    #[test]
    fn string_escapes() {
        assert_eq!(toks(r#""a\"b\\c""#), vec![Tok::Str(r#"a"b\c"#.to_owned()), Tok::Eof]);
        let err = tokenize(r#"  "a\n""#).expect_err("bad escape");
        assert_eq!(err.pos, Pos { line: 1, column: 5 });
    }

    #[test]
    fn non_finite_words_are_refused() {
        for word in ["nan", "NaN", "inf", "Infinity"] {
            let err = tokenize(&format!("fov {word}")).expect_err(word);
            assert_eq!(err.pos, Pos { line: 1, column: 5 });
            assert!(err.message.contains("finite"), "{}", err.message);
        }
    }
}
