//! Each bounded instruction rewritten as the least precise conformant
//! driver may compute it (docs/guarantees.md, The worst conformant driver).
//! A rewrite emits new instructions and ends with an OpCopyObject into the
//! original id, so that no use of it changes.

use super::emit::{glsl, Emit, Val};
use super::module::{op, Inst, Shape};
use super::own;
use super::{Bounds, Report};

/// One function instruction: rewritten (true) or left to the caller.
pub fn rewrite(e: &mut Emit, inst: &Inst, bounds: &Bounds, report: &mut Report) -> bool {
    let Some((ty, id)) = inst.typed_result() else {
        return false;
    };
    let Some(&shape) = e.m.float_shapes.get(&ty) else {
        return false;
    };
    let a = &inst.operands;
    // What draws the error's sign: the operation and its inputs alone, as
    // a driver's own error is, never the instruction's id, so that two
    // variants of a shader (the recording one of `glint explain`) compute
    // a sample alike.
    let salt = if inst.op == op::EXT_INST {
        0x1000 + a[3]
    } else {
        u32::from(inst.op)
    };
    let val = |id: u32, e: &Emit| Val {
        id,
        shape: e
            .m
            .float_shapes
            .get(&type_of(e, id))
            .copied()
            .unwrap_or(shape),
    };
    let v = |i: usize| Val { id: a[i], shape };
    let result = match inst.op {
        op::F_ADD | op::F_SUB => add(e, inst, shape, id, salt),
        op::F_MUL | op::VECTOR_TIMES_SCALAR => {
            // Rounded on its own: a sum it feeds chooses to fuse or not.
            e.arith(inst.op, shape, &a[2..])
        }
        op::F_DIV => div(e, v(2), v(3), bounds, salt),
        op::DOT => {
            let x = val(a[2], e);
            let y = val(a[3], e);
            dot(e, x, y, salt)
        }
        op::EXT_INST if Some(a[2]) == e.m.glsl => {
            let inst_no = a[3];
            let args: Vec<Val> = a[4..].iter().map(|&x| val(x, e)).collect();
            match glsl_inst(e, inst_no, &args, shape, bounds, salt) {
                Some(r) => r,
                // Exact (abs, min, floor, ...), or reported by the caller.
                None => return false,
            }
        }
        _ => return false,
    };
    report.count(name(inst));
    e.finish(ty, id, result);
    true
}

/// The type of a value, or 0.
fn type_of(e: &Emit, id: u32) -> u32 {
    e.m.value_types.get(&id).copied().unwrap_or(0)
}

/// x ± y: where an operand is a product that may be contracted with it
/// (neither marked NoContraction), fused or not by a hash of the inputs.
fn add(e: &mut Emit, inst: &Inst, shape: Shape, id: u32, salt: u32) -> Val {
    let (x, y) = (inst.operands[2], inst.operands[3]);
    let unfused = e.arith(inst.op, shape, &[x, y]);
    if e.m.no_contraction_before(id) {
        return unfused;
    }
    let product = |e: &Emit, operand: u32| {
        e.m.defs
            .get(&operand)
            .filter(|d| matches!(d.op, op::F_MUL | op::VECTOR_TIMES_SCALAR))
            .filter(|d| !e.m.no_contraction_before(d.operands[1]))
            .cloned()
    };
    let xs = Val { id: x, shape };
    let ys = Val { id: y, shape };
    let h = e.hash(&[xs, ys], shape, salt);
    // Which product fuses, where both could: the hash's bit 30.
    let first = e.bit(h, shape, 30);
    let mut choices = Vec::new();
    for (operand, other, negated) in [(x, ys, false), (y, xs, inst.op == op::F_SUB)] {
        if let Some(p) = product(e, operand) {
            let f = factors(e, &p, shape);
            let (fa, fb) = if negated { (e.negate(f.0), f.1) } else { f };
            let c = if inst.op == op::F_SUB && !negated {
                e.negate(other)
            } else {
                other
            };
            choices.push(own::mul_add(e, fa, fb, c, Some(unfused), h));
        }
    }
    match choices[..] {
        [] => unfused,
        [one] => one,
        [one, two] => e.select(first, one, two),
        _ => unreachable!("a sum has two operands"),
    }
}

