//! `--spec-worst`: a compiled shader rewritten to compute as the least
//! precise conformant Vulkan driver may (docs/guarantees.md). Every float
//! instruction whose precision the Vulkan spec bounds ("Precision and
//! Operation of SPIR-V Instructions") gets an error at that bound, of a
//! sign drawn from a hash of its inputs; every product that may be
//! contracted with the sum it feeds is fused or not by the same kind of
//! hash; every float result that is denormal is flushed to zero.
//!
//! It works on the SPIR-V, after glslang, so that it covers a user's own
//! shaders (`-I`, `--shader`) as glint's. Only 32-bit floats are touched:
//! the f64 shader's doubles are left to the driver.

mod emit;
mod module;
mod own;
mod rewrite;

use std::collections::BTreeMap;

/// The error each instruction gets, in steps of one representable float
/// (ULP) added to the driver's own result, or as an absolute offset. Each
/// is the spec's bound less what the driver's own result may already be
/// off: a correctly rounded result is ½ ULP off, and glint's own functions
/// (`own`) about 1 ULP; a driver's own may be far worse (tests/spec_worst.rs
/// checks every one against f64, and that each reaches its bound).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// OpFDiv: 2.5 ULP; the quotient is correctly rounded, so 2 steps.
    pub div: u32,
    /// inversesqrt: 2 ULP; 1 step on a value within about ½ ULP.
    pub inverse_sqrt: u32,
    /// log2 outside [0.5, 2]: 3 ULP; steps on glint's own (within 1 ULP).
    pub log: u32,
    /// log outside [0.5, 2]: 3 ULP; steps on log2 · ln 2 (within 1.6 ULP).
    pub log_natural: u32,
    /// log, log2 inside [0.5, 2]: an absolute 2^-21; 2^-21 − 2^-23.
    pub log_absolute: f32,
    /// asin, acos, atan, atan2: 4096 ULP; steps on glint's own (within
    /// 3 ULP).
    pub trig_inverse: u32,
    /// sin, cos: an absolute 2^-11 in [−π, π]; 2^-11 − 2^-16.
    pub trig_absolute: f32,
}

/// The spec's bounds, less what the value moved may be off already. exp2
/// (3 + 2|x| ULP) takes ⌊1.75 + 2|x|⌋ steps, exp ⌊1.75 + |x|/2⌋, per call.
pub const BOUNDS: Bounds = Bounds {
    div: 2,
    inverse_sqrt: 1,
    log: 2,
    log_natural: 1,
    log_absolute: 3.0 / 8_388_608.0,
    trig_inverse: 4096 - 4,
    trig_absolute: 1.0 / 2048.0 - 1.0 / 65536.0,
};

/// What the rewrite did: how many instructions of each kind it perturbed,
/// and the ones it met whose precision the spec inherits from a formula
/// that this simulation does not expand (left to the driver).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Report {
    /// Instructions perturbed, by name.
    pub perturbed: BTreeMap<&'static str, usize>,
    /// Instructions left to the driver, by name.
    pub native: BTreeMap<&'static str, usize>,
}

impl Report {
    fn count(&mut self, name: &'static str) {
        *self.perturbed.entry(name).or_default() += 1;
    }

    fn native(&mut self, name: &'static str) {
        *self.native.entry(name).or_default() += 1;
    }

