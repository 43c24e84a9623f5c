//! The flat program an implicit function compiles to, and its evaluators.
//!
//! A program is a postfix sequence of [`ImplicitOp`] records run on a small stack: plain
//! data that lives in one array of the render scene and that a GPU kernel can run as
//! is. One generic interpreter serves every number type: `f64` for values,
//! [`Dual3`] for exact gradients (forward-mode differentiation), and
//! [`DualInterval`] for the enclosures the root finder prunes with.

use bytemuck::NoUninit;
use std::ops::{Add, Div, Mul, Neg, Sub};

use glam::DVec3;

use super::interval::{DualInterval, Interval};

/// The deepest stack a program may need; compile rejects deeper expressions, so every
/// evaluator runs on a fixed array.
pub const MAX_STACK: usize = 32;

/// The most instructions one function may have.
pub const MAX_PROGRAM: usize = 4096;

/// What an instruction does. Operands are popped from the stack (the right operand on
/// top) and the result is pushed.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum OpCode {
    /// Push `arg`.
    Const = 0,
    X = 1,
    Y = 2,
    Z = 3,
    Add = 4,
    Sub = 5,
    Mul = 6,
    Div = 7,
    Neg = 8,
    /// Integer power; `arg` holds the exponent `n ≥ 0`.
    PowI = 9,
    /// `1/x` (for negative integer powers).
    Recip = 10,
    /// `√max(x, 0)`.
    Sqrt = 11,
    Abs = 12,
    Sin = 13,
    Cos = 14,
    Exp = 15,
    Min = 16,
    Max = 17,
}

/// One instruction: 8 bytes of plain data.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct ImplicitOp {
    pub code: OpCode,
    /// The constant of `Const`, the exponent of `PowI`; 0 otherwise.
    pub arg: f32,
}

impl ImplicitOp {
    pub const fn new(code: OpCode) -> Self {
        ImplicitOp { code, arg: 0.0 }
    }

    /// How the instruction changes the stack depth.
    pub fn stack_effect(&self) -> i32 {
        match self.code {
            OpCode::Const | OpCode::X | OpCode::Y | OpCode::Z => 1,
            OpCode::Add | OpCode::Sub | OpCode::Mul | OpCode::Div | OpCode::Min | OpCode::Max => -1,
            _ => 0,
        }
    }
}

/// The arithmetic an evaluator needs from its number type.
pub trait Arith:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    fn constant(c: f64) -> Self;
    fn powi(self, n: u32) -> Self;
    fn recip(self) -> Self;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn exp(self) -> Self;
    fn min(self, o: Self) -> Self;
    fn max(self, o: Self) -> Self;
}

/// Runs `code` at `(x, y, z)`. The program must be valid (as compiled): balanced, and
/// never deeper than [`MAX_STACK`].
pub fn run<N: Arith>(code: &[ImplicitOp], x: N, y: N, z: N) -> N {
    let mut stack = [N::constant(0.0); MAX_STACK];
    let mut top = 0usize;
    for op in code {
        match op.code {
            OpCode::Const | OpCode::X | OpCode::Y | OpCode::Z => {
                stack[top] = match op.code {
                    OpCode::X => x,
                    OpCode::Y => y,
                    OpCode::Z => z,
                    _ => N::constant(op.arg as f64),
                };
                top += 1;
            }
            OpCode::Add | OpCode::Sub | OpCode::Mul | OpCode::Div | OpCode::Min | OpCode::Max => {
                // Pop the right operand `b`, then replace `a` with the result.
                top -= 1;
                let (a, b) = (stack[top - 1], stack[top]);
                stack[top - 1] = match op.code {
                    OpCode::Add => a + b,
                    OpCode::Sub => a - b,
                    OpCode::Mul => a * b,
                    OpCode::Div => a / b,
                    OpCode::Min => a.min(b),
                    _ => a.max(b),
                };
            }
            unary => {
                let a = stack[top - 1];
                stack[top - 1] = match unary {
                    OpCode::PowI => a.powi(op.arg as u32),
                    OpCode::Neg => -a,
                    OpCode::Recip => a.recip(),
                    OpCode::Sqrt => a.sqrt(),
                    OpCode::Abs => a.abs(),
                    OpCode::Sin => a.sin(),
                    OpCode::Cos => a.cos(),
                    _ => a.exp(),
                };
            }
        }
    }
    stack[0]
}

/// The deepest stack `code` needs, or `None` if it is unbalanced (pops an empty stack
/// or does not end with exactly one value).
pub fn stack_depth(code: &[ImplicitOp]) -> Option<usize> {
    let mut depth = 0i32;
    let mut deepest = 0i32;
    for op in code {
        let needs = match op.stack_effect() {
            1 => 0,
            -1 => 2,
            _ => 1,
        };
        if depth < needs {
            return None;
        }
        depth += op.stack_effect();
        deepest = deepest.max(depth);
    }
    (depth == 1).then_some(deepest as usize)
}

