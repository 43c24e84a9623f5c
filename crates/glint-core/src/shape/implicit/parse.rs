//! The expression language of implicit surfaces, compiled straight to bytecode.
//!
//! ```text
//! expr     = term (("+" | "-") term)*
//! term     = unary (("*" | "/") unary)*
//! unary    = ("-" | "+") unary | power
//! power    = atom ("^" exponent)?          # -x^2 is -(x^2)
//! exponent = ["-" | "+"] INTEGER | "(" ["-" | "+"] INTEGER ")"
//! atom     = NUMBER | "x" | "y" | "z" | "pi" | FUNC "(" expr ("," expr)* ")" | "(" expr ")"
//! FUNC     = sqrt | abs | sin | cos | exp (one argument) | min | max (two or more)
//! ```
//!
//! A recursive-descent parser emits postfix code as it goes; errors carry the character
//! offset in the expression so the scene reader can point at the exact column.

use super::bytecode::{ImplicitOp, MAX_PROGRAM, MAX_STACK, OpCode, stack_depth};

/// Largest integer exponent of `^`.
pub const MAX_EXPONENT: i64 = 64;

/// Deepest nesting of parentheses, function calls and unary signs.
const MAX_NESTING: usize = 64;

/// A mistake in an expression, `offset` characters from its start (0-based).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {} of the expression: {message}", .offset + 1)]
pub struct ExprError {
    pub offset: usize,
    pub message: String,
}

/// Compiles `text` to a program that leaves `f(x, y, z)` on the stack.
pub fn compile_expression(text: &str) -> Result<Vec<ImplicitOp>, ExprError> {
    let tokens = tokenize(text)?;
    let mut parser = Parser { tokens: &tokens, next: 0, code: Vec::new(), depth: 0, end: text.chars().count() };
    parser.expr()?;
    if let Some(extra) = parser.peek() {
        return Err(parser.error_at(extra, format!("unexpected {} after a complete expression", extra.tok.describe())));
    }
    if parser.code.len() > MAX_PROGRAM {
        return Err(ExprError {
            offset: 0,
            message: format!("the expression compiles to {} instructions; at most {MAX_PROGRAM}", parser.code.len()),
        });
    }
    match stack_depth(&parser.code) {
        Some(depth) if depth <= MAX_STACK => Ok(parser.code),
        Some(depth) => Err(ExprError {
            offset: 0,
            message: format!(
                "the expression needs {depth} intermediate values at once, at most {MAX_STACK}; \
                 write long sums left to right instead of nesting parentheses"
            ),
        }),
        None => Err(ExprError { offset: 0, message: "internal error: unbalanced program".into() }),
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Number(f64),
    Name(String),
    Op(char),
}

impl Tok {
    fn describe(&self) -> String {
        match self {
            Tok::Number(x) => format!("number {x}"),
            Tok::Name(n) => format!("name '{n}'"),
            Tok::Op(c) => format!("'{c}'"),
        }
    }
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    offset: usize,
}

fn tokenize(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let literal: String = chars[start..i].iter().collect();
            let value: f64 = literal
                .parse()
                .map_err(|_| ExprError { offset: start, message: format!("'{literal}' is not a number") })?;
            if !(value as f32).is_finite() {
                return Err(ExprError { offset: start, message: format!("{literal} does not fit in a 32-bit float") });
            }
            tokens.push(Token { tok: Tok::Number(value), offset: start });
        } else if c.is_ascii_alphabetic() || c == '_' {
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(Token { tok: Tok::Name(chars[start..i].iter().collect()), offset: start });
        } else if "+-*/^(),".contains(c) {
            tokens.push(Token { tok: Tok::Op(c), offset: start });
            i += 1;
        } else {
            return Err(ExprError {
                offset: start,
                message: format!("unexpected character '{c}'; expected numbers, x y z, + - * / ^, ( ) or functions"),
            });
        }
    }
    Ok(tokens)
}

const FUNCTIONS: [&str; 7] = ["sqrt", "abs", "sin", "cos", "exp", "min", "max"];

