/* Per-kernel profiling from OpenCL event timestamps (sph run --profile,
 * sph bench). Only a profiling run creates its queue with
 * CL_QUEUE_PROFILING_ENABLE and asks for events, so a normal run pays
 * nothing. Each launch's event is kept until profile_flush, which waits for
 * them and adds end - start to its kernel's total. The bytes of a launch are
 * the sizes of the buffers it takes (as allocated: a kernel that reads part
 * of a buffer, or not every argument, counts more than it moves, one that
 * re-reads neighbours from memory counts less; a rough measure of traffic,
 * not a bound); the flops of the neighbour kernels are
 * the pair interactions times the per-pair count of profile.c's table,
 * counted by hand from the kernel source. */
#ifndef SPH_PROFILE_H
#define SPH_PROFILE_H

#include "device.h"

#define PROFILE_MAX_KERNELS 64
#define PROFILE_PENDING 4096

struct profile_kernel {
    char name[64];
    long calls;
    double device_s; /* sum of end - start, s */
    double bytes;    /* sizes of the buffers given, over all calls, B */
    double flops;    /* estimated floating-point operations over all calls */
};

struct profiler {
    struct profile_kernel kernels[PROFILE_MAX_KERNELS];
    int kernel_count;
    cl_event pending[PROFILE_PENDING];
    int pending_kernel[PROFILE_PENDING];
    int pending_count;
    double pairs_per_call; /* pair interactions of one neighbour pass (sum over i) */
    double wall_s;         /* host clock over the profiled stepping, s */
    double host_output_s;  /* of which writing snapshots and history, less their kernels, s */
};

/* Device ceilings measured by the probe kernels (kernels/probe.cl). */
struct device_ceilings {
    double bandwidth_gb_s; /* copy kernel: (read + write) bytes / s / 1e9 */
    double gflop_s;        /* FMA chains: 2 flops per FMA */
};

/* Profiling state of the running process: NULL unless profiling. */
extern struct profiler *sph_profiler;

/* Called by the argument setters: adds a buffer argument's size to the
 * bytes of the next launch. */
void profile_note_buffer(cl_mem buffer);

/* Called by the launcher with the launch's event (owned from then on). */
void profile_record(cl_kernel kernel, cl_event event);

/* Waits for the pending events and adds their times to the table. */
void profile_flush(struct profiler *p);

/* The host's monotonic clock, s. */
double profile_clock(void);

/* Total device time over all kernels, s. */
double profile_device_seconds(const struct profiler *p);

/* Prints the per-kernel table: calls, time per call, share of the device
 * time, GB/s and GFLOP/s, and their fractions of the ceilings when known
 * (ceilings may be NULL). `steps` scales the per-step column. */
void profile_print(const struct profiler *p, const struct device_ceilings *ceilings, long steps,
                   FILE *out);

/* Writes the table as a JSON array (no trailing newline). */
void profile_write_json(const struct profiler *p, long steps, FILE *out);

/* Measures the ceilings with the probe kernels of dev's program, or reads
 * them from the user cache folder when this device was measured before.
 * Returns 0, or non-zero with `error`. */
int device_ceilings(struct sph_device *dev, struct device_ceilings *out, char *error,
                    size_t error_size);

#endif
