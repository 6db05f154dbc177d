//! A SPIR-V module as words: its instructions, what each id is, and the
//! types and constants a rewrite adds. Just enough of the format for
//! `spec_worst`: the sections it reads and the few it writes to.

use std::collections::{HashMap, HashSet};

/// Opcodes this pass reads or writes (SPIR-V spec, 3.52).
pub mod op {
    pub const EXT_INST_IMPORT: u16 = 11;
    pub const EXT_INST: u16 = 12;
    pub const MEMORY_MODEL: u16 = 14;
    pub const TYPE_BOOL: u16 = 20;
    pub const TYPE_INT: u16 = 21;
    pub const TYPE_FLOAT: u16 = 22;
    pub const TYPE_VECTOR: u16 = 23;
    pub const CONSTANT: u16 = 43;
    pub const CONSTANT_COMPOSITE: u16 = 44;
    pub const FUNCTION: u16 = 54;
    pub const DECORATE: u16 = 71;
    pub const MEMBER_DECORATE: u16 = 72;
    pub const DECORATION_GROUP: u16 = 73;
    pub const GROUP_DECORATE: u16 = 74;
    pub const GROUP_MEMBER_DECORATE: u16 = 75;
    pub const COMPOSITE_CONSTRUCT: u16 = 80;
    pub const COMPOSITE_EXTRACT: u16 = 81;
    pub const COPY_OBJECT: u16 = 83;
    pub const CONVERT_F_TO_U: u16 = 109;
    pub const CONVERT_U_TO_F: u16 = 112;
    pub const BITCAST: u16 = 124;
    pub const F_NEGATE: u16 = 127;
    pub const F_ADD: u16 = 129;
    pub const I_SUB: u16 = 130;
    pub const F_SUB: u16 = 131;
    pub const I_MUL: u16 = 132;
    pub const F_MUL: u16 = 133;
    pub const F_DIV: u16 = 136;
    pub const VECTOR_TIMES_SCALAR: u16 = 142;
    pub const DOT: u16 = 148;
    pub const LOGICAL_NOT_EQUAL: u16 = 165;
    pub const LOGICAL_AND: u16 = 167;
    pub const SELECT: u16 = 169;
    pub const U_GREATER_THAN: u16 = 172;
    pub const U_GREATER_THAN_EQUAL: u16 = 174;
    pub const U_LESS_THAN: u16 = 176;
    pub const F_ORD_LESS_THAN: u16 = 184;
    pub const F_ORD_LESS_THAN_EQUAL: u16 = 188;
    pub const F_ORD_GREATER_THAN_EQUAL: u16 = 190;
    pub const SHIFT_RIGHT_LOGICAL: u16 = 194;
    pub const SHIFT_LEFT_LOGICAL: u16 = 196;
    pub const BITWISE_OR: u16 = 197;
    pub const BITWISE_XOR: u16 = 198;
    pub const BITWISE_AND: u16 = 199;
    pub const DECORATE_ID: u16 = 332;
    pub const DECORATE_STRING: u16 = 5632;
    pub const MEMBER_DECORATE_STRING: u16 = 5633;
}

/// The NoContraction decoration: an operation rounded on its own.
pub const NO_CONTRACTION: u32 = 42;

/// One instruction: its opcode and the words after the first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Inst {
    pub op: u16,
    pub operands: Vec<u32>,
}

impl Inst {
    pub fn new(op: u16, operands: Vec<u32>) -> Self {
        Self { op, operands }
    }

    /// Its result type and result id, for the opcodes this pass rewrites
    /// (each has both).
    pub fn typed_result(&self) -> Option<(u32, u32)> {
        match self.op {
            op::EXT_INST
            | op::F_ADD
            | op::F_SUB
            | op::F_MUL
            | op::F_DIV
            | op::VECTOR_TIMES_SCALAR
            | op::DOT
            | op::F_NEGATE => Some((self.operands[0], self.operands[1])),
            _ => None,
        }
    }
}

/// What a float type is: its component count (1 for a scalar) where it is
/// a 32-bit float scalar or vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shape(pub u32);

/// A parsed module: the header and every instruction in order, the index
/// of the first function, and the ids it has and adds.
pub struct Module {
    pub header: [u32; 5],
    /// Everything before the first OpFunction.
    pub globals: Vec<Inst>,
    /// The functions, as they were.
    pub functions: Vec<Inst>,
    /// Types, constants and decorations this pass adds: appended to the
    /// globals' end (types and constants) and after the last annotation.
    added_globals: Vec<Inst>,
    added_decorations: Vec<Inst>,
    /// The GLSL.std.450 import, where the module has one.
    pub glsl: Option<u32>,
    /// The 32-bit float scalar and vector types, by id.
    pub float_shapes: HashMap<u32, Shape>,
    /// Ids decorated NoContraction.
    pub no_contraction: HashSet<u32>,
    /// Each rewritable result id's defining instruction (within functions).
    pub defs: HashMap<u32, Inst>,
    /// Each value's type id, globals' and functions' alike.
    pub value_types: HashMap<u32, u32>,
    types: HashMap<(u16, Vec<u32>), u32>,
    constants: HashMap<(u32, Vec<u32>), u32>,
}

