/*
 * The PID on the target: every scenario of tests/vectors/pid_vectors.h
 * (weights, forms, filters, anti-windup modes, rate limit, manual and gain
 * change) against the numpy reference with the host test's tolerance, and
 * the work of one pdt_pid_update in a closed loop (instructions under QEMU
 * -icount, averaged over many scans) with the stack it used.
 */
#include <math.h>
#include <string.h>

#include "target_checks.h"
#include "target_util.h"

#include "pdt_port.h"
#include "pdt_port_target.h"

#include "pid_vectors.h"

#include "pid_cases.h"

#if PDT_REAL_DOUBLE
#define PID_RTOL 2e-8
#else
#define PID_RTOL 4e-6
#endif

#define PID_WORK_SCANS 20000u

/* The first closed loop of the vectors (the FOPDT at Ts = 0.01 s, the
 * plant in float here) for PID_WORK_SCANS scans, with pdt_pid_update as the
 * controller (pid != NULL) or a constant output; returns the ticks of the
 * whole loop, and in *ok whether every update succeeded and the loop
 * settled at the set-point. */
static uint64_t run_loop(pdt_pid_t *pid, bool *ok)
{
    enum { HIST = 200 };
    static float hist[HIST];
    memset(hist, 0, sizeof hist);
    const double *pl = pid_cl_plant;
    float x = 0.0f;
    uint32_t lag = (uint32_t)pid_cl_l[0];
    float phi = (float)pl[0], g0 = (float)pl[4], g1 = (float)pl[6], cc = (float)pl[8];
    uint32_t head = 0u;
    bool good = lag + 2u <= (uint32_t)HIST;
    uint64_t t0 = pdt_port_ticks();
    for (uint32_t k = 0; good && k < PID_WORK_SCANS; k++) {
        pdt_real_t u = (pdt_real_t)1.0;
        if (pid != NULL) {
            good = pdt_pid_update(pid, (pdt_real_t)1.0, (pdt_real_t)(cc * x), &u) == PDT_OK;
        }
        head = (head + HIST - 1u) % HIST;
        hist[head] = (float)u;
        x = phi * x + g0 * hist[(head + lag) % HIST] + g1 * hist[(head + lag + 1u) % HIST];
    }
    uint64_t spent = pdt_port_ticks() - t0;
    *ok = good && fabsf(cc * x - 1.0f) < 0.01f;
    return spent;
}

/* The work of pdt_pid_update: the closed loop with the PID, less the same
 * loop with a constant output, per scan; and the stack it used. */
static int pid_work(void)
{
    pdt_pid_config_t c = pid_case_config(&pid_cl_cfg[0]);
    pdt_pid_t pid;
    bool ok = pdt_pid_init(&pid, &c, (pdt_real_t)0.0) == PDT_OK &&
              pdt_pid_track(&pid, (pdt_real_t)0.0, (pdt_real_t)0.0, (pdt_real_t)0.0) == PDT_OK;
    size_t depth = pdt_port_stack_depth();
    t_stack_repaint();
    bool settled = false;
    bool open_ok = false;
    uint64_t with = ok ? run_loop(&pid, &settled) : 0u;
    size_t stack = pdt_port_stack_used() - depth;
    uint64_t without = run_loop(NULL, &open_ok);
    ok = ok && settled && with > without;
    uint64_t per = ok ? t_ticks_to_instructions(with - without) / PID_WORK_SCANS : 0u;
    tline_t l;
    tl_init(&l);
    tl_str(&l, "pid: ");
    tl_uint(&l, PID_WORK_SCANS);
    tl_str(&l, " closed-loop scans, ");
    tl_uint(&l, per);
    tl_str(&l, " instructions per pdt_pid_update (the loop less the loop without it); stack ");
    tl_uint(&l, stack);
    tl_str(&l, " B (loop and update)");
    return t_verdict(ok, &l);
}

int target_check_pid(void)
{
    int failed = 0;
    double worst = 0.0;
    bool ok = true;
    for (size_t s = 0; s < PID_SC_COUNT; s++) {
        double e = 0.0;
        size_t bad = 0u;
        pdt_status_t st = pid_case_run(s, 20.0 * PID_RTOL, &e, &bad);
        ok = ok && st == PDT_OK && bad == PID_SC_STEPS;
        worst = fmax(worst, e);
    }
    tline_t l;
    tl_init(&l);
    tl_str(&l, "pid: ");
    tl_uint(&l, PID_SC_COUNT);
    tl_str(&l, " scenarios, largest error ");
    tl_num(&l, worst, 3);
    tl_str(&l, " of the output range");
    failed += t_verdict(ok, &l);
    failed += pid_work();
    return failed;
}
