//! The Vulkan layer: one file per concept, thin RAII structs whose raw
//! handles stay visible. Each frees its handles in reverse creation order.

pub mod bounded;
pub mod buffer;
pub mod command;
pub mod descriptor;
pub mod device;
pub mod instance;
pub mod pipeline;
pub mod pipeline_cache;
pub mod query;
pub mod texel_view;
