/* OpenCL device layer. Every call is checked; failures name the call, the
 * error, the file and the line (as the Khronos OpenCL-SDK samples do). */
#include "device.h"
#include "domain.h"
#include "sph_case.h" /* sph_shared.h: the reduction slots */

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef SPH_SOURCE_DIR
#define SPH_SOURCE_DIR "."
#endif

/* Kernel sources in the order the program is assembled, one per line
 * (clang-format would pack them). */
// clang-format off
static const char *const source_files[] = {
    "include/sph_shared.h",
    "kernels/lane_types.cl",
    "kernels/smoothing.cl",
    "kernels/common.cl",
    "kernels/matrix.cl",
    "kernels/grid.cl",
    "kernels/material_models.cl",
    "kernels/material.cl",
    "kernels/lanes.cl",
    "kernels/tensor_smoothing.cl",
    "kernels/sphere_wall.cl", /* pass 1 and projectile.cl use it */
    "kernels/pass1.cl",
    "kernels/pass2.cl",
    "kernels/total_lagrangian.cl",
    "kernels/contact_current.cl",
    "kernels/ghost.cl",
    "kernels/halo.cl",
    "kernels/integrate.cl",
    "kernels/reduce.cl",
    "kernels/health.cl",
    "kernels/projectile.cl",
    "kernels/probe.cl",
};
// clang-format on

const char *cl_error_name(cl_int code)
{
    switch (code) {
#define NAME(c)                                                                                    \
    case c:                                                                                        \
        return #c;
        NAME(CL_DEVICE_NOT_FOUND)
        NAME(CL_DEVICE_NOT_AVAILABLE)
        NAME(CL_COMPILER_NOT_AVAILABLE)
        NAME(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        NAME(CL_OUT_OF_RESOURCES)
        NAME(CL_OUT_OF_HOST_MEMORY)
        NAME(CL_BUILD_PROGRAM_FAILURE)
        NAME(CL_INVALID_VALUE)
        NAME(CL_INVALID_DEVICE)
        NAME(CL_INVALID_BINARY)
        NAME(CL_INVALID_BUILD_OPTIONS)
        NAME(CL_INVALID_PROGRAM)
        NAME(CL_INVALID_PROGRAM_EXECUTABLE)
        NAME(CL_INVALID_KERNEL_NAME)
        NAME(CL_INVALID_KERNEL)
        NAME(CL_INVALID_ARG_INDEX)
        NAME(CL_INVALID_ARG_VALUE)
        NAME(CL_INVALID_ARG_SIZE)
        NAME(CL_INVALID_KERNEL_ARGS)
        NAME(CL_INVALID_WORK_GROUP_SIZE)
        NAME(CL_INVALID_WORK_ITEM_SIZE)
        NAME(CL_INVALID_GLOBAL_WORK_SIZE)
        NAME(CL_INVALID_MEM_OBJECT)
        NAME(CL_INVALID_BUFFER_SIZE)
        NAME(CL_INVALID_COMMAND_QUEUE)
        NAME(CL_INVALID_CONTEXT)
        NAME(CL_INVALID_PLATFORM)
        NAME(CL_INVALID_EVENT)
        NAME(CL_INVALID_OPERATION)
        NAME(CL_PLATFORM_NOT_FOUND_KHR)
#undef NAME
    default:
        return "an unknown OpenCL error";
    }
}

static struct {
    int failed, host_memory;
    char message[512];
    long calls, fail_at; /* checked calls so far; SPH_FAIL_CL_CALL (0: none) */
    int fail_at_read;
} cl_status;

void cl_fail(const char *call, cl_int code, const char *file, int line)
{
    if (cl_status.failed)
        return;
    cl_status.failed = 1;
    snprintf(cl_status.message, sizeof cl_status.message,
             "OpenCL call %.300s failed with %s (%d) at %s:%d", call, cl_error_name(code),
             (int)code, file, line);
}

void device_fail(const char *what, const char *file, int line)
{
    if (cl_status.failed)
        return;
    cl_status.failed = 1;
    snprintf(cl_status.message, sizeof cl_status.message, "%.400s at %s:%d", what, file, line);
}

void cl_failure_clear(void)
{
    memset(&cl_status, 0, sizeof cl_status);
}

void host_alloc_failed(const char *what, size_t bytes, const char *file, int line)
{
    if (cl_status.failed)
        return;
    cl_status.failed = cl_status.host_memory = 1;
    snprintf(cl_status.message, sizeof cl_status.message,
             "out of host memory: %.200s (%zu bytes) at %s:%d", what, bytes, file, line);
}

void *checked_calloc(size_t count, size_t size, const char *what, const char *file, int line)
{
    static long calls, fail_at = -1;
    if (fail_at < 0) {
        const char *env = getenv("SPH_FAIL_ALLOC");
        fail_at = env ? atol(env) : 0;
    }
    void *p = ++calls == fail_at ? NULL : calloc(count ? count : 1, size ? size : 1);
    if (!p)
        host_alloc_failed(what, count * size, file, line);
    return p;
}

const char *cl_failure_status(void)
{
    return cl_status.host_memory ? "out_of_memory" : "device_error";
}

int cl_failed(void)
{
    return cl_status.failed;
}

const char *cl_failure(void)
{
    return cl_status.message;
}

cl_int cl_checked(cl_int code)
{
    if (!cl_status.fail_at_read) {
        const char *env = getenv("SPH_FAIL_CL_CALL");
        cl_status.fail_at = env ? atol(env) : 0;
        cl_status.fail_at_read = 1;
    }
    return ++cl_status.calls == cl_status.fail_at ? CL_OUT_OF_RESOURCES : code;
}

const char *device_source_dir(void)
{
    const char *env = getenv("SPH_SOURCE_DIR");
    return env && *env ? env : SPH_SOURCE_DIR;
}

static void device_string(cl_device_id d, cl_device_info what, char *out, size_t size)
{
    out[0] = '\0';
    CL_CHECK(clGetDeviceInfo(d, what, size, out, NULL));
}

static const char *device_type_name(cl_device_id d)
{
    cl_device_type type = 0;
    CL_CHECK(clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof type, &type, NULL));
    return (type & CL_DEVICE_TYPE_GPU) ? "GPU" : (type & CL_DEVICE_TYPE_CPU) ? "CPU" : "other";
}

