//! Under `--spec-worst`, which of the shader's perturbed instructions
//! compute a quantity of the tree (docs/guarantees.md, On any conformant
//! driver), so that a divergence names the function behind it.

/// The renderer's name for a tree recorded under `--spec-worst`.
pub const SUFFIX: &str = " --spec-worst";

/// The perturbed instructions that compute the quantity `what` (a
/// label's field: "specular", "direction", ...), with the spec's bound on
/// each.
pub fn functions(what: &str) -> &'static str {
    match what {
        "direction" | "shadow ray direction" => {
            "normalize (x / length(x), its square root from 1 / inversesqrt: up to 9 ULP)"
        }
        "distance" | "point" | "hit" | "shadow ray" | "shadow ray origin" => {
            "the intersection's divisions (2.5 ULP), square roots (6.5 ULP) and contracted products"
        }
        "normal" | "shading_normal" => {
            "the division by the radius or the normalization (2.5 to 9 ULP)"
        }
        "uv" => "glint's own atan2 and asin, through their divisions (2.5 ULP each)",
        "specular" | "cone" => "pow (from exp2(y·log2(x)): 3 ULP of log2, times the exponent)",
        "n_dot_l" => "normalize (up to 9 ULP) and the dot product's contractions",
        "diffuse" | "ambient" => "the texture's divisions (2.5 ULP) and n·l's normalization",
        _ => "divisions (2.5 ULP), square roots (6.5 ULP) and contracted products",
    }
}

/// The clause a divergence of the quantity `what` on a `--spec-worst`
/// tree adds.
pub fn clause(what: &str) -> String {
    format!(
        "; under --spec-worst: {} carry a conformant driver's worst error there",
        functions(what)
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_quantity_names_the_functions_that_compute_it() {
        assert!(super::functions("specular").starts_with("pow"));
        assert!(super::functions("uv").contains("atan2"));
        assert!(super::functions("direction").starts_with("normalize"));
        assert!(super::clause("weight").contains("divisions"));
    }
}
