/* CPU steal over an interval (cpu_steal.h). */
#include "cpu_steal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* user nice system idle iowait irq softirq steal: guest time is already
 * inside user and nice, so the first eight fields are the whole */
#define STAT_FIELDS 8
#define STEAL_FIELD 7

int cpu_times_parse(const char *line, struct cpu_times *out)
{
    out->total = out->steal = 0;
    out->valid = 0;
    if (strncmp(line, "cpu ", 4) != 0)
        return -1;
    double field[STAT_FIELDS] = {0};
    int read = 0, used = 0;
    const char *p = line + 4;
    while (read < STAT_FIELDS && sscanf(p, "%lf%n", &field[read], &used) == 1) {
        if (field[read] < 0)
            return -1;
        p += used;
        ++read;
    }
    if (read < 4) /* user, nice, system and idle at least */
        return -1;
    for (int k = 0; k < read; ++k)
        out->total += field[k];
    out->steal = field[STEAL_FIELD];
    out->valid = 1;
    return 0;
}

struct cpu_times cpu_times_now(void)
{
    struct cpu_times t = {0, 0, 0};
    FILE *f = fopen("/proc/stat", "r");
    if (!f)
        return t;
    char line[512];
    if (fgets(line, sizeof line, f))
        cpu_times_parse(line, &t);
    fclose(f);
    return t;
}

double cpu_steal_fraction(const struct cpu_times *a, const struct cpu_times *b)
{
    const double total = b->total - a->total, steal = b->steal - a->steal;
    if (!a->valid || !b->valid || !(total > 0) || steal < 0)
        return NAN;
    return fmin(steal / total, 1.0);
}
