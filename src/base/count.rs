//! What a renderer counts, without the slots they are kept in: the ray
//! types and the counted events (the trait a renderer counts through is
//! `super::tally`'s). The slots, sized by the table of kinds, and their
//! names are `crate::stats`'s.

/// The types of ray, in the order of their slots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RayType {
    /// From the eye through a pixel.
    #[default]
    Eye,
    /// A mirror ray.
    Reflect,
    /// A refraction ray.
    Refract,
    /// Towards a light.
    Shadow,
}

impl RayType {
    /// Every type, in slot order.
    pub const ALL: [RayType; 4] = [
        RayType::Eye,
        RayType::Reflect,
        RayType::Refract,
        RayType::Shadow,
    ];

    /// Its name in `--stats` and, upper-cased with `RAY_`, in GLSL.
    pub fn name(self) -> &'static str {
        match self {
            RayType::Eye => "eye",
            RayType::Reflect => "reflect",
            RayType::Refract => "refract",
            RayType::Shadow => "shadow",
        }
    }
}

/// One counted event. Tests and node visits count against the ray type
/// the renderer last declared (`Tally::ray_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Counter {
    /// An eye ray cast.
    Eye,
    /// An eye ray that met something.
    EyeHit,
    /// A mirror ray cast.
    Reflect,
    /// A refraction ray cast.
    Refract,
    /// A shadow ray cast.
    Shadow,
    /// A BVH node visited.
    Node,
    /// A table's cell read: a shadow ray's light buffer, an eye ray's
    /// tile (`accel::tables`).
    Cell,
    /// A ray tested against a primitive of the kind `crate::prim::KINDS[k]`.
    Test(u32),
}
