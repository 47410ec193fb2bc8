/* Checkpoint files (host/checkpoint.h): named byte records in HDF5, and the
 * solver's part of them. */
#include "checkpoint.h"

#include "output.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* checkpoint.h5; over several processes one file per rank,
 * checkpoint.rank<R>-of-<N>.h5 (a resume needs the same N). */
static void set_names(struct checkpoint *k, const char *folder)
{
    memset(k, 0, sizeof *k);
    k->file = H5I_INVALID_HID;
    if (dist_size() > 1)
        snprintf(k->path, sizeof k->path, "%s/checkpoint.rank%d-of-%d.h5", folder, dist_rank(),
                 dist_size());
    else
        snprintf(k->path, sizeof k->path, "%s/checkpoint.h5", folder);
    output_temporary_name(k->path, k->temporary, sizeof k->temporary);
}

void checkpoint_fail(struct checkpoint *k, const char *what, const char *name)
{
    if (!k->failed)
        snprintf(k->error, sizeof k->error, "%s record '%s' of %s", what, name, k->path);
    k->failed = 1;
}

int checkpoint_begin(struct checkpoint *k, const char *folder)
{
    set_names(k, folder);
    H5E_BEGIN_TRY
    {
        k->file = H5Fcreate(k->temporary, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    }
    H5E_END_TRY;
    if (k->file < 0) {
        snprintf(k->error, sizeof k->error, "cannot write %s", k->temporary);
        return k->failed = 1;
    }
    int format = SPH_CHECKPOINT_FORMAT;
    CHECKPOINT_RECORD(k, "", format, 0);
    return 0;
}

void checkpoint_put(struct checkpoint *k, const char *name, const void *data, size_t bytes)
{
    if (k->failed)
        return;
    const hsize_t count = bytes;
    hid_t space = H5Screate_simple(1, &count, NULL), set = H5I_INVALID_HID;
    herr_t status = -1;
    H5E_BEGIN_TRY
    {
        set = H5Dcreate2(k->file, name, H5T_NATIVE_UCHAR, space, H5P_DEFAULT, H5P_DEFAULT,
                         H5P_DEFAULT);
        if (set >= 0)
            status =
                bytes ? H5Dwrite(set, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
    }
    H5E_END_TRY;
    if (set >= 0)
        H5Dclose(set);
    H5Sclose(space);
    if (status < 0)
        checkpoint_fail(k, "cannot write", name);
}

int checkpoint_end(struct checkpoint *k)
{
    const int closed = k->file >= 0 && H5Fclose(k->file) >= 0;
    k->file = H5I_INVALID_HID;
    if (!closed && !k->failed)
        snprintf(k->error, sizeof k->error, "cannot complete %s", k->temporary);
    if (closed && !k->failed && rename(k->temporary, k->path) != 0)
        snprintf(k->error, sizeof k->error, "cannot rename %s to %s: %s", k->temporary, k->path,
                 strerror(errno)),
            k->failed = 1;
    if (!closed || k->failed) {
        remove(k->temporary); /* the previous checkpoint stays */
        return k->failed = 1;
    }
    return 0;
}

int checkpoint_open(struct checkpoint *k, const char *folder)
{
    set_names(k, folder);
    H5E_BEGIN_TRY
    {
        k->file = H5Fopen(k->path, H5F_ACC_RDONLY, H5P_DEFAULT);
    }
    H5E_END_TRY;
    if (k->file < 0) {
        snprintf(k->error, sizeof k->error,
                 "no checkpoint in %s (%s missing or unreadable; a run over N processes writes "
                 "one file per rank and resumes with mpirun -np N); output.checkpoint_"
                 "interval or checkpoint_wall_interval make a run write one",
                 folder, strrchr(k->path, '/') + 1);
        return k->failed = 1;
    }
    int format = 0;
    CHECKPOINT_RECORD(k, "", format, 1);
    if (!k->failed && format != SPH_CHECKPOINT_FORMAT) {
        snprintf(k->error, sizeof k->error, "%s has format %d; this build reads format %d", k->path,
                 format, SPH_CHECKPOINT_FORMAT);
        k->failed = 1;
    }
    return k->failed;
}

size_t checkpoint_size(struct checkpoint *k, const char *name)
{
    if (k->file < 0)
        return 0;
    hsize_t count = 0;
    H5E_BEGIN_TRY
    {
        hid_t set = H5Dopen2(k->file, name, H5P_DEFAULT);
        if (set >= 0) {
            hid_t space = H5Dget_space(set);
            if (H5Sget_simple_extent_ndims(space) == 1)
                H5Sget_simple_extent_dims(space, &count, NULL);
            H5Sclose(space);
            H5Dclose(set);
        }
    }
    H5E_END_TRY;
    return (size_t)count;
}

void checkpoint_get(struct checkpoint *k, const char *name, void *data, size_t bytes)
{
    if (k->failed)
        return;
    if (checkpoint_size(k, name) != bytes) {
        checkpoint_fail(k, "a build with other structures wrote (or the case differs in)", name);
        return;
    }
    herr_t status = bytes ? -1 : 0;
    H5E_BEGIN_TRY
    {
        hid_t set = H5Dopen2(k->file, name, H5P_DEFAULT);
        if (set >= 0 && bytes)
            status = H5Dread(set, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
        if (set >= 0)
            H5Dclose(set);
    }
    H5E_END_TRY;
    if (status < 0)
        checkpoint_fail(k, "cannot read", name);
}

void checkpoint_record(struct checkpoint *k, const char *name, void *data, size_t bytes, int load)
{
    if (load)
        checkpoint_get(k, name, data, bytes);
    else
        checkpoint_put(k, name, data, bytes);
}

void checkpoint_close(struct checkpoint *k)
{
    if (k->file >= 0)
        H5Fclose(k->file);
    k->file = H5I_INVALID_HID;
}

/* ---- the solver's records */

/* The device buffers beside the fields that a step reads before writing:
 * the sort keys (the lane loop reads them), the cell ranges, the ghosts'
 * lists, the total Lagrangian contact search's list and the projectile's
 * state. NULL where not in use. */
struct named_buffer {
    const char *name;
    cl_mem *buffer;
};
#define SOLVER_BUFFERS(s)                                                                          \
    {                                                                                              \
        {"sort_keys", &(s)->sort_keys}, {"cell_start", &(s)->cell_start},                          \
            {"cell_end", &(s)->cell_end}, {"cell_level", &(s)->cell_level},                        \
            {"ghost_source_id", &(s)->ghosts.source_id}, {"ghost_mask", &(s)->ghosts.mask},        \
            {"ghost_index_of_id", &(s)->ghosts.index_of_id}, {"contact_keys", &(s)->contact_keys}, \
            {"contact_cell_start", &(s)->contact_cell_start},                                      \
            {"contact_cell_end", &(s)->contact_cell_end},                                          \
            {"contact_cell_part_bits", &(s)->contact_cell_part_bits},                              \
        {                                                                                          \
            "projectile_state", &(s)->projectile.state                                             \
        }                                                                                          \
    }

static size_t buffer_bytes(cl_mem m)
{
    size_t bytes = 0;
    if (m)
        CL_CHECK(clGetMemObjectInfo(m, CL_MEM_SIZE, sizeof bytes, &bytes, NULL));
    return bytes;
}

/* One device buffer into the checkpoint (load 0) or back (load 1), through
 * a host copy. */
static void transfer(struct solver *s, struct checkpoint *k, const char *name, cl_mem m,
                     size_t bytes, int load)
{
    void *host = CHECKED_CALLOC(bytes + 1, 1, "checkpoint buffer");
    if (!host) {
        checkpoint_fail(k, "out of host memory for", name);
        return;
    }
    if (load) {
        checkpoint_get(k, name, host, bytes);
        if (!k->failed)
            CL_CHECK(
                clEnqueueWriteBuffer(s->dev->queue, m, CL_TRUE, 0, bytes, host, 0, NULL, NULL));
    } else {
        CL_CHECK(clEnqueueReadBuffer(s->dev->queue, m, CL_TRUE, 0, bytes, host, 0, NULL, NULL));
        checkpoint_put(k, name, host, bytes);
    }
    free(host);
}

/* Every persistent field in use (the n slots of particles and ghosts) and
 * the other buffers a step reads before writing, one walk for both ways. */
static void solver_buffers(struct solver *s, struct checkpoint *k, int load)
{
    char name[128];
    for (int f = 0; f < FIELD_COUNT; ++f)
        if (field_table[f].persistent && solver_field_used(s, (enum field)f)) {
            snprintf(name, sizeof name, "field.%s", field_table[f].name);
            transfer(s, k, name, s->field[f], s->element_size[field_table[f].kind] * (size_t)s->n,
                     load);
        }
    if (load)
        /* made at the first sort, which a resumed run does not repeat */
        solver_make_cell_buffers(s, checkpoint_size(k, "cell_start"));
    const struct named_buffer buffers[] = SOLVER_BUFFERS(s);
    for (size_t b = 0; b < sizeof buffers / sizeof buffers[0]; ++b) {
        const cl_mem m = *buffers[b].buffer;
        if (load && !m != !checkpoint_size(k, buffers[b].name))
            checkpoint_fail(k, "a configuration with other buffers wrote", buffers[b].name);
        else if (m)
            transfer(s, k, buffers[b].name, m, buffer_bytes(m), load);
    }
}

/* The host values that go with the buffers, then the buffers. */
void solver_checkpoint_records(struct solver *s, struct checkpoint *k, int load)
{
    if (s->domain.active) /* this rank's share and halo (host/domain.c) */
        solver_domain_records(s, k, load);
    CHECKPOINT_RECORD(k, "solver.", s->n, load);
    CHECKPOINT_RECORD(k, "solver.", s->ghosts.count, load);
    CHECKPOINT_RECORD(k, "solver.", s->grid, load);
    CHECKPOINT_RECORD(k, "solver.", s->moved_since_sort, load);
    CHECKPOINT_RECORD(k, "solver.", s->moved_since_contact_search, load);
    CHECKPOINT_RECORD(k, "solver.", s->reference_updates, load);
    if (load && !k->failed && (s->n < s->n_real || s->n > s->capacity))
        checkpoint_fail(k, "an impossible particle count in", "solver.s->n");
    if (!k->failed)
        solver_buffers(s, k, load);
    if (load && !k->failed) /* not saved: they follow from the grid and positions */
        solver_lane_lists_build(s);
}
