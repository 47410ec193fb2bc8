/* Per-kernel profiling from OpenCL events (see profile.h). */
#include "profile.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

struct profiler *sph_profiler = NULL;

static double next_launch_bytes = 0; /* buffers noted since the last launch, B */

/* Floating-point operations per pair interaction of the neighbour kernels,
 * counted by hand from the kernel source for a 3-D run with CSPH and XSPH
 * (an FMA counts 2, a division or square root 1; the distance test of a
 * rejected candidate is not counted). The other kernels are memory-bound
 * and report bytes only. */
static const struct {
    const char *kernel;
    double flops_per_pair;
} pair_flops[] = {
    {"pass1_velocity_gradient", 84}, /* gradient, velocity gradient, CSPH moment */
    {"pass2_momentum_energy", 170},  /* stresses, CSPH, viscosity, XSPH */
    {"tl_deformation", 84},          {"tl_momentum", 120},
    {"tl_correction", 45},           {"health_pairs", 30},
    {"health_neighbour_count", 10},
};

void profile_note_buffer(cl_mem buffer)
{
    if (!sph_profiler || !buffer)
        return;
    size_t size = 0;
    if (clGetMemObjectInfo(buffer, CL_MEM_SIZE, sizeof size, &size, NULL) == CL_SUCCESS)
        next_launch_bytes += (double)size;
}

static int kernel_slot(struct profiler *p, cl_kernel kernel)
{
    char name[64] = "?";
    CL_CHECK(clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, sizeof name, name, NULL));
    for (int k = 0; k < p->kernel_count; ++k)
        if (strcmp(p->kernels[k].name, name) == 0)
            return k;
    if (p->kernel_count == PROFILE_MAX_KERNELS)
        return PROFILE_MAX_KERNELS - 1; /* more kernels than the table holds: pooled */
    struct profile_kernel *e = &p->kernels[p->kernel_count];
    memset(e, 0, sizeof *e);
    snprintf(e->name, sizeof e->name, "%s", name);
    return p->kernel_count++;
}

static double flops_per_pair(const char *name)
{
    for (size_t k = 0; k < sizeof pair_flops / sizeof pair_flops[0]; ++k)
        if (strcmp(pair_flops[k].kernel, name) == 0)
            return pair_flops[k].flops_per_pair;
    return 0;
}

void profile_record(cl_kernel kernel, cl_event event)
{
    struct profiler *p = sph_profiler;
    if (p->pending_count == PROFILE_PENDING)
        profile_flush(p);
    const int slot = kernel_slot(p, kernel);
    struct profile_kernel *e = &p->kernels[slot];
    e->calls++;
    e->bytes += next_launch_bytes;
    e->flops += flops_per_pair(e->name) * p->pairs_per_call;
    next_launch_bytes = 0;
    p->pending[p->pending_count] = event;
    p->pending_kernel[p->pending_count++] = slot;
}

void profile_flush(struct profiler *p)
{
    if (p->pending_count == 0)
        return;
    CL_CHECK(clWaitForEvents((cl_uint)p->pending_count, p->pending));
    for (int k = 0; k < p->pending_count; ++k) {
        cl_ulong start = 0, end = 0;
        CL_CHECK(clGetEventProfilingInfo(p->pending[k], CL_PROFILING_COMMAND_START, sizeof start,
                                         &start, NULL));
        CL_CHECK(clGetEventProfilingInfo(p->pending[k], CL_PROFILING_COMMAND_END, sizeof end, &end,
                                         NULL));
        p->kernels[p->pending_kernel[k]].device_s += 1e-9 * (double)(end - start);
        clReleaseEvent(p->pending[k]);
    }
    p->pending_count = 0;
}

double profile_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double profile_device_seconds(const struct profiler *p)
{
    double total = 0;
    for (int k = 0; k < p->kernel_count; ++k)
        total += p->kernels[k].device_s;
    return total;
}

static int by_time_descending(const void *a, const void *b)
{
    const double ta = ((const struct profile_kernel *)a)->device_s;
    const double tb = ((const struct profile_kernel *)b)->device_s;
    return (ta < tb) - (ta > tb);
}

