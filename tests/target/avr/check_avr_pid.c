/*
 * The PID on the AVR: every scenario of tests/vectors/pid_vectors.h
 * (steps of the set-point and the load, weights, forms, filters,
 * anti-windup modes, rate limit, manual and gain change) against the numpy
 * reference with the Cortex-M4F check's tolerance, and the cycles of one
 * pdt_pid_update.
 *
 * The tables (17 KiB) stay in flash: avr-gcc's __flash address space (GNU
 * C) reads them with LPM, and one scenario at a time is copied into the
 * arena under the names pid_cases.h runs a scenario from.
 */
#include <math.h>
#include <string.h>

#include "avr_checks.h"
#include "target_util.h"

#include "pdt_port.h"
#include "pdt_port_avr.h"

/* The generated tables, in flash, under other names. */
#define pid_sc_cfg flash_pid_sc_cfg
#define pid_sc_u0  flash_pid_sc_u0
#define pid_sc_op  flash_pid_sc_op
#define pid_sc_in  flash_pid_sc_in
#define pid_sc_out flash_pid_sc_out
#define const const __flash
#include "pid_vectors.h"
#undef const
#undef pid_sc_cfg
#undef pid_sc_u0
#undef pid_sc_op
#undef pid_sc_in
#undef pid_sc_out

/* One scenario in RAM, as scenario 0 of tables of one. */
#define pid_sc_cfg (g_avr_arena.pid.cfg)
#define pid_sc_u0  (g_avr_arena.pid.u0)
#define pid_sc_op  (g_avr_arena.pid.op)
#define pid_sc_in  (g_avr_arena.pid.in)
#define pid_sc_out (g_avr_arena.pid.out)
#include "pid_cases.h"

#define PID_RTOL 4e-6

#if PID_SC_STEPS != AVR_PID_STEPS || PID_CFG_N * 2u != 28u
#error "the PID vectors changed shape: update avr_arena_t's pid rows"
#endif

#define PID_WORK_UPDATES 1000u

static void load_scenario(size_t s)
{
    for (size_t i = 0; i < 2u * PID_CFG_N; i++) {
        pid_sc_cfg[i] = flash_pid_sc_cfg[2u * s * PID_CFG_N + i];
    }
    pid_sc_u0[0] = flash_pid_sc_u0[s];
    for (size_t k = 0; k < PID_SC_STEPS; k++) {
        const size_t j = s * PID_SC_STEPS + k;
        pid_sc_op[k] = flash_pid_sc_op[j];
        pid_sc_out[k] = flash_pid_sc_out[j];
        for (size_t i = 0; i < 3u; i++) {
            pid_sc_in[3u * k + i] = flash_pid_sc_in[3u * j + i];
        }
    }
}

/* Cycles of one pdt_pid_update of scenario 0's configuration, from a
 * set-point step on (PID_WORK_UPDATES calls, less the same loop without
 * the call), and the stack it used. */
static int pid_work(void)
{
    load_scenario(0u);
    const pdt_pid_config_t c = pid_case_config(&pid_sc_cfg[0]);
    pdt_pid_t pid;
    bool ok = pdt_pid_init(&pid, &c, (pdt_real_t)0.0) == PDT_OK;
    volatile pdt_real_t pv = (pdt_real_t)0.0;
    pdt_real_t u = (pdt_real_t)0.0;
    const size_t depth = pdt_avr_stack_depth();
    t_stack_repaint();
    uint64_t t0 = pdt_port_ticks();
    for (uint16_t k = 0; ok && k < PID_WORK_UPDATES; k++) {
        ok = pdt_pid_update(&pid, (pdt_real_t)1.0, pv, &u) == PDT_OK;
    }
    const uint64_t with = pdt_port_ticks() - t0;
    const size_t stack = pdt_avr_stack_used() - depth;
    t0 = pdt_port_ticks();
    for (uint16_t k = 0; ok && k < PID_WORK_UPDATES; k++) {
        u = pv;
    }
    const uint64_t without = pdt_port_ticks() - t0;
    ok = ok && with > without && isfinite((double)u);
    tline_t l;
    tl_init(&l);
    TL_STR(&l, "pid: ");
    tl_uint(&l, ok ? (with - without) / PID_WORK_UPDATES : 0u);
    TL_STR(&l, " cycles per pdt_pid_update (");
    tl_uint(&l, PID_WORK_UPDATES);
    TL_STR(&l, " after a set-point step); stack ");
    tl_uint(&l, stack);
    TL_STR(&l, " bytes");
    return t_verdict(ok, &l);
}

int avr_check_pid(void)
{
    double worst = 0.0;
    bool ok = true;
    for (size_t s = 0; s < PID_SC_COUNT; s++) {
        double e = 0.0;
        size_t bad = 0u;
        load_scenario(s);
        const pdt_status_t st = pid_case_run(0u, 20.0 * PID_RTOL, &e, &bad);
        ok = ok && st == PDT_OK && bad == PID_SC_STEPS;
        worst = fmax(worst, e);
    }
    tline_t l;
    tl_init(&l);
    TL_STR(&l, "pid: ");
    tl_uint(&l, PID_SC_COUNT);
    TL_STR(&l, " scenarios of ");
    tl_uint(&l, PID_SC_STEPS);
    TL_STR(&l, " scans, largest error ");
    tl_num(&l, worst, 3);
    TL_STR(&l, " of the output range (max ");
    tl_num(&l, 20.0 * PID_RTOL, 2);
    TL_STR(&l, ")");
    return t_verdict(ok, &l) + pid_work();
}
