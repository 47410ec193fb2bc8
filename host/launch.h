/* Kernel-argument helpers shared by the host files that enqueue kernels
 * (launch.c, step.c, ballistics.c, ghost.c): SET_ARGS(s, kernel,
 * MEM("name", buf), INT("n", i), ...) binds every argument by name and
 * checks each call; real_value and real4_value pass a scalar or a 4-vector
 * in the device precision. */
#ifndef SPH_LAUNCH_H
#define SPH_LAUNCH_H

#include "device.h"
#include "profile.h"
#include "solver.h"

/* A value for the kernel argument of that name. */
struct arg {
    size_t size;
    const void *value;
    int is_buffer; /* profiling counts the buffer's bytes */
    const char *name;
};
#define MEM(name, m) ((struct arg){sizeof(cl_mem), &(m), 1, (name)})
#define INT(name, i) ((struct arg){sizeof(cl_int), &(i), 0, (name)})
#define RAW(name, size, p) ((struct arg){(size), (p), 0, (name)})

/* SET_ARGS(s, kernel, a, b, ...) binds every argument of the kernel by the
 * name the kernel declares it with (host/launch.c, set_args): a value given
 * by that name, else the particle field of that name in the registry
 * (field_table[].arg), else the solver's own (run, materials, walls,
 * wall_count, the grid), so a call lists only what is particular to it. An
 * argument with none of these, a given value the kernel does not take, or
 * one given for a field or solver argument, is a failure that names the
 * kernel and the argument. */
#define SET_ARGS(s, k, ...)                                                                        \
    set_args((s), (k), (struct arg[]){__VA_ARGS__},                                                \
             (int)(sizeof((struct arg[]){__VA_ARGS__}) / sizeof(struct arg)))
void set_args(const struct solver *s, cl_kernel k, const struct arg *args, int count);

/* A real scalar argument in the device precision. */
struct real_arg {
    cl_double d;
    cl_float f;
};
static inline struct arg real_value(const struct solver *s, struct real_arg *holder,
                                    const char *name, double v)
{
    holder->d = v;
    holder->f = (cl_float)v;
    return s->double_precision ? RAW(name, sizeof(cl_double), &holder->d)
                               : RAW(name, sizeof(cl_float), &holder->f);
}

/* A real4 argument in the device precision. */
struct real4_arg {
    cl_double4 d;
    cl_float4 f;
};
static inline struct arg real4_value(const struct solver *s, struct real4_arg *holder,
                                     const char *name, const double v[3])
{
    for (int a = 0; a < 4; ++a) {
        holder->d.s[a] = a < 3 ? v[a] : 0.0;
        holder->f.s[a] = (cl_float)holder->d.s[a];
    }
    return s->double_precision ? RAW(name, sizeof(cl_double4), &holder->d)
                               : RAW(name, sizeof(cl_float4), &holder->f);
}

#endif
