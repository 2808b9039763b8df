/*
 * The work of the loop-performance monitor, for callgrind
 * (tools/bench/monitor_report.py): mc_scans runs pdt_monitor_scan over a
 * synthetic closed-loop-like record with a FOPDT model (every part of the
 * monitor active), mc_result computes the verdict once. The record is
 * deterministic (the generator of tools/sim/sim_rng.h), its content does not
 * change the work per scan.
 * Argument: the decimation (default 1; Ts is 0.5 s over it).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "pdt/pdt.h"
#include "sim_rng.h"

#define N 4000

static pdt_monitor_t mon;

static pdt_real_t noise(sim_rng64_t *s)
{
    return (pdt_real_t)(sim_rng64_uniform(s) - 0.5);
}

__attribute__((noinline)) void mc_scans(void);
__attribute__((noinline)) void mc_scans(void)
{
    sim_rng64_t s = sim_rng64_seed(1u);
    for (int k = 0; k < N; k++) {
        const pdt_real_t sp = (pdt_real_t)((k / 500) % 2);
        const pdt_real_t pv = sp + (pdt_real_t)(0.3 * sin(0.3 * k)) + (pdt_real_t)0.05 * noise(&s);
        const pdt_real_t u = (pdt_real_t)50.0 + sp + (pdt_real_t)0.1 * noise(&s);
        (void)pdt_monitor_scan(&mon, sp, pv, u);
    }
}

__attribute__((noinline)) pdt_monitor_verdict_t mc_result(void);
__attribute__((noinline)) pdt_monitor_verdict_t mc_result(void)
{
    pdt_monitor_result_t r;
    (void)pdt_monitor_result(&mon, &r);
    return r.verdict;
}

int main(int argc, char **argv)
{
    pdt_monitor_config_t c;
    pdt_monitor_config_default(&c);
    c.decimation = argc > 1 ? (uint32_t)atoi(argv[1]) : 1u;
    c.Ts = (pdt_real_t)0.5 / (pdt_real_t)c.decimation;
    c.has_model = true;
    c.model.kind = PDT_MODEL_FOPDT;
    c.model.p.fopdt.K = (pdt_real_t)1.0;
    c.model.p.fopdt.tau = (pdt_real_t)10.0;
    c.model.p.fopdt.Td = (pdt_real_t)2.0;
    c.u_min = (pdt_real_t)0.0;
    c.u_max = (pdt_real_t)100.0;
    if (pdt_monitor_init(&mon, &c) != PDT_OK) return 1;
    mc_scans();
    printf("%s %u\n", pdt_monitor_verdict_str(mc_result()), (unsigned)sizeof mon);
    return 0;
}
