//! pbrt's tokens: bare words (directives, `true`/`false`), quoted strings, numbers and
//! the brackets around parameter values; `#` starts a comment to the end of the line.
//! Every token keeps the line and column it starts at, so errors point into the file.

use crate::error::{SceneError, SceneErrorKind};
use crate::source::{Pos, Source};

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum TokenKind {
    /// A bare word: a directive name, or `true`/`false`.
    Word(String),
    /// A quoted string, escapes resolved.
    Str(String),
    /// A number (always finite).
    Number(f64),
    Open,
    Close,
}

/// One token and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Token {
    pub kind: TokenKind,
    pub pos: Pos,
}

impl Token {
    /// How the token reads in a message.
    pub fn describe(&self) -> String {
        match &self.kind {
            TokenKind::Word(w) => format!("'{w}'"),
            TokenKind::Str(s) => format!("the string \"{s}\""),
            TokenKind::Number(n) => format!("the number {n}"),
            TokenKind::Open => "'['".to_owned(),
            TokenKind::Close => "']'".to_owned(),
        }
    }
}

/// Splits `text` into tokens; a malformed string or number is a syntax error at its
/// position in `src`.
pub(super) fn tokenize(text: &str, src: &Source) -> Result<Vec<Token>, SceneError> {
    let mut lexer = Lexer { chars: text.chars().peekable(), pos: Pos { line: 1, column: 1 } };
    let mut tokens = Vec::new();
    while let Some(token) = lexer.next_token(src)? {
        tokens.push(token);
    }
    Ok(tokens)
}

struct Lexer<'t> {
    chars: std::iter::Peekable<std::str::Chars<'t>>,
    pos: Pos,
}

impl Lexer<'_> {
    fn bump(&mut self) -> Option<char> {
        let c = self.chars.next()?;
        if c == '\n' {
            self.pos = Pos { line: self.pos.line + 1, column: 1 };
        } else {
            self.pos.column += 1;
        }
        Some(c)
    }

    fn next_token(&mut self, src: &Source) -> Result<Option<Token>, SceneError> {
        loop {
            match self.chars.peek() {
                None => return Ok(None),
                Some(c) if c.is_whitespace() || *c == '\u{feff}' => {
                    self.bump();
                }
                Some('#') => {
                    while self.chars.peek().is_some_and(|&c| c != '\n') {
                        self.bump();
                    }
                }
                Some(_) => break,
            }
        }
        let pos = self.pos;
        let c = self.bump().expect("peeked a character");
        let kind = match c {
            '[' => TokenKind::Open,
            ']' => TokenKind::Close,
            '"' => TokenKind::Str(self.string(src, pos)?),
            c if c.is_ascii_digit() || matches!(c, '-' | '+' | '.') => self.number(c, src, pos)?,
            c if c.is_alphabetic() || c == '_' => TokenKind::Word(self.word(c)),
            c => {
                return Err(src.error(SceneErrorKind::Syntax, pos, format!("unexpected character '{c}'")));
            }
        };
        Ok(Some(Token { kind, pos }))
    }

    /// The rest of a quoted string; pbrt's escapes `\" \\ \n \t` are resolved.
    fn string(&mut self, src: &Source, start: Pos) -> Result<String, SceneError> {
        let mut out = String::new();
        loop {
            match self.bump() {
                None | Some('\n') => {
                    return Err(src.error(
                        SceneErrorKind::Syntax,
                        start,
                        "unterminated string: a '\"' is missing before the end of the line",
                    ));
                }
                Some('"') => return Ok(out),
                Some('\\') => match self.bump() {
                    Some('n') => out.push('\n'),
                    Some('t') => out.push('\t'),
                    Some(c @ ('"' | '\\' | '\'')) => out.push(c),
                    other => {
                        let what = other.map_or("the end of the file".to_owned(), |c| format!("'{c}'"));
                        return Err(src.error(
                            SceneErrorKind::Syntax,
                            self.pos,
                            format!("unknown escape '\\' + {what}"),
                        ));
                    }
                },
                Some(c) => out.push(c),
            }
        }
    }

    fn number(&mut self, first: char, src: &Source, pos: Pos) -> Result<TokenKind, SceneError> {
        let mut text = String::from(first);
        while let Some(&c) = self.chars.peek() {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '+') {
                text.push(c);
                self.bump();
            } else {
                break;
            }
        }
        let value: f64 = text
            .parse()
            .ok()
            .filter(|v: &f64| {
                v.is_finite() && !text.contains(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
            })
            .ok_or_else(|| src.error(SceneErrorKind::Syntax, pos, format!("'{text}' is not a finite number")))?;
        Ok(TokenKind::Number(value))
    }

    fn word(&mut self, first: char) -> String {
        let mut text = String::from(first);
        while let Some(&c) = self.chars.peek() {
            if c.is_alphanumeric() || c == '_' {
                text.push(c);
                self.bump();
            } else {
                break;
            }
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn src() -> Source {
        Source { name: "t.pbrt".into(), dir: ".".into() }
    }

    #[test]
    fn tokens_carry_positions_and_skip_comments() {
        let t = tokenize("Shape \"sphere\" # c\n  \"float radius\" [ -1.5e1 ]", &src()).unwrap();
        assert_eq!(t[0].kind, TokenKind::Word("Shape".into()));
        assert_eq!(t[1].kind, TokenKind::Str("sphere".into()));
        assert_eq!(t[2].pos, Pos { line: 2, column: 3 });
        assert_eq!(t[4].kind, TokenKind::Number(-15.0));
        assert_eq!(t[5].kind, TokenKind::Close);
    }

    #[test]
    fn bad_tokens_are_located() {
        let e = tokenize("Shape\n  \"sphere", &src()).unwrap_err();
        assert_eq!((e.line, e.column), (2, 3));
        let e = tokenize("Translate 1 2 1e999", &src()).unwrap_err();
        assert_eq!((e.line, e.column), (1, 15));
        assert!(tokenize("Scale 1..2 1 1", &src()).is_err());
    }
}
