//! The instructions a rewrite emits: a hash of an operation's inputs (the
//! sign of its error, whether it is fused), a result moved k ULP, an
//! absolute error added, a denormal flushed, a product and sum fused or not.

use std::collections::HashSet;

use super::module::{op, Inst, Module, Shape};

/// GLSL.std.450's instructions (its spec, section 2).
pub mod glsl {
    pub const ROUND_EVEN: u32 = 2;
    pub const FABS: u32 = 4;
    pub const FLOOR: u32 = 8;
    pub const SIN: u32 = 13;
    pub const COS: u32 = 14;
    pub const TAN: u32 = 15;
    pub const ASIN: u32 = 16;
    pub const ACOS: u32 = 17;
    pub const ATAN: u32 = 18;
    pub const ATAN2: u32 = 25;
    pub const POW: u32 = 26;
    pub const EXP: u32 = 27;
    pub const LOG: u32 = 28;
    pub const EXP2: u32 = 29;
    pub const LOG2: u32 = 30;
    pub const SQRT: u32 = 31;
    pub const INVERSE_SQRT: u32 = 32;
    pub const FMIN: u32 = 37;
    pub const FMAX: u32 = 40;
    pub const FCLAMP: u32 = 43;
    pub const FMA: u32 = 50;
    pub const LENGTH: u32 = 66;
    pub const DISTANCE: u32 = 67;
    pub const CROSS: u32 = 68;
    pub const NORMALIZE: u32 = 69;
}

/// A float value: its id and shape.
#[derive(Debug, Clone, Copy)]
pub struct Val {
    pub id: u32,
    pub shape: Shape,
}

/// Emits one function's instructions.
pub struct Emit<'a> {
    pub m: &'a mut Module,
    pub out: Vec<Inst>,
    /// Ids whose instruction was replaced (their decorations go).
    pub replaced: HashSet<u32>,
    glsl: u32,
}

impl<'a> Emit<'a> {
    pub fn new(m: &'a mut Module, glsl: u32) -> Self {
        Self {
            m,
            out: Vec::new(),
            replaced: HashSet::new(),
            glsl,
        }
    }

    /// `opcode` with a new result of type `ty`; its id.
    pub fn op(&mut self, opcode: u16, ty: u32, args: &[u32]) -> u32 {
        let id = self.m.fresh();
        let mut words = vec![ty, id];
        words.extend(args);
        self.out.push(Inst::new(opcode, words));
        id
    }

    /// A float operation rounded on its own (NoContraction), its result
    /// flushed where denormal.
    pub fn arith(&mut self, opcode: u16, shape: Shape, args: &[u32]) -> Val {
        let ty = self.m.float_ty(shape);
        let id = self.op(opcode, ty, args);
        self.m.no_contraction(id);
        self.flush(Val { id, shape })
    }

    /// A GLSL.std.450 instruction of float `shape`, as the driver computes it.
    pub fn ext(&mut self, inst: u32, shape: Shape, args: &[u32]) -> Val {
        let ty = self.m.float_ty(shape);
        let mut words = vec![self.glsl, inst];
        words.extend(args);
        Val {
            id: self.op(op::EXT_INST, ty, &words),
            shape,
        }
    }

    /// `v`'s component `i`.
    pub fn extract(&mut self, v: Val, i: u32) -> Val {
        let ty = self.m.float_ty(Shape(1));
        Val {
            id: self.op(op::COMPOSITE_EXTRACT, ty, &[v.id, i]),
            shape: Shape(1),
        }
    }

    /// A vector of `shape` from scalars.
    pub fn construct(&mut self, shape: Shape, parts: &[u32]) -> Val {
        let ty = self.m.float_ty(shape);
        Val {
            id: self.op(op::COMPOSITE_CONSTRUCT, ty, parts),
            shape,
        }
    }

    /// The scalar `v` in every component of `shape`.
    pub fn splat(&mut self, v: Val, shape: Shape) -> Val {
        if shape.0 == 1 {
            v
        } else {
            self.construct(shape, &vec![v.id; shape.0 as usize])
        }
    }