/// A product's two factors, as values of `shape` (a scalar factor splat).
fn factors(e: &mut Emit, p: &Inst, shape: Shape) -> (Val, Val) {
    let a = Val {
        id: p.operands[2],
        shape,
    };
    let b = if p.op == op::VECTOR_TIMES_SCALAR {
        let s = Val {
            id: p.operands[3],
            shape: Shape(1),
        };
        e.splat(s, shape)
    } else {
        Val {
            id: p.operands[3],
            shape,
        }
    };
    (a, b)
}

/// x / y, 2.5 ULP off: the driver's quotient (correctly rounded on
/// lavapipe) moved `bounds.div` steps.
fn div(e: &mut Emit, x: Val, y: Val, bounds: &Bounds, salt: u32) -> Val {
    let q = e.arith(op::F_DIV, x.shape, &[x.id, y.id]);
    let h = e.hash(&[x, y], x.shape, salt);
    let k = e.steps(x.shape, bounds.div);
    let moved = e.step(q, k, h);
    e.flush(moved)
}

/// A dot product as a sum of products, each sum fused with its product or
/// not (a driver may contract either).
fn dot(e: &mut Emit, x: Val, y: Val, salt: u32) -> Val {
    let n = x.shape.0;
    let (x0, y0) = (e.extract(x, 0), e.extract(y, 0));
    let mut sum = e.arith(op::F_MUL, Shape(1), &[x0.id, y0.id]);
    for i in 1..n {
        let (xi, yi) = (e.extract(x, i), e.extract(y, i));
        let h = e.hash(
            &[xi, yi, sum],
            Shape(1),
            salt.wrapping_mul(8).wrapping_add(i),
        );
        sum = own::mul_add(e, xi, yi, sum, None, h);
    }
    sum
}

/// inversesqrt(x), 2 ULP: the driver's refined to about ½ ULP
/// (`own::inverse_sqrt`), moved `bounds.inverse_sqrt` steps.
fn inverse_sqrt(e: &mut Emit, x: Val, bounds: &Bounds, salt: u32) -> Val {
    let native = e.ext(glsl::INVERSE_SQRT, x.shape, &[x.id]);
    let base = own::inverse_sqrt(e, x, native);
    step(e, base, &[x], bounds.inverse_sqrt, salt)
}

/// sqrt(x), inherited from 1 / inversesqrt(x).
fn sqrt(e: &mut Emit, x: Val, bounds: &Bounds, salt: u32) -> Val {
    let r = inverse_sqrt(e, x, bounds, salt);
    let one = e.constant(x.shape, 1.0);
    div(e, one, r, bounds, salt.wrapping_mul(8).wrapping_add(1))
}

/// length(x), inherited from sqrt(dot(x, x)).
fn length(e: &mut Emit, x: Val, bounds: &Bounds, salt: u32) -> Val {
    let d = if x.shape.0 == 1 {
        e.arith(op::F_MUL, x.shape, &[x.id, x.id])
    } else {
        dot(e, x, x, salt)
    };
    sqrt(e, d, bounds, salt.wrapping_mul(8).wrapping_add(2))
}

/// `base` moved k steps, the sign drawn from `inputs`.
fn step(e: &mut Emit, base: Val, inputs: &[Val], k: u32, salt: u32) -> Val {
    let h = e.hash(inputs, base.shape, salt);
    let k = e.steps(base.shape, k);
    let r = e.step(base, k, h);
    e.flush(r)
}

/// The driver's `inst` off by `delta`, absolutely.
fn offset(e: &mut Emit, inst: u32, x: Val, delta: f32, salt: u32) -> Val {
    let native = e.ext(inst, x.shape, &[x.id]);
    let h = e.hash(&[x], x.shape, salt);
    let r = e.offset(native, delta, h);
    e.flush(r)
}

