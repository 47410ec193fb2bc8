/* The launch core, below everything that enqueues kernels: make a kernel,
 * launch it (timed when profiling), sort the keys, gather the persistent
 * fields into the sorted order. step.c (the step), ghost.c (symmetry
 * planes) and ballistics.c (the projectile) build on it; it calls none of
 * them. */
#include "launch.h"
#include "solver.h"

#include <stdio.h>
#include <string.h>

#define LOCAL_SIZE 64

static size_t round_up(size_t n, size_t m)
{
    return (n + m - 1) / m * m;
}

/* The names a kernel declares its arguments with (the program is built
 * with -cl-kernel-arg-info; host/device.c rebuilds a cached binary that lost
 * them), read once when the kernel is made, with the registry's field of
 * each name found then. */
#define MAX_KERNEL_ARGS 40
#define MAX_ARG_NAME 32
#define MAX_SIGNATURES 96 /* a solver makes 36 kernels */
struct signature {
    cl_kernel kernel; /* NULL: a free slot */
    char function[64];
    int count;
    char name[MAX_KERNEL_ARGS][MAX_ARG_NAME];
    int field[MAX_KERNEL_ARGS]; /* the registry's field of that name, or -1 */
};
static struct signature signatures[MAX_SIGNATURES];

static struct signature *signature_slot(cl_kernel k)
{
    for (int i = 0; i < MAX_SIGNATURES; ++i)
        if (signatures[i].kernel == k)
            return &signatures[i];
    return NULL;
}

static void fail_binding(const char *what, const char *function, const char *arg)
{
    char message[200];
    snprintf(message, sizeof message, "binding the arguments of kernel %s: %s `%s`", function, what,
             arg);
    device_fail(message, __FILE__, __LINE__);
}

static void read_signature(cl_kernel k, const char *function)
{
    struct signature *sig = signature_slot(NULL);
    cl_uint count = 0;
    if (!sig) {
        fail_binding("more kernels than MAX_SIGNATURES", function, "");
        return;
    }
    CL_CHECK(clGetKernelInfo(k, CL_KERNEL_NUM_ARGS, sizeof count, &count, NULL));
    if (count > MAX_KERNEL_ARGS) {
        fail_binding("more arguments than MAX_KERNEL_ARGS", function, "");
        return;
    }
    for (cl_uint a = 0; a < count; ++a) {
        CL_CHECK(clGetKernelArgInfo(k, a, CL_KERNEL_ARG_NAME, MAX_ARG_NAME, sig->name[a], NULL));
        sig->field[a] = -1;
        for (int f = 0; f < FIELD_COUNT; ++f)
            if (strcmp(field_table[f].arg, sig->name[a]) == 0)
                sig->field[a] = f;
    }
    if (cl_failed())
        return;
    sig->kernel = k;
    snprintf(sig->function, sizeof sig->function, "%s", function);
    sig->count = (int)count;
}

/* Arguments that belong to the solver rather than to one launch (the run
 * parameters, materials, walls and the neighbour grid), bound by name like
 * the fields. The grid's origin and inverse cell size are converted to the
 * device precision here; clSetKernelArg copies them at once, so one static
 * holder serves every launch. */
static int solver_value(const struct solver *s, const char *name, struct arg *out)
{
    static struct real4_arg grid_origin;
    static struct real_arg grid_inv_cell_size;
    const struct arg values[] = {
        real4_value(s, &grid_origin, "grid_origin", s->grid.origin),
        real_value(s, &grid_inv_cell_size, "grid_inv_cell_size", 1.0 / s->grid.cell_size),
        MEM("run", s->run_params),
        MEM("materials", s->materials),
        MEM("walls", s->walls),
        INT("wall_count", s->wall_count),
        MEM("sort_keys", s->sort_keys),
        MEM("cell_start", s->cell_start),
        MEM("cell_end", s->cell_end),
        MEM("contact_keys", s->contact_keys),
        MEM("contact_cell_start", s->contact_cell_start),
        MEM("contact_cell_end", s->contact_cell_end),
        MEM("contact_cell_part_bits", s->contact_cell_part_bits),
        MEM("cell_level", s->cell_level),
        MEM("lane_list_range", s->lane_list_range),
        MEM("lane_list", s->lane_list),
        MEM("projectile_state", s->projectile.state),
        RAW("grid_dims", sizeof s->grid.dims4, &s->grid.dims4),
    };
    for (size_t v = 0; v < sizeof values / sizeof values[0]; ++v)
        if (strcmp(values[v].name, name) == 0) {
            *out = values[v];
            return 1;
        }
    return 0;
}