    /// `-v`.
    pub fn negate(&mut self, v: Val) -> Val {
        let ty = self.m.float_ty(v.shape);
        Val {
            id: self.op(op::F_NEGATE, ty, &[v.id]),
            shape: v.shape,
        }
    }

    fn bits(&mut self, v: Val) -> u32 {
        let ty = self.m.uint_ty(v.shape);
        self.op(op::BITCAST, ty, &[v.id])
    }

    fn float_of(&mut self, bits: u32, shape: Shape) -> Val {
        let ty = self.m.float_ty(shape);
        Val {
            id: self.op(op::BITCAST, ty, &[bits]),
            shape,
        }
    }

    fn uop(&mut self, opcode: u16, shape: Shape, a: u32, b: u32) -> u32 {
        let ty = self.m.uint_ty(shape);
        self.op(opcode, ty, &[a, b])
    }

    fn bop(&mut self, opcode: u16, shape: Shape, a: u32, b: u32) -> u32 {
        let ty = self.m.bool_ty(shape);
        self.op(opcode, ty, &[a, b])
    }

    /// A hash of `inputs`' bits for each component of `shape`, salted by
    /// `salt` (the operation's: two operations on the same inputs draw apart)
    /// and the component (a splat's lanes draw apart). Scalar inputs count
    /// in every lane; a vector input of another shape by its first
    /// component.
    pub fn hash(&mut self, inputs: &[Val], shape: Shape, salt: u32) -> u32 {
        let lanes = std::array::from_fn(|lane| {
            (salt.wrapping_mul(0x9e37_79b9) ^ (lane as u32).wrapping_mul(0x85eb_ca6b))
                .wrapping_add(0x27d4_eb2f)
        });
        let mut h = self.m.uint_lanes(shape, lanes);
        let mix = self.m.uint(shape, 0xcc9e_2d51);
        let sixteen = self.m.uint(shape, 16);
        for &v in inputs {
            let v = if v.shape == shape {
                v
            } else if v.shape.0 == 1 {
                self.splat(v, shape)
            } else {
                let first = self.extract(v, 0);
                self.splat(first, shape)
            };
            let b = self.bits(v);
            h = self.uop(op::BITWISE_XOR, shape, h, b);
            h = self.uop(op::I_MUL, shape, h, mix);
            let high = self.uop(op::SHIFT_RIGHT_LOGICAL, shape, h, sixteen);
            h = self.uop(op::BITWISE_XOR, shape, h, high);
        }
        h
    }

    /// Where hash `h`'s bit `bit` is set.
    pub fn bit(&mut self, h: u32, shape: Shape, bit: u32) -> u32 {
        let mask = self.m.uint(shape, 1 << bit);
        let zero = self.m.uint(shape, 0);
        let set = self.uop(op::BITWISE_AND, shape, h, mask);
        self.bop(op::U_GREATER_THAN, shape, set, zero)
    }

    /// `a` where `cond`, else `b`.
    pub fn select(&mut self, cond: u32, a: Val, b: Val) -> Val {
        let ty = self.m.float_ty(a.shape);
        Val {
            id: self.op(op::SELECT, ty, &[cond, a.id, b.id]),
            shape: a.shape,
        }
    }

