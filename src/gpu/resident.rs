//! The buffers a prepared scene keeps on the device: the scene's read-only
//! arrays, made once and bound by each of its stages, and each stage's own
//! (its output tile, counters, wavefront paths and refinement list).

use std::sync::Arc;

use ash::vk as raw;

use super::access;
use super::blocks::Block;
use super::blocks::Form;
use super::layout::Uploads;
use super::variant::Variant;
use super::vk::buffer::Buffer;
use super::vk::command::OneShot;
use super::vk::descriptor::Resource;
use super::vk::device::Device;
use super::vk::texel_view::TexelBuffer;
use super::GpuError;
use crate::base::interface::Array;
use crate::base::record;
use crate::stats::Counter;

/// What one binding holds: a buffer, a texel buffer (a buffer seen
/// through its view), or a buffer read through its address (the binding's
/// uniform block holds the address).
pub(crate) enum Bound {
    Buffer(Buffer),
    Texels(TexelBuffer),
    Address { data: Buffer, address: Buffer },
}

impl Bound {
    pub fn buffer(&self) -> &Buffer {
        match self {
            Bound::Buffer(b) => b,
            Bound::Texels(t) => &t.buffer,
            Bound::Address { data, .. } => data,
        }
    }

    pub fn resource(&self) -> Resource {
        match self {
            Bound::Buffer(b) => Resource::Buffer(b.raw),
            Bound::Texels(t) => Resource::Texels(t.view),
            Bound::Address { address, .. } => Resource::Buffer(address.raw),
        }
    }
}

/// Buffers by the block they are bound at.
#[derive(Default)]
pub(crate) struct Blocks(Vec<(Block, Bound)>);

impl Blocks {
    pub fn get(&self, block: Block) -> Option<&Bound> {
        self.0.iter().find(|(b, _)| *b == block).map(|(_, x)| x)
    }

    /// `bound` in place of what `block` held; what it held, returned.
    pub fn replace(&mut self, block: Block, bound: Bound) -> Option<Bound> {
        let at = self.0.iter_mut().find(|(b, _)| *b == block)?;
        Some(std::mem::replace(&mut at.1, bound))
    }
}

/// What fills a scene block's buffer: the bytes, in place.
type Write<'u> = Box<dyn FnOnce(&mut [u8]) + 'u>;

/// A scene block of `variant`'s bindings and what it holds of `up`: the
/// form its array is read in, its size in bytes and what writes them;
/// None for a block that is not the scene's.
fn scene_block<'u>(
    block: Block,
    variant: &Variant,
    up: &'u Uploads,
) -> Option<(Option<Form>, usize, Write<'u>)> {
    let array = match block {
        Block::Globals => None,
        Block::Kind(k) => Some(&up.kinds[k]),
        Block::Materials => Some(&up.materials),
        Block::Lights => Some(&up.lights),
        Block::Textures => Some(&up.textures),
        Block::Texels => Some(&up.texels),
        Block::Uvs => Some(&up.uvs),
        Block::Nodes => Some(up.nodes.as_ref().expect("a BVH variant has nodes")),
        Block::Tables => Some(up.tables.as_ref().expect("a tables variant has tables")),
        _ => return None,
    };
    let form = access::ArrayDecl::of(block).map(|_| variant.form(block));
    // The arrays are written straight into the (staging) buffer; a
    // uniform block declared longer than its array (the nodes':
    // `Features::nodes`) is padded with zeros to the length declared.
    let size = match (array, form) {
        (None, _) => up.globals.len(),
        (Some(a), Some(Form::Uniform(n))) if n > a.len => a.byte_len() / a.len.max(1) * n,
        (Some(a), _) => a.byte_len(),
    };
    let write = move |dst: &mut [u8]| match array {
        Some(a) => {
            let (items, padding) = dst.split_at_mut(a.byte_len());
            a.write(items);
            padding.fill(0);
        }
        None => dst.copy_from_slice(&up.globals),
    };
    Some((form, size, Box::new(write)))
}

/// The scene's read-only arrays of `variant`'s bindings, holding `up`:
/// device-local through staging where `staged`, else mapped.
pub(crate) fn scene_blocks(
    device: &Arc<Device>,
    commands: &mut OneShot,
    staged: bool,
    variant: &Variant,
    up: &Uploads,
) -> Result<Blocks, GpuError> {
    let mut blocks = Vec::new();
    for (block, _, ty) in variant.bindings() {
        let Some((form, size, write)) = scene_block(block, variant, up) else {
            continue;
        };
        // Written again on the device where the scene is updated.
        let usage = usage(form, ty) | raw::BufferUsageFlags::TRANSFER_DST;
        let what = if block == Block::Globals {
            "the uniform block"
        } else {
            block.name()
        };
        let buffer = if staged {
            Buffer::staged_written(device, commands, size, write, usage, what)?
        } else {
            Buffer::written(device, size, write, usage, what)?
        };
        blocks.push((block, bind_as(device, form, buffer)?));
    }
    Ok(Blocks(blocks))
}

