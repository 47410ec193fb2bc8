/*
 * Lane vectors: the arithmetic type of the neighbour passes and of the
 * smoothing kernels' shapes (kernels/lanes.cl, smoothing.cl). `realv` holds
 * SPH_LANES reals, one per particle of a lane block (a plain real where
 * SPH_LANES is 1), `maskv` the matching comparison result.
 */

#if SPH_LANES == 1
typedef real realv;
#ifdef SPH_DOUBLE
typedef long maskv;
#else
typedef int maskv;
#endif
#elif SPH_LANES == 4
#ifdef SPH_DOUBLE
typedef double4 realv;
typedef long4 maskv;
#else
typedef float4 realv;
typedef int4 maskv;
#endif
#elif SPH_LANES == 8
#ifdef SPH_DOUBLE
typedef double8 realv;
typedef long8 maskv;
#else
typedef float8 realv;
typedef int8 maskv;
#endif
#elif SPH_LANES == 16
#ifdef SPH_DOUBLE
typedef double16 realv;
typedef long16 maskv;
#else
typedef float16 realv;
typedef int16 maskv;
#endif
#else
#error "SPH_LANES must be 1, 4, 8 or 16"
#endif

#ifdef SPH_DOUBLE
typedef long mask_scalar;
#else
typedef int mask_scalar;
#endif

typedef union {
    realv v;
    real s[SPH_LANES];
} lanes_union;

typedef union {
    maskv v;
    mask_scalar s[SPH_LANES];
} mask_union;

static inline real lane_of(realv v, int l)
{
    lanes_union u;
    u.v = v;
    return u.s[l];
}

/* The pair's smoothing length: one number on a uniform lattice, a lane
 * vector on a graded one (the mean of the two particles' h, common.cl
 * PAIR_H), where each lane's particle has its own level. */
#ifdef SPH_GRADED
typedef realv hreal;
#else
typedef real hreal;
#endif
