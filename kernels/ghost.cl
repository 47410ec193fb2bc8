/*
 * Mirror (ghost) particles for symmetry planes (host/ghost.c): each ghost is
 * the image of a real particle in one, two or three planes normal to the
 * coordinate axes. Ghosts take part in the neighbour sums like any particle
 * but are never integrated: before each neighbour pass their fields are
 * copied from their source and reflected (a vector's reflected components
 * change sign, a position is reflected about the plane, a tensor component
 * T_ab changes sign when exactly one of a, b is reflected). The neighbour
 * sums of a particle near a plane then see the material beyond it as the
 * mirror of its own side, which is what symmetry means (Libersky et al.
 * 1993 use the same images for symmetry boundaries).
 *
 * Ghost g (0 <= g < ghost_count) has id first_ghost + g (after the real
 * particles and any MPI halo, kernels/halo.cl); index_of_id maps every
 * id to its current slot (rebuilt after each sort); ghost_source_id[g] is
 * the id of its real source and ghost_mask[g] has bit a set when axis a is
 * reflected; plane holds the planes' coordinates.
 */
#define GHOST_ARGS                                                                                 \
    __global const int *restrict ghost_source_id, __global const int *restrict ghost_mask,         \
        __global const int *restrict index_of_id, const int first_ghost, const int ghost_count

/* reads id; writes index_of_id. */
__kernel void ghost_index_of_id(__global const int *restrict id, __global int *restrict index_of_id,
                                const int n)
{
    const int i = get_global_id(0);
    if (i < n)
        index_of_id[id[i]] = i;
}

/* Sort keys that put every particle in id order (reals first, in their
 * original order, then ghosts), to compact the arrays before the ghosts are
 * rebuilt. reads id; writes sort_keys. */
__kernel void ghost_id_keys(__global const int *restrict id, __global ulong *restrict sort_keys,
                            const int n)
{
    const int i = get_global_id(0);
    if (i < n)
        sort_keys[i] = ((ulong)(uint)id[i] << 32) | (ulong)(uint)i;
}

/* New ghosts occupy slots first_ghost .. first_ghost + ghost_count - 1
 * right after a compaction. writes id, flags of those slots. */
__kernel void ghost_init(__global int *restrict id, __global int *restrict flags,
                         const int first_ghost, const int ghost_count)
{
    const int g = get_global_id(0);
    if (g >= ghost_count)
        return;
    id[first_ghost + g] = first_ghost + g;
    flags[first_ghost + g] = SPH_FLAG_GHOST;
}

#define GHOST_SLOTS                                                                                \
    const int g = get_global_id(0);                                                                \
    if (g >= ghost_count)                                                                          \
        return;                                                                                    \
    const int dst = index_of_id[first_ghost + g], src = index_of_id[ghost_source_id[g]];           \
    const int mask = ghost_mask[g];                                                                \
    (void)mask

static inline real ghost_sign(int mask, int a)
{
    return (mask >> a) & 1 ? (real)-1 : (real)1;
}

__kernel void ghost_refresh_real(__global real *restrict field, GHOST_ARGS)
{
    GHOST_SLOTS;
    field[dst] = field[src];
}

/* Integers are copied; for the flags (`keep` not ~0) only the bits a
 * neighbour reads of an image (spacing level, search reach, damage) are
 * copied, and the ghost bit is set. */
__kernel void ghost_refresh_int(__global int *restrict field, GHOST_ARGS, const int keep,
                                const int set)
{
    GHOST_SLOTS;
    field[dst] = (field[src] & keep) | set;
}

/* is_position: reflect about the planes (x -> 2 plane - x), else flip the
 * reflected components. */
__kernel void ghost_refresh_vec(__global vec *restrict field, GHOST_ARGS, const real4 plane,
                                const int is_position)
{
    GHOST_SLOTS;
    const real planes[3] = {plane.x, plane.y, plane.z};
    real c[3];
#pragma unroll
    for (int a = 0; a < 3; ++a) {
        c[a] = vec_get(field[src], a);
        if ((mask >> a) & 1)
            c[a] = is_position ? (real)2 * planes[a] - c[a] : -c[a];
    }
    field[dst] = vec_make(c[0], c[1], c[2]);
}

/* A tensor seen in the mirror: T_ab -> s_a s_b T_ab, s = -1 across each
 * reflecting plane. */
static inline void reflect_tensor(real t[3][3], int mask)
{
#pragma unroll
    for (int a = 0; a < 3; ++a)
#pragma unroll
        for (int b = 0; b < 3; ++b)
            t[a][b] *= ghost_sign(mask, a) * ghost_sign(mask, b);
}

__kernel void ghost_refresh_symt(__global symt *restrict field, GHOST_ARGS)
{
    GHOST_SLOTS;
    real t[3][3];
    symt_load(field[src], t);
    reflect_tensor(t, mask);
    field[dst] = symt_store(t);
}

__kernel void ghost_refresh_fullt(__global fullt *restrict field, GHOST_ARGS)
{
    GHOST_SLOTS;
    real t[3][3];
    fullt_load(field[src], t);
    reflect_tensor(t, mask);
    field[dst] = fullt_store(t);
}
