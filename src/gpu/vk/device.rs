//! Choosing a physical device and opening a logical one with a compute queue.

use std::ffi::CStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use ash::vk;
use serde::Serialize;

use super::instance::Instance;
use crate::gpu::error::{GpuError, VkContext};
use crate::gpu::workarounds::{LOOP_BUDGET, NO_BRANCH_SKIP, NO_UNIFORM_ARRAYS, NO_WAVEFRONT};

/// What `glint info` shows of a device and what the renderer needs to know.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(test, derive(Default))]
pub struct DeviceInfo {
    /// The device's name, as `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// `discrete GPU`, `integrated GPU`, `virtual GPU`, `CPU` or `other`.
    pub kind: String,
    /// The Vulkan version it supports, as `1.3.230`.
    pub api_version: String,
    /// The driver's name and version.
    pub driver: String,
    /// Whether shaders may use doubles (`--precision f64` on the GPU).
    pub shader_float64: bool,
    /// Whether the driver may cut an invocation's loops short: llvmpipe
    /// before Mesa 25.0 does after about 65,535 iterations, and a driver
    /// not known to run every loop to its end is taken to. Shaders carry
    /// the canary of shaders/budget.glsl where this holds.
    pub loop_budget: bool,
    /// Whether a branch that no invocation of a SIMD group takes costs
    /// nothing: llvmpipe runs both sides of every branch before Mesa 24.3
    /// ("gallivm: Skip inactive branches"); a GPU skips a branch its whole
    /// group leaves. Where it holds, the robust intersections take their
    /// cheap filter (shaders/exact.glsl).
    pub skips_untaken_branches: bool,
    /// Whether the driver is known to run the wavefront schedule: llvmpipe
    /// before Mesa 25.0 aborts the process ("stack smashing detected") on
    /// scenes/glass.toml's naive wavefront variant, so there it is refused.
    pub runs_the_wavefront: bool,
    /// Whether the scene's arrays may be read from uniform buffers: not on
    /// llvmpipe before Mesa 25.0, which corrupted its heap or crashed in a
    /// worker thread on such variants (`glint fuzz`'s CI set: 3 runs of 3
    /// over 64 generated scenes on Mesa 22.3, none with storage buffers;
    /// two mixes of kinds were known before).
    pub reads_uniform_arrays: bool,
    /// Whether compute shaders have the subgroup ballot operations
    /// (`subgroupBallot`, `subgroupBallotExclusiveBitCount`), with which the
    /// wavefront schedule compacts its queues; Vulkan 1.1 requires only the
    /// basic ones.
    pub subgroup_ballot: bool,
    /// Whether shaders may read buffers through their device addresses
    /// (Vulkan 1.2's bufferDeviceAddress; enabled where the device has it).
    pub buffer_device_address: bool,
    /// The largest storage buffer a shader may bind, in bytes.
    pub max_storage_buffer_range: u32,
    /// The largest uniform buffer a shader may bind, in bytes.
    pub max_uniform_buffer_range: u32,
    /// The most texels a texel buffer may hold.
    pub max_texel_buffer_elements: u32,
    /// The most workgroups a dispatch may have in x, y and z.
    pub max_compute_work_group_count: [u32; 3],
    /// The most invocations a workgroup may have.
    pub max_compute_work_group_invocations: u32,
    /// The queue family glint submits to, where one has compute.
    pub compute_queue_family: Option<u32>,
    /// Nanoseconds a timestamp tick, and the ticks' valid bits, where the
    /// compute queue writes timestamps.
    pub timestamps: Option<(f32, u32)>,
}

impl DeviceInfo {
    /// A file-name-safe tag for this device and driver, for cache files.
    pub fn cache_id(&self) -> String {
        format!("{} {}", self.name, self.driver)
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect()
    }
}

/// A candidate, with the rank that orders the default choice.
pub struct Candidate {
    pub physical: vk::PhysicalDevice,
    pub info: DeviceInfo,
    rank: u32,
    api: u32,
}

fn version(v: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(v),
        vk::api_version_minor(v),
        vk::api_version_patch(v)
    )
}

