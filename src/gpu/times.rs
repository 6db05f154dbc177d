//! What preparing and rendering a scene cost, in seconds.

/// One-time costs, apart from any render: opening the device, and compiling
/// the scene's shader variant (or reading it from the SPIR-V cache) and
/// creating its pipeline; zero when the variant was already built.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct SetupTimes {
    /// Opening the device (the renderer's, once).
    pub device_s: f64,
    /// Compiling the variant's shader, or reading its SPIR-V from the cache.
    pub compile_s: f64,
    /// Creating its pipeline.
    pub pipeline_s: f64,
    /// Whether the SPIR-V came from the cache.
    pub spirv_cached: bool,
    /// The pipeline's first dispatch, one workgroup that shades no pixel:
    /// where the driver compiles the shader to machine code (lavapipe runs
    /// LLVM there), bounded by `COMPILE_TIMEOUT` rather than the render's
    /// watchdog.
    pub driver_compile_s: f64,
}

/// The cost of one render. The first render of a [`Prepared`](super::Prepared) scene also
/// carries what preparing it cost (its setup, BVH and upload); later
/// renders of it carry none of that.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct RenderTimes {
    /// What this call spent compiling its variant and creating its
    /// pipeline (zero where an earlier call did); `device_s` is the
    /// renderer's, spent once when it was made.
    pub setup: SetupTimes,
    /// Building the BVH: a setup cost, apart from the render's total.
    pub bvh_s: f64,
    /// Building the light buffers and the eye's tiles (`--accel tables`):
    /// a setup cost like the BVH's.
    pub tables_s: f64,
    /// Laying the scene out (apart from the BVH) and uploading it.
    pub upload_s: f64,
    /// The dispatches, with their submissions and waits.
    pub dispatch_s: f64,
    /// Copying the tiles out of mapped memory into the image.
    pub readback_s: f64,
    /// Adaptive sampling's work on the host between its levels' dispatches:
    /// choosing the squares to split, listing their points, summing them.
    pub refine_s: f64,
    /// The dispatches' own time on the device, from timestamp queries;
    /// None where its queue writes none. `dispatch_s` also holds the
    /// submission, the fill of the output and the wait.
    pub device_dispatch_s: Option<f64>,
}

impl RenderTimes {
    /// Upload, dispatch, readback and the refinement's host work: the
    /// render, without its setup.
    pub fn total_s(&self) -> f64 {
        self.upload_s + self.dispatch_s + self.readback_s + self.refine_s
    }
}
