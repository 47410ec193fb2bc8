/* Checkpoints (RUN_DIR/checkpoint.h5): everything a run needs to go on as
 * if it had never stopped. The file is written under a temporary name and
 * renamed over the previous one when complete, so a crash while writing
 * leaves the previous checkpoint. Each part of a run saves and loads its own
 * records by name (the solver here, the loop in host/run.c, the outputs in
 * host/output.c); a record's size must match on loading, so a checkpoint
 * from a build whose structures differ is refused, not misread. */
#ifndef SPH_CHECKPOINT_H
#define SPH_CHECKPOINT_H

#include <hdf5.h>
#include <stddef.h>

#include "solver.h"

/* 2: the energy ledger and the ballistics record the work of the force
 * holding a prescribed projectile (session 19); 3: the total Lagrangian
 * contact search's list and its drift bound (session 42); 4: the total
 * Lagrangian reference's offset, density and update count (session 43) */
#define SPH_CHECKPOINT_FORMAT 4

struct checkpoint {
    hid_t file;
    char path[SPH_PATH_MAX + 32], temporary[SPH_PATH_MAX + 48];
    int failed;                   /* a record could not be written or read */
    char error[3 * SPH_PATH_MAX]; /* room for both paths */
};

/* Writing: begin, put records, end (close and rename). Returns non-zero
 * with `error` filled. */
int checkpoint_begin(struct checkpoint *k, const char *folder);
void checkpoint_put(struct checkpoint *k, const char *name, const void *data, size_t bytes);
int checkpoint_end(struct checkpoint *k);

/* Reading: open, get records (each exactly `bytes` long), close. */
int checkpoint_open(struct checkpoint *k, const char *folder);
void checkpoint_get(struct checkpoint *k, const char *name, void *data, size_t bytes);
/* the byte size of a record; 0 when it is absent */
size_t checkpoint_size(struct checkpoint *k, const char *name);
void checkpoint_close(struct checkpoint *k);
/* Marks the checkpoint failed: "<what> record '<name>' of <path>". */
void checkpoint_fail(struct checkpoint *k, const char *what, const char *name);

/* A record written (load 0) or read (load 1): each part of a run lists its
 * records once, in one function that serves both ways. */
void checkpoint_record(struct checkpoint *k, const char *name, void *data, size_t bytes, int load);
/* A plain value or struct by its own name and size. */
#define CHECKPOINT_RECORD(k, prefix, value, load)                                                  \
    checkpoint_record((k), prefix #value, &(value), sizeof(value), (load))

/* The solver's state on the device and the host values that go with it:
 * every persistent field in use (field_table), the sort keys and cell
 * ranges, the ghosts' lists and the projectile. */
void solver_checkpoint_records(struct solver *s, struct checkpoint *k, int load);
/* Over several processes, this rank's domain: its reals' count and scene
 * indices, the bisection tree, the halo's lists (host/domain.c). */
void solver_domain_records(struct solver *s, struct checkpoint *k, int load);

#endif