/// Every device the instance sees, best first: discrete GPUs, integrated
/// GPUs, virtual GPUs, then CPU implementations such as lavapipe.
pub fn candidates(instance: &Instance) -> Result<Vec<Candidate>, GpuError> {
    let raw = &instance.raw;
    // SAFETY: `raw` is a live instance (borrowed for the call).
    let physicals =
        unsafe { raw.enumerate_physical_devices() }.doing("vkEnumeratePhysicalDevices")?;
    let mut out = Vec::new();
    for physical in physicals {
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut v12);
        // SAFETY: `physical` came from this instance; the chain is one
        // Vulkan 1.2 features struct that the driver fills.
        unsafe { raw.get_physical_device_features2(physical, &mut features2) };
        let buffer_device_address = v12.buffer_device_address == vk::TRUE;
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut driver)
            .push_next(&mut subgroup);
        // SAFETY: `physical` came from this instance; the chain is two
        // properties structs of Vulkan 1.1 and 1.2 that the driver fills;
        // Vulkan 1.1+ is required of the loader (the instance asked for 1.2).
        unsafe { raw.get_physical_device_properties2(physical, &mut props2) };
        let props = props2.properties;
        // SAFETY: as above, queries of a handle from this instance.
        let (features, families) = unsafe {
            (
                raw.get_physical_device_features(physical),
                raw.get_physical_device_queue_family_properties(physical),
            )
        };
        let compute_queue_family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .map(|i| i as u32);
        let cstr = |s: Result<&CStr, _>| {
            s.map_or_else(
                |_| "?".to_owned(),
                |c: &CStr| c.to_string_lossy().into_owned(),
            )
        };
        let (kind, rank) = match props.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => ("discrete GPU", 0),
            vk::PhysicalDeviceType::INTEGRATED_GPU => ("integrated GPU", 1),
            vk::PhysicalDeviceType::VIRTUAL_GPU => ("virtual GPU", 2),
            vk::PhysicalDeviceType::CPU => ("CPU", 3),
            _ => ("other", 4),
        };
        let limits = props.limits;
        let driver_name = cstr(driver.driver_name_as_c_str());
        let driver_info = cstr(driver.driver_info_as_c_str());
        let timestamps = compute_queue_family
            .map(|f| families[f as usize].timestamp_valid_bits)
            .filter(|bits| *bits > 0)
            .map(|bits| (limits.timestamp_period, bits));
        out.push(Candidate {
            physical,
            rank,
            api: props.api_version,
            info: DeviceInfo {
                name: cstr(props.device_name_as_c_str()),
                kind: kind.to_owned(),
                api_version: version(props.api_version),
                driver: format!("{driver_name} {driver_info}"),
                shader_float64: features.shader_float64 == vk::TRUE,
                loop_budget: LOOP_BUDGET.applies(&driver_name, &driver_info),
                skips_untaken_branches: !NO_BRANCH_SKIP.applies(&driver_name, &driver_info),
                runs_the_wavefront: !NO_WAVEFRONT.applies(&driver_name, &driver_info),
                reads_uniform_arrays: !NO_UNIFORM_ARRAYS.applies(&driver_name, &driver_info),
                buffer_device_address,
                subgroup_ballot: subgroup
                    .supported_stages
                    .contains(vk::ShaderStageFlags::COMPUTE)
                    && subgroup
                        .supported_operations
                        .contains(vk::SubgroupFeatureFlags::BALLOT),
                max_storage_buffer_range: limits.max_storage_buffer_range,
                max_uniform_buffer_range: limits.max_uniform_buffer_range,
                max_texel_buffer_elements: limits.max_texel_buffer_elements,
                max_compute_work_group_count: limits.max_compute_work_group_count,
                max_compute_work_group_invocations: limits.max_compute_work_group_invocations,
                compute_queue_family,
                timestamps,
            },
        });
    }
    out.sort_by_key(|c| c.rank);
    Ok(out)
}

fn usable(c: &Candidate) -> bool {
    c.info.compute_queue_family.is_some() && c.api >= vk::API_VERSION_1_2
}

/// A logical device and its compute queue. Shared (`Arc`) by everything
/// made from it, each of which keeps it alive: the device is destroyed
/// after the last of them, and the instance after the device.
pub struct Device {
    pub raw: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub memory: vk::PhysicalDeviceMemoryProperties,
    pub info: DeviceInfo,
    /// A wait on this device's work timed out: the work may still run, so
    /// nothing more is submitted ([`Device::hung`]).
    hung: AtomicBool,
    /// Dropped after the device is destroyed (fields drop after `drop`).
    instance: Arc<Instance>,
}