impl Module {
    /// Parses `words`; an error names what is not SPIR-V.
    pub fn parse(words: &[u32]) -> Result<Self, String> {
        if words.len() < 5 || words[0] != 0x0723_0203 {
            return Err("not a SPIR-V module (no magic number)".into());
        }
        let header = [words[0], words[1], words[2], words[3], words[4]];
        let mut insts = Vec::new();
        let mut at = 5;
        while at < words.len() {
            let count = (words[at] >> 16) as usize;
            let opcode = (words[at] & 0xffff) as u16;
            if count == 0 || at + count > words.len() {
                return Err(format!(
                    "a SPIR-V instruction at word {at} runs past the module"
                ));
            }
            insts.push(Inst::new(opcode, words[at + 1..at + count].to_vec()));
            at += count;
        }
        let split = insts
            .iter()
            .position(|i| i.op == op::FUNCTION)
            .unwrap_or(insts.len());
        let functions = insts.split_off(split);
        let mut m = Module {
            header,
            globals: insts,
            functions,
            added_globals: Vec::new(),
            added_decorations: Vec::new(),
            glsl: None,
            float_shapes: HashMap::new(),
            no_contraction: HashSet::new(),
            defs: HashMap::new(),
            value_types: HashMap::new(),
            types: HashMap::new(),
            constants: HashMap::new(),
        };
        m.index();
        Ok(m)
    }

    fn index(&mut self) {
        let mut float32 = None;
        for i in &self.globals {
            match i.op {
                op::EXT_INST_IMPORT if string(&i.operands[1..]) == "GLSL.std.450" => {
                    self.glsl = Some(i.operands[0]);
                }
                op::DECORATE if i.operands.get(1) == Some(&NO_CONTRACTION) => {
                    self.no_contraction.insert(i.operands[0]);
                }
                op::TYPE_BOOL | op::TYPE_INT | op::TYPE_FLOAT | op::TYPE_VECTOR => {
                    self.types
                        .insert((i.op, i.operands[1..].to_vec()), i.operands[0]);
                    if i.op == op::TYPE_FLOAT && i.operands[1] == 32 {
                        float32 = Some(i.operands[0]);
                        self.float_shapes.insert(i.operands[0], Shape(1));
                    }
                    if i.op == op::TYPE_VECTOR && Some(i.operands[1]) == float32 {
                        self.float_shapes
                            .insert(i.operands[0], Shape(i.operands[2]));
                    }
                }
                _ => {}
            }
        }
        for i in &self.functions {
            if let Some((_, id)) = i.typed_result() {
                self.defs.insert(id, i.clone());
            }
        }
        // An instruction whose first operand is a type has a result type
        // and id (ids are unique: an OpStore's pointer is never a type);
        // declarations of types are not values.
        let type_ids: HashSet<u32> = self
            .globals
            .iter()
            .filter(|i| (19..=39).contains(&i.op))
            .map(|i| i.operands[0])
            .collect();
        for i in self.globals.iter().chain(&self.functions) {
            if (19..=39).contains(&i.op) || i.operands.len() < 2 {
                continue;
            }
            if type_ids.contains(&i.operands[0]) {
                self.value_types.insert(i.operands[1], i.operands[0]);
            }
        }
    }

    /// Whether `id` was decorated NoContraction (by the shader, or by
    /// this pass).
    pub fn no_contraction_before(&self, id: u32) -> bool {
        self.no_contraction.contains(&id)
    }

    /// Adds the GLSL.std.450 import (before the memory model); its id.
    pub fn import_glsl(&mut self) -> u32 {
        let id = self.fresh();
        let mut words = vec![id];
        let mut bytes = b"GLSL.std.450".to_vec();
        bytes.resize(bytes.len() / 4 * 4 + 4, 0);
        words.extend(
            bytes
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        );
        let at = self
            .globals
            .iter()
            .position(|i| i.op == op::MEMORY_MODEL)
            .unwrap_or(0);
        self.globals
            .insert(at, Inst::new(op::EXT_INST_IMPORT, words));
        self.glsl = Some(id);
        id
    }

    /// A new id.
    pub fn fresh(&mut self) -> u32 {
        let id = self.header[3];
        self.header[3] += 1;
        id
    }