/// log2(x) or log(x) (`natural`): 3 ULP outside [0.5, 2], 2^-21 inside,
/// from glint's own log2 (`own::log2`; log = log2 · ln 2).
fn log(e: &mut Emit, x: Val, natural: bool, bounds: &Bounds, salt: u32) -> Val {
    let inst = if natural { glsl::LOG } else { glsl::LOG2 };
    // The driver's value where x is not a positive normal (own::log2 and
    // the natural log's select below both take it there).
    let native = e.ext(inst, x.shape, &[x.id]);
    let mut base = own::log2(e, x, native);
    if natural {
        let ln2 = e.constant(x.shape, std::f32::consts::LN_2);
        let scaled = e.arith(op::F_MUL, x.shape, &[base.id, ln2.id]);
        let normal = e.positive_normal(x);
        base = e.select(normal, scaled, native);
    }
    let h = e.hash(&[x], x.shape, salt);
    let near = e.near_one(x);
    let absolute = e.offset(base, bounds.log_absolute, h);
    let k = e.steps(
        x.shape,
        if natural {
            bounds.log_natural
        } else {
            bounds.log
        },
    );
    let relative = e.step(base, k, h);
    let r = e.select(near, absolute, relative);
    e.flush(r)
}

/// exp2(x) or exp(x) (`natural`): 3 + 2|x| ULP, from glint's own exp2
/// (`own::exp2`, within 1 ULP; exp = exp2(x · log2 e), whose product adds
/// up to 1.5|x| ULP), moved the rest.
fn exp(e: &mut Emit, x: Val, natural: bool, salt: u32) -> Val {
    let (m, c0, c1) = if natural {
        let log2e = e.constant(x.shape, std::f32::consts::LOG2_E);
        let m = e.arith(op::F_MUL, x.shape, &[x.id, log2e.id]);
        (m, 1.75, 0.5)
    } else {
        (x, 1.75, 2.0)
    };
    let base = own::exp2(e, m);
    let h = e.hash(&[x], x.shape, salt);
    let k = e.exp_steps(x, c0, c1);
    let r = e.step(base, k, h);
    e.flush(r)
}

/// A GLSL.std.450 instruction the spec bounds, or None for one left to
/// the driver.
fn glsl_inst(
    e: &mut Emit,
    inst: u32,
    args: &[Val],
    shape: Shape,
    bounds: &Bounds,
    salt: u32,
) -> Option<Val> {
    let x = *args.first()?;
    let trig = bounds.trig_inverse;
    Some(match inst {
        glsl::ATAN => {
            let one = e.constant(shape, 1.0);
            let base = own::atan2(e, x, one);
            step(e, base, args, trig, salt)
        }
        glsl::ATAN2 => {
            let base = own::atan2(e, x, args[1]);
            step(e, base, args, trig, salt)
        }
        glsl::ASIN => {
            let base = own::asin(e, x);
            step(e, base, args, trig, salt)
        }
        glsl::ACOS => {
            let base = own::acos(e, x);
            step(e, base, args, trig, salt)
        }
        glsl::SIN | glsl::COS => offset(e, inst, x, bounds.trig_absolute, salt),
        glsl::TAN => {
            let s = offset(e, glsl::SIN, x, bounds.trig_absolute, salt);
            let c = offset(e, glsl::COS, x, bounds.trig_absolute, salt ^ 1);
            div(e, s, c, bounds, salt.wrapping_mul(8).wrapping_add(3))
        }
        glsl::EXP | glsl::EXP2 => exp(e, x, inst == glsl::EXP, salt),
        glsl::LOG | glsl::LOG2 => log(e, x, inst == glsl::LOG, bounds, salt),
        glsl::POW => {
            // Inherited from exp2(y log2(x)).
            let l = log(e, x, false, bounds, salt);
            let m = e.arith(op::F_MUL, shape, &[args[1].id, l.id]);
            exp(e, m, false, salt.wrapping_mul(8).wrapping_add(4))
        }
        glsl::INVERSE_SQRT => inverse_sqrt(e, x, bounds, salt),
        glsl::SQRT => sqrt(e, x, bounds, salt),
        glsl::LENGTH => length(e, x, bounds, salt),
        glsl::DISTANCE => {
            let d = e.arith(op::F_SUB, x.shape, &[x.id, args[1].id]);
            length(e, d, bounds, salt)
        }
        glsl::NORMALIZE => {
            // Inherited from x / length(x).
            let l = length(e, x, bounds, salt);
            let l = e.splat(l, shape);
            div(e, x, l, bounds, salt.wrapping_mul(8).wrapping_add(5))
        }
        glsl::CROSS => cross(e, x, args[1], salt),
        glsl::FMA => {
            // Inherited from OpFMul followed by OpFAdd: fused or not.
            let h = e.hash(args, shape, salt);
            own::mul_add(e, args[0], args[1], args[2], None, h)
        }
        _ => return None,
    })
}