    /// One line: "fdiv 12, normalize 3; left to the driver: reflect 1".
    pub fn line(&self) -> String {
        let list = |m: &BTreeMap<&str, usize>| {
            m.iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut s = format!("perturbed {}", list(&self.perturbed));
        if !self.native.is_empty() {
            s += &format!(
                "; left to the driver (precision inherited, not simulated): {}",
                list(&self.native)
            );
        }
        s
    }
}

/// GLSL.std.450 instructions and core opcodes whose f32 precision the spec
/// inherits from a formula this simulation does not expand.
fn inherited_not_simulated(inst: &module::Inst, glsl: Option<u32>) -> Option<&'static str> {
    const GLSL: &[u32] = &[
        11, 12, 19, 20, 21, 22, 23, 24, 33, 34, 46, 49, 53, 70, 71, 72,
    ];
    match inst.op {
        140 => Some("frem"),
        141 => Some("fmod"),
        143 => Some("matrix*scalar"),
        144 => Some("vector*matrix"),
        145 => Some("matrix*vector"),
        146 => Some("matrix*matrix"),
        147 => Some("outer product"),
        module::op::EXT_INST
            if Some(inst.operands[2]) == glsl && GLSL.contains(&inst.operands[3]) =>
        {
            Some(rewrite::glsl_name(inst.operands[3]))
        }
        _ => None,
    }
}

/// `spirv` rewritten to compute as the least precise conformant driver may,
/// with `bounds`; what it perturbed. An error where the words are not a
/// module this pass can read.
pub fn apply(spirv: &[u32], bounds: &Bounds) -> Result<(Vec<u32>, Report), String> {
    let mut m = module::Module::parse(spirv)?;
    let mut report = Report::default();
    let glsl = match m.glsl {
        Some(g) => g,
        None => {
            // Division and contraction need no import; fma does: add one.
            m.import_glsl()
        }
    };
    let functions = std::mem::take(&mut m.functions);
    let mut e = emit::Emit::new(&mut m, glsl);
    for inst in &functions {
        if rewrite::rewrite(&mut e, inst, bounds, &mut report) {
            continue;
        }
        if e.m
            .float_shapes
            .contains_key(&inst.operands.first().copied().unwrap_or(0))
        {
            if let Some(name) = inherited_not_simulated(inst, e.m.glsl) {
                report.native(name);
            }
        }
        e.out.push(inst.clone());
    }
    let out = std::mem::take(&mut e.out);
    let replaced = std::mem::take(&mut e.replaced);
    m.functions = out;
    m.undecorate(&replaced);
    Ok((m.words(), report))
}

#[cfg(test)]
mod tests {
    /// The words of a function whose only float work is %10 = %8 / %9.
    fn one_division() -> Vec<u32> {
        let mut w = vec![0x0723_0203, 0x0001_0500, 0, 20, 0];
        let glsl = [1, 0x4c53_4c47, 0x6474_732e, 0x3035_342e, 0];
        let insts: &[(u32, &[u32])] = &[
            (17, &[1]),
            (11, &glsl),
            (14, &[0, 1]),
            (22, &[2, 32]),
            (54, &[2, 7, 0, 6]),
            (136, &[2, 10, 8, 9]),
            (56, &[]),
        ];
        for (opcode, operands) in insts {
            w.push(((operands.len() as u32 + 1) << 16) | opcode);
            w.extend(*operands);
        }
        w
    }

    #[test]
    fn a_division_is_rewritten_into_its_own_id() {
        let (words, report) = super::apply(&one_division(), &super::BOUNDS).unwrap();
        assert_eq!(report.perturbed.get("fdiv"), Some(&1));
        let m = super::module::Module::parse(&words).unwrap();
        // The last instruction before OpFunctionEnd defines %10 again.
        let last = &m.functions[m.functions.len() - 2];
        assert_eq!(last.op, super::module::op::COPY_OBJECT);
        assert_eq!(last.operands[1], 10);
        let divisions = m
            .functions
            .iter()
            .filter(|i| i.op == super::module::op::F_DIV)
            .count();
        assert_eq!(divisions, 1, "the driver's quotient, then its step");
        assert_eq!(report.line(), "perturbed fdiv 1");
    }

    #[test]
    fn the_bounds_stay_within_the_specs() {
        let b = super::BOUNDS;
        // A correctly rounded quotient (½ ULP) moved k steps.
        assert!(f64::from(b.div) + 0.5 <= 2.5);
        assert!(b.log_absolute < 2f32.powi(-21));
        assert!(b.trig_absolute < 2f32.powi(-11));
        assert!(b.trig_inverse < 4096);
    }
}