    /// The type `op operands` (no result id), found or added.
    fn ty(&mut self, opcode: u16, operands: Vec<u32>) -> u32 {
        if let Some(&id) = self.types.get(&(opcode, operands.clone())) {
            return id;
        }
        let id = self.fresh();
        let mut words = vec![id];
        words.extend(&operands);
        self.added_globals.push(Inst::new(opcode, words));
        self.types.insert((opcode, operands), id);
        id
    }

    /// The 32-bit float type of `shape`.
    pub fn float_ty(&mut self, shape: Shape) -> u32 {
        let f = self.ty(op::TYPE_FLOAT, vec![32]);
        self.float_shapes.insert(f, Shape(1));
        self.vector(f, shape)
    }

    /// The 32-bit unsigned integer type of `shape`.
    pub fn uint_ty(&mut self, shape: Shape) -> u32 {
        let u = self.ty(op::TYPE_INT, vec![32, 0]);
        self.vector(u, shape)
    }

    /// The boolean type of `shape`.
    pub fn bool_ty(&mut self, shape: Shape) -> u32 {
        let b = self.ty(op::TYPE_BOOL, vec![]);
        self.vector(b, shape)
    }

    fn vector(&mut self, scalar: u32, shape: Shape) -> u32 {
        if shape.0 == 1 {
            scalar
        } else {
            let id = self.ty(op::TYPE_VECTOR, vec![scalar, shape.0]);
            if self.float_shapes.contains_key(&scalar) {
                self.float_shapes.insert(id, shape);
            }
            id
        }
    }

    /// A constant of `shape` with each component's bits `lanes[i]` (a
    /// scalar takes `lanes[0]`), typed by `scalar_ty` and `ty`.
    fn constant(&mut self, scalar_ty: u32, ty: u32, shape: Shape, lanes: [u32; 4]) -> u32 {
        let key = (ty, lanes[..shape.0 as usize].to_vec());
        if let Some(&id) = self.constants.get(&key) {
            return id;
        }
        let id = if shape.0 == 1 {
            let id = self.fresh();
            self.added_globals
                .push(Inst::new(op::CONSTANT, vec![scalar_ty, id, lanes[0]]));
            id
        } else {
            let parts: Vec<u32> = (0..shape.0 as usize)
                .map(|i| self.constant(scalar_ty, scalar_ty, Shape(1), [lanes[i]; 4]))
                .collect();
            let id = self.fresh();
            let mut words = vec![ty, id];
            words.extend(parts);
            self.added_globals
                .push(Inst::new(op::CONSTANT_COMPOSITE, words));
            id
        };
        self.constants.insert(key, id);
        id
    }

    /// A uint constant of `shape`, lane by lane.
    pub fn uint_lanes(&mut self, shape: Shape, lanes: [u32; 4]) -> u32 {
        let s = self.uint_ty(Shape(1));
        let t = self.uint_ty(shape);
        self.constant(s, t, shape, lanes)
    }

    /// A uint constant of `shape`, every lane `v`.
    pub fn uint(&mut self, shape: Shape, v: u32) -> u32 {
        self.uint_lanes(shape, [v; 4])
    }

    /// A float constant of `shape`, every lane `v`.
    pub fn float(&mut self, shape: Shape, v: f32) -> u32 {
        let s = self.float_ty(Shape(1));
        let t = self.float_ty(shape);
        self.constant(s, t, shape, [v.to_bits(); 4])
    }

    /// Decorates `id` NoContraction, once.
    pub fn no_contraction(&mut self, id: u32) {
        if self.no_contraction.insert(id) {
            self.added_decorations
                .push(Inst::new(op::DECORATE, vec![id, NO_CONTRACTION]));
        }
    }

    /// Removes every decoration of `ids` (their instructions were replaced
    /// by others, which a decoration such as NoContraction may not sit on).
    pub fn undecorate(&mut self, ids: &HashSet<u32>) {
        let decorates = |i: &Inst| {
            matches!(i.op, op::DECORATE | op::DECORATE_ID | op::DECORATE_STRING)
                && ids.contains(&i.operands[0])
        };
        self.globals.retain(|i| !decorates(i));
        self.added_decorations.retain(|i| !decorates(i));
        for id in ids {
            self.no_contraction.remove(id);
        }
    }

