//! A wide node's boxes in bytes, as the shader reads them: each bound is
//! `origin + q * 2^e` on its axis, q a byte, so that a node is four 16-byte
//! words instead of seven (Ylitie, Karras and Laine, "Efficient incoherent
//! ray traversal on GPUs through compressed wide BVHs", HPG 2017). On
//! llvmpipe each word is a texel fetch, an out-of-line call
//! (docs/performance.md, Reading the scene).
//!
//! The bounds are decoded in f32, a product that is exact (a byte times a
//! power of two) and one rounded sum, which the shader computes `precise`
//! and the CPU the same way, so both walk the same boxes bit for bit. Each
//! byte is chosen against that rounding: the decoded box holds the box it
//! stands for, so the image does not depend on it.

use super::node::{Node, EMPTY, WIDTH};

crate::base::interface::gpu_struct!(
    /// A node as the shader reads it: 64 bytes, the same in both precisions.
    pub mod packed: "PackedNode" {
        /// Where the four boxes' bytes count from.
        origin: float3,
        /// Each axis' step, 2^e, as e + 127 in bits 0-7 (x), 8-15 (y) and
        /// 16-23 (z): an f32's exponent bits.
        steps: uint,
        /// The low x, high x, low y and high y bytes of the four children,
        /// child k in bits 8k to 8k + 7.
        xy: uvec4,
        /// The low z and high z bytes; z and w unused.
        z: uvec4,
        /// The children's words (`node::Child`).
        child: uvec4,
    }
);

pub use packed::Values as Packed;

/// A box bound's byte: the largest step count whose bound is at most `x`
/// (a low bound, `down`), or the smallest whose bound is at least `x` (a
/// high bound); None where no byte reaches it.
fn quantize(x: f32, origin: f32, step: f32, down: bool) -> Option<u8> {
    let decode = |q: u8| decode(origin, step, q);
    // The estimate in f64, then the rounding of the f32 sums: decode is
    // monotone in q.
    let estimate = (f64::from(x) - f64::from(origin)) / f64::from(step);
    if down {
        let mut q = estimate.floor().clamp(0.0, 255.0) as u8;
        while q < 255 && decode(q + 1) <= x {
            q += 1;
        }
        while q > 0 && decode(q) > x {
            q -= 1;
        }
        (decode(q) <= x).then_some(q)
    } else {
        let mut q = estimate.ceil().clamp(0.0, 255.0) as u8;
        while q > 0 && decode(q - 1) >= x {
            q -= 1;
        }
        while q < 255 && decode(q) < x {
            q += 1;
        }
        (decode(q) >= x).then_some(q)
    }
}

/// A bound from its byte, in f32 as the shader decodes it.
pub fn decode(origin: f32, step: f32, q: u8) -> f32 {
    origin + f32::from(q) * step
}

/// The step of an axis from its exponent bits (e + 127).
fn step_of(bits: u32) -> f32 {
    f32::from_bits(bits << 23)
}

/// The node's bytes, and the node with the boxes they decode to (each
/// holding the box it stands for), which the CPU walks.
pub fn pack(node: &Node) -> (Packed, Node) {
    let used: Vec<usize> = (0..WIDTH).filter(|&k| node.child[k] != EMPTY).collect();
    let rows = |lo: &[f32; 4], hi: &[f32; 4]| {
        let origin = used.iter().map(|&k| lo[k]).fold(f32::INFINITY, f32::min);
        let top = used
            .iter()
            .map(|&k| hi[k])
            .fold(f32::NEG_INFINITY, f32::max);
        (origin, top)
    };
    let axes = [
        (&node.lo_x, &node.hi_x),
        (&node.lo_y, &node.hi_y),
        (&node.lo_z, &node.hi_z),
    ];
    let mut decoded = *node;
    let mut origin = [0.0f32; 3];
    let mut exps = [0u32; 3];
    let mut bytes = [[0u32; 2]; 3];
    for (a, (lo, hi)) in axes.into_iter().enumerate() {
        let (o, top) = rows(lo, hi);
        origin[a] = o;
        // The smallest step whose 253 steps span the axis, leaving two
        // for the rounding of the sums; at least 2^-126 (no subnormals).
        let span = f64::from(top) - f64::from(o);
        let short = |bits: u32| f64::from(step_of(bits)) * 253.0 < span;
        // From an estimate of the exponent, not from 1: the climb took
        // 100 steps an axis, most of a refit's time.
        let mut bits = if span > 0.0 {
            ((span / 253.0).log2().floor() + 127.0).clamp(1.0, 254.0) as u32
        } else {
            1
        };
        while bits > 1 && !short(bits - 1) {
            bits -= 1;
        }
        while bits < 254 && short(bits) {
            bits += 1;
        }
        exps[a] = bits;
        let step = step_of(bits);
        // An empty slot's bytes are 0: its box decodes to the origin.
        let rows = match a {
            0 => (&mut decoded.lo_x, &mut decoded.hi_x),
            1 => (&mut decoded.lo_y, &mut decoded.hi_y),
            _ => (&mut decoded.lo_z, &mut decoded.hi_z),
        };
        *rows.0 = [o; WIDTH];
        *rows.1 = [o; WIDTH];
        for &k in &used {
            let q_lo = quantize(lo[k], o, step, true).unwrap_or(0);
            let q_hi = quantize(hi[k], o, step, false).unwrap_or(255);
            let (dl, dh) = (decode(o, step, q_lo), decode(o, step, q_hi));
            assert!(
                dl <= lo[k] && dh >= hi[k],
                "a byte box holds its box ({dl} <= {}, {dh} >= {})",
                lo[k],
                hi[k]
            );
            bytes[a][0] |= u32::from(q_lo) << (8 * k);
            bytes[a][1] |= u32::from(q_hi) << (8 * k);
            let rows = match a {
                0 => (&mut decoded.lo_x, &mut decoded.hi_x),
                1 => (&mut decoded.lo_y, &mut decoded.hi_y),
                _ => (&mut decoded.lo_z, &mut decoded.hi_z),
            };
            rows.0[k] = dl;
            rows.1[k] = dh;
        }
    }
    let packed = Packed {
        origin,
        steps: exps[0] | exps[1] << 8 | exps[2] << 16,
        xy: [bytes[0][0], bytes[0][1], bytes[1][0], bytes[1][1]],
        z: [bytes[2][0], bytes[2][1], 0, 0],
        child: node.child,
    };
    (packed, decoded)
}