/* Every device of every platform, flattened in the order sph info prints. */
struct device_entry {
    cl_platform_id platform;
    cl_device_id device;
};

static int enumerate(struct device_entry *out, int capacity)
{
    cl_uint platform_count = 0;
    cl_int err = clGetPlatformIDs(0, NULL, &platform_count);
    if (err == CL_PLATFORM_NOT_FOUND_KHR || platform_count == 0)
        return 0;
    CL_CHECK(err);
    cl_platform_id platforms[16];
    if (platform_count > 16)
        platform_count = 16;
    CL_CHECK(clGetPlatformIDs(platform_count, platforms, NULL));
    int count = 0;
    for (cl_uint p = 0; p < platform_count; ++p) {
        cl_device_id devices[32];
        cl_uint n = 0;
        err = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 32, devices, &n);
        if (err == CL_DEVICE_NOT_FOUND)
            continue;
        CL_CHECK_ERR("clGetDeviceIDs", err);
        if (n > 32)
            n = 32; /* clGetDeviceIDs reports the total, not what it wrote */
        for (cl_uint d = 0; d < n && count < capacity; ++d) {
            out[count].platform = platforms[p];
            out[count].device = devices[d];
            ++count;
        }
    }
    return count;
}

int device_list(FILE *out)
{
    struct device_entry entries[64];
    const int count = enumerate(entries, 64);
    if (cl_failed())
        return 0;
    if (count == 0) {
        fprintf(out, "no OpenCL devices found (install an ICD, e.g. pocl-opencl-icd)\n");
        return 0;
    }
    for (int i = 0; i < count; ++i) {
        char name[256] = "", platform[256] = "", version[128] = "", driver[128] = "";
        cl_uint units = 0;
        cl_ulong memory = 0, alloc = 0;
        device_string(entries[i].device, CL_DEVICE_NAME, name, sizeof name);
        device_string(entries[i].device, CL_DEVICE_VERSION, version, sizeof version);
        device_string(entries[i].device, CL_DRIVER_VERSION, driver, sizeof driver);
        CL_CHECK(clGetPlatformInfo(entries[i].platform, CL_PLATFORM_NAME, sizeof platform, platform,
                                   NULL));
        CL_CHECK(clGetDeviceInfo(entries[i].device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units,
                                 &units, NULL));
        CL_CHECK(clGetDeviceInfo(entries[i].device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof memory,
                                 &memory, NULL));
        CL_CHECK(clGetDeviceInfo(entries[i].device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof alloc,
                                 &alloc, NULL));
        fprintf(out,
                "[%d] %s: %s (%s)\n    platform %s, driver %s, %u compute units, %.1f GiB "
                "memory, %.1f GiB per buffer\n",
                i, device_type_name(entries[i].device), name, version, platform, driver, units,
                (double)memory / (1 << 30), (double)alloc / (1 << 30));
    }
    return count;
}