    /// `v` moved k ULP (`k` a uint of its shape) away from zero or towards
    /// it, as `h`'s top bit says: an error of k ULP on top of `v`'s own.
    /// The ULP is that of the binade below where `v` lies within 8 steps
    /// above a power of two, so that a value rounded across one (and a
    /// step across one) is never off by more than k ULP of the exact.
    /// Values under 2^-103 (whose ULP is not normal), above 2^127,
    /// infinities and NaN are left as they are.
    pub fn step(&mut self, v: Val, k: u32, h: u32) -> Val {
        let s = v.shape;
        let b = self.bits(v);
        let magnitude_mask = self.m.uint(s, 0x7fff_ffff);
        let magnitude = self.uop(op::BITWISE_AND, s, b, magnitude_mask);
        let eight = self.m.uint(s, 8);
        let lowered = self.uop(op::I_SUB, s, magnitude, eight);
        let exponent_mask = self.m.uint(s, 0x7f80_0000);
        let exponent = self.uop(op::BITWISE_AND, s, lowered, exponent_mask);
        let significand = self.m.uint(s, 23 << 23);
        let ulp_bits = self.uop(op::I_SUB, s, exponent, significand);
        let ulp = self.float_of(ulp_bits, s);
        let fty = self.m.float_ty(s);
        let steps = Val {
            id: self.op(op::CONVERT_U_TO_F, fty, &[k]),
            shape: s,
        };
        let delta = self.arith(op::F_MUL, s, &[steps.id, ulp.id]);
        let towards = self.bit(h, s, 31);
        let negative = self.sign_bit(v);
        // Towards zero: against v's sign.
        let bty = self.m.bool_ty(s);
        let against = self.op(op::LOGICAL_NOT_EQUAL, bty, &[towards, negative]);
        let minus = self.negate(delta);
        let signed = self.select(against, minus, delta);
        let moved = self.arith(op::F_ADD, s, &[v.id, signed.id]);
        let smallest = self.m.uint(s, 24 << 23 | 8);
        let largest = self.m.uint(s, 0x7f00_0000);
        let above = self.bop(op::U_GREATER_THAN_EQUAL, s, magnitude, smallest);
        let below = self.bop(op::U_LESS_THAN, s, magnitude, largest);
        let inside = self.op(op::LOGICAL_AND, bty, &[above, below]);
        self.select(inside, moved, v)
    }

    /// `v` plus or minus `delta`, as `h`'s top bit says (an absolute error).
    pub fn offset(&mut self, v: Val, delta: f32, h: u32) -> Val {
        let s = v.shape;
        let plus = self.m.float(s, delta);
        let minus = self.m.float(s, -delta);
        let towards = self.bit(h, s, 31);
        let plus = Val { id: plus, shape: s };
        let minus = Val {
            id: minus,
            shape: s,
        };
        let d = self.select(towards, minus, plus);
        self.arith(op::F_ADD, s, &[v.id, d.id])
    }

    /// `v` with a denormal flushed to a zero of its sign.
    pub fn flush(&mut self, v: Val) -> Val {
        let s = v.shape;
        let b = self.bits(v);
        let magnitude_mask = self.m.uint(s, 0x7fff_ffff);
        let magnitude = self.uop(op::BITWISE_AND, s, b, magnitude_mask);
        let smallest = self.m.uint(s, 0x0080_0000);
        let tiny = self.bop(op::U_LESS_THAN, s, magnitude, smallest);
        let sign_mask = self.m.uint(s, 0x8000_0000);
        let zero = self.uop(op::BITWISE_AND, s, b, sign_mask);
        let uty = self.m.uint_ty(s);
        let chosen = self.op(op::SELECT, uty, &[tiny, zero, b]);
        self.float_of(chosen, s)
    }

    /// A constant float of `shape`.
    pub fn constant(&mut self, shape: Shape, v: f32) -> Val {
        Val {
            id: self.m.float(shape, v),
            shape,
        }
    }

    /// Ends a rewrite: `result` (of type `ty`) becomes the original
    /// instruction's id `id`.
    pub fn finish(&mut self, ty: u32, id: u32, result: Val) {
        self.out
            .push(Inst::new(op::COPY_OBJECT, vec![ty, id, result.id]));
        self.replaced.insert(id);
    }

    /// k, as a uint of `shape`.
    pub fn steps(&mut self, shape: Shape, k: u32) -> u32 {
        self.m.uint(shape, k)
    }

