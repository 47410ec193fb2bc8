/* CPU time the hypervisor gave to other guests ("steal", Linux /proc/stat)
 * over an interval: on a virtual machine whose neighbours take some of its
 * cores, timings are comparable only where it stays low, so sph bench
 * reports it beside every scene (docs/performance.md measured it with
 * vmstat until then). */
#ifndef SPH_CPU_STEAL_H
#define SPH_CPU_STEAL_H

/* The machine's CPU time since boot, in clock ticks: all of it and the
 * stolen part; valid 0 where it could not be read. */
struct cpu_times {
    double total, steal;
    int valid;
};

/* Parses /proc/stat's aggregate line ("cpu  user nice system idle iowait
 * irq softirq steal ..."; kernels before 2.6.11 stop before steal, which
 * is then 0). Returns 0, or -1 for a line that is not one. */
int cpu_times_parse(const char *line, struct cpu_times *out);
/* The times now (valid 0 without a readable /proc/stat). */
struct cpu_times cpu_times_now(void);
/* The stolen share of the CPU time from a to b, in [0, 1]; NAN where either
 * is not valid or no time passed. */
double cpu_steal_fraction(const struct cpu_times *a, const struct cpu_times *b);

#endif
