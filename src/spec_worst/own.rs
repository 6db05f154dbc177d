//! The simulation's own values of the functions whose driver results
//! cannot be trusted to be near exact: a perturbation at the spec's bound
//! goes on top of a value within about 1 ULP, whatever the driver's own
//! function gives (lavapipe's asin is 3,800 ULP off, its exp2 0.8 of its
//! bound: tests/spec_worst.rs prints both). Emitted as SPIR-V, from +, −,
//! ×, ÷ and sqrt (the driver's, correctly rounded on lavapipe), and exact
//! where the step is done on bits. The polynomials are those of
//! shaders/own_math.glsl and benches/own_math_fit.py.

use super::emit::{glsl, Emit, Val};
use super::module::op;

/// `v` as a constant of `x`'s shape.
fn k(e: &mut Emit, x: Val, v: f32) -> Val {
    e.constant(x.shape, v)
}

fn mul(e: &mut Emit, a: Val, b: Val) -> Val {
    e.arith(op::F_MUL, a.shape, &[a.id, b.id])
}

fn add(e: &mut Emit, a: Val, b: Val) -> Val {
    e.arith(op::F_ADD, a.shape, &[a.id, b.id])
}

fn sub(e: &mut Emit, a: Val, b: Val) -> Val {
    e.arith(op::F_SUB, a.shape, &[a.id, b.id])
}

fn div(e: &mut Emit, a: Val, b: Val) -> Val {
    e.arith(op::F_DIV, a.shape, &[a.id, b.id])
}

/// c0 + s (c1 + s (c2 + ...)), by Horner.
fn poly(e: &mut Emit, s: Val, coefficients: &[f32]) -> Val {
    let (last, rest) = coefficients.split_last().expect("a polynomial");
    let mut acc = k(e, s, *last);
    for &c in rest.iter().rev() {
        let p = mul(e, s, acc);
        let c = k(e, s, c);
        acc = add(e, c, p);
    }
    acc
}

/// a·b + c with one rounding, as a fused multiply-add gives it: the
/// product exactly (Dekker's TwoProduct), summed by Knuth's TwoSum; the
/// last addition may round a tie apart from fma, one ULP. lavapipe's fma()
/// is two roundings, and a driver may fuse.
pub fn fused(e: &mut Emit, a: Val, b: Val, c: Val) -> Val {
    let (p, product_error) = two_product(e, a, b);
    let s = add(e, p, c);
    let bb = sub(e, s, p);
    let sb = sub(e, s, bb);
    let pa = sub(e, p, sb);
    let cb = sub(e, c, bb);
    let sum_error = add(e, pa, cb);
    let tail = add(e, sum_error, product_error);
    add(e, s, tail)
}

/// a·b + c, fused (one rounding, `fused`) or not (two), as `h`'s top bit
/// says; `unfused` is the two-rounding value where the caller has it.
pub fn mul_add(e: &mut Emit, a: Val, b: Val, c: Val, unfused: Option<Val>, h: u32) -> Val {
    let unfused = match unfused {
        Some(u) => u,
        None => {
            let p = mul(e, a, b);
            add(e, p, c)
        }
    };
    let fused = fused(e, a, b, c);
    let cond = e.bit(h, c.shape, 31);
    e.select(cond, fused, unfused)
}

/// Veltkamp's split of `a` into a high half and a low half.
fn split(e: &mut Emit, a: Val) -> (Val, Val) {
    let factor = k(e, a, 4097.0);
    let c = mul(e, factor, a);
    let d = sub(e, c, a);
    let hi = sub(e, c, d);
    let lo = sub(e, a, hi);
    (hi, lo)
}

fn bit_select(e: &mut Emit, cond: u32, a: Val, b: Val) -> Val {
    e.select(cond, a, b)
}

fn less(e: &mut Emit, a: Val, b: Val) -> u32 {
    e.compare(op::F_ORD_LESS_THAN, a, b)
}

