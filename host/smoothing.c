/* The device's smoothing kernels, compiled on the host from the same file
 * (kernels/smoothing.cl is written in the common subset of C and OpenCL C). */
#include <math.h>

#include "sph_shared.h"
#include "../kernels/smoothing.cl"

double sph_support_q(int kernel)
{
    return sph_kernel_support_q(kernel);
}

double sph_kernel_w_host(int kernel, int dim, double r, double h)
{
    return sph_kernel_value(kernel, dim, (real)r, (real)h);
}