impl Device {
    /// Opens the best usable device, or the first whose name contains
    /// `wanted` (case-insensitive).
    pub fn open(instance: Arc<Instance>, wanted: Option<&str>) -> Result<Arc<Self>, GpuError> {
        let all = candidates(&instance)?;
        let chosen = match wanted {
            Some(name) => {
                let needle = name.to_lowercase();
                all.iter()
                    .find(|c| c.info.name.to_lowercase().contains(&needle) && usable(c))
                    .ok_or_else(|| GpuError::NoMatchingDevice {
                        wanted: name.to_owned(),
                        available: if all.is_empty() {
                            "(none)".to_owned()
                        } else {
                            all.iter()
                                .map(|c| c.info.name.clone())
                                .collect::<Vec<_>>()
                                .join(", ")
                        },
                    })?
            }
            None => all.iter().find(|c| usable(c)).ok_or(GpuError::NoDevice)?,
        };
        let queue_family = chosen.info.compute_queue_family.ok_or(GpuError::NoDevice)?;
        let priorities = [1.0f32];
        let queue_info = vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities);
        let features =
            vk::PhysicalDeviceFeatures::default().shader_float64(chosen.info.shader_float64);
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default()
            .buffer_device_address(chosen.info.buffer_device_address);
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(std::slice::from_ref(&queue_info))
            .enabled_features(&features)
            .push_next(&mut v12);
        // SAFETY: `chosen.physical` came from this instance; the create
        // info asks for one queue of a family it has and only features it
        // reported (shaderFloat64 and bufferDeviceAddress where supported).
        let raw = unsafe { instance.raw.create_device(chosen.physical, &info, None) }
            .doing("vkCreateDevice")?;
        // SAFETY: queue 0 of the family the device was created with.
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        // SAFETY: a query of a handle from this instance.
        let memory = unsafe {
            instance
                .raw
                .get_physical_device_memory_properties(chosen.physical)
        };
        Ok(Arc::new(Self {
            raw,
            queue,
            queue_family,
            memory,
            info: chosen.info.clone(),
            hung: AtomicBool::new(false),
            instance,
        }))
    }

    /// The instance the device was opened on.
    pub fn instance(&self) -> &Instance {
        &self.instance
    }

    /// Whether a wait on this device timed out. Its work may still be
    /// running, so [`OneShot::run`](super::command::OneShot::run) submits
    /// nothing more, and whatever that work used is never freed.
    pub fn hung(&self) -> bool {
        self.hung.load(Ordering::Acquire)
    }

    /// Marks the device hung ([`Device::hung`]).
    pub(super) fn mark_hung(&self) {
        self.hung.store(true, Ordering::Release);
    }

    /// A memory type allowed by `type_bits` with all of `flags`.
    pub fn memory_type(&self, type_bits: u32, flags: vk::MemoryPropertyFlags) -> Option<u32> {
        self.memory_type_without(type_bits, flags, vk::MemoryPropertyFlags::empty())
    }

    /// A memory type with `flags` and none of `without`.
    pub fn memory_type_without(
        &self,
        type_bits: u32,
        flags: vk::MemoryPropertyFlags,
        without: vk::MemoryPropertyFlags,
    ) -> Option<u32> {
        (0..self.memory.memory_type_count).find(|&i| {
            let f = self.memory.memory_types[i as usize].property_flags;
            type_bits & (1 << i) != 0 && f.contains(flags) && !f.intersects(without)
        })
    }

    /// Whether the device has memory of its own that the host cannot map
    /// (a discrete GPU's), which staged uploads are for.
    pub fn has_private_memory(&self) -> bool {
        self.memory_type_without(
            !0,
            vk::MemoryPropertyFlags::DEVICE_LOCAL,
            vk::MemoryPropertyFlags::HOST_VISIBLE,
        )
        .is_some()
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // Work that timed out may never end (a runaway loop on a driver
        // without a loop limit): the device is leaked, not waited for, and
        // so is its instance, which may not be destroyed before it.
        if self.hung() {
            std::mem::forget(self.instance.clone());
            return;
        }
        // SAFETY: every object made from this device holds an Arc of it, so
        // all of them are gone, and no submission is pending (none hung).
        unsafe {
            self.raw.destroy_device(None);
        }
    }
}