static int select_device(const struct device_entry *entries, int count, const char *selector,
                         char *error, size_t error_size)
{
    if (count == 0) {
        snprintf(error, error_size,
                 "no OpenCL device found: install an OpenCL driver (for CPUs: apt-get install "
                 "pocl-opencl-icd)");
        return -1;
    }
    if (!selector) {
        /* over several processes each rank on a node takes its own GPU
         * (its rank on the node modulo the GPUs): the first for one process */
        int gpus = 0;
        for (int i = 0; dist_size() > 1 && i < count; ++i)
            gpus += strcmp(device_type_name(entries[i].device), "GPU") == 0;
        for (int i = 0, k = gpus ? dist_local_rank() % gpus : 0; i < count; ++i)
            if (strcmp(device_type_name(entries[i].device), "GPU") == 0 && k-- == 0)
                return i;
        for (int i = 0; i < count; ++i)
            if (strcmp(device_type_name(entries[i].device), "CPU") == 0)
                return i;
        return 0;
    }
    char *end = NULL;
    long index = strtol(selector, &end, 10);
    if (end != selector && *end == '\0') {
        if (index < 0 || index >= count) {
            snprintf(error, error_size,
                     "--device %s: no such device; there are %d (0 to %d), see 'sph info'",
                     selector, count, count - 1);
            return -1;
        }
        return (int)index;
    }
    for (int i = 0; i < count; ++i) {
        char name[256];
        device_string(entries[i].device, CL_DEVICE_NAME, name, sizeof name);
        if (strstr(name, selector))
            return i;
    }
    snprintf(error, error_size, "--device %s: no device name contains '%s'; see 'sph info'",
             selector, selector);
    return -1;
}

/* The reductions run work-groups of REDUCE_WG (64, kernels/common.cl) with
 * a local array of that many rows of their slots (at most SPH_RED_SLOTS
 * reals, 8 B each in double); the other launches leave the work-group size
 * to the implementation. A device below either limit is refused by name. */
static int check_group_limits(const struct sph_device *dev, char *error, size_t error_size)
{
    size_t max_group = 0;
    cl_ulong local_memory = 0;
    CL_CHECK(clGetDeviceInfo(dev->device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max_group,
                             &max_group, NULL));
    CL_CHECK(clGetDeviceInfo(dev->device, CL_DEVICE_LOCAL_MEM_SIZE, sizeof local_memory,
                             &local_memory, NULL));
    const cl_ulong needed = (cl_ulong)REDUCE_GROUP * SPH_RED_SLOTS * sizeof(cl_double);
    if (!cl_failed() && (max_group < REDUCE_GROUP || local_memory < needed))
        return snprintf(error, error_size,
                        "%s allows work-groups of %zu and %llu B of local memory; the reduction "
                        "kernels need %d and %llu B",
                        dev->name, max_group, (unsigned long long)local_memory, REDUCE_GROUP,
                        (unsigned long long)needed) > 0;
    return 0;
}