    /// The module's words, with what was added in its place.
    pub fn words(mut self) -> Vec<u32> {
        let annotation = |i: &Inst| {
            matches!(
                i.op,
                op::DECORATE
                    | op::MEMBER_DECORATE
                    | op::DECORATION_GROUP
                    | op::GROUP_DECORATE
                    | op::GROUP_MEMBER_DECORATE
                    | op::DECORATE_ID
                    | op::DECORATE_STRING
                    | op::MEMBER_DECORATE_STRING
            )
        };
        // Types (19-39), constants (41-52) and global variables (59).
        let is_type = |i: &Inst| matches!(i.op, 19..=39 | 41..=52 | 59);
        // After the last annotation; where there is none, before the first
        // type or constant.
        let at = match self.globals.iter().rposition(annotation) {
            Some(i) => i + 1,
            None => self
                .globals
                .iter()
                .position(is_type)
                .unwrap_or(self.globals.len()),
        };
        let decorations = std::mem::take(&mut self.added_decorations);
        self.globals.splice(at..at, decorations);
        self.globals.append(&mut self.added_globals);
        let mut out = self.header.to_vec();
        for i in self.globals.iter().chain(&self.functions) {
            out.push(((i.operands.len() as u32 + 1) << 16) | u32::from(i.op));
            out.extend(&i.operands);
        }
        out
    }
}

/// A literal string's text (nul-terminated, packed little-endian).
pub fn string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take_while(|&b| b != 0)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A module's words from (opcode, operands) pairs, bound `bound`.
    fn assemble(bound: u32, insts: &[(u16, &[u32])]) -> Vec<u32> {
        let mut w = vec![0x0723_0203, 0x0001_0500, 0, bound, 0];
        for (opcode, operands) in insts {
            w.push(((operands.len() as u32 + 1) << 16) | u32::from(*opcode));
            w.extend(*operands);
        }
        w
    }

    fn glsl_words() -> Vec<u32> {
        let mut v = vec![1];
        v.extend([0x4c53_4c47, 0x6474_732e, 0x3035_342e, 0]);
        v
    }

    /// %1 GLSL import, %2 float, %3 vec3, a function whose %10 = %8 / %9
    /// and %11 = %8 * %9 decorated NoContraction.
    fn sample() -> Vec<u32> {
        let glsl = glsl_words();
        assemble(
            20,
            &[
                (17, &[1]),
                (op::EXT_INST_IMPORT, &glsl),
                (op::MEMORY_MODEL, &[0, 1]),
                (op::DECORATE, &[11, NO_CONTRACTION]),
                (op::TYPE_FLOAT, &[2, 32]),
                (op::TYPE_VECTOR, &[3, 2, 3]),
                (op::FUNCTION, &[2, 7, 0, 6]),
                (op::F_DIV, &[2, 10, 8, 9]),
                (op::F_MUL, &[2, 11, 8, 9]),
                (56, &[]),
            ],
        )
    }

    #[test]
    fn a_module_reads_and_writes_back_word_for_word() {
        let words = sample();
        let m = Module::parse(&words).unwrap();
        assert_eq!(m.glsl, Some(1));
        assert_eq!(m.float_shapes.get(&2), Some(&Shape(1)));
        assert_eq!(m.float_shapes.get(&3), Some(&Shape(3)));
        assert!(m.no_contraction_before(11));
        assert_eq!(m.value_types.get(&10), Some(&2));
        assert_eq!(m.words(), words);
    }

    #[test]
    fn what_is_not_spir_v_is_refused() {
        assert!(Module::parse(&[1, 2, 3]).is_err_and(|e| e.contains("magic")));
        let mut cut = sample();
        cut.pop();
        cut.push(0x0005_0081);
        let Err(e) = Module::parse(&cut) else {
            panic!("a cut module read")
        };
        assert!(e.contains("runs past"), "{e}");
    }

    #[test]
    fn types_are_found_or_added_once_and_ids_come_after_the_bound() {
        let mut m = Module::parse(&sample()).unwrap();
        assert_eq!(m.float_ty(Shape(3)), 3, "the module's own vec3");
        let u4 = m.uint_ty(Shape(4));
        assert!(u4 >= 20);
        assert_eq!(m.uint_ty(Shape(4)), u4, "once");
        let c = m.uint(Shape(4), 7);
        assert_eq!(m.uint(Shape(4), 7), c);
        m.no_contraction(10);
        m.no_contraction(10);
        let words = m.words();
        let back = Module::parse(&words).unwrap();
        assert!(back.no_contraction_before(10));
        let decorations = back
            .globals
            .iter()
            .filter(|i| i.op == op::DECORATE && i.operands[0] == 10)
            .count();
        assert_eq!(decorations, 1);
        assert!(back.header[3] > u4);
    }

    #[test]
    fn an_import_is_added_before_the_memory_model() {
        let mut m = Module::parse(&sample()).unwrap();
        m.glsl = None;
        let id = m.import_glsl();
        let at = m
            .globals
            .iter()
            .position(|i| i.op == op::MEMORY_MODEL)
            .unwrap();
        assert_eq!(m.globals[at - 1].operands[0], id);
        assert_eq!(string(&m.globals[at - 1].operands[1..]), "GLSL.std.450");
    }
}