/// Writes `up` into `blocks`, the scene blocks `scene_blocks` made for
/// `variant`, in place, leaving out those `unchanged` names; Err names
/// the first block whose array no longer fits its buffer (nothing is
/// written then).
pub(crate) fn rewrite_scene_blocks(
    device: &Arc<Device>,
    commands: &mut OneShot,
    blocks: &Blocks,
    variant: &Variant,
    up: &Uploads,
    unchanged: &[Block],
) -> Result<Result<(), String>, GpuError> {
    let mut writes = Vec::new();
    for (block, bound) in &blocks.0 {
        let Some((_, size, write)) = scene_block(*block, variant, up) else {
            continue;
        };
        let buffer = bound.buffer();
        if size.max(16) as u64 != buffer.size {
            return Ok(Err(format!(
                "{}: {} bytes, where {} were uploaded",
                block.name(),
                size,
                buffer.size
            )));
        }
        if !unchanged.contains(block) {
            writes.push((buffer, size, write));
        }
    }
    Buffer::overwrite(device, commands, writes)?;
    Ok(Ok(()))
}

/// What a stage's own buffers are made from, beside its variant.
#[derive(Clone, Copy)]
pub(crate) enum StageInput<'a> {
    /// The main stage, and the sample it records, where it records one.
    Main(Option<[u32; 4]>),
    /// A refinement's stage and the list it refines.
    Refine(&'a Array<'a>),
}

/// A stage's own buffers among `variant`'s bindings: its output tile of
/// `tile` pixels, its counters, its record, its wavefront paths and
/// queues, and the list it refines.
pub(crate) fn stage_blocks(
    device: &Arc<Device>,
    variant: &Variant,
    tile: (u32, u32),
    own: StageInput<'_>,
) -> Result<Blocks, GpuError> {
    let pixels = u64::from(tile.0) * u64::from(tile.1);
    let storage = raw::BufferUsageFlags::STORAGE_BUFFER;
    let filled = storage | raw::BufferUsageFlags::TRANSFER_DST;
    let mut blocks = Vec::new();
    for (block, _, _) in variant.bindings() {
        let buffer = match block {
            Block::Counts => Buffer::new(
                device,
                (2 * Counter::SLOTS * std::mem::size_of::<u32>()) as u64,
                filled,
                block.name(),
            )?,
            Block::Record => {
                let StageInput::Main(Some(sample)) = own else {
                    unreachable!("a recording variant is the main stage's, with its sample")
                };
                let words = record::HEADER_WORDS + record::CAPACITY * record::ENTRY_WORDS;
                Buffer::written(
                    device,
                    4 * words,
                    |dst| record_header(dst, sample),
                    filled,
                    block.name(),
                )?
            }
            Block::Refine => {
                let StageInput::Refine(list) = own else {
                    unreachable!("a refining variant is a refinement's stage, with its list")
                };
                list_buffer(device, list)?
            }
            Block::PathReals | Block::PathWords => {
                let (reals, words) = variant.path_bytes();
                let size = if block == Block::PathReals {
                    reals
                } else {
                    words
                };
                Buffer::device_local(device, pixels * size, storage, block.name())?
            }
            Block::Queues => Buffer::new(
                device,
                32 + 2 * 4 * pixels,
                filled | raw::BufferUsageFlags::INDIRECT_BUFFER,
                block.name(),
            )?,
            Block::Pixels => Buffer::new(
                device,
                pixels * 16 * u64::from(variant.outputs_per_invocation()),
                filled,
                block.name(),
            )?,
            Block::Aovs => Buffer::new(
                device,
                pixels * 4 * crate::base::aov::WORDS as u64,
                filled,
                block.name(),
            )?,
            _ => continue,
        };
        blocks.push((block, Bound::Buffer(buffer)));
    }
    Ok(Blocks(blocks))
}

/// A refinement's list in a buffer of its own (`Block::Refine`).
pub(crate) fn list_buffer(device: &Arc<Device>, list: &Array<'_>) -> Result<Buffer, GpuError> {
    Buffer::written(
        device,
        list.byte_len(),
        |dst| list.write(dst),
        raw::BufferUsageFlags::STORAGE_BUFFER,
        Block::Refine.name(),
    )
}

/// The usage of a scene array's buffer read in `form` through a binding of
/// type `ty`.
fn usage(form: Option<Form>, ty: raw::DescriptorType) -> raw::BufferUsageFlags {
    match (form, ty) {
        (Some(Form::Address), _) => {
            raw::BufferUsageFlags::STORAGE_BUFFER | raw::BufferUsageFlags::SHADER_DEVICE_ADDRESS
        }
        (_, raw::DescriptorType::UNIFORM_BUFFER) => raw::BufferUsageFlags::UNIFORM_BUFFER,
        (_, raw::DescriptorType::UNIFORM_TEXEL_BUFFER) => {
            raw::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
        }
        _ => raw::BufferUsageFlags::STORAGE_BUFFER,
    }
}

/// `buffer` as its binding sees it: through a texel view, through its
/// address, or whole.
fn bind_as(device: &Arc<Device>, form: Option<Form>, buffer: Buffer) -> Result<Bound, GpuError> {
    Ok(match form {
        Some(Form::Texels) => Bound::Texels(TexelBuffer::new(device, buffer)?),
        Some(Form::Address) => {
            let at = [buffer.address(), 0u64];
            let address = Buffer::with_data(
                device,
                &at,
                raw::BufferUsageFlags::UNIFORM_BUFFER,
                "an array's address",
            )?;
            Bound::Address {
                data: buffer,
                address,
            }
        }
        _ => Bound::Buffer(buffer),
    })
}

/// A record's header: the sample it records and no entry yet. Each render
/// zeroes the count again, on the device (`Prepared::tiles`).
fn record_header(dst: &mut [u8], sample: [u32; 4]) {
    let mut header = [0u32; record::HEADER_WORDS];
    header[..4].copy_from_slice(&sample);
    dst[..4 * record::HEADER_WORDS].copy_from_slice(bytemuck::cast_slice(&header));
}
