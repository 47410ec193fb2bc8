/*
 * Device ceilings for the profile table (sph bench): the memory bandwidth of
 * a plain copy and the throughput of independent FMA chains. Both are in
 * single precision whatever the solver's precision, and neither touches the
 * particle state.
 */

/* reads in; writes out: one float4 per work-item (16 B read, 16 B written). */
__kernel void probe_copy(__global const float4 *restrict in, __global float4 *restrict out)
{
    const size_t i = get_global_id(0);
    out[i] = in[i];
}

/* 12 independent float8 FMA chains per work-item, `iterations` times:
 * 192 flops per iteration and work-item (enough chains to cover the FMA
 * latency of a CPU core's pipes). The multiplier stays near 1 so the chains
 * neither overflow nor flush to zero. */
__kernel void probe_fma(__global float *restrict out, const int iterations, const float seed)
{
    const float8 m = (float8)(0.999999f), c = (float8)(seed * 1e-7f);
    const float8 a0_ = (float8)(seed) + (float8)(0, 1, 2, 3, 4, 5, 6, 7);
    float8 a0 = a0_, a1 = a0_ + 1.0f, a2 = a0_ + 2.0f, a3 = a0_ + 3.0f, a4 = a0_ + 4.0f,
           a5 = a0_ + 5.0f, a6 = a0_ + 6.0f, a7 = a0_ + 7.0f, a8 = a0_ + 8.0f, a9 = a0_ + 9.0f,
           a10 = a0_ + 10.0f, a11 = a0_ + 11.0f;
    for (int k = 0; k < iterations; ++k) {
        a0 = fma(a0, m, c);
        a1 = fma(a1, m, c);
        a2 = fma(a2, m, c);
        a3 = fma(a3, m, c);
        a4 = fma(a4, m, c);
        a5 = fma(a5, m, c);
        a6 = fma(a6, m, c);
        a7 = fma(a7, m, c);
        a8 = fma(a8, m, c);
        a9 = fma(a9, m, c);
        a10 = fma(a10, m, c);
        a11 = fma(a11, m, c);
    }
    const float8 s = a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7 + a8 + a9 + a10 + a11;
    out[get_global_id(0)] = s.s0 + s.s1 + s.s2 + s.s3 + s.s4 + s.s5 + s.s6 + s.s7;
}