/// The node a packed one decodes to (the shader's `unpack` in bvh.glsl).
#[cfg(test)]
pub fn unpack(p: &Packed) -> Node {
    let step = |a: u32| step_of(p.steps >> (8 * a) & 0xff);
    let row = |word: u32, a: usize| -> [f32; 4] {
        std::array::from_fn(|k| decode(p.origin[a], step(a as u32), (word >> (8 * k)) as u8))
    };
    Node {
        lo_x: row(p.xy[0], 0),
        hi_x: row(p.xy[1], 0),
        lo_y: row(p.xy[2], 1),
        hi_y: row(p.xy[3], 1),
        lo_z: row(p.z[0], 2),
        hi_z: row(p.z[1], 2),
        child: p.child,
    }
}

#[cfg(test)]
mod tests {
    use super::super::node::EMPTY;
    use super::*;

    fn node(boxes: &[([f32; 3], [f32; 3])]) -> Node {
        let mut n = Node {
            child: [EMPTY; WIDTH],
            ..Node::default()
        };
        for (k, b) in boxes.iter().enumerate() {
            n.set_child(k, *b, (k as u32 + 1) << 4);
        }
        n
    }

    fn holds(outer: &Node, inner: &Node, k: usize) -> bool {
        outer.lo_x[k] <= inner.lo_x[k]
            && outer.lo_y[k] <= inner.lo_y[k]
            && outer.lo_z[k] <= inner.lo_z[k]
            && outer.hi_x[k] >= inner.hi_x[k]
            && outer.hi_y[k] >= inner.hi_y[k]
            && outer.hi_z[k] >= inner.hi_z[k]
    }

    #[test]
    fn byte_boxes_hold_their_boxes_and_decode_as_the_cpu_walks_them() {
        let cases = [
            // Ordinary, far from the origin, tiny against their place, flat,
            // and of very different sizes in one node.
            node(&[
                ([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]),
                ([0.5, -1.0, 2.0], [4.0, 0.0, 2.5]),
            ]),
            node(&[
                ([1e6, -3e5, 7e4], [1e6 + 0.25, -3e5 + 1.0, 7e4 + 0.5]),
                ([1e6 + 0.5, -3e5, 7e4], [1e6 + 2.0, -3e5 + 0.5, 7e4 + 9.0]),
            ]),
            node(&[([1.0, 1.0, 1.0], [1.0000001, 1.0, 1.0000002])]),
            node(&[
                ([-1e-3, 0.0, 5.0], [1e-3, 0.0, 5.0]),
                ([-1e4, -1e4, -1e4], [1e4, 1e4, 1e4]),
                ([3.0, 3.0, 3.0], [3.0, 3.0, 3.0]),
                ([-7.5, 2.0, 2.0], [-7.25, 2.5, 2.125]),
            ]),
        ];
        for n in &cases {
            let (packed, decoded) = pack(n);
            assert_eq!(unpack(&packed), decoded);
            for k in 0..WIDTH {
                if n.child[k] != EMPTY {
                    assert!(holds(&decoded, n, k), "{n:?} child {k}: {decoded:?}");
                }
            }
        }
    }

    #[test]
    fn a_byte_box_is_close_to_its_box() {
        let n = node(&[
            ([0.0, 0.0, 0.0], [100.0, 100.0, 100.0]),
            ([10.0, 20.0, 30.0], [11.0, 21.0, 31.0]),
        ]);
        let (_, d) = pack(&n);
        // A step of 0.5 (253 of them span 100): within a step either side.
        assert!(d.lo_x[1] >= 9.5 && d.hi_x[1] <= 11.5, "{d:?}");
        assert!(d.lo_z[1] >= 29.5 && d.hi_z[1] <= 31.5, "{d:?}");
    }
}
