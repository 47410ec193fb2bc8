/* One case over many processes (MPI): the processes, their collectives,
 * and the spatial domains (host/domain.c). Without MPI, or without a
 * launcher, there is one process and every call here is trivial. */
#ifndef SPH_DOMAIN_H
#define SPH_DOMAIN_H

#include <stddef.h>

#include "device.h"

/* MPI_Init under a launcher (mpirun sets its variables); a plain `sph run`
 * stays one process without MPI's runtime. dist_stop at the end of main. */
void dist_start(int *argc, char ***argv);
void dist_stop(void);
int dist_rank(void);
int dist_size(void);
/* This process's rank among those on its node (the launcher's variable), 0
 * for one process. */
int dist_local_rank(void);
/* Ends every process of the job with `code` (MPI_Abort), or this one. */
void dist_abort(int code);

/* Collectives over every process (in place; no-ops on one). */
void dist_sum(double *v, size_t n);
void dist_max(double *v, size_t n);
void dist_min(double *v, size_t n);
void dist_sum_ints(int *v, size_t n);
void dist_or_bytes(char *v, size_t n);
/* Sums of `sums` and maxima of `maxima` in one collective (a step's
 * reduction: one latency, not two); at most 64 values together. */
void dist_sum_max(double *sums, int n_sums, double *maxima, int n_maxima);
int dist_any(int flag);
int dist_bcast_int(int value); /* rank 0's */
/* Whether any process failed: the lowest failing rank's `error` (with its
 * rank) becomes every process's. */
int dist_agree(int failed, char *error, size_t size);
/* Every process sends send_bytes[r] bytes of `send` (blocks in rank order)
 * to rank r and gets recv_bytes[r] from it into *recv (allocated here,
 * freed by the caller). Returns non-zero when out of host memory. */
int dist_exchange(const void *send, const int *send_bytes, void **recv, int *recv_bytes);
/* The same when every process knows what it gets from each (recv_bytes
 * into `recv`, allocated by the caller): point-to-point messages with the
 * ranks concerned only. */
void dist_exchange_known(const void *send, const int *send_bytes, void *recv,
                         const int *recv_bytes);
/* Every process's `count` doubles, in rank order, into *all (allocated). */
int dist_allgather(const double *mine, int count, double **all, int *total);

#ifdef SPH_PARALLEL_HDF5
#include <hdf5.h>
/* Sets HDF5 file access and dataset transfer properties for one file that
 * every process writes together (MPI-IO, collective transfers); non-zero
 * on failure. */
int dist_hdf5_collective(hid_t file_access, hid_t transfer);
#endif

/* The spatial domains: boxes, one per rank, the leaves of an orthogonal
 * recursive bisection (each cut at the share of the ranks on either side,
 * across the axis whose cut the fewest particles reach), cut again when
 * the shares drift apart (DOMAIN_IMBALANCE). Ghost slots after the real
 * particles hold the halo: the particles of other ranks within a support
 * (plus the grid's skin) of this rank's box, refreshed before each
 * neighbour pass. */
#define DOMAIN_IMBALANCE 0.1 /* largest share over the mean, less one */
struct domain {
    int active; /* more than one process */
    int rank, size;
    /* the bisection tree, size - 1 nodes in preorder, node 0 the root: node
     * c cuts across axis split_axis[c] at split_at[c] (m); child[2c] is
     * below the cut, child[2c + 1] above, each a node or -1 - rank */
    int *split_axis, *child;
    double *split_at;
    int n_scene;       /* particles of the whole case */
    int initial_reals; /* this rank's share of the scene */
    int *global_id;    /* scene index of each local real particle (local id) */
    int halo_count;    /* halo slots in use, ids n_real .. n_real + halo_count - 1 */
    int halo_capacity;
    int *send_count, *recv_count; /* halo particles to and from each rank */
    int send_total;
    long migrated;          /* particles that changed rank, all ranks, whole run */
    double halo_bytes_sent; /* by this rank's halo refreshes, whole run */
    int rebalances;         /* times the domains were cut again */
    cl_mem send_ids, staging_out, staging_in;
    size_t staging_words;         /* of each staging buffer, device and host */
    void *host_out, *host_in;     /* the exchange's host side */
    int *send_bytes, *recv_bytes; /* per rank, of one refresh */
    cl_kernel pack, unpack;
};

#endif
