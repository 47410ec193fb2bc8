/* The launch core, below everything that enqueues kernels: make a kernel,
 * launch it (timed when profiling), sort the keys, gather the persistent
 * fields into the sorted order. step.c (the step), ghost.c (symmetry
 * planes) and ballistics.c (the projectile) build on it; it calls none of
 * them. */
#include "launch.h"
#include "solver.h"

#include <stdio.h>

#define LOCAL_SIZE 64

static size_t round_up(size_t n, size_t m)
{
    return (n + m - 1) / m * m;
}

cl_kernel solver_make_kernel(struct solver *s, const char *name)
{
    if (cl_failed())
        return NULL;
    cl_int err = CL_SUCCESS;
    cl_kernel k = clCreateKernel(s->dev->program, name, &err);
    if (cl_checked(err) != CL_SUCCESS) {
        char call[160];
        snprintf(call, sizeof call, "clCreateKernel(%s)", name);
        cl_fail(call, err != CL_SUCCESS ? err : CL_OUT_OF_RESOURCES, __FILE__, __LINE__);
    }
    return k;
}

void solver_make_kernels(struct solver *s, const struct kernel_slot *slots, int count)
{
    for (int k = 0; k < count; ++k)
        *slots[k].kernel = slots[k].name ? solver_make_kernel(s, slots[k].name) : NULL;
}

void solver_release_kernels(const struct kernel_slot *slots, int count)
{
    for (int k = 0; k < count; ++k) {
        if (*slots[k].kernel)
            clReleaseKernel(*slots[k].kernel);
        *slots[k].kernel = NULL;
    }
}

void solver_launch(struct solver *s, cl_kernel k, size_t global, size_t local)
{
    /* an explicit work-group size: PoCL's own choice for a NULL size costs
     * far more per launch on a CPU */
    const size_t l = local ? local : LOCAL_SIZE;
    const size_t g = round_up(global ? global : 1, l);
    if (cl_failed()) /* the run is unwinding (host/device.h) */
        return;
    cl_event event = NULL;
    const cl_int err = cl_checked(clEnqueueNDRangeKernel(s->dev->queue, k, 1, NULL, &g, &l, 0, NULL,
                                                         sph_profiler ? &event : NULL));
    if (err != CL_SUCCESS) {
        char name[128] = "?";
        clGetKernelInfo(k, CL_KERNEL_FUNCTION_NAME, sizeof name, name, NULL);
        char call[200];
        snprintf(call, sizeof call, "clEnqueueNDRangeKernel(%s, %zu work-items)", name, g);
        cl_fail(call, err, __FILE__, __LINE__);
        if (event)
            clReleaseEvent(event);
        return;
    }
    if (sph_profiler)
        profile_record(k, event);
}

void solver_bitonic_sort(struct solver *s)
{
    /* bitonic network over the next power of two N >= n, log2(N) (log2(N)
     * + 1) / 2 compare-exchange stages, the keys past n virtual
     * (kernels/grid.cl) */
    const cl_uint n = (cl_uint)s->n;
    for (cl_uint k = 2; k / 2 < n; k <<= 1)
        for (cl_uint j = k >> 1; j > 0; j >>= 1) {
            const cl_int flip = j == k >> 1;
            SET_ARGS(s->k.bitonic_step, MEM(s->sort_keys), RAW(sizeof j, &j), INT(flip),
                     RAW(sizeof n, &n));
            solver_launch(s, s->k.bitonic_step, (size_t)s->n, 0);
        }
}

void solver_gather_persistent(struct solver *s)
{
    for (int f = 0; f < FIELD_PERSISTENT_END; ++f) {
        if (!solver_field_used(s, (enum field)f))
            continue;
        const enum element_kind kind = field_table[f].kind;
        SET_ARGS(s->k.gather[kind], MEM(s->sort_keys), MEM(s->field[f]), MEM(s->gather_spare),
                 INT(s->n));
        solver_launch(s, s->k.gather[kind], (size_t)s->n, 0);
        /* one spare for every field (not one per element kind, swapped in):
         * the copy back costs a read and a write per sort, the spares
         * would cost 56 B per particle in 3-D */
        CL_CHECK(clEnqueueCopyBuffer(s->dev->queue, s->gather_spare, s->field[f], 0, 0,
                                     s->element_size[kind] * (size_t)s->n, 0, NULL, NULL));
    }
}
