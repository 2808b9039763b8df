/*
 * The PID vectors' rows as pdt_pid calls, shared by the host test
 * (tests/test_pid.c) and the target check (check_pid.c): the configuration
 * of a row, and one scenario run against its expected outputs. Include
 * after pid_vectors.h.
 */
#ifndef PDT_PID_CASES_H
#define PDT_PID_CASES_H

#include <math.h>
#include <stddef.h>

#include "pdt/pdt_pid.h"

/* The configuration stored at v (PID_CFG_N numbers, tools/vectorgen/pid.py). */
static inline pdt_pid_config_t pid_case_config(const double *v)
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

/* Runs scenario s. *worst: the largest |u - reference| relative to the
 * scenario's output range (at least 1); *bad_step: the first step whose
 * error exceeds tol (PID_SC_STEPS if none). Returns the first status other
 * than PDT_OK of a pdt_pid call, else PDT_OK. */
static inline pdt_status_t pid_case_run(size_t s, double tol, double *worst, size_t *bad_step)
{
    pdt_pid_config_t c1 = pid_case_config(&pid_sc_cfg[(2u * s) * PID_CFG_N]);
    pdt_pid_config_t c2 = pid_case_config(&pid_sc_cfg[(2u * s + 1u) * PID_CFG_N]);
    pdt_pid_t pid;
    *worst = 0.0;
    *bad_step = PID_SC_STEPS;
    pdt_status_t st = pdt_pid_init(&pid, &c1, (pdt_real_t)pid_sc_u0[s]);
    double scale = 1.0;
    for (size_t k = 0; k < PID_SC_STEPS; k++) {
        scale = fmax(scale, fabs(pid_sc_out[s * PID_SC_STEPS + k]));
    }
    for (size_t k = 0; st == PDT_OK && k < PID_SC_STEPS; k++) {
        size_t j = s * PID_SC_STEPS + k;
        const double *in = &pid_sc_in[3u * j];
        pdt_real_t u = (pdt_real_t)0.0;
        if (pid_sc_op[j] == 1) {
            st = pdt_pid_track(&pid, (pdt_real_t)in[0], (pdt_real_t)in[1], (pdt_real_t)in[2]);
            u = pid.u;
        } else {
            st = pid_sc_op[j] == 2 ? pdt_pid_set_config(&pid, &c2) : PDT_OK;
            if (st == PDT_OK) {
                st = pdt_pid_update(&pid, (pdt_real_t)in[0], (pdt_real_t)in[1], &u);
            }
        }
        double err = fabs((double)u - pid_sc_out[j]) / scale;
        *worst = fmax(*worst, err);
        if (!(err <= tol) && *bad_step == PID_SC_STEPS) {
            *bad_step = k;
        }
    }
    return st;
}

#endif /* PDT_PID_CASES_H */