    /// k = ⌊c0 + c1·|x|⌋ (at most 2^22): exp's bound of 3 + 2|x| ULP
    /// less what the value it moves may be off already.
    pub fn exp_steps(&mut self, x: Val, c0: f32, c1: f32) -> u32 {
        let s = x.shape;
        let a = self.ext(glsl::FABS, s, &[x.id]);
        let c0 = self.constant(s, c0);
        let c1 = self.constant(s, c1);
        let twice = self.ext(glsl::FMA, s, &[c1.id, a.id, c0.id]);
        let most = self.constant(s, 4_194_304.0);
        let k = self.ext(glsl::FMIN, s, &[twice.id, most.id]);
        let uty = self.m.uint_ty(s);
        self.op(op::CONVERT_F_TO_U, uty, &[k.id])
    }

    /// The boolean `a opcode b` of two floats.
    pub fn compare(&mut self, opcode: u16, a: Val, b: Val) -> u32 {
        self.bop(opcode, a.shape, a.id, b.id)
    }

    /// Where `v`'s sign bit is set (−0 too).
    pub fn sign_bit(&mut self, v: Val) -> u32 {
        let b = self.bits(v);
        let high = self.m.uint(v.shape, 0x7fff_ffff);
        self.bop(op::U_GREATER_THAN, v.shape, b, high)
    }

    /// Where `v` is positive, normal and finite.
    pub fn positive_normal(&mut self, v: Val) -> u32 {
        let s = v.shape;
        let b = self.bits(v);
        let low = self.m.uint(s, 0x007f_ffff);
        let high = self.m.uint(s, 0x7f80_0000);
        let above = self.bop(op::U_GREATER_THAN, s, b, low);
        let below = self.bop(op::U_LESS_THAN, s, b, high);
        let bty = self.m.bool_ty(s);
        self.op(op::LOGICAL_AND, bty, &[above, below])
    }

    /// 2^n for a whole float n in [−126, 127], exactly.
    pub fn power_of_two(&mut self, n: Val) -> Val {
        let s = n.shape;
        let bias = self.constant(s, 127.0);
        let biased = self.arith(op::F_ADD, s, &[n.id, bias.id]);
        let uty = self.m.uint_ty(s);
        let e = self.op(op::CONVERT_F_TO_U, uty, &[biased.id]);
        let shift = self.m.uint(s, 23);
        let b = self.uop(op::SHIFT_LEFT_LOGICAL, s, e, shift);
        self.float_of(b, s)
    }

    /// A positive normal x as its exponent (a whole float) and its
    /// significand in [1, 2).
    pub fn exponent_and_significand(&mut self, x: Val) -> (Val, Val) {
        let s = x.shape;
        let b = self.bits(x);
        let shift = self.m.uint(s, 23);
        let biased = self.uop(op::SHIFT_RIGHT_LOGICAL, s, b, shift);
        let fty = self.m.float_ty(s);
        let biased = Val {
            id: self.op(op::CONVERT_U_TO_F, fty, &[biased]),
            shape: s,
        };
        let bias = self.constant(s, 127.0);
        let exponent = self.arith(op::F_SUB, s, &[biased.id, bias.id]);
        let fraction = self.m.uint(s, 0x007f_ffff);
        let one = self.m.uint(s, 0x3f80_0000);
        let f = self.uop(op::BITWISE_AND, s, b, fraction);
        let m = self.uop(op::BITWISE_OR, s, f, one);
        (exponent, self.float_of(m, s))
    }

    /// Where x lies in [0.5, 2] (log's absolute bound there).
    pub fn near_one(&mut self, x: Val) -> u32 {
        let s = x.shape;
        let half = self.constant(s, 0.5);
        let two = self.constant(s, 2.0);
        let above = self.bop(op::F_ORD_GREATER_THAN_EQUAL, s, x.id, half.id);
        let below = self.bop(op::F_ORD_LESS_THAN_EQUAL, s, x.id, two.id);
        let bty = self.m.bool_ty(s);
        self.op(op::LOGICAL_AND, bty, &[above, below])
    }
}