int device_open(const char *selector, int profiling, struct sph_device *dev, char *error,
                size_t error_size)
{
    memset(dev, 0, sizeof *dev);
    struct device_entry entries[64];
    const int count = enumerate(entries, 64);
    const int chosen = select_device(entries, count, selector, error, error_size);
    if (chosen < 0)
        return 1;
    dev->platform = entries[chosen].platform;
    dev->device = entries[chosen].device;
    device_string(dev->device, CL_DEVICE_NAME, dev->name, sizeof dev->name);
    device_string(dev->device, CL_DRIVER_VERSION, dev->driver_version, sizeof dev->driver_version);
    CL_CHECK(clGetPlatformInfo(dev->platform, CL_PLATFORM_NAME, sizeof dev->platform_name,
                               dev->platform_name, NULL));
    CL_CHECK(clGetDeviceInfo(dev->device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof dev->global_memory,
                             &dev->global_memory, NULL));
    CL_CHECK(clGetDeviceInfo(dev->device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof dev->max_allocation,
                             &dev->max_allocation, NULL));
    cl_device_fp_config fp64 = 0;
    CL_CHECK(clGetDeviceInfo(dev->device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, NULL));
    dev->has_double = fp64 != 0;
    cl_device_type type = 0;
    CL_CHECK(clGetDeviceInfo(dev->device, CL_DEVICE_TYPE, sizeof type, &type, NULL));
    dev->is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
    if (check_group_limits(dev, error, error_size))
        return 1;
    cl_int err = CL_SUCCESS;
    dev->context = clCreateContext(NULL, 1, &dev->device, NULL, NULL, &err);
    CL_CHECK_ERR("clCreateContext", err);
    dev->queue = clCreateCommandQueue(dev->context, dev->device,
                                      profiling ? CL_QUEUE_PROFILING_ENABLE : 0, &err);
    CL_CHECK_ERR("clCreateCommandQueue", err);
    if (cl_failed()) {
        snprintf(error, error_size, "%s", cl_failure());
        return 1;
    }
    return 0;
}

/* FNV-1a, 64 bit: the cache key only needs to separate different inputs. */
static uint64_t fnv1a(uint64_t hash, const void *data, size_t size)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; ++i) {
        hash ^= p[i];
        hash *= 1099511628211ull;
    }
    return hash;
}

static char *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long length = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = length >= 0 ? malloc((size_t)length + 1) : NULL;
    if (text && fread(text, 1, (size_t)length, f) != (size_t)length) {
        free(text);
        text = NULL;
    }
    fclose(f);
    if (text) {
        text[length] = '\0';
        if (size)
            *size = (size_t)length;
    }
    return text;
}

static char *assemble_source(const char *source_dir, char *error, size_t error_size)
{
    size_t total = 0, capacity = 1 << 16;
    char *source = malloc(capacity);
    if (!source) {
        snprintf(error, error_size, "out of host memory for the kernel source");
        return NULL;
    }
    source[0] = '\0';
    for (size_t k = 0; k < sizeof source_files / sizeof source_files[0]; ++k) {
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", source_dir, source_files[k]);
        size_t size = 0;
        char *text = read_file(path, &size);
        if (!text) {
            snprintf(error, error_size,
                     "cannot read kernel source %s: %s (set SPH_SOURCE_DIR to the impact-sph "
                     "source folder)",
                     path, strerror(errno));
            free(source);
            return NULL;
        }
        char line[2100];
        int header = snprintf(line, sizeof line, "#line 1 \"%s\"\n", source_files[k]);
        while (total + size + (size_t)header + 2 > capacity)
            capacity *= 2;
        char *grown = realloc(source, capacity);
        if (!grown) {
            free(text);
            free(source);
            return NULL;
        }
        source = grown;
        memcpy(source + total, line, (size_t)header);
        total += (size_t)header;
        memcpy(source + total, text, size);
        total += size;
        source[total++] = '\n';
        source[total] = '\0';
        free(text);
    }
    return source;
}

