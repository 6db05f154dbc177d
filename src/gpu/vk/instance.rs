//! The Vulkan instance, with the Khronos validation layer and a messenger
//! that collects every message it sends when validation is on.

use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::{ext::debug_utils, vk};

use crate::gpu::error::{GpuError, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Messages from the validation layer, shared with the callback.
#[derive(Default)]
pub struct Messages(Mutex<Vec<String>>);

impl Messages {
    /// The messages so far, leaving none.
    pub fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.0.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

struct Messenger {
    loader: debug_utils::Instance,
    raw: vk::DebugUtilsMessengerEXT,
    // Boxed so that the address handed to the callback stays put.
    messages: Box<Messages>,
}

/// A Vulkan instance; devices opened on it hold an `Arc` of it.
pub struct Instance {
    messenger: Option<Messenger>,
    pub raw: ash::Instance,
    /// The loaded Vulkan library, which must outlive the instance.
    _entry: ash::Entry,
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: Vulkan hands back the pointer given at creation, which points
    // into the boxed `Messages` that outlives the messenger; `data` is valid
    // for the call.
    let (messages, data) = unsafe { (&*(user as *const Messages), &*data) };
    let text = if data.p_message.is_null() {
        "(no message)".to_owned()
    } else {
        // SAFETY: non-null, and a NUL-terminated string for the call's length.
        unsafe { CStr::from_ptr(data.p_message) }
            .to_string_lossy()
            .into_owned()
    };
    messages
        .0
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(format!("[{severity:?}] {text}"));
    vk::FALSE
}

/// Whether the loader `entry` finds the Khronos validation layer, where
/// it looks ($XDG_DATA_DIRS, $VK_ADD_LAYER_PATH, /etc, ...).
fn has_validation_layer(entry: &ash::Entry) -> Result<bool, GpuError> {
    // SAFETY: a query of the loaded loader.
    let available = unsafe { entry.enumerate_instance_layer_properties() }
        .doing("vkEnumerateInstanceLayerProperties")?;
    Ok(available
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER)))
}

/// Whether this process's Vulkan loader finds the Khronos validation
/// layer: asked of the loader, since only it knows where it looks.
pub fn validation_layer_installed() -> Result<bool, GpuError> {
    // SAFETY: loading libvulkan runs its initialisers; it is the system loader.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::NoLoader(e.to_string()))?;
    has_validation_layer(&entry)
}

impl Instance {
    /// Loads the system's Vulkan loader and creates an instance, with the
    /// validation layer and a messenger collecting its messages where
    /// `validate`.
    pub fn new(validate: bool) -> Result<Arc<Self>, GpuError> {
        // SAFETY: loading libvulkan runs its initialisers; it is the system loader.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::NoLoader(e.to_string()))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"glint")
            .application_version(1)
            .engine_name(c"glint")
            .api_version(vk::API_VERSION_1_2);

        let mut layers = Vec::new();
        let mut extensions = Vec::new();
        if validate {
            if !has_validation_layer(&entry)? {
                return Err(GpuError::NoValidationLayer);
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(debug_utils::NAME.as_ptr());
        }

        let messages = Box::<Messages>::default();
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                    | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_message))
            .user_data(&*messages as *const Messages as *mut c_void);

        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validate {
            // Chained too, so that instance creation and destruction are checked.
            info = info.push_next(&mut messenger_info);
        }
        // SAFETY: the create info and every name and struct it points to
        // live until the call returns; the layers and extensions asked for
        // are ones the loader listed (validation is checked above).
        let raw = match unsafe { entry.create_instance(&info, None) } {
            Ok(raw) => raw,
            // The loader's answer when it finds no driver at all.
            Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => return Err(GpuError::NoDevice),
            Err(result) => return Err(GpuError::vk("vkCreateInstance", result)),
        };

        let messenger = if validate {
            let loader = debug_utils::Instance::new(&entry, &raw);
            // SAFETY: the callback's user data is the boxed `Messages`, kept
            // in the `Messenger` until after the messenger is destroyed.
            match unsafe { loader.create_debug_utils_messenger(&messenger_info, None) } {
                Ok(handle) => Some(Messenger {
                    loader,
                    raw: handle,
                    messages,
                }),
                Err(result) => {
                    // SAFETY: the instance was just made and has no children.
                    unsafe { raw.destroy_instance(None) };
                    return Err(GpuError::vk("vkCreateDebugUtilsMessengerEXT", result));
                }
            }
        } else {
            None
        };
        Ok(Arc::new(Self {
            messenger,
            raw,
            _entry: entry,
        }))
    }

    /// The validation messages since the last call; empty without validation.
    pub fn take_messages(&self) -> Vec<String> {
        self.messenger
            .as_ref()
            .map_or_else(Vec::new, |m| m.messages.take())
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: every child object is gone: a device holds an Arc of its
        // instance, so the last device was destroyed before this runs.
        unsafe {
            if let Some(m) = self.messenger.take() {
                m.loader.destroy_debug_utils_messenger(m.raw, None);
                // Messages from destroying the instance itself would have no
                // one to read them; they were checked at the last render.
                self.raw.destroy_instance(None);
                drop(m.messages);
            } else {
                self.raw.destroy_instance(None);
            }
        }
    }
}
