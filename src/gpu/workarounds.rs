//! The driver workarounds, a row each: the drivers a fault was seen on,
//! what glint does there instead, and the test that shows the fault or
//! holds the workaround. `DeviceInfo`'s flags are read from this table
//! (vk/device.rs), and the variant takes them from there (features.rs,
//! variant.rs); no other place names a driver's version.

/// Which drivers a row applies to, by the driver's name and info string
/// (`llvmpipe`, `Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drivers {
    /// llvmpipe (lavapipe) before this Mesa version.
    LlvmpipeBefore(u32, u32),
    /// Every driver but llvmpipe from this Mesa version on: what is not
    /// known to be safe is taken not to be.
    AllButLlvmpipeFrom(u32, u32),
}

impl Drivers {
    /// Whether the driver `name`, `info` is among these.
    pub fn include(self, name: &str, info: &str) -> bool {
        let llvmpipe = name == "llvmpipe";
        match self {
            Drivers::LlvmpipeBefore(major, minor) => {
                llvmpipe && mesa_version(info) < (major, minor)
            }
            Drivers::AllButLlvmpipeFrom(major, minor) => {
                !(llvmpipe && mesa_version(info) >= (major, minor))
            }
        }
    }
}

/// One workaround.
#[derive(Debug, Clone, Copy)]
pub struct Workaround {
    /// Its name, the `DeviceInfo` flag it sets where it applies.
    pub name: &'static str,
    /// The drivers it applies to.
    pub drivers: Drivers,
    /// The fault, and what glint does there instead.
    pub does: &'static str,
    /// The test that shows the fault or holds the workaround
    /// (`tests/<file>.rs::<function>`, or a unit test's path).
    pub test: &'static str,
}

impl Workaround {
    /// Whether it applies to the driver `name`, `info`.
    pub fn applies(&self, name: &str, info: &str) -> bool {
        self.drivers.include(name, info)
    }
}

/// The loop budget: llvmpipe before Mesa 25.0 cuts an invocation's loops
/// after about 65,535 iterations ("gallivm: Remove loop limiting", 25.0.0's
/// release notes), and a driver not known to run every loop to its end is
/// taken to. Shaders carry the canary of shaders/budget.glsl there
/// (`DeviceInfo::loop_budget`).
pub const LOOP_BUDGET: Workaround = Workaround {
    name: "loop_budget",
    drivers: Drivers::AllButLlvmpipeFrom(25, 0),
    does: "the shader carries the loop-budget canary, and a pixel whose loops were cut \
           short is an error, never a wrong image",
    test: "tests/loop_budget.rs::a_linear_scan_past_the_budget_is_an_error_or_the_right_image",
};

/// Both sides of every branch: llvmpipe before Mesa 24.3 runs a branch no
/// invocation of a SIMD group takes ("gallivm: Skip inactive branches"),
/// so the robust forms' cheap filter costs there what it saves.
pub const NO_BRANCH_SKIP: Workaround = Workaround {
    name: "no_branch_skip",
    drivers: Drivers::LlvmpipeBefore(24, 3),
    does: "the robust intersections take the exact power everywhere, without the \
           POWER_FILTER branch (a cost, not a fault: both render the same bits)",
    test: "tests/variants.rs::each_variant_equals_the_generic_shader",
};

/// The wavefront's crash: llvmpipe before Mesa 25.0 aborts the process
/// ("stack smashing detected") on scenes/glass.toml's naive wavefront
/// variant.
pub const NO_WAVEFRONT: Workaround = Workaround {
    name: "no_wavefront",
    drivers: Drivers::LlvmpipeBefore(25, 0),
    does: "--schedule wavefront is refused, and auto takes the megakernel (the abort \
           is not shown: it ends the process)",
    test: "tests/schedules.rs::runs_the_wavefront",
};