/// cross(x, y): each component a·b − c·d, either product fused with the
/// difference, or neither (a hash's bits 31 and 30).
fn cross(e: &mut Emit, x: Val, y: Val, salt: u32) -> Val {
    let mut parts = Vec::new();
    for (i, j) in [(1, 2), (2, 0), (0, 1)] {
        let (xi, yj, xj, yi) = (
            e.extract(x, i),
            e.extract(y, j),
            e.extract(x, j),
            e.extract(y, i),
        );
        let s = Shape(1);
        let p = e.arith(op::F_MUL, s, &[xi.id, yj.id]);
        let q = e.arith(op::F_MUL, s, &[xj.id, yi.id]);
        let unfused = e.arith(op::F_SUB, s, &[p.id, q.id]);
        let h = e.hash(&[xi, yj, xj, yi], s, salt.wrapping_mul(8).wrapping_add(i));
        let minus_q = e.negate(q);
        let first = own::mul_add(e, xi, yj, minus_q, Some(unfused), h);
        let minus_xj = e.negate(xj);
        let second = own::mul_add(e, minus_xj, yi, p, Some(unfused), h);
        let which = e.bit(h, s, 30);
        parts.push(e.select(which, first, second).id);
    }
    e.construct(x.shape, &parts)
}

/// The report's name of a rewritten instruction.
fn name(inst: &Inst) -> &'static str {
    match inst.op {
        op::F_ADD => "fadd",
        op::F_SUB => "fsub",
        op::F_MUL => "fmul",
        op::VECTOR_TIMES_SCALAR => "vector*scalar",
        op::F_DIV => "fdiv",
        op::DOT => "dot",
        op::EXT_INST => glsl_name(inst.operands[3]),
        _ => "another instruction",
    }
}

/// GLSL.std.450 instruction names, for the report.
pub fn glsl_name(inst: u32) -> &'static str {
    const NAMES: &[&str] = &[
        "?",
        "round",
        "roundEven",
        "trunc",
        "abs",
        "sabs",
        "sign",
        "ssign",
        "floor",
        "ceil",
        "fract",
        "radians",
        "degrees",
        "sin",
        "cos",
        "tan",
        "asin",
        "acos",
        "atan",
        "sinh",
        "cosh",
        "tanh",
        "asinh",
        "acosh",
        "atanh",
        "atan2",
        "pow",
        "exp",
        "log",
        "exp2",
        "log2",
        "sqrt",
        "inversesqrt",
        "determinant",
        "inverse",
        "modf",
        "modfStruct",
        "min",
        "umin",
        "smin",
        "max",
        "umax",
        "smax",
        "clamp",
        "uclamp",
        "sclamp",
        "mix",
        "imix",
        "step",
        "smoothstep",
        "fma",
        "frexp",
        "frexpStruct",
        "ldexp",
    ];
    match inst {
        66 => "length",
        67 => "distance",
        68 => "cross",
        69 => "normalize",
        70 => "faceforward",
        71 => "reflect",
        72 => "refract",
        _ => NAMES
            .get(inst as usize)
            .copied()
            .unwrap_or("another GLSL.std.450 instruction"),
    }
}
