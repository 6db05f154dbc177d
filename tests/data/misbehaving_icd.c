/* A Vulkan driver that forwards to a real one (REAL_LIBRARY, lavapipe in
 * the tests) and misbehaves on purpose in one way (MODE), so that the
 * tests hold `glint drivers` to faults no correct driver makes
 * (issue 42, defect 8):
 *
 *   1 skip     vkCmdDispatch and vkCmdDispatchIndirect record nothing;
 *   2 lose     vkWaitForFences waits, then says VK_ERROR_DEVICE_LOST;
 *   3 hang     vkWaitForFences never returns;
 *   4 garbage  every dispatch is followed by a fill of 1.0 over the
 *              buffer last filled with 0xffffffff (glint's image).
 *
 * Every object is the real driver's: this library hands the loader the
 * real entry points except for the few it wraps, so the loader's dispatch
 * word is the real driver's too. No Vulkan header is needed: handles are
 * pointers (dispatchable) or 64-bit integers, results are int32.
 *
 * Built by tests/drivers.rs: cc -shared -fPIC -DMODE=n
 * -DREAL_LIBRARY='"..."' misbehaving_icd.c -ldl */

#include <dlfcn.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#ifndef MODE
#error "MODE must be 1 (skip), 2 (lose), 3 (hang) or 4 (garbage)"
#endif

typedef void (*Fn)(void);
typedef Fn (*GetProc)(void *, const char *);
typedef int32_t (*Negotiate)(uint32_t *);
typedef void (*Dispatch)(void *, uint32_t, uint32_t, uint32_t);
typedef void (*DispatchIndirect)(void *, uint64_t, uint64_t);
typedef void (*Fill)(void *, uint64_t, uint64_t, uint64_t, uint32_t);
typedef int32_t (*WaitForFences)(void *, uint32_t, const uint64_t *, uint32_t, uint64_t);

#define VK_ERROR_DEVICE_LOST (-4)
#define VK_WHOLE_SIZE (~0ULL)
#define ONE_F32 0x3f800000u

static void *real;
static GetProc real_instance_proc;
static GetProc real_device_proc;
static Dispatch real_dispatch;
static DispatchIndirect real_dispatch_indirect;
static Fill real_fill;
static WaitForFences real_wait;
/* The buffer glint fills with NaN before a dispatch: its image. */
static uint64_t image_buffer;

static void *open_real(void) {
    if (!real) real = dlopen(REAL_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    return real;
}

static Fn real_symbol(const char *name) {
    void *lib = open_real();
    return lib ? (Fn)dlsym(lib, name) : 0;
}

static void spoil(void *cb) {
    if (MODE == 4 && image_buffer) real_fill(cb, image_buffer, 0, VK_WHOLE_SIZE, ONE_F32);
}

static void cmd_dispatch(void *cb, uint32_t x, uint32_t y, uint32_t z) {
    if (MODE == 1) return;
    real_dispatch(cb, x, y, z);
    spoil(cb);
}

static void cmd_dispatch_indirect(void *cb, uint64_t buffer, uint64_t offset) {
    if (MODE == 1) return;
    real_dispatch_indirect(cb, buffer, offset);
    spoil(cb);
}

static void cmd_fill_buffer(void *cb, uint64_t buffer, uint64_t offset, uint64_t size,
                            uint32_t data) {
    if (data == 0xffffffffu) image_buffer = buffer;
    real_fill(cb, buffer, offset, size, data);
}

static int32_t wait_for_fences(void *device, uint32_t count, const uint64_t *fences,
                               uint32_t all, uint64_t timeout) {
    if (MODE == 3)
        for (;;) pause();
    int32_t r = real_wait(device, count, fences, all, timeout);
    return MODE == 2 && r == 0 ? VK_ERROR_DEVICE_LOST : r;
}

/* The wrapped entry point of `name`, with the real one it calls fetched
 * through `get` from `object`; 0 where `name` is not wrapped. */
static Fn wrapped(GetProc get, void *object, const char *name) {
    if (!strcmp(name, "vkCmdDispatch")) {
        real_dispatch = (Dispatch)get(object, name);
        return real_dispatch ? (Fn)cmd_dispatch : 0;
    }
    if (!strcmp(name, "vkCmdDispatchIndirect")) {
        real_dispatch_indirect = (DispatchIndirect)get(object, name);
        return real_dispatch_indirect ? (Fn)cmd_dispatch_indirect : 0;
    }
    if (!strcmp(name, "vkCmdFillBuffer")) {
        real_fill = (Fill)get(object, name);
        return real_fill ? (Fn)cmd_fill_buffer : 0;
    }
    if (!strcmp(name, "vkWaitForFences")) {
        real_wait = (WaitForFences)get(object, name);
        return real_wait ? (Fn)wait_for_fences : 0;
    }
    return 0;
}

static Fn get_device_proc(void *device, const char *name) {
    Fn w = wrapped(real_device_proc, device, name);
    return w ? w : real_device_proc(device, name);
}

__attribute__((visibility("default"))) int32_t
vk_icdNegotiateLoaderICDInterfaceVersion(uint32_t *version) {
    Negotiate n = (Negotiate)real_symbol("vk_icdNegotiateLoaderICDInterfaceVersion");
    return n ? n(version) : -9; /* VK_ERROR_INCOMPATIBLE_DRIVER */
}

__attribute__((visibility("default"))) Fn vk_icdGetInstanceProcAddr(void *instance,
                                                                    const char *name) {
    if (!real_instance_proc) real_instance_proc = (GetProc)real_symbol("vk_icdGetInstanceProcAddr");
    if (!real_instance_proc) return 0;
    if (!strcmp(name, "vkGetDeviceProcAddr")) {
        real_device_proc = (GetProc)real_instance_proc(instance, name);
        return real_device_proc ? (Fn)get_device_proc : 0;
    }
    Fn w = wrapped(real_instance_proc, instance, name);
    return w ? w : real_instance_proc(instance, name);
}

__attribute__((visibility("default"))) Fn vk_icdGetPhysicalDeviceProcAddr(void *instance,
                                                                          const char *name) {
    GetProc p = (GetProc)real_symbol("vk_icdGetPhysicalDeviceProcAddr");
    return p ? p(instance, name) : 0;
}
