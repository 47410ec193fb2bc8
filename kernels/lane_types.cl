/*
 * Lane vectors: the arithmetic type of the neighbour passes and of the
 * smoothing kernels' shapes (kernels/lanes.cl, smoothing.cl). `realv` holds
 * SPH_LANES reals, one per particle of a lane block (a plain real where
 * SPH_LANES is 1), `maskv` the matching comparison result.
 */

#ifdef SPH_DOUBLE
typedef long mask_scalar;
#else
typedef int mask_scalar;
#endif

/* The widths host/state.c builds (solver_lanes): 1 and 8. */
#if SPH_LANES == 1
typedef real realv;
typedef mask_scalar maskv;
#elif SPH_LANES == 8 && defined(SPH_DOUBLE)
typedef double8 realv;
typedef long8 maskv;
#elif SPH_LANES == 8
typedef float8 realv;
typedef int8 maskv;
#else
#error "SPH_LANES must be 1 or 8 (host/state.c, solver_lanes)"
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
 * PAIR_H), where each lane's particle has its own level, and with a tensor
 * smoothing length (the two ellipsoids' lengths along the pair,
 * tensor_smoothing.cl). */
#if defined(SPH_GRADED) || defined(SPH_TENSOR_SMOOTHING)
typedef realv hreal;
#else
typedef real hreal;
#endif