/// Uniform buffers' heap corruption: llvmpipe before Mesa 25.0 corrupted
/// its heap or crashed in a worker thread on variants that read the
/// scene's arrays from uniform buffers (`glint fuzz`'s CI set: 3 runs of 3
/// over 64 generated scenes on Mesa 22.3, none with storage buffers).
pub const NO_UNIFORM_ARRAYS: Workaround = Workaround {
    name: "no_uniform_arrays",
    drivers: Drivers::LlvmpipeBefore(25, 0),
    does: "every scene's arrays are read as storage or texel buffers, never uniform blocks",
    test: "tests/variants.rs::every_mix_of_kinds_and_lights_renders",
};

/// Every row, in the order of `DeviceInfo`'s flags.
pub const WORKAROUNDS: &[Workaround] =
    &[LOOP_BUDGET, NO_BRANCH_SKIP, NO_WAVEFRONT, NO_UNIFORM_ARRAYS];

/// The Mesa version in a driver's info string (0.0 where it names none).
fn mesa_version(info: &str) -> (u32, u32) {
    let version = info
        .split_whitespace()
        .skip_while(|w| *w != "Mesa")
        .nth(1)
        .unwrap_or("");
    let mut numbers = version
        .split(|c: char| !c.is_ascii_digit())
        .map(|n| n.parse().unwrap_or(0));
    (numbers.next().unwrap_or(0), numbers.next().unwrap_or(0))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MESA_25: &str = "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)";
    const MESA_26: &str = "Mesa 26.2.6-1 (LLVM 22.1.8)";
    const MESA_24_3: &str = "Mesa 24.3.0 (LLVM 19.1.0)";
    const MESA_24_2: &str = "Mesa 24.2.8 (LLVM 19.1.0)";
    const MESA_22: &str = "Mesa 22.3.6 (LLVM 15.0.6)";
    const GPU: (&str, &str) = ("NVIDIA", "570.86.15");

    /// Each row holds on the drivers it was seen on and on none it was
    /// not: Debian 12's lavapipe (22.3) takes every one; 24.2 all but the
    /// branch skip's lifting; 25.0 and 26 none; a GPU the loop budget alone,
    /// not being known to run every loop to its end.
    #[test]
    fn each_row_names_the_drivers_it_was_seen_on() {
        let on = |info: &str| -> Vec<&str> {
            WORKAROUNDS
                .iter()
                .filter(|w| w.applies("llvmpipe", info))
                .map(|w| w.name)
                .collect()
        };
        assert_eq!(
            on(MESA_22),
            [
                "loop_budget",
                "no_branch_skip",
                "no_wavefront",
                "no_uniform_arrays"
            ]
        );
        assert_eq!(
            on(MESA_24_2),
            [
                "loop_budget",
                "no_branch_skip",
                "no_wavefront",
                "no_uniform_arrays"
            ]
        );
        assert_eq!(
            on(MESA_24_3),
            ["loop_budget", "no_wavefront", "no_uniform_arrays"]
        );
        assert!(on(MESA_25).is_empty());
        assert!(on(MESA_26).is_empty());
        assert!(on("no version").contains(&"loop_budget"));
        let gpu: Vec<&str> = WORKAROUNDS
            .iter()
            .filter(|w| w.applies(GPU.0, GPU.1))
            .map(|w| w.name)
            .collect();
        assert_eq!(gpu, ["loop_budget"]);
    }

    /// Each row's test is there: a file of tests/ or src/ holding a
    /// function of that name.
    #[test]
    fn each_row_names_a_test_that_is_there() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        for w in WORKAROUNDS {
            let (file, function) = w.test.split_once("::").expect("file::function");
            let function = function.rsplit("::").next().unwrap();
            let text = std::fs::read_to_string(root.join(file))
                .unwrap_or_else(|e| panic!("{}: {file}: {e}", w.name));
            assert!(
                text.contains(&format!("fn {function}(")),
                "{}: {file} has no fn {function}",
                w.name
            );
        }
    }
}