void device_cache_folder(char *folder, size_t size)
{
    const char *base = getenv("SPH_CACHE_DIR");
    if (base && *base)
        snprintf(folder, size, "%s", base);
    else if (getenv("XDG_CACHE_HOME") && *getenv("XDG_CACHE_HOME"))
        snprintf(folder, size, "%s/impact-sph", getenv("XDG_CACHE_HOME"));
    else
        snprintf(folder, size, "%s/.cache/impact-sph", getenv("HOME") ? getenv("HOME") : "/tmp");
}

void device_cache_file(const struct sph_device *dev, const char *stem, const char *key1,
                       const char *key2, const char *suffix, char *path, size_t size)
{
    uint64_t h = 14695981039346656037ull;
    h = fnv1a(h, key1, strlen(key1));
    h = fnv1a(h, key2, strlen(key2));
    h = fnv1a(h, dev->name, strlen(dev->name));
    h = fnv1a(h, dev->driver_version, strlen(dev->driver_version));
    h = fnv1a(h, dev->platform_name, strlen(dev->platform_name));
    char folder[1024];
    device_cache_folder(folder, sizeof folder);
    snprintf(path, size, "%s/%s-%016llx.%s", folder, stem, (unsigned long long)h, suffix);
}

void device_make_parent_dirs(const char *path)
{
    char buffer[1200];
    snprintf(buffer, sizeof buffer, "%s", path);
    for (char *p = buffer + 1; *p; ++p)
        if (*p == '/') {
            *p = '\0';
            mkdir(buffer, 0755);
            *p = '/';
        }
}

/* Whether the program's kernels report their argument names: host/launch.c
 * binds arguments by them, and the OpenCL specification promises them only
 * for programs built from source, so a driver may drop them from a binary. */
static int has_argument_names(cl_program program)
{
    char names[4096] = "", arg[64];
    if (clGetProgramInfo(program, CL_PROGRAM_KERNEL_NAMES, sizeof names, names, NULL) != CL_SUCCESS)
        return 0;
    names[strcspn(names, ";")] = '\0';
    cl_int err = CL_SUCCESS;
    cl_kernel k = clCreateKernel(program, names, &err);
    if (err != CL_SUCCESS)
        return 0;
    cl_uint count = 0;
    int ok = clGetKernelInfo(k, CL_KERNEL_NUM_ARGS, sizeof count, &count, NULL) == CL_SUCCESS;
    if (ok && count > 0)
        ok = clGetKernelArgInfo(k, 0, CL_KERNEL_ARG_NAME, sizeof arg, arg, NULL) == CL_SUCCESS;
    clReleaseKernel(k);
    return ok;
}

static cl_program load_cached(struct sph_device *dev, const char *path, const char *options)
{
    size_t size = 0;
    unsigned char *binary = (unsigned char *)read_file(path, &size);
    if (!binary)
        return NULL;
    cl_int status = CL_SUCCESS, err = CL_SUCCESS;
    const unsigned char *binaries[1] = {binary};
    cl_program program =
        clCreateProgramWithBinary(dev->context, 1, &dev->device, &size, binaries, &status, &err);
    free(binary);
    if (err != CL_SUCCESS || status != CL_SUCCESS) {
        if (err == CL_SUCCESS)
            clReleaseProgram(program);
        return NULL;
    }
    if (clBuildProgram(program, 1, &dev->device, options, NULL, NULL) != CL_SUCCESS ||
        !has_argument_names(program)) {
        clReleaseProgram(program);
        return NULL; /* a stale or foreign binary, or one without argument names: from source */
    }
    return program;
}

