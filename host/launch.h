/* Kernel-argument helpers shared by the host files that enqueue kernels
 * (launch.c, step.c, ballistics.c, ghost.c): SET_ARGS(kernel, MEM(buf), INT(i), ...)
 * sets every argument and checks each call; real_value and real4_value
 * pass a scalar or a 4-vector in the device precision. */
#ifndef SPH_LAUNCH_H
#define SPH_LAUNCH_H

#include "device.h"
#include "profile.h"
#include "solver.h"

/* Sets the kernel's arguments from a list of (size, pointer) pairs. */
struct arg {
    size_t size;
    const void *value;
    int is_buffer; /* profiling counts the buffer's bytes */
};
#define MEM(m) ((struct arg){sizeof(cl_mem), &(m), 1})
#define INT(i) ((struct arg){sizeof(cl_int), &(i), 0})
#define RAW(size, p) ((struct arg){(size), (p), 0})

/* SET_ARGS(kernel, a, b, ...) sets every argument, counting them itself. */
#define SET_ARGS(k, ...)                                                                           \
    set_args((k), (struct arg[]){__VA_ARGS__},                                                     \
             (int)(sizeof((struct arg[]){__VA_ARGS__}) / sizeof(struct arg)))

/* One buffer argument; a profiling run counts the buffer's bytes. */
static inline void set_buffer_arg(cl_kernel k, cl_uint index, const cl_mem *buffer)
{
    CL_CHECK(clSetKernelArg(k, index, sizeof(cl_mem), buffer));
    profile_note_buffer(*buffer);
}

static inline void set_args(cl_kernel k, const struct arg *args, int count)
{
    for (int a = 0; a < count; ++a) {
        if (args[a].is_buffer)
            set_buffer_arg(k, (cl_uint)a, (const cl_mem *)args[a].value);
        else
            CL_CHECK(clSetKernelArg(k, (cl_uint)a, args[a].size, args[a].value));
    }
}

/* A real scalar argument in the device precision. */
struct real_arg {
    cl_double d;
    cl_float f;
};
static inline struct arg real_value(const struct solver *s, struct real_arg *holder, double v)
{
    holder->d = v;
    holder->f = (cl_float)v;
    return s->double_precision ? RAW(sizeof(cl_double), &holder->d)
                               : RAW(sizeof(cl_float), &holder->f);
}

/* A real4 argument in the device precision. */
struct real4_arg {
    cl_double4 d;
    cl_float4 f;
};
static inline struct arg real4_value(const struct solver *s, struct real4_arg *holder,
                                     const double v[3])
{
    for (int a = 0; a < 4; ++a) {
        holder->d.s[a] = a < 3 ? v[a] : 0.0;
        holder->f.s[a] = (cl_float)holder->d.s[a];
    }
    return s->double_precision ? RAW(sizeof(cl_double4), &holder->d)
                               : RAW(sizeof(cl_float4), &holder->f);
}

#endif