impl Arith for f64 {
    fn constant(c: f64) -> Self {
        c
    }
    fn powi(self, n: u32) -> Self {
        f64::powi(self, n as i32)
    }
    fn recip(self) -> Self {
        1.0 / self
    }
    fn sqrt(self) -> Self {
        self.max(0.0).sqrt()
    }
    fn abs(self) -> Self {
        f64::abs(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn exp(self) -> Self {
        f64::exp(self)
    }
    fn min(self, o: Self) -> Self {
        f64::min(self, o)
    }
    fn max(self, o: Self) -> Self {
        f64::max(self, o)
    }
}

/// A value with its gradient: forward-mode differentiation in x, y and z at once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual3 {
    pub v: f64,
    pub g: DVec3,
}

impl Dual3 {
    pub fn variable(v: f64, axis: usize) -> Self {
        let mut g = DVec3::ZERO;
        g[axis] = 1.0;
        Dual3 { v, g }
    }

    /// The chain rule for a unary function with value `v` and slope `slope` here.
    fn chain(self, v: f64, slope: f64) -> Self {
        Dual3 { v, g: self.g * slope }
    }
}

impl Add for Dual3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual3 { v: self.v + o.v, g: self.g + o.g }
    }
}

impl Sub for Dual3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual3 { v: self.v - o.v, g: self.g - o.g }
    }
}

/// The product rule.
impl Mul for Dual3 {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Dual3 { v: self.v * o.v, g: self.g * o.v + o.g * self.v }
    }
}

/// The quotient rule.
impl Div for Dual3 {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Dual3 { v, g: (self.g - o.g * v) / o.v }
    }
}

impl Neg for Dual3 {
    type Output = Self;
    fn neg(self) -> Self {
        Dual3 { v: -self.v, g: -self.g }
    }
}

impl Arith for Dual3 {
    fn constant(c: f64) -> Self {
        Dual3 { v: c, g: DVec3::ZERO }
    }
    fn powi(self, n: u32) -> Self {
        if n == 0 {
            return Dual3::constant(1.0);
        }
        self.chain(self.v.powi(n as i32), n as f64 * self.v.powi(n as i32 - 1))
    }
    fn recip(self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r)
    }
    fn sqrt(self) -> Self {
        let s = self.v.max(0.0).sqrt();
        self.chain(s, if self.v > 0.0 { 0.5 / s } else { 0.0 })
    }
    fn abs(self) -> Self {
        self.chain(self.v.abs(), if self.v < 0.0 { -1.0 } else { 1.0 })
    }
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn exp(self) -> Self {
        let e = self.v.exp();
        self.chain(e, e)
    }
    fn min(self, o: Self) -> Self {
        if o.v < self.v { o } else { self }
    }
    fn max(self, o: Self) -> Self {
        if o.v > self.v { o } else { self }
    }
}

impl Arith for DualInterval {
    fn constant(c: f64) -> Self {
        DualInterval::constant(c)
    }
    fn powi(self, n: u32) -> Self {
        DualInterval::powi(self, n)
    }
    fn recip(self) -> Self {
        DualInterval::recip(self)
    }
    fn sqrt(self) -> Self {
        DualInterval::sqrt(self)
    }
    fn abs(self) -> Self {
        DualInterval::abs(self)
    }
    fn sin(self) -> Self {
        DualInterval::sin(self)
    }
    fn cos(self) -> Self {
        DualInterval::cos(self)
    }
    fn exp(self) -> Self {
        DualInterval::exp(self)
    }
    fn min(self, o: Self) -> Self {
        DualInterval::min(self, o)
    }
    fn max(self, o: Self) -> Self {
        DualInterval::max(self, o)
    }
}

/// `f` at a point.
pub fn value(code: &[ImplicitOp], p: DVec3) -> f64 {
    run(code, p.x, p.y, p.z)
}

/// `f` and `∇f` at a point.
pub fn gradient(code: &[ImplicitOp], p: DVec3) -> Dual3 {
    run(code, Dual3::variable(p.x, 0), Dual3::variable(p.y, 1), Dual3::variable(p.z, 2))
}

/// Enclosures of `f(o + t·d)` and of its derivative in `t`, for every `t` in `t`.
pub fn enclose_along(code: &[ImplicitOp], o: DVec3, d: DVec3, t: Interval) -> DualInterval {
    let coord = |axis: usize| DualInterval { v: t.along(o[axis], d[axis]), d: Interval::point(d[axis]) };
    run(code, coord(0), coord(1), coord(2))
}
