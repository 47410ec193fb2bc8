/* OpenCL device layer: discovery, selection, checked calls, program build
 * with an on-disk binary cache. */
#ifndef SPH_DEVICE_H
#define SPH_DEVICE_H

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#ifndef CL_PLATFORM_NOT_FOUND_KHR
#define CL_PLATFORM_NOT_FOUND_KHR -1001 /* cl_khr_icd: no platform installed */
#endif
#include <stddef.h>
#include <stdio.h>

/* Work-group size of the reduction kernels (REDUCE_WG in kernels/common.cl),
 * checked against the device at device_open. */
#define REDUCE_GROUP 64
/* Work-groups of a reduction launch at most (solver.reduce_groups): the
 * host's arrays of per-group partials are sized for this many. */
#define REDUCE_MAX_GROUPS 64

struct sph_device {
    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    cl_program program;
    char name[256];
    char platform_name[256];
    char driver_version[128];
    cl_ulong global_memory;
    cl_ulong max_allocation;
    int has_double;
    int is_gpu;     /* CL_DEVICE_TYPE_GPU: numerics.neighbour_loop auto takes plain */
    int from_cache; /* the program came from the binary cache */
};

/* Name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES". */
const char *cl_error_name(cl_int code);

/* A failed OpenCL call does not exit: the first failure of the process is
 * recorded ("OpenCL call <text> failed with <name> (<code>) at
 * <file>:<line>"; the caller that unwinds prints it) and from then on every checked
 * call is skipped, so no call runs on the objects a failure left behind.
 * The callers unwind: device_open, device_build and solver_create return
 * the message, the run loop (host/run.c) checks cl_failed() after every
 * step and output, stops, cleans up in reverse order, writes summary.json
 * with status "device_error" and exits 2. Reads that were skipped leave
 * their (zeroed) destination untouched.
 * SPH_FAIL_CL_CALL=N makes the N-th checked call report
 * CL_OUT_OF_RESOURCES (fault injection for the tests). */
void cl_fail(const char *call, cl_int code, const char *file, int line);
/* A device-side failure that is not one call's (a kernel argument nothing
 * binds): recorded as "<what> at <file>:<line>", status device_error. */
void device_fail(const char *what, const char *file, int line);
int cl_failed(void);
const char *cl_failure(void); /* the recorded message, "" before any failure */
/* Forgets a recorded failure: for unit tests that provoke one on purpose. */
void cl_failure_clear(void);
/* A host allocation that failed is recorded the same way ("out of host
 * memory: <what> (<bytes> bytes) at <file>:<line>"), so that the run
 * unwinds as after a failed OpenCL call; the caller returns without using
 * the pointer. cl_failure_status() says which: "device_error" or
 * "out_of_memory" (summary.json's status). */
void host_alloc_failed(const char *what, size_t bytes, const char *file, int line);
#define ALLOC_FAILED(what, bytes) host_alloc_failed((what), (bytes), __FILE__, __LINE__)
const char *cl_failure_status(void);
/* calloc that records its failure as above (count or size 0: one byte);
 * SPH_FAIL_ALLOC=N makes the N-th one fail (fault injection for the tests) */
void *checked_calloc(size_t count, size_t size, const char *what, const char *file, int line);
#define CHECKED_CALLOC(count, size, what)                                                          \
    checked_calloc((count), (size), (what), __FILE__, __LINE__)
cl_int cl_checked(cl_int code); /* code, or the injected fault */

#define CL_CHECK(call)                                                                             \
    do {                                                                                           \
        if (!cl_failed()) {                                                                        \
            cl_int cl_check_code_ = cl_checked(call);                                              \
            if (cl_check_code_ != CL_SUCCESS)                                                      \
                cl_fail(#call, cl_check_code_, __FILE__, __LINE__);                                \
        }                                                                                          \
    } while (0)

/* For calls that return an object and report through an errcode pointer. */
#define CL_CHECK_ERR(expr, err_var)                                                                \
    do {                                                                                           \
        if (!cl_failed() && cl_checked(err_var) != CL_SUCCESS)                                     \
            cl_fail(expr, (err_var) != CL_SUCCESS ? (err_var) : CL_OUT_OF_RESOURCES, __FILE__,     \
                    __LINE__);                                                                     \
    } while (0)

/* Lists every platform and device (sph info). Returns the device count. */
int device_list(FILE *out);

/* Opens a device: `selector` is NULL (first GPU, else first CPU, else the
 * first device), an index as printed by device_list, or a substring of the
 * device name. Returns 0, or non-zero with one sentence in `error`. */
int device_open(const char *selector, int profiling, struct sph_device *dev, char *error,
                size_t error_size);

/* Builds the solver program from the kernel sources under `source_dir`
 * (include/sph_shared.h then kernels/ *.cl in pipeline order) with `options`.
 * A binary cache keyed by a hash of source, options, device and driver makes
 * a second build of the same program a load. Returns 0, or non-zero with the
 * reason (and the build log on stderr). */
int device_build(struct sph_device *dev, const char *source_dir, const char *options, char *error,
                 size_t error_size);

void device_close(struct sph_device *dev);

/* The user cache folder: $SPH_CACHE_DIR, else $XDG_CACHE_HOME/impact-sph,
 * else ~/.cache/impact-sph (program binaries, device ceilings). */
void device_cache_folder(char *folder, size_t size);

/* The path of a file in the cache folder, stem-<hash>.suffix, the hash of
 * key1, key2 (may be "") and the device, its driver and its platform. */
void device_cache_file(const struct sph_device *dev, const char *stem, const char *key1,
                       const char *key2, const char *suffix, char *path, size_t size);

/* Creates the folders above `path` (a file path). */
void device_make_parent_dirs(const char *path);

/* The folder that holds include/ and kernels/: $SPH_SOURCE_DIR if set, else
 * the source folder the program was built from. */
const char *device_source_dir(void);

#endif
