/*
 * Smoothing kernels W(r, h) and dW/dr, normalised in 1-, 2- and 3-D.
 *
 * Written in the common subset of C11 and OpenCL C so the unit tests compile
 * this very file on the host and check normalisation and gradient moments
 * (tests/test_smoothing.c); on the device the shapes run on lane vectors
 * (below) and the kernel type and dimension are compile-time constants, so
 * the switches fold away.
 *
 * Shapes: thesis Fig. 3.1 and shared/REFERENCES.md 4. The normalisation
 * constants sigma_d below are derived here (the thesis table has misprints):
 * sigma_d = 1 / integral of the shape over R^d in units of h.
 *   cubic B-spline (Monaghan & Lattanzio 1985), support 2h:
 *     1D 2/3, 2D 10/(7 pi), 3D 1/pi
 *   Gaussian cut at q = 3 and shifted by its value there, exp(-q^2) - e^-9,
 *   so that W is continuous and the first moment of grad W is exactly the
 *   identity (a bare cut leaves a 1e-3 surface term):
 *     1D 1/(sqrt(pi) erf 3 - 6 e^-9), 2D 1/(pi (1 - 10 e^-9)),
 *     3D 1/(pi^1.5 erf 3 - 42 pi e^-9)
 *   quintic B-spline (Morris 1996), support 3h:
 *     1D 1/120, 2D 7/(478 pi), 3D 1/(120 pi)
 *   Wendland C2 (1 - q/2)^4 (2q + 1), support 2h:
 *     1D 3/4, 2D 7/(4 pi), 3D 21/(16 pi)
 *   double-cosine 4 cos(pi q/k) + cos(2 pi q/k) + 3 with k = 2 (Yang et al.
 *   2014), support 2h:
 *     1D 1/(6k), 2D 1/(pi k^2 (3 - 16/pi^2)), 3D 1/(4 pi k^3 (1 - 7.5/pi^2))
 *   hyperbolic-shaped q^3 - 6q + 6 (q <= 1), (2 - q)^3 (1 < q <= 2)
 *   (Yang et al. 2014), support 2h:
 *     1D 1/7, 2D 1/(3 pi), 3D 15/(62 pi)
 */
#ifndef SPH_SMOOTHING_CL
#define SPH_SMOOTHING_CL

#define SPH_PI 3.14159265358979323846
/* erf(3) and exp(-9), for the cut Gaussian */
#define SPH_ERF3 0.99997790950300141456
#define SPH_EXPM9 1.2340980408667954950e-4
#define SPH_DOUBLE_COSINE_K 2.0

/* Support radius in units of h. */
static inline real sph_kernel_support_q(int type)
{
    return (type == SPH_KERNEL_GAUSSIAN || type == SPH_KERNEL_QUINTIC_SPLINE) ? (real)3 : (real)2;
}

/* sigma_d: the normalisation constant times h^d. */
static inline real sph_kernel_sigma(int type, int dim)
{
    const real pi = (real)SPH_PI;
    const real k = (real)SPH_DOUBLE_COSINE_K;
    switch (type) {
    case SPH_KERNEL_CUBIC_SPLINE:
        return dim == 1 ? (real)(2.0 / 3.0) : dim == 2 ? (real)10 / ((real)7 * pi) : (real)1 / pi;
    case SPH_KERNEL_GAUSSIAN:
        return dim == 1 ? (real)1 / (sqrt(pi) * (real)SPH_ERF3 - (real)6 * (real)SPH_EXPM9)
               : dim == 2
                   ? (real)1 / (pi * ((real)1 - (real)10 * (real)SPH_EXPM9))
                   : (real)1 / (pi * sqrt(pi) * (real)SPH_ERF3 - (real)42 * pi * (real)SPH_EXPM9);
    case SPH_KERNEL_QUINTIC_SPLINE:
        return dim == 1   ? (real)1 / (real)120
               : dim == 2 ? (real)7 / ((real)478 * pi)
                          : (real)1 / ((real)120 * pi);
    case SPH_KERNEL_WENDLAND_C2:
        return dim == 1   ? (real)0.75
               : dim == 2 ? (real)7 / ((real)4 * pi)
                          : (real)21 / ((real)16 * pi);
    case SPH_KERNEL_DOUBLE_COSINE:
        return dim == 1 ? (real)1 / ((real)6 * k)
               : dim == 2
                   ? (real)1 / (pi * k * k * ((real)3 - (real)16 / (pi * pi)))
                   : (real)1 / ((real)4 * pi * k * k * k * ((real)1 - (real)7.5 / (pi * pi)));
    default: /* SPH_KERNEL_HYPERBOLIC */
        return dim == 1   ? (real)1 / (real)7
               : dim == 2 ? (real)1 / ((real)3 * pi)
                          : (real)15 / ((real)62 * pi);
    }
}

/* The shapes are written once, for one value or a lane vector of them
 * (realv, kernels/lane_types.cl): branch-free, with SPH_SELECT(a, b, c) =
 * c ? b : a per lane. Compiled as C (host/smoothing.c, the unit tests)
 * realv is a real. On the device `type` is the build's SPH_KERNEL, so one
 * branch survives. */
#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
/* the cast: a one-lane comparison is an int, which select's double form
 * cannot take unambiguously */
#define SPH_SELECT(a, b, c) select(a, b, (maskv)(c))
#else
typedef real realv;
#define SPH_SELECT(a, b, c) ((c) ? (b) : (a))
#endif