static void store_cached(struct sph_device *dev, const char *path)
{
    size_t size = 0;
    if (clGetProgramInfo(dev->program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, NULL) !=
            CL_SUCCESS ||
        size == 0)
        return;
    unsigned char *binary = malloc(size);
    unsigned char *binaries[1] = {binary};
    if (binary && clGetProgramInfo(dev->program, CL_PROGRAM_BINARIES, sizeof binaries, binaries,
                                   NULL) == CL_SUCCESS) {
        device_make_parent_dirs(path);
        char temporary[1200];
        snprintf(temporary, sizeof temporary, "%s.%ld.tmp", path, (long)getpid());
        FILE *f = fopen(temporary, "wb");
        if (f) {
            const int ok = fwrite(binary, 1, size, f) == size;
            if (fclose(f) == 0 && ok)
                rename(temporary, path); /* atomic: parallel runs never read half a file */
            else
                remove(temporary);
        }
    }
    free(binary);
}

static void print_build_log(struct sph_device *dev, cl_program program, const char *options)
{
    size_t size = 0;
    clGetProgramBuildInfo(program, dev->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &size);
    char *log = malloc(size + 1);
    if (log && clGetProgramBuildInfo(program, dev->device, CL_PROGRAM_BUILD_LOG, size, log, NULL) ==
                   CL_SUCCESS) {
        log[size] = '\0';
        fprintf(stderr, "sph: kernel build failed with options: %s\n%s\n", options, log);
    }
    free(log);
}

int device_build(struct sph_device *dev, const char *source_dir, const char *options, char *error,
                 size_t error_size)
{
    if (dev->program) { /* a second case on the same device (sph bench) */
        clReleaseProgram(dev->program);
        dev->program = NULL;
    }
    char *source = assemble_source(source_dir, error, error_size);
    if (!source)
        return 1;
    char path[1100];
    device_cache_file(dev, "program", source, options, "bin", path, sizeof path);
    dev->program = load_cached(dev, path, options);
    dev->from_cache = dev->program != NULL;
    /* one checked call for the program's creation on either path, so that
     * SPH_FAIL_CL_CALL=N names the same call with a cold or a warm cache */
    if (dev->program)
        CL_CHECK_ERR("clCreateProgramWithBinary", CL_SUCCESS);
    if (!dev->program) {
        cl_int err = CL_SUCCESS;
        const char *sources[1] = {source};
        dev->program = clCreateProgramWithSource(dev->context, 1, sources, NULL, &err);
        CL_CHECK_ERR("clCreateProgramWithSource", err);
        if (cl_failed()) {
            snprintf(error, error_size, "%s", cl_failure());
            free(source);
            return 1;
        }
        err = clBuildProgram(dev->program, 1, &dev->device, options, NULL, NULL);
        if (err != CL_SUCCESS) {
            print_build_log(dev, dev->program, options);
            snprintf(error, error_size, "the kernels did not compile (%s); the build log is above",
                     cl_error_name(err));
            free(source);
            return 1;
        }
        store_cached(dev, path);
    }
    free(source);
    return 0;
}

void device_close(struct sph_device *dev)
{
    /* what was enqueued must finish before the process exits: PoCL compiles
     * a kernel at its first launch in a thread of its own, which crashed
     * when a run stopped early (a binding error) and exit() tore LLVM down
     * under it. Unchecked: a failed device has nothing left to finish. */
    if (dev->queue)
        clFinish(dev->queue);
    if (dev->program)
        clReleaseProgram(dev->program);
    if (dev->queue)
        clReleaseCommandQueue(dev->queue);
    if (dev->context)
        clReleaseContext(dev->context);
    memset(dev, 0, sizeof *dev);
}
