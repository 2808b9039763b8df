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
#include "pdt_port_cm4.h"

#include "pid_vectors.h"

#if PDT_REAL_DOUBLE
#define PID_RTOL 2e-8
#else
#define PID_RTOL 4e-6
#endif

#define PID_WORK_SCANS 20000u

static pdt_pid_config_t cfg_from(const double *v)
{
    pdt_pid_config_t c;
    c.Ts = (pdt_real_t)v[0];
    c.form = (pdt_pid_form_t)(int)v[1];
    c.Kc = (pdt_real_t)v[2];
    c.Ti = (pdt_real_t)v[3];
    c.Td = (pdt_real_t)v[4];
    c.Tf = (pdt_real_t)v[5];
    c.N = (pdt_real_t)v[6];
    c.b = (pdt_real_t)v[7];
    c.c = (pdt_real_t)v[8];
    c.u_min = (pdt_real_t)v[9];
    c.u_max = (pdt_real_t)v[10];
    c.rate_max = (pdt_real_t)v[11];
    c.antiwindup = (pdt_pid_antiwindup_t)(int)v[12];
    c.Tt = (pdt_real_t)v[13];
    return c;
}

/* Largest error of one scenario relative to its output range; < 0 when a
 * call failed. */
static double scenario_err(size_t s)
{
    pdt_pid_config_t c1 = cfg_from(&pid_sc_cfg[(2u * s) * PID_CFG_N]);
    pdt_pid_config_t c2 = cfg_from(&pid_sc_cfg[(2u * s + 1u) * PID_CFG_N]);
    pdt_pid_t pid;
    if (pdt_pid_init(&pid, &c1, (pdt_real_t)pid_sc_u0[s]) != PDT_OK) {
        return -1.0;
    }
    double scale = 1.0;
    for (size_t k = 0; k < PID_SC_STEPS; k++) {
        scale = fmax(scale, fabs(pid_sc_out[s * PID_SC_STEPS + k]));
    }
    double worst = 0.0;
    for (size_t k = 0; k < PID_SC_STEPS; k++) {
        size_t j = s * PID_SC_STEPS + k;
        const double *in = &pid_sc_in[3u * j];
        pdt_real_t u = (pdt_real_t)0.0;
        pdt_status_t st;
        if (pid_sc_op[j] == 1) {
            st = pdt_pid_track(&pid, (pdt_real_t)in[0], (pdt_real_t)in[1], (pdt_real_t)in[2]);
            u = pid.u;
        } else {
            st = pid_sc_op[j] == 2 ? pdt_pid_set_config(&pid, &c2) : PDT_OK;
            if (st == PDT_OK) {
                st = pdt_pid_update(&pid, (pdt_real_t)in[0], (pdt_real_t)in[1], &u);
            }
        }
        if (st != PDT_OK) {
            return -1.0;
        }
        worst = fmax(worst, fabs((double)u - pid_sc_out[j]) / scale);
    }
    return worst;
}

/* pdt_pid_update in the first closed loop of the vectors (the FOPDT at
 * Ts = 0.01 s, the plant in float here: only the controller's work is
 * measured). Instructions per update, and the stack used. */
static int pid_work(void)
{
    pdt_pid_config_t c = cfg_from(&pid_cl_cfg[0]);
    const double *pl = pid_cl_plant;
    pdt_pid_t pid;
    if (pdt_pid_init(&pid, &c, (pdt_real_t)0.0) != PDT_OK) {
        tline_t l;
        tl_init(&l);
        tl_str(&l, "pid work: init failed");
        return t_verdict(false, &l);
    }
    enum { HIST = 200 };
    float hist[HIST];
    memset(hist, 0, sizeof hist);
    float x = 0.0f;
    int lag = pid_cl_l[0];
    float phi = (float)pl[0], g0 = (float)pl[4], g1 = (float)pl[6], cc = (float)pl[8];
    uint32_t head = 0u;
    uint64_t spent = 0u;
    size_t depth = pdt_cm4_stack_depth();
    t_stack_repaint();
    bool ok = lag + 2 <= HIST;
    for (uint32_t k = 0; ok && k < PID_WORK_SCANS; k++) {
        pdt_real_t u;
        pdt_real_t pv = (pdt_real_t)(cc * x);
        uint64_t t0 = pdt_port_ticks();
        ok = pdt_pid_update(&pid, (pdt_real_t)1.0, pv, &u) == PDT_OK;
        spent += pdt_port_ticks() - t0;
        head = (head + HIST - 1u) % HIST;
        hist[head] = (float)u;
        x = phi * x + g0 * hist[(head + (uint32_t)lag) % HIST] +
            g1 * hist[(head + (uint32_t)lag + 1u) % HIST];
    }
    size_t stack = pdt_cm4_stack_used() - depth;
    /* The two counter reads alone, to subtract. */
    uint64_t reads = 0u;
    for (uint32_t k = 0; k < PID_WORK_SCANS; k++) {
        uint64_t t0 = pdt_port_ticks();
        reads += pdt_port_ticks() - t0;
    }
    /* The loop settles at the set-point: the controller ran as designed. */
    ok = ok && fabsf(cc * x - 1.0f) < 0.01f;
    tline_t l;
    tl_init(&l);
    tl_str(&l, "pid: ");
    tl_uint(&l, PID_WORK_SCANS);
    tl_str(&l, " closed-loop updates, ");
    tl_uint(&l, t_ticks_to_instructions(spent) / PID_WORK_SCANS);
    tl_str(&l, " instructions per update with the two counter reads, which alone take ");
    tl_uint(&l, t_ticks_to_instructions(reads) / PID_WORK_SCANS);
    tl_str(&l, "; stack ");
    tl_uint(&l, stack);
    tl_str(&l, " B");
    return t_verdict(ok, &l);
}

int target_check_pid(void)
{
    int failed = 0;
    double worst = 0.0;
    bool ok = true;
    for (size_t s = 0; s < PID_SC_COUNT; s++) {
        double e = scenario_err(s);
        ok = ok && e >= 0.0 && e <= 20.0 * PID_RTOL;
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