/* The kernels sorted by device time, longest first, into rows (room for
 * PROFILE_MAX_KERNELS). */
static struct profile_kernel *sorted(const struct profiler *p, struct profile_kernel *rows)
{
    memcpy(rows, p->kernels, sizeof *rows * (size_t)p->kernel_count);
    qsort(rows, (size_t)p->kernel_count, sizeof *rows, by_time_descending);
    return rows;
}

void profile_print(const struct profiler *p, const struct device_ceilings *ceilings, long steps,
                   FILE *out)
{
    const double total = profile_device_seconds(p);
    struct profile_kernel sorted_rows[PROFILE_MAX_KERNELS];
    const struct profile_kernel *rows = sorted(p, sorted_rows);
    fprintf(out, "%-28s %8s %10s %10s %6s %8s %6s %8s %6s\n", "kernel", "calls", "us/call",
            "ms/step", "share", "GB/s", "%bw", "GFLOP/s", "%peak");
    for (int k = 0; k < p->kernel_count; ++k) {
        const struct profile_kernel *e = &rows[k];
        const double gb = e->device_s > 0 ? e->bytes / e->device_s / 1e9 : 0;
        const double gf = e->device_s > 0 ? e->flops / e->device_s / 1e9 : 0;
        fprintf(out, "%-28s %8ld %10.1f %10.3f %5.1f%% %8.2f", e->name, e->calls,
                1e6 * e->device_s / (double)(e->calls ? e->calls : 1),
                1e3 * e->device_s / (double)(steps > 0 ? steps : 1),
                total > 0 ? 100 * e->device_s / total : 0, gb);
        if (ceilings && ceilings->bandwidth_gb_s > 0)
            fprintf(out, " %5.1f%%", 100 * gb / ceilings->bandwidth_gb_s);
        else
            fprintf(out, " %6s", "-");
        if (e->flops > 0)
            fprintf(out, " %8.2f", gf);
        else
            fprintf(out, " %8s", "-");
        if (e->flops > 0 && ceilings && ceilings->gflop_s > 0)
            fprintf(out, " %5.1f%%\n", 100 * gf / ceilings->gflop_s);
        else
            fprintf(out, " %6s\n", "-");
    }
    fprintf(out, "%-28s %8s %10s %10.3f\n", "device total", "", "",
            1e3 * total / (double)(steps > 0 ? steps : 1));
    if (p->wall_s > 0)
        fprintf(out,
                "wall %.3f s: kernels %.3f s (%.1f%%), output %.3f s, the rest (launches, "
                "read-backs, host work, idle device) %.3f s\n",
                p->wall_s, total, 100 * total / p->wall_s, p->host_output_s,
                p->wall_s - total - p->host_output_s);
}

void profile_write_json(const struct profiler *p, long steps, FILE *out)
{
    struct profile_kernel sorted_rows[PROFILE_MAX_KERNELS];
    const struct profile_kernel *rows = sorted(p, sorted_rows);
    const double total = profile_device_seconds(p);
    fprintf(out, "[");
    for (int k = 0; k < p->kernel_count; ++k) {
        const struct profile_kernel *e = &rows[k];
        fprintf(out,
                "%s\n    {\"kernel\": \"%s\", \"calls\": %ld, \"device_s\": %.9g, "
                "\"s_per_call\": %.9g, \"s_per_step\": %.9g, \"share\": %.6f, \"bytes\": %.9g, "
                "\"gb_per_s\": %.6g, \"flops\": %.9g, \"gflop_per_s\": %.6g}",
                k ? "," : "", e->name, e->calls, e->device_s,
                e->device_s / (double)(e->calls ? e->calls : 1),
                e->device_s / (double)(steps > 0 ? steps : 1),
                total > 0 ? e->device_s / total : 0.0, e->bytes,
                e->device_s > 0 ? e->bytes / e->device_s / 1e9 : 0.0, e->flops,
                e->device_s > 0 ? e->flops / e->device_s / 1e9 : 0.0);
    }
    fprintf(out, "\n  ]");
}
