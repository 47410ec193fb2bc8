/* `sph run`: load, build, step, write. */
#ifndef SPH_RUN_H
#define SPH_RUN_H

struct run_options {
    const char *case_path;
    const char *out_dir; /* NULL: runs/<case>-<date>-<time> */
    const char *device;  /* NULL: first GPU, else first CPU */
    int set_count;
    char **sets; /* "key.path=value" overrides */
    int quiet;
    int profile; /* per-kernel table on stdout and profile.json in the run folder */
    int resume;  /* sph resume: out_dir is the run folder, its checkpoint the start */
};

/* Returns the process exit status: 0 completed, 1 bad input or output
 * error, 2 device or kernel build error, 3 the run went unstable, 130 / 143
 * interrupted by SIGINT / SIGTERM (a checkpoint written). */
int run_case(const struct run_options *opt);

#endif
