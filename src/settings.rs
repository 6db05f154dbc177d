//! The settings a render is asked for by name, on the command line and in
//! the library alike: each is a [`Choice`], a fixed set of lowercase words.
//! The command line builds its parsers from [`Choice::ALL`], so the
//! library needs no command-line parser.

pub use crate::accel::Accel;
pub use crate::base::Precision;

/// A setting with a fixed set of values, each named by one lowercase word.
pub trait Choice: Copy + PartialEq + 'static {
    /// Each value, its name, and a line on what it does.
    const ALL: &'static [(Self, &'static str, &'static str)];

    /// This value's name.
    fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(v, _, _)| *v == self)
            .map(|(_, n, _)| *n)
            .expect("every value is listed in ALL")
    }

    /// The value named `name`, if there is one.
    fn named(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(_, n, _)| *n == name)
            .map(|(v, _, _)| *v)
    }
}

/// Which ray/primitive intersection forms the shader uses.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Intersect {
    /// Camera-relative coordinates, the stable sphere roots with an exact
    /// power term, and secondary rays that know which surface they left.
    #[default]
    Robust,
    /// The textbook forms with a fixed epsilon of 1e-4, in world coordinates.
    Naive,
}

impl Choice for Intersect {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            Intersect::Robust,
            "robust",
            "Camera-relative coordinates, stable sphere roots and secondary rays that know which surface they left",
        ),
        (
            Intersect::Naive,
            "naive",
            "The textbook forms with a fixed epsilon of 1e-4, in world coordinates",
        ),
    ];
}

/// The schedule a render asks for.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Schedule {
    /// The one that measured faster for scenes like this one: today the
    /// megakernel for every scene (`auto_picks_wavefront`).
    #[default]
    Auto,
    /// One invocation per pixel, each tracing its whole ray tree.
    Megakernel,
    /// A dispatch per ray segment over a compacted queue of live paths.
    Wavefront,
}

impl Choice for Schedule {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            Schedule::Auto,
            "auto",
            "The one that measured faster for scenes like this one",
        ),
        (
            Schedule::Megakernel,
            "megakernel",
            "One invocation per pixel, each tracing its whole ray tree",
        ),
        (
            Schedule::Wavefront,
            "wavefront",
            "A dispatch per ray segment over a compacted queue of live paths",
        ),
    ];
}

impl Choice for Accel {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            Accel::Auto,
            "auto",
            "The BVH from 16 bounded primitives up, else the linear scan",
        ),
        (
            Accel::Bvh,
            "bvh",
            "A BVH over the bounded primitives; the unbounded ones (planes) are scanned",
        ),
        (Accel::None, "none", "Every ray tests every object"),
        (
            Accel::Tables,
            "tables",
            "The BVH, with a light buffer for shadow rays and screen tiles for eye rays",
        ),
    ];
}

impl Choice for Precision {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (Precision::F32, "f32", "Floats throughout"),
        (
            Precision::F64,
            "f64",
            "Doubles throughout; on the GPU it needs the device's shaderFloat64",
        ),
    ];
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each value has one name, and the name gives the value back.
    fn round_trips<T: Choice + std::fmt::Debug>() {
        for (value, name, _) in T::ALL {
            assert_eq!(value.name(), *name);
            assert_eq!(T::named(name), Some(*value));
        }
        assert_eq!(T::named("no such value"), None);
    }

    #[test]
    fn every_choice_round_trips() {
        round_trips::<Intersect>();
        round_trips::<Schedule>();
        round_trips::<Accel>();
        round_trips::<Precision>();
    }
}
