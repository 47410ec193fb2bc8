/* Device ceilings (profile.h): the probe kernels of kernels/probe.cl timed
 * on the host clock, best of five, cached per device in the user cache. */
#include "profile.h"

#include <stdlib.h>
#include <string.h>

#define COPY_BYTES (64u << 20) /* per buffer: far beyond any CPU cache */
#define FMA_ITEMS (1u << 16)
#define FMA_ITERATIONS 1000
#define REPEATS 5

/* Best-of-REPEATS time of one launch of k over `items` work-items, s. */
static double best_time(struct sph_device *dev, cl_kernel k, size_t items)
{
    const size_t local = 64;
    double best = 1e30;
    for (int r = 0; r <= REPEATS; ++r) { /* the first is a warm-up */
        const double t0 = profile_clock();
        CL_CHECK(clEnqueueNDRangeKernel(dev->queue, k, 1, NULL, &items, &local, 0, NULL, NULL));
        CL_CHECK(clFinish(dev->queue));
        const double t = profile_clock() - t0;
        if (r > 0 && t < best)
            best = t;
    }
    return best;
}

static double measure_bandwidth(struct sph_device *dev, cl_kernel copy)
{
    cl_int err = CL_SUCCESS;
    cl_mem in = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, COPY_BYTES, NULL, &err);
    CL_CHECK_ERR("clCreateBuffer(probe in)", err);
    cl_mem out = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, COPY_BYTES, NULL, &err);
    CL_CHECK_ERR("clCreateBuffer(probe out)", err);
    const cl_float zero = 0;
    CL_CHECK(clEnqueueFillBuffer(dev->queue, in, &zero, sizeof zero, 0, COPY_BYTES, 0, NULL, NULL));
    CL_CHECK(clSetKernelArg(copy, 0, sizeof in, &in));
    CL_CHECK(clSetKernelArg(copy, 1, sizeof out, &out));
    const double t = best_time(dev, copy, COPY_BYTES / sizeof(cl_float4));
    clReleaseMemObject(out);
    clReleaseMemObject(in);
    return 2.0 * COPY_BYTES / t / 1e9;
}

static double measure_fma(struct sph_device *dev, cl_kernel fma)
{
    cl_int err = CL_SUCCESS;
    cl_mem out =
        clCreateBuffer(dev->context, CL_MEM_WRITE_ONLY, FMA_ITEMS * sizeof(cl_float), NULL, &err);
    CL_CHECK_ERR("clCreateBuffer(probe fma)", err);
    const cl_int iterations = FMA_ITERATIONS;
    const cl_float seed = 1.0f;
    CL_CHECK(clSetKernelArg(fma, 0, sizeof out, &out));
    CL_CHECK(clSetKernelArg(fma, 1, sizeof iterations, &iterations));
    CL_CHECK(clSetKernelArg(fma, 2, sizeof seed, &seed));
    const double t = best_time(dev, fma, FMA_ITEMS);
    clReleaseMemObject(out);
    return 192.0 * FMA_ITEMS * FMA_ITERATIONS / t / 1e9;
}

int device_ceilings(struct sph_device *dev, struct device_ceilings *out, char *error,
                    size_t error_size)
{
    char path[1200];
    device_cache_file(dev, "ceilings", "", "", "txt", path, sizeof path);
    FILE *f = fopen(path, "r");
    if (f) {
        const int got = fscanf(f, "%lf %lf", &out->bandwidth_gb_s, &out->gflop_s);
        fclose(f);
        if (got == 2 && out->bandwidth_gb_s > 0 && out->gflop_s > 0)
            return 0;
    }
    cl_int err = CL_SUCCESS;
    cl_kernel copy = clCreateKernel(dev->program, "probe_copy", &err);
    CL_CHECK_ERR("clCreateKernel(probe_copy)", err);
    cl_kernel fma = clCreateKernel(dev->program, "probe_fma", &err);
    CL_CHECK_ERR("clCreateKernel(probe_fma)", err);
    out->bandwidth_gb_s = measure_bandwidth(dev, copy);
    out->gflop_s = measure_fma(dev, fma);
    clReleaseKernel(fma);
    clReleaseKernel(copy);
    if (!(out->bandwidth_gb_s > 0 && out->gflop_s > 0)) {
        snprintf(error, error_size, "the device probe measured no bandwidth or throughput");
        return 1;
    }
    device_make_parent_dirs(path);
    f = fopen(path, "w");
    if (f) { /* a cache that cannot be written only costs a re-measurement */
        fprintf(f, "%.6g %.6g\n# GB/s (copy, read + write), GFLOP/s (float FMA) of %s\n",
                out->bandwidth_gb_s, out->gflop_s, dev->name);
        fclose(f);
    }
    return 0;
}
