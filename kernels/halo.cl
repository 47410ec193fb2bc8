/*
 * MPI halos (host/domain.c): the particles of other ranks within reach of
 * this rank's slab live in ghost slots with ids n_real .. n_real +
 * halo_count - 1, like the mirror images of kernels/ghost.cl. Before a
 * neighbour pass the owner packs, for each particle it sends, one record of
 * the fields the pass reads across (field by field, `words` 32-bit words
 * per element at `offset` in a record of `record_words`); the host
 * exchanges the records and the receiver unpacks them into the halo slots.
 * Words, not reals: one pair of kernels serves every element kind and
 * precision.
 */

/* reads source at the slots of send_ids; writes staging. */
__kernel void halo_pack(__global const uint *restrict source, const int words,
                        const int record_words, const int offset,
                        __global const int *restrict send_ids,
                        __global const int *restrict index_of_id, __global uint *restrict staging,
                        const int count)
{
    const int k = get_global_id(0);
    if (k >= count)
        return;
    const size_t from = (size_t)index_of_id[send_ids[k]] * (size_t)words;
    const size_t to = (size_t)k * (size_t)record_words + (size_t)offset;
    for (int w = 0; w < words; ++w)
        staging[to + w] = source[from + w];
}

/* reads staging; writes target at the halo slots. The flags keep the bits
 * a ghost keeps and get the ghost bit (keep ~0 and set 0 elsewhere). */
__kernel void halo_unpack(__global uint *restrict target, const int words, const int record_words,
                          const int offset, __global const uint *restrict staging,
                          __global const int *restrict index_of_id, const int first_id,
                          const int count, const int keep, const int set)
{
    const int k = get_global_id(0);
    if (k >= count)
        return;
    const size_t from = (size_t)k * (size_t)record_words + (size_t)offset;
    const size_t to = (size_t)index_of_id[first_id + k] * (size_t)words;
    for (int w = 0; w < words; ++w)
        target[to + w] = (staging[from + w] & (uint)keep) | (uint)set;
}