/* The kernel's shape f(q), without sigma_d / h^d. */
static inline realv sph_kernel_shape(int type, realv q)
{
    const realv zero = (realv)0, one = (realv)1, two = (realv)2;
    const real pi = (real)SPH_PI, k = (real)SPH_DOUBLE_COSINE_K;
    switch (type) {
    case SPH_KERNEL_CUBIC_SPLINE: {
        const realv t = fmax(two - q, zero);
        return SPH_SELECT((real)0.25 * t * t * t, one - (real)1.5 * q * q + (real)0.75 * q * q * q,
                          q < one);
    }
    case SPH_KERNEL_GAUSSIAN:
        return SPH_SELECT(zero, exp(-q * q) - (real)SPH_EXPM9, q <= (real)3);
    case SPH_KERNEL_QUINTIC_SPLINE: {
        const realv a = fmax((real)3 - q, zero), b = fmax(two - q, zero), c = fmax(one - q, zero);
        const realv a2 = a * a, b2 = b * b, c2 = c * c;
        return a2 * a2 * a - (real)6 * b2 * b2 * b + (real)15 * c2 * c2 * c;
    }
    case SPH_KERNEL_WENDLAND_C2: {
        const realv t = fmax(one - (real)0.5 * q, zero);
        return (t * t) * (t * t) * ((real)2 * q + one);
    }
    case SPH_KERNEL_DOUBLE_COSINE:
        return SPH_SELECT(zero, (real)4 * cos(pi * q / k) + cos((real)2 * pi * q / k) + (real)3,
                          q <= k);
    default: { /* SPH_KERNEL_HYPERBOLIC */
        const realv t = fmax(two - q, zero);
        return SPH_SELECT(t * t * t, q * q * q - (real)6 * q + (real)6, q <= one);
    }
    }
}

/* df/dq. */
static inline realv sph_kernel_shape_dq(int type, realv q)
{
    const realv zero = (realv)0, one = (realv)1, two = (realv)2;
    const real pi = (real)SPH_PI, k = (real)SPH_DOUBLE_COSINE_K;
    switch (type) {
    case SPH_KERNEL_CUBIC_SPLINE: {
        const realv t = fmax(two - q, zero);
        return SPH_SELECT((real)-0.75 * t * t, (real)-3 * q + (real)2.25 * q * q, q < one);
    }
    case SPH_KERNEL_GAUSSIAN:
        return SPH_SELECT(zero, (real)-2 * q * exp(-q * q), q <= (real)3);
    case SPH_KERNEL_QUINTIC_SPLINE: {
        const realv a = fmax((real)3 - q, zero), b = fmax(two - q, zero), c = fmax(one - q, zero);
        const realv a2 = a * a, b2 = b * b, c2 = c * c;
        return (real)-5 * a2 * a2 + (real)30 * b2 * b2 - (real)75 * c2 * c2;
    }
    case SPH_KERNEL_WENDLAND_C2: { /* d/dq (1 - q/2)^4 (2q + 1) = -5 q (1 - q/2)^3 */
        const realv t = fmax(one - (real)0.5 * q, zero);
        return (real)-5 * q * t * t * t;
    }
    case SPH_KERNEL_DOUBLE_COSINE:
        return SPH_SELECT(zero,
                          -(real)4 * pi / k * sin(pi * q / k) -
                              (real)2 * pi / k * sin((real)2 * pi * q / k),
                          q <= k);
    default: { /* SPH_KERNEL_HYPERBOLIC */
        const realv t = fmax(two - q, zero);
        return SPH_SELECT((real)-3 * t * t, (real)3 * q * q - (real)6, q <= one);
    }
    }
}

/* (df/dq) / q, what a kernel gradient dW/dr x_ij / r needs: for the
 * Wendland C2 and the Gaussian kernels q cancels, so the pair loops do not
 * divide by r (a vector division costs many multiply-adds on a CPU); the
 * others divide. */
static inline realv sph_kernel_shape_dq_over_q(int type, realv q)
{
    if (type == SPH_KERNEL_WENDLAND_C2) {
        const realv t = fmax((realv)1 - (real)0.5 * q, (realv)0);
        return (real)-5 * t * t * t;
    }
    if (type == SPH_KERNEL_GAUSSIAN)
        return SPH_SELECT((realv)0, (real)-2 * exp(-q * q), q <= (real)3);
    return sph_kernel_shape_dq(type, q) / q;
}

/* One value of the shapes where the lanes are wider (the health
 * indicators; sums that are not over lane blocks): lane 0 of a broadcast. */
#if defined(SPH_LANES) && SPH_LANES > 1
static inline real sph_kernel_shape_scalar(int type, real q)
{
    return lane_of(sph_kernel_shape(type, (realv)q), 0);
}
static inline real sph_kernel_shape_dq_scalar(int type, real q)
{
    return lane_of(sph_kernel_shape_dq(type, (realv)q), 0);
}
#else
#define sph_kernel_shape_scalar sph_kernel_shape
#define sph_kernel_shape_dq_scalar sph_kernel_shape_dq
#endif

/* 1 / h^dim */
static inline real sph_inv_h_pow(real h, int dim)
{
    real ih = (real)1 / h;
    return dim == 1 ? ih : dim == 2 ? ih * ih : ih * ih * ih;
}

/* W(r, h) */
static inline real sph_kernel_value(int type, int dim, real r, real h)
{
    return sph_kernel_sigma(type, dim) * sph_inv_h_pow(h, dim) *
           sph_kernel_shape_scalar(type, r / h);
}

/* dW/dr (r, h); the gradient with respect to x_i is dW/dr (x_i - x_j) / r. */
static inline real sph_kernel_dwdr(int type, int dim, real r, real h)
{
    return sph_kernel_sigma(type, dim) * sph_inv_h_pow(h, dim) / h *
           sph_kernel_shape_dq_scalar(type, r / h);
}

#endif /* SPH_SMOOTHING_CL */