struct Parser<'t> {
    tokens: &'t [Token],
    next: usize,
    code: Vec<ImplicitOp>,
    depth: usize,
    /// Length of the text, where "unexpected end" errors point.
    end: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.next)
    }

    fn peek_op(&self) -> Option<char> {
        match self.peek() {
            Some(Token { tok: Tok::Op(c), .. }) => Some(*c),
            _ => None,
        }
    }

    fn error_at(&self, token: &Token, message: String) -> ExprError {
        ExprError { offset: token.offset, message }
    }

    /// An error at the current token (or the end of the text).
    fn error_here(&self, expected: &str) -> ExprError {
        match self.peek() {
            Some(t) => self.error_at(t, format!("expected {expected}, found {}", t.tok.describe())),
            None => {
                ExprError { offset: self.end, message: format!("expected {expected}, found the end of the expression") }
            }
        }
    }

    fn expect_op(&mut self, c: char, expected: &str) -> Result<(), ExprError> {
        if self.peek_op() == Some(c) {
            self.next += 1;
            Ok(())
        } else {
            Err(self.error_here(expected))
        }
    }

    fn emit(&mut self, code: OpCode) {
        self.code.push(ImplicitOp::new(code));
    }

    fn nested(&mut self, at: usize) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(ExprError { offset: at, message: format!("nested more than {MAX_NESTING} deep") });
        }
        Ok(())
    }

    fn expr(&mut self) -> Result<(), ExprError> {
        self.term()?;
        while let Some(c @ ('+' | '-')) = self.peek_op() {
            self.next += 1;
            self.term()?;
            self.emit(if c == '+' { OpCode::Add } else { OpCode::Sub });
        }
        Ok(())
    }

    fn term(&mut self) -> Result<(), ExprError> {
        self.unary()?;
        while let Some(c @ ('*' | '/')) = self.peek_op() {
            self.next += 1;
            self.unary()?;
            self.emit(if c == '*' { OpCode::Mul } else { OpCode::Div });
        }
        Ok(())
    }

    fn unary(&mut self) -> Result<(), ExprError> {
        match self.peek_op() {
            Some(sign @ ('-' | '+')) => {
                let at = self.tokens[self.next].offset;
                self.next += 1;
                self.nested(at)?;
                let start = self.code.len();
                self.unary()?;
                self.depth -= 1;
                if sign == '-' {
                    // Fold a negated literal into the constant.
                    if self.code.len() == start + 1 && self.code[start].code == OpCode::Const {
                        self.code[start].arg = -self.code[start].arg;
                    } else {
                        self.emit(OpCode::Neg);
                    }
                }
                Ok(())
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<(), ExprError> {
        self.atom()?;
        if self.peek_op() != Some('^') {
            return Ok(());
        }
        self.next += 1;
        let parenthesized = self.peek_op() == Some('(');
        if parenthesized {
            self.next += 1;
        }
        let negative = match self.peek_op() {
            Some(sign @ ('-' | '+')) => {
                self.next += 1;
                sign == '-'
            }
            _ => false,
        };
        let exponent = match self.peek() {
            Some(Token { tok: Tok::Number(n), offset }) => {
                if n.fract() != 0.0 || *n > MAX_EXPONENT as f64 {
                    return Err(ExprError {
                        offset: *offset,
                        message: format!(
                            "the exponent of '^' must be a whole number from -{MAX_EXPONENT} to {MAX_EXPONENT}, \
                             found {n}; use exp() or sqrt() for other powers"
                        ),
                    });
                }
                *n as u32
            }
            _ => return Err(self.error_here("a whole-number exponent after '^'")),
        };
        self.next += 1;
        if parenthesized {
            self.expect_op(')', "')' to close the exponent")?;
        }
        self.code.push(ImplicitOp { code: OpCode::PowI, arg: exponent as f32 });
        if negative {
            self.emit(OpCode::Recip);
        }
        if self.peek_op() == Some('^') {
            let t = &self.tokens[self.next];
            return Err(self.error_at(t, "chained '^' is ambiguous; add parentheses, like (x^2)^3".into()));
        }
        Ok(())
    }

    fn atom(&mut self) -> Result<(), ExprError> {
        let Some(token) = self.peek().cloned() else {
            return Err(self.error_here("a number, x, y, z, a function or '('"));
        };
        self.next += 1;
        match &token.tok {
            Tok::Number(x) => {
                self.code.push(ImplicitOp { code: OpCode::Const, arg: *x as f32 });
                Ok(())
            }
            Tok::Op('(') => {
                self.nested(token.offset)?;
                self.expr()?;
                self.depth -= 1;
                self.expect_op(')', "')'")
            }
            Tok::Name(name) => match name.as_str() {
                axis @ ("x" | "y" | "z") => {
                    self.emit(match axis {
                        "x" => OpCode::X,
                        "y" => OpCode::Y,
                        _ => OpCode::Z,
                    });
                    Ok(())
                }
                "pi" => {
                    self.code.push(ImplicitOp { code: OpCode::Const, arg: std::f32::consts::PI });
                    Ok(())
                }
                f if FUNCTIONS.contains(&f) => self.call(f, &token),
                other => Err(self.error_at(
                    &token,
                    format!("unknown name '{other}'; expected x, y, z, pi or a function ({})", FUNCTIONS.join(", ")),
                )),
            },
            other => {
                self.next -= 1;
                Err(self.error_at(
                    &token,
                    format!("expected a number, x, y, z, a function or '(', found {}", other.describe()),
                ))
            }
        }
    }

    fn call(&mut self, name: &str, token: &Token) -> Result<(), ExprError> {
        if self.peek_op() != Some('(') {
            return Err(self.error_here(&format!("'(' after '{name}'")));
        }
        self.next += 1;
        self.nested(token.offset)?;
        let mut args = 0;
        loop {
            self.expr()?;
            args += 1;
            if args >= 2 {
                self.emit(if name == "min" { OpCode::Min } else { OpCode::Max });
            }
            if self.peek_op() == Some(',') && matches!(name, "min" | "max") {
                self.next += 1;
                continue;
            }
            break;
        }
        self.depth -= 1;
        let unary = !matches!(name, "min" | "max");
        if !unary && args < 2 {
            return Err(self.error_at(token, format!("'{name}' takes two or more arguments separated by ','")));
        }
        self.expect_op(')', if unary { "')' (this function takes one argument)" } else { "',' or ')'" })?;
        if unary {
            self.emit(match name {
                "sqrt" => OpCode::Sqrt,
                "abs" => OpCode::Abs,
                "sin" => OpCode::Sin,
                "cos" => OpCode::Cos,
                _ => OpCode::Exp,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::bytecode::value;
    use super::*;

    fn eval(text: &str, p: [f64; 3]) -> f64 {
        value(&compile_expression(text).unwrap_or_else(|e| panic!("{text}: {e}")), DVec3::from(p))
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(eval("1 + 2 * 3", [0.0; 3]), 7.0);
        assert_eq!(eval("8 / 4 / 2", [0.0; 3]), 1.0);
        assert_eq!(eval("2 - 3 - 4", [0.0; 3]), -5.0);
        assert_eq!(eval("-x^2", [3.0, 0.0, 0.0]), -9.0);
        assert_eq!(eval("(-x)^2", [3.0, 0.0, 0.0]), 9.0);
        assert_eq!(eval("x^-2", [2.0, 0.0, 0.0]), 0.25);
        assert_eq!(eval("x^(-1) + y^(3)", [2.0, 2.0, 0.0]), 8.5);
        assert_eq!(eval("x^2 + y^2 + z^2 - 1", [1.0, 2.0, 2.0]), 8.0);
        assert_eq!(eval("min(x, y, z) + max(1, 2)", [3.0, -1.0, 2.0]), 1.0);
        assert_eq!(eval("sqrt(abs(-4)) * exp(0) + cos(0) - sin(0)", [0.0; 3]), 3.0);
        assert!((eval("2 * pi", [0.0; 3]) - std::f64::consts::TAU).abs() < 1e-6);
        assert_eq!(eval("1.5e1 + .5 - -1", [0.0; 3]), 16.5);
    }

    #[test]
    fn negated_literals_fold() {
        let code = compile_expression("-2").unwrap();
        assert_eq!(code, vec![ImplicitOp { code: OpCode::Const, arg: -2.0 }]);
    }

    #[test]
    fn errors_point_at_the_offending_character() {
        let cases = [
            ("x^2 + y^2 +", 11, "end of the expression"),
            ("x^2 + (y - 1", 12, "')'"),
            ("x ^ 2.5", 4, "whole number"),
            ("2x", 1, "after a complete expression"),
            ("x + w", 4, "unknown name 'w'"),
            ("x $ y", 2, "unexpected character '$'"),
            ("sqrt(x, y)", 6, "one argument"),
            ("min(x)", 0, "two or more"),
            ("x^2^2", 3, "chained"),
            ("", 0, "expected a number"),
            ("1e99", 0, "32-bit"),
        ];
        for (text, offset, words) in cases {
            let e = compile_expression(text).expect_err(text);
            assert_eq!(e.offset, offset, "{text}: {e}");
            assert!(e.message.contains(words), "{text}: {e}");
        }
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowed() {
        let deep = format!("{}x{}", "(".repeat(200), ")".repeat(200));
        assert!(compile_expression(&deep).unwrap_err().message.contains("nested"));
        let deep_minus = format!("{}x", "-".repeat(200));
        assert!(compile_expression(&deep_minus).is_err());
        // Long flat sums are fine.
        let long = vec!["x"; 500].join(" + ");
        assert_eq!(eval(&long, [1.0, 0.0, 0.0]), 500.0);
    }
}