/// atan(y / x) in (x, y)'s quadrant (own_atan2 in shaders/own_math.glsl).
pub fn atan2(e: &mut Emit, y: Val, x: Val) -> Val {
    let ax = e.ext(glsl::FABS, x.shape, &[x.id]);
    let ay = e.ext(glsl::FABS, y.shape, &[y.id]);
    let hi = e.ext(glsl::FMAX, x.shape, &[ax.id, ay.id]);
    let lo = e.ext(glsl::FMIN, x.shape, &[ax.id, ay.id]);
    let tan_pi_8 = k(e, x, 0.414_213_57);
    let bound = mul(e, tan_pi_8, hi);
    let reduced = less(e, bound, lo);
    let num = sub(e, lo, hi);
    let den = add(e, lo, hi);
    let t_far = div(e, num, den);
    let one = k(e, x, 1.0);
    let zero = k(e, x, 0.0);
    let nonzero = less(e, zero, hi);
    let safe_hi = bit_select(e, nonzero, hi, one);
    let t_near = div(e, lo, safe_hi);
    let t = bit_select(e, reduced, t_far, t_near);
    let quarter = k(e, x, std::f32::consts::FRAC_PI_4);
    let base = bit_select(e, reduced, quarter, zero);
    let s = mul(e, t, t);
    let p = poly(e, s, &ATAN);
    let ts = mul(e, t, s);
    let tsp = mul(e, ts, p);
    let at = add(e, t, tsp);
    let r = add(e, base, at);
    let half_pi = k(e, x, std::f32::consts::FRAC_PI_2);
    let flipped = sub(e, half_pi, r);
    let steep = less(e, ax, ay);
    let r = bit_select(e, steep, flipped, r);
    let pi = k(e, x, std::f32::consts::PI);
    let back = sub(e, pi, r);
    let x_negative = e.sign_bit(x);
    let r = bit_select(e, x_negative, back, r);
    let minus = e.negate(r);
    let y_negative = e.sign_bit(y);
    bit_select(e, y_negative, minus, r)
}

/// asin(y) for y in [−1, 1] (own_asin in shaders/own_math.glsl).
pub fn asin(e: &mut Emit, y: Val) -> Val {
    let a = e.ext(glsl::FABS, y.shape, &[y.id]);
    let r = asin_of_magnitude(e, a);
    let minus = e.negate(r);
    let negative = e.sign_bit(y);
    bit_select(e, negative, minus, r)
}

/// asin(a), a in [0, 1].
fn asin_of_magnitude(e: &mut Emit, a: Val) -> Val {
    let s = mul(e, a, a);
    let q = poly(e, s, &ASIN);
    let as_ = mul(e, a, s);
    let asq = mul(e, as_, q);
    let near = add(e, a, asq);
    let twice = twice_asin_of_half_angle(e, a);
    let half_pi = k(e, a, std::f32::consts::FRAC_PI_2);
    let far = sub(e, half_pi, twice);
    let half = k(e, a, 0.5);
    let small = e.compare(op::F_ORD_LESS_THAN_EQUAL, a, half);
    bit_select(e, small, near, far)
}

/// 2·asin(w), w = √((1 − a)/2), for a in [0, 1] (1 − a exact for a ≥ ½):
/// π/2 − asin(a), and acos(a).
fn twice_asin_of_half_angle(e: &mut Emit, a: Val) -> Val {
    let one = k(e, a, 1.0);
    let half = k(e, a, 0.5);
    let d = sub(e, one, a);
    let ws = mul(e, d, half);
    let w = e.ext(glsl::SQRT, a.shape, &[ws.id]);
    let wq = poly(e, ws, &ASIN);
    let wsw = mul(e, w, ws);
    let t = mul(e, wsw, wq);
    let inner = add(e, w, t);
    let two = k(e, a, 2.0);
    mul(e, two, inner)
}

/// acos(y) for y in [−1, 1]: π/2 − asin(y) within ½ of zero, else from
/// the half angle, so that no result near 0 or π comes of a cancellation.
pub fn acos(e: &mut Emit, y: Val) -> Val {
    let middle_asin = asin(e, y);
    let half_pi = k(e, y, std::f32::consts::FRAC_PI_2);
    let middle = sub(e, half_pi, middle_asin);
    let a = e.ext(glsl::FABS, y.shape, &[y.id]);
    let near_one = twice_asin_of_half_angle(e, a);
    let pi = k(e, y, std::f32::consts::PI);
    let near_minus_one = sub(e, pi, near_one);
    let negative = e.sign_bit(y);
    let ends = bit_select(e, negative, near_minus_one, near_one);
    let half = k(e, y, 0.5);
    let inside = e.compare(op::F_ORD_LESS_THAN_EQUAL, a, half);
    bit_select(e, inside, middle, ends)
}

/// 2^x: 2^f (f = x − n, |f| ≤ ½) by a polynomial, scaled by 2^n in two
/// exact halves (n as far as ±252 stays in range).
pub fn exp2(e: &mut Emit, x: Val) -> Val {
    let n = e.ext(glsl::ROUND_EVEN, x.shape, &[x.id]);
    let lo = k(e, x, -252.0);
    let hi = k(e, x, 254.0);
    let n = e.ext(glsl::FCLAMP, x.shape, &[n.id, lo.id, hi.id]);
    let f = sub(e, x, n);
    let p = poly(e, f, &EXP2);
    let fp = mul(e, f, p);
    let one = k(e, x, 1.0);
    let r = add(e, one, fp);
    let half = k(e, x, 0.5);
    let nh = mul(e, n, half);
    let n1 = e.ext(glsl::FLOOR, x.shape, &[nh.id]);
    let n2 = sub(e, n, n1);
    let s1 = e.power_of_two(n1);
    let s2 = e.power_of_two(n2);
    let r = mul(e, r, s1);
    mul(e, r, s2)
}

