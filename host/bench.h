/* `sph bench`: throughput and per-kernel profile of a fixed suite. */
#ifndef SPH_BENCH_H
#define SPH_BENCH_H

#define BENCH_MAX_REPEATS 15

struct bench_options {
    const char *device;    /* as sph run --device */
    const char *json_path; /* NULL: no JSON */
    const char *only;      /* NULL, or run the scenes whose name contains it */
    int quick, large;      /* the quick tier (a smoke test); add the large sizes */
    int warmup, steps, repeats;
    int set_count;
    char **sets; /* --set overrides applied to every scene */
};

/* Returns the exit status: 0, 1 bad options or output error, 2 device error
 * or a scene that failed. */
int bench_main(const struct bench_options *o);

#endif