/* The value of argument a: the one given by its name, else the particle
 * field the registry names so (field_table[].arg), else the solver's. A
 * given value may not stand in for a field or a solver value (the same
 * name meaning two buffers is what binding by name rules out). */
static int find_value(const struct solver *s, const struct signature *sig, int a,
                      const struct arg *args, int count, struct arg *out)
{
    for (int v = 0; v < count; ++v)
        if (strcmp(args[v].name, sig->name[a]) == 0) {
            struct arg other;
            if (sig->field[a] >= 0 || solver_value(s, sig->name[a], &other)) {
                fail_binding("given a value for the field or solver argument", sig->function,
                             sig->name[a]);
                return 0;
            }
            *out = args[v];
            return 1;
        }
    if (sig->field[a] >= 0) {
        *out = (struct arg){sizeof(cl_mem), &s->field[sig->field[a]], 1, sig->name[a]};
        return 1;
    }
    if (solver_value(s, sig->name[a], out))
        return 1;
    fail_binding("no field, solver value or given value for argument", sig->function, sig->name[a]);
    return 0;
}

void set_args(const struct solver *s, cl_kernel k, const struct arg *args, int count)
{
    if (cl_failed())
        return;
    const struct signature *sig = k ? signature_slot(k) : NULL;
    if (!sig) {
        fail_binding("no signature (a kernel not made by solver_kernels)", "?", "");
        return;
    }
    for (int a = 0; a < sig->count; ++a) {
        struct arg value;
        if (!find_value(s, sig, a, args, count, &value))
            return;
        CL_CHECK(clSetKernelArg(k, (cl_uint)a, value.size, value.value));
        if (value.is_buffer)
            profile_note_buffer(*(const cl_mem *)value.value);
    }
    for (int v = 0; v < count; ++v) {
        int taken = 0;
        for (int a = 0; a < sig->count && !taken; ++a)
            taken = strcmp(args[v].name, sig->name[a]) == 0;
        if (!taken) {
            fail_binding("takes no argument", sig->function, args[v].name);
            return;
        }
    }
}

static const char *const element_suffix[ELEM_COUNT] = {[ELEM_REAL] = "real",
                                                       [ELEM_INT] = "int",
                                                       [ELEM_VEC] = "vec",
                                                       [ELEM_SYMT] = "symt",
                                                       [ELEM_FULLT] = "fullt"};

static cl_kernel make_kernel(struct solver *s, const char *name)
{
    if (cl_failed())
        return NULL;
    cl_int err = CL_SUCCESS;
    cl_kernel k = clCreateKernel(s->dev->program, name, &err);
    if (cl_checked(err) != CL_SUCCESS) {
        char call[160];
        snprintf(call, sizeof call, "clCreateKernel(%s)", name);
        cl_fail(call, err != CL_SUCCESS ? err : CL_OUT_OF_RESOURCES, __FILE__, __LINE__);
        return k;
    }
    read_signature(k, name);
    return k;
}

static void release_kernel(cl_kernel *k)
{
    if (*k) {
        struct signature *sig = signature_slot(*k);
        if (sig)
            memset(sig, 0, sizeof *sig);
        clReleaseKernel(*k);
    }
    *k = NULL;
}

static void make_kernels(struct solver *s, const struct kernel_slot *slots, int count)
{
    for (int k = 0; k < count; ++k) {
        if (!slots[k].per_element) {
            *slots[k].kernel = slots[k].name ? make_kernel(s, slots[k].name) : NULL;
            continue;
        }
        for (int e = 0; e < ELEM_COUNT; ++e) {
            char name[96];
            snprintf(name, sizeof name, "%s_%s", slots[k].name, element_suffix[e]);
            slots[k].kernel[e] = make_kernel(s, name);
        }
    }
}