/// log2(x) for a positive normal x: e + log2(m), m in [√½, √2), log2(m)
/// by the series of atanh in s = (m − 1)/(m + 1). Elsewhere (0, a
/// denormal, a negative, infinity, NaN) the driver's.
pub fn log2(e: &mut Emit, x: Val, native: Val) -> Val {
    let (exponent, m) = e.exponent_and_significand(x);
    let sqrt2 = k(e, x, std::f32::consts::SQRT_2);
    let big = less(e, sqrt2, m);
    let half = k(e, x, 0.5);
    let halved = mul(e, m, half);
    let m = bit_select(e, big, halved, m);
    let one = k(e, x, 1.0);
    let bumped = add(e, exponent, one);
    let exponent = bit_select(e, big, bumped, exponent);
    let num = sub(e, m, one);
    let den = add(e, m, one);
    let s = div(e, num, den);
    let t = mul(e, s, s);
    let p = poly(e, t, &LOG2);
    let l = mul(e, s, p);
    let r = add(e, exponent, l);
    let normal = e.positive_normal(x);
    bit_select(e, normal, r, native)
}

/// 1/√x to about ½ ULP for a positive normal x: x = m·4^j with m in
/// [1, 4) (so that no product below overflows), the driver's 1/√m refined
/// by one Newton step whose residual 1 − m r² is computed exactly
/// (TwoProduct twice), scaled by 2^-j. Elsewhere (0, a denormal,
/// infinity, NaN) `native`, the driver's 1/√x.
pub fn inverse_sqrt(e: &mut Emit, x: Val, native: Val) -> Val {
    let (exponent, m) = e.exponent_and_significand(x);
    let half = k(e, x, 0.5);
    let he = mul(e, exponent, half);
    let j = e.ext(glsl::FLOOR, x.shape, &[he.id]);
    let two = k(e, x, 2.0);
    let even = mul(e, two, j);
    let odd = sub(e, exponent, even);
    let one = k(e, x, 1.0);
    let factor = add(e, one, odd);
    let m = mul(e, m, factor);
    let r = e.ext(glsl::INVERSE_SQRT, x.shape, &[m.id]);
    let (y, y_err) = two_product(e, m, r);
    let (z, z_err) = two_product(e, y, r);
    let d = sub(e, one, z);
    let d = sub(e, d, z_err);
    let yr = mul(e, y_err, r);
    let residual = sub(e, d, yr);
    let hr = mul(e, half, r);
    let step = mul(e, hr, residual);
    let refined = add(e, r, step);
    let minus_j = e.negate(j);
    let scale = e.power_of_two(minus_j);
    let scaled = mul(e, refined, scale);
    let normal = e.positive_normal(x);
    bit_select(e, normal, scaled, native)
}

/// a·b as p + err exactly (Dekker).
fn two_product(e: &mut Emit, a: Val, b: Val) -> (Val, Val) {
    let (ah, al) = split(e, a);
    let (bh, bl) = split(e, b);
    let p = mul(e, a, b);
    let hh = mul(e, ah, bh);
    let hl = mul(e, ah, bl);
    let lh = mul(e, al, bh);
    let ll = mul(e, al, bl);
    let r = sub(e, hh, p);
    let r = add(e, r, hl);
    let r = add(e, r, lh);
    (p, add(e, r, ll))
}

/// atan(t) = t + t s P(s), s = t², |t| ≤ tan(π/8).
const ATAN: [f32; 5] = [
    -0.333_333_3,
    0.199_995_49,
    -0.142_641_74,
    0.107_456_71,
    -0.064_574_24,
];
/// asin(a) = a + a s Q(s), s = a², a ≤ ½.
const ASIN: [f32; 6] = [
    0.166_666_66,
    0.075_000_99,
    0.044_598_1,
    0.031_115_372,
    0.017_081_447,
    0.033_800_017,
];
/// 2^f = 1 + f E(f), |f| ≤ ½.
const EXP2: [f32; 6] = [
    std::f32::consts::LN_2,
    0.240_226_48,
    0.055_503_324,
    0.009_618_437,
    0.001_339_890_6,
    0.000_153_535_63,
];
/// log2((1 + s)/(1 − s)) = s L(s²): L's coefficients are (2/ln 2)/(2k + 1).
const LOG2: [f32; 6] = [
    2.885_39,
    0.961_796_7,
    0.577_078_04,
    0.412_198_57,
    0.320_598_9,
    0.262_308_18,
];