void solver_kernels(struct solver *s, const struct kernel_slot *slots, int count, int make)
{
    if (make) {
        make_kernels(s, slots, count);
        return;
    }
    for (int k = 0; k < count; ++k)
        for (int e = 0; e < (slots[k].per_element ? ELEM_COUNT : 1); ++e)
            release_kernel(&slots[k].kernel[e]);
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

void solver_exclusive_scan(struct solver *s, cl_mem counts, int count, cl_mem block_totals)
{
    const cl_int blocks = (count + SPH_SCAN_BLOCK - 1) / SPH_SCAN_BLOCK;
    SET_ARGS(s, s->k.bucket_block_total, MEM("bucket", counts), MEM("block_total", block_totals),
             INT("buckets", count));
    solver_launch(s, s->k.bucket_block_total, (size_t)blocks, 0);
    SET_ARGS(s, s->k.bucket_block_offsets, MEM("block_total", block_totals), INT("blocks", blocks));
    solver_launch(s, s->k.bucket_block_offsets, 1, 0);
    SET_ARGS(s, s->k.bucket_block_scan, MEM("bucket", counts), MEM("block_total", block_totals),
             INT("buckets", count));
    solver_launch(s, s->k.bucket_block_scan, (size_t)blocks, 0);
}

void solver_sort_keys(struct solver *s, cl_mem keys, int buckets)
{
    if (buckets > s->sort_bucket_capacity) {
        solver_release_buffer(&s->sort_buckets);
        solver_release_buffer(&s->sort_block_totals);
        s->sort_bucket_capacity = buckets + buckets / 4;
        const size_t blocks = (size_t)s->sort_bucket_capacity / SPH_SCAN_BLOCK + 1;
        s->sort_buckets = solver_create_buffer(s, sizeof(cl_int) * (size_t)s->sort_bucket_capacity);
        s->sort_block_totals = solver_create_buffer(s, sizeof(cl_int) * blocks);
    }
    const cl_int zero = 0;
    /* the gather spare (8 B or more per slot) is free until the gathers */
    SET_ARGS(s, s->k.fill_int, MEM("a", s->sort_buckets), INT("value", zero), INT("n", buckets));
    solver_launch(s, s->k.fill_int, (size_t)buckets, 0);
    SET_ARGS(s, s->k.bucket_count, MEM("keys", keys), MEM("bucket", s->sort_buckets),
             INT("n", s->n));
    solver_launch(s, s->k.bucket_count, (size_t)s->n, 0);
    solver_exclusive_scan(s, s->sort_buckets, buckets, s->sort_block_totals);
    SET_ARGS(s, s->k.bucket_scatter, MEM("keys", keys), MEM("bucket", s->sort_buckets),
             MEM("scattered", s->gather_spare), INT("n", s->n));
    solver_launch(s, s->k.bucket_scatter, (size_t)s->n, 0);
    SET_ARGS(s, s->k.bucket_order, MEM("scattered", s->gather_spare),
             MEM("bucket", s->sort_buckets), MEM("keys", keys), INT("buckets", buckets));
    solver_launch(s, s->k.bucket_order, (size_t)buckets, 0);
}

void solver_gather_persistent(struct solver *s)
{
    for (int f = 0; f < FIELD_COUNT; ++f) {
        if (!field_table[f].persistent || !solver_field_used(s, (enum field)f))
            continue;
        const enum element_kind kind = field_table[f].kind;
        SET_ARGS(s, s->k.gather[kind], MEM("in", s->field[f]), MEM("out", s->gather_spare),
                 INT("n", s->n));
        solver_launch(s, s->k.gather[kind], (size_t)s->n, 0);
        /* one spare for every field (not one per element kind, swapped in):
         * the copy back costs a read and a write per sort, the spares
         * would cost 56 B per particle in 3-D */
        SET_ARGS(s, s->k.copy[kind], MEM("in", s->gather_spare), MEM("out", s->field[f]),
                 INT("n", s->n));
        solver_launch(s, s->k.copy[kind], (size_t)s->n, 0);
    }
}
